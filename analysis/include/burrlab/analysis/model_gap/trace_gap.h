// The trace-only effects of the library (sim/effects.h: load_cell_lag,
// arm_compliance) tested on the descent rig's time traces: steady v(F) cannot
// see them, the loading transient after contact can.
//
// A lumped transient model of the rig stands for the voxel simulator: the
// arm moves under the rig's own PI law on the measured force (sim/descent.h);
// the contact force is Hertz's c_e R^2 (h/R)^{3/2} (eq. 7.3) with h the burr
// tip's depth below the eroded surface; the surface erodes quasi-steadily at
// ds/dt = alpha R / kappa((h/R)^{3/2}) (descent_surrogate.h, from eqs. 7.2
// and 7.12), so the model holds exactly the steady state the surrogate
// predicts; the load cell is the rig's first-order filter, then the
// load_cell_lag stage; arm_compliance is a massless series spring between
// the arm and the tip. The controller's settings are the defaults of
// sim::DescentOptions (kp 4 mm/(N s), ki 8 mm/(N s^2), kd 0, 100 Hz filter,
// 5 mm/s limit, 1 ms period), assumed to be the real rig's.
//
// c_e is a nuisance parameter fitted to the traces (v(F) pins only a
// combination of c_e and alpha, and a wrong c_e moves the indentation depth
// as a spring would), alpha following it along the base fit of v(F) so that
// v(F) stays fitted as well. Each trace-only effect's parameter is fitted
// (bounded, at least its null) with c_e to every run's recorded force and
// depth from its start to window_s after contact; the likelihood ratio
// against the null is referred to the 50:50 chi-bar-squared mixture (the
// parameter sits on its boundary under the null; Self & Liang 1987), and
// Holm's correction runs over the trace effects. The lumped model is not the
// truth: its error against the voxel rig is smooth and correlated in time, so
// each channel (force, depth) counts only its effectively independent
// residuals, n (1 - rho) / (1 + rho) with rho the null fit's lag-1
// autocorrelation, and its residual variance carries a model-error floor.
// Replicates at one force weigh as one trace together (they share the rig's
// systematic transient).
#ifndef BURRLAB_ANALYSIS_MODEL_GAP_TRACE_GAP_H_
#define BURRLAB_ANALYSIS_MODEL_GAP_TRACE_GAP_H_

#include <string>
#include <vector>

#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/analysis/model_gap/trace_data.h"
#include "burrlab/base/result.h"
#include "burrlab/sim/descent.h"
#include "burrlab/sim/effects.h"

namespace burrlab::analysis {

// One traced run and the force the rig held in it.
struct TraceRun {
  RunTrace trace;
  double force_n = 0.0;
};

// Pairs each trace with its measured run's force (MatchTracesToRuns first).
std::vector<TraceRun> PairTraces(const TraceData& traces,
                                 const MeasuredData& measured);

struct TraceGapOptions {
  double c_e_n_per_mm2 = 0.0;  // base fit's elastic constant
  double alpha_per_s = 0.0;    // base fit's erosion constant
  double radius_mm = 0.0;      // burr radius R
  // The rig's controller, load-cell filter, speed limit and period
  // (kp_mm_per_n_s, ki_mm_per_n_s2, kd_mm_per_n, filter_hz, max_speed_mm_s,
  // dt_s); the material and effects fields are not used.
  sim::DescentOptions rig;
  double window_s = 3.0;     // fitted span after contact, s
  double test_level = 0.05;  // family-wise level over the trace effects
  // Model-error floor of each channel's RMS residual, as a fraction of the
  // held force (force channel) and of the static Hertz immersion
  // R (F / (c_e R^2))^{2/3} (depth channel): about the lumped model's own
  // RMS error against an effect-free voxel rig (bone, loads 0.5-1.5: force
  // 0.3-0.7 %, depth 2-4 %; analysis/README.md).
  double model_error_fraction = 0.03;

  // Names the first bad field, its value and the rule broken.
  Status Validate() const;
};

// A trace-only effect fitted and tested.
struct TraceEffectTest {
  std::string id;
  double value = 0.0;          // fitted parameter (sim/effects.h units)
  double c_e_n_per_mm2 = 0.0;  // c_e fitted with it (a nuisance parameter)
  double lr = 0.0;             // likelihood ratio against the null
  double p = 1.0;              // 50:50 chi-bar-squared mixture
  double p_holm = 1.0;         // Holm-adjusted over the trace effects
  double rmse_force_n = 0.0;   // trace RMSE with the effect fitted
  double rmse_depth_mm = 0.0;  // likewise
};

struct TraceGapResult {
  std::vector<TraceEffectTest> effects;  // library order
  double c_e_n_per_mm2 = 0.0;            // c_e of the null fit to the traces
  double rmse_force_n = 0.0;             // trace RMSE of the null model
  double rmse_depth_mm = 0.0;            // likewise
  int runs = 0;                          // traces used
  int samples = 0;  // samples fitted (runs with identical traces once)
  // The significant effect (p_holm < test_level) with the largest LR, or "".
  std::string named;
};

// Fits and tests the trace-only effects. Errors: bad options, no traces,
// a trace that never reaches 5 % of its force (no contact).
Result<TraceGapResult> TestTraceEffects(const std::vector<TraceRun>& runs,
                                        const TraceGapOptions& options);

// The lumped model's recorded force and arm depth at a run's sample times
// (those up to `until_s`), started from its first sample, with `effects`'
// trace-only parameters. For tests and plots.
struct LumpedTrace {
  std::vector<double> t_s, force_n, depth_mm;
  std::vector<double> burr_depth_mm;  // the tip: depth_mm less C F
  std::vector<double> surface_mm;     // the eroded surface s
};
LumpedTrace SimulateLumpedRig(const RunTrace& trace, double force_n,
                              const TraceGapOptions& options,
                              const sim::Effects& effects, double until_s);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_MODEL_GAP_TRACE_GAP_H_
