// Synthetic "measured" burring data: the full virtual descent rig
// (sim/descent.h, the rig of `burrlab sim descent`) once per force level, with
// physical effects hidden in the simulated model and log-normal run-to-run
// noise; the velocity is the rig's under the named definition. The
// calibration sees only the CSV it produces (and fits the continuum
// surrogate, not the voxel rig).
#ifndef BURRLAB_ANALYSIS_MODEL_GAP_SYNTHETIC_MEASUREMENT_H_
#define BURRLAB_ANALYSIS_MODEL_GAP_SYNTHETIC_MEASUREMENT_H_

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/sim/descent.h"
#include "burrlab/sim/effects.h"
#include "burrlab/sim/model.h"

namespace burrlab::analysis {

struct SyntheticMeasurementOptions {
  sim::Material material;         // the truth
  sim::Effects effects;           // hidden effects (null: none)
  std::vector<double> forces_n;   // force levels, N
  int replicates = 3;             // runs per force level
  double noise_cv = 0.1;          // coefficient of variation of the log-normal
                                  // run-to-run factor (0: none)
  std::uint64_t seed = 1;         // erosion streams and noise
  double radius_mm = 1.0;         // burr radius R
  double spindle_rad_s = 2094.0;  // burr spin
  // What the velocity is (sim/descent.h); written to the CSV.
  sim::VelocityDefinition definition = sim::kDefaultVelocityDefinition;
  // Rig discretisation: the voxel size (0: the rig's default for each force
  // level, sim::RigVoxelsPerRadius), and a control and simulation period of
  // 5 ms instead of the rig's 1 ms: five times cheaper, and within 0.3 % of
  // it (tests/runner/sim_commands_test.cc).
  double voxel_mm = 0.0;
  double dt_s = 5e-3;
  // The octree's accuracy scale as a fraction of R (unset: the rig's default
  // for each force level, sim::RigEllOverR).
  std::optional<double> ell_over_r;
  // Moment reuse between steps (sim::DescentOptions::moment_reuse_over_h).
  double moment_reuse_over_h = sim::DescentOptions{}.moment_reuse_over_h;
  // Keep each level's time trace (trace_data.h): every 10 ms (100 Hz) until
  // this long after contact, at the rig's coarser trace period after.
  bool keep_traces = false;
  double trace_fine_s = 10.0;  // s
  // Sensor noise of the written traces (FormatTraceCsv): white, Gaussian,
  // drawn afresh for every run and sample, standard deviations. Defaults:
  // a few mN, as a small 6-axis load cell, and a depth encoder's 1 um.
  // Added to the recorded channels only; the rig's controller sees the
  // noise-free load cell.
  double trace_force_noise_n = 0.005;
  double trace_depth_noise_mm = 0.001;
  // Force levels run at once, each on its own thread. Each level has its own
  // seed, so the output does not depend on this.
  int jobs = 1;
  // Called after each force level's rig run with the levels done and their
  // total, one call at a time (from whichever thread finished the level).
  std::function<void(int done, int total)> progress;

  // Names the first bad field.
  Status Validate() const;
};

struct SyntheticRun {
  int run = 0;  // 1-based
  double force_n = 0.0;
  double velocity_mm_s = 0.0;      // rig velocity times the noise factor
  double rig_velocity_mm_s = 0.0;  // the rig's velocity, noise-free
};

struct SyntheticMeasurement {
  std::vector<SyntheticRun> runs;            // force levels in the given order,
                                             // replicates together
  std::vector<double> skipped_forces_n;      // levels where the rig measured no
                                             // velocity (the burr did not cut,
                                             // e.g. below a cutting threshold)
  std::vector<std::string> skipped_reasons;  // why, one per skipped level
  // With keep_traces: the rig's trace per force level (the replicates of a
  // level share it, as they share its rig velocity).
  std::vector<std::vector<sim::DescentSample>> level_traces;
};

// The rig's trace at one force from its start to `after_contact_s` after
// contact, every 10 ms: the first samples of RigSteadyVelocityMmS's run with
// the same seed (cheap: the steady window is what costs).
Result<std::vector<sim::DescentSample>> RigTransientTrace(
    const SyntheticMeasurementOptions& options, double force_n,
    std::uint64_t seed, double after_contact_s);

// The rig's velocity at one force under the options' definition; an error
// when the rig fails, 0 when it measured none. With `trace`, also the rig's
// trace, 100 Hz until options.trace_fine_s after contact.
// `no_velocity_reason` receives the rig's reason when there is none.
Result<double> RigSteadyVelocityMmS(
    const SyntheticMeasurementOptions& options, double force_n,
    std::uint64_t seed, std::vector<sim::DescentSample>* trace = nullptr,
    std::string* no_velocity_reason = nullptr);

// Runs the rig once per force level (its own erosion stream) and draws the
// replicates' noise: velocity = rig velocity x exp(s z), z ~ N(0, 1),
// s^2 = ln(1 + cv^2) (median = the rig's velocity).
Result<SyntheticMeasurement> MeasureSynthetic(
    const SyntheticMeasurementOptions& options);

// The two halves of MeasureSynthetic, so that Monte-Carlo studies run the
// rig once per level and draw many noise seeds: the rig's velocity per
// force level of `options` (0 where it reached none), and the replicates
// drawn around them with options.seed.
Result<std::vector<double>> RigVelocitiesMmS(
    const SyntheticMeasurementOptions& options,
    std::vector<std::vector<sim::DescentSample>>* traces = nullptr,
    std::vector<std::string>* no_velocity_reasons = nullptr);
SyntheticMeasurement DrawReplicates(const SyntheticMeasurementOptions& options,
                                    const std::vector<double>& rig_mm_s);

// The CSV of measured_data.h: run,material,burr_radius_mm,spindle_rad_s,
// force_n,velocity_mm_s,velocity_definition.
std::string FormatMeasuredCsv(const SyntheticMeasurement& measurement,
                              const std::string& material_name,
                              const SyntheticMeasurementOptions& options);

// The traces of trace_data.h, run,t_s,force_n,depth_mm: each run's level
// trace (measurement.level_traces, in options.forces_n order) with the
// options' sensor noise, drawn for each run from options.seed and the run
// number (replicates share the rig trace, not the noise).
std::string FormatTraceCsv(const SyntheticMeasurement& measurement,
                           const SyntheticMeasurementOptions& options);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_MODEL_GAP_SYNTHETIC_MEASUREMENT_H_
