// The virtual calibration rig of dissertation ch. 8: a spinning burr descends
// vertically into a flat sample while a PID-style loop holds the contact force
// constant, as on the real robot arm (fig. 8.5). Yields the displacement-time
// trace and the penetration velocity under one of two named definitions
// (VelocityDefinition): the dissertation's initial penetration velocity
// (§8.6-8.7) or the settled velocity of a long run.
#ifndef BURRLAB_SIM_DESCENT_H_
#define BURRLAB_SIM_DESCENT_H_

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/sim/model.h"

namespace burrlab::sim {

// What "the penetration velocity at force F" means. Every tool that makes,
// reads or fits velocities (the rig, synthetic measurements, the CSV format,
// the surrogate, calibrate, discover) names one of these.
//
// kInitial (§8.6, fig. 8.6; §8.7's "initial penetration velocity"): after the
// impact the burr "proceeds at an essentially constant velocity until it is
// well inside (more than one third of its radius)". The impact transient ends
// when the measured force enters the settling band (DescentOptions::
// settling_band around the held force) and stays there; the velocity is the
// least-squares slope of depth against time from then until the burr has cut
// R/3 further. (The cut is counted from the transient's end, not from the
// surface: the model's elastic indentation h = R (F / c_e R^2)^(2/3) of eqs.
// 7.2-7.3 alone passes R/3 for F > c_e R^2 / 3^(3/2), 1.65 N for bone at
// R = 2 mm.)
//
// kSettled: the velocity once the density profile inside the burr no longer
// changes: the slope over consecutive windows, each at least three residence
// times h / v of the material in the burr at its own slope, until two agree
// within 2 % (the material relaxes over about one residence time, so the last
// window is then within about 0.1 % of the limit).
enum class VelocityDefinition { kInitial, kSettled };

// The definition every tool uses unless told otherwise: the dissertation's
// (§8.6), which is also what a lab's rig measures in seconds rather than hours.
inline constexpr VelocityDefinition kDefaultVelocityDefinition =
    VelocityDefinition::kInitial;

// "initial" or "settled".
std::string_view VelocityDefinitionName(VelocityDefinition definition);
// The definition named `name`, or nothing.
std::optional<VelocityDefinition> ParseVelocityDefinition(
    std::string_view name);
// One line per definition, for usage texts.
std::string_view VelocityDefinitionHelp();

// Voxels per burr radius of the rig's sample when DescentOptions::voxel_mm is
// 0, at the load y = F / (c_e R^2) (F = c_e R^2 (h/R)^{3/2}, eq. 7.3).
//
// The burr cuts a skin of material about sqrt(R v / alpha) thick (where the
// erosion of eq. 7.12 has used up what flows into the sphere), and v falls
// steeply with the load: at light loads the skin is thinner than a voxel and
// the rig's velocity is low by an error first-order in the voxel size. At
// R/12, R = 2 mm, against the continuum limit: bone 5 N (y = 0.58) 0.8 %,
// 2 N (0.23) 3.4 %, 1 N (0.12) 7.7 %, 0.5 N (0.058) 27 %; at R/40 a third
// of that. The skin thickness over R goes as about y^0.94, so the rig keeps
// R/12 from y = 0.5 up and refines as 12 (0.5 / y)^0.94 below, at most R/40
// (y below about 0.14), where a run's cost stops it: within about 2 % of the
// continuum limit down to y = 0.15 (bone 1.3 N at R = 2 mm), 2.5 % at bone
// 1 N, 8 % at bone 0.5 N with ell = 0.3 R. Below y = 0.2 most of what is
// left is the octree's accuracy scale ell (eq. 7.10), coarse against the
// skin, so the rig also shrinks ell with the skin (RigEllOverR): at R/40 bone
// 0.5 N is then low by 3.3 % (ell 0.04 R; R/60 would give 1.8 % at 10
// CPU-minutes a run), 0.75 N by 2.3 %, 1 N by 1.3 %, 1.5 N by 1.1 % (5 ms
// loop; a run costs 5, 2, 1.2 and 0.3 CPU-minutes).
inline constexpr double kRigVoxelsPerRadius = 12.0;
inline constexpr double kRigResolvedLoad = 0.5;
inline constexpr double kRigMaxVoxelsPerRadius = 40.0;
// The rig's default voxels per radius at the load y (rounded to a whole
// number; 12 for
// a load that is not positive and finite).
double RigVoxelsPerRadius(double load);

// The rig's default octree accuracy scale ell / R (Model::ell_over_r,
// eq. 7.10) at the load y. Partial blocks up to ell are taken whole, so ell
// follows the skin: the simulator's 0.3 from y = 0.5 up (where the skin is
// about 0.3 R thick), 0.3 (y / 0.5)^0.94 below, at least kRigMinEllOverR
// (0.3 for a load that is not positive and finite).
inline constexpr double kRigMinEllOverR = 0.03;
double RigEllOverR(double load);

struct DescentOptions {
  Material material;       // sample material
  Effects effects;         // physical effects beyond the base model (null)
  double force_n = 2.0;    // force held by the controller
  double radius_mm = 3.0;  // burr radius
  double spindle_rad_s =
      2094.0;  // burr spin (MINICRAFT MB150, about 20 000 rpm)
  // Voxel size of the virtual sample; 0 = radius_mm / RigVoxelsPerRadius at
  // the load force_n / (c_e R^2).
  double voxel_mm = 0.0;
  // The octree's accuracy scale ell as a fraction of R (Model::ell_over_r,
  // eq. 7.10): partial blocks up to ell are taken whole; smaller is finer
  // and slower, 0 refines every partial block to voxels. Unset:
  // RigEllOverR at the load force_n / (c_e R^2).
  std::optional<double> ell_over_r;
  // Model::moment_reuse_over_h: the moments are computed afresh once the burr
  // has moved 0.002 h (or eroded 0.002 m0) since they were last computed.
  // Against computing them every step the velocities of `sim measure` move by
  // 0.1-0.2 % (bone, 4 loads) at under half the cost; 0 computes them every
  // step.
  double moment_reuse_over_h = 0.002;
  VelocityDefinition definition = kDefaultVelocityDefinition;
  // Longest simulated time after contact; 0 = 3600 s for the initial
  // velocity, 36000 s for the settled one.
  double duration_s = 0.0;
  // The impact transient is over once the measured force stays within this
  // fraction of force_n (the 5 % settling time of control engineering).
  double settling_band = 0.05;
  std::uint64_t seed = 1;       // erosion random stream
  double dt_s = 1e-3;           // control and simulation period
  double kp_mm_per_n_s = 4.0;   // velocity command per newton of force error
  double ki_mm_per_n_s2 = 8.0;  // integral gain
  double kd_mm_per_n = 0.0;     // derivative gain
  double filter_hz = 100.0;  // force measurement bandwidth (rig: ~100 Hz, §8.5)
  double max_speed_mm_s = 5.0;  // arm speed limit (also the approach speed)
  // Trace sampling period; doubled (every other sample dropped) whenever the
  // trace reaches 200 000 samples.
  double trace_period_s = 0.01;
  // Keep running this long after the velocity is measured (for traces that
  // show what follows the window); 0 = stop at once.
  double run_on_s = 0.0;
  // Called once per simulated second after contact with that time and the
  // depth (for progress bars); may be empty.
  std::function<void(double after_contact_s, double depth_mm)> progress;

  // Names the first bad field.
  Status Validate() const;
  // voxel_mm, or its default for the radius.
  double VoxelMm() const;
  // ell_over_r, or the rig's default at the load.
  double EllOverR() const;
  // duration_s, or its default for the definition.
  double DurationS() const;
};

struct DescentSample {
  double t_s = 0.0;  // time since the start of the approach
  // Lowest point of the burr below the original surface as the arm reports
  // it (the arm's position; the burr itself unless arm_compliance bends the
  // spring between them).
  double depth_mm = 0.0;
  double force_n = 0.0;        // measured (filtered) vertical contact force
  double velocity_mm_s = 0.0;  // commanded descent velocity
  // Lowest point of the burr itself: depth_mm less the spring's deflection.
  double burr_depth_mm = 0.0;
};

// The rig's force measurement, one tick at a time: a first-order filter of
// bandwidth filter_hz (time constant 1 / (2 pi filter_hz)), then the extra
// first-order lag of the load_cell_lag effect (none at 0 s), each stage
// y += dt / (tau + dt) (x - y) (backward Euler).
class LoadCell {
 public:
  LoadCell(double filter_hz, double lag_s, double dt_s);
  // Feeds this tick's true force; returns the measured force.
  double Read(double force_n);
  double measured_n() const { return measured_; }

 private:
  double smoothing_ = 1.0, lag_smoothing_ = 1.0;
  bool lagged_ = false;
  double filtered_ = 0.0, measured_ = 0.0;
};

struct DescentResult {
  VelocityDefinition definition = kDefaultVelocityDefinition;
  // The velocity under `definition`, when measured.
  std::optional<double> velocity_mm_s;
  // Why there is none (one line), e.g. the burr did not cut R/3 within the
  // duration; empty when velocity_mm_s is set.
  std::string no_velocity_reason;
  // Simulated time the window would need at the velocity reached so far
  // (for advice when the duration ran out); 0 when unknown.
  double needed_duration_s = 0.0;
  double contact_s = 0.0;        // first contact (load cell > 5 % of F)
  double transient_end_s = 0.0;  // the force settled into its band
  double window_start_s = 0.0;   // the measured window (since the start)
  double window_end_s = 0.0;     //
  double window_start_depth_mm = 0.0;
  double window_end_depth_mm = 0.0;
  double final_depth_mm = 0.0;
  double removed_mm3 = 0.0;
  std::int64_t steps = 0;
  int sample_shifts = 0;  // times the sample moved up under the burr
  std::vector<DescentSample> trace;
};

// Runs the rig until the velocity is measured (or the duration is over). The
// sample follows the burr down: whenever the burr nears its bottom, the
// content moves up and fresh material fills in below, so the rig never runs
// out of sample however deep it cuts.
Result<DescentResult> RunDescent(const DescentOptions& options);

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_DESCENT_H_
