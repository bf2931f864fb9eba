// Presenting one interval of a trial on the simulator with a simulated hand,
// in virtual time (as fast as the step function runs): the task the subject
// performs (probe: burr not rotating, pressing into the surface; drill: burr
// rotating, holding a force and cutting), the force and position trace it
// produces, and the perceptual cue a simulated observer derives from that
// trace (never from the material's parameters directly).
#ifndef BURRLAB_STIMULI_INTERVAL_H_
#define BURRLAB_STIMULI_INTERVAL_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/sim/model.h"

namespace burrlab::stimuli {

// What the subject does in an interval.
enum class Task {
  kProbe,  // burr not rotating: repeated presses into the surface
  kDrill,  // burr rotating: a held force, cutting into the material
};
// "probe" or "drill".
std::string_view TaskName(Task task);

// The burr radius of simulated intervals, and of sessions, studies, validate
// and the station unless --radius-mm says otherwise.
inline constexpr double kDefaultBurrRadiusMm = 2.0;

// One simulated interval.
struct IntervalOptions {
  sim::Material material;                   // what the interval renders
  Task task = Task::kProbe;                 // what the simulated hand does
  double duration_s = 20.0;                 // virtual time of the interval, > 0
  double radius_mm = kDefaultBurrRadiusMm;  // burr radius
  double spindle_rad_s = 2094.0;  // drill: burr spin (about 20 000 rpm)
  double probe_force_n = 2.0;     // probe: peak force of each press
  double press_period_s = 1.0;    // probe: one press (load and unload) lasts
  double drill_force_n = 3.0;     // drill: force the hand holds
  double voxel_mm = 0.3;          // voxel size of the material block
  int trace_hz = 1000;            // trace rate; divides 1000
  std::uint64_t seed = 1;         // erosion random stream of this interval
  // sim::Model::moment_reuse_over_h of each task: the moments are computed
  // afresh once the burr has moved this fraction of h (or eroded this
  // fraction of m0) since they were last computed; 0 computes them every
  // step. Probing erodes nothing, so its reused moments stay within 1e-4 N of
  // computed ones (presses to 2 N) and it computes them in about half the
  // steps. A drill's reused moments drift with the erosion until the next
  // computation (at most 0.01 N at 3 N held); it computes them in 3-14 % of
  // the steps.
  double probe_moment_reuse_over_h = 0.005;
  double drill_moment_reuse_over_h = 0.002;

  // Names the first bad field, its value and the rule broken; a probe needs
  // probe_force_n <= MaxProbeForceN(material, radius_mm, voxel_mm).
  Status Validate() const;
};

// What an interval produced.
struct IntervalResult {
  // Trace columns: "position_z_mm" (burr centre above the block's original
  // surface), "force_n" (vertical force the hand feels, positive pushing the
  // burr up), "depth_mm" (lowest point of the burr below the original
  // surface), "target_force_n" (the hand's force target), "removed_mm3"
  // (solid-equivalent material eroded since the interval began). Rows at
  // trace_hz from t = 0, block means of the 1 kHz ticks (so no aliasing); the
  // last row averages the ticks left when duration_s is not a whole number of
  // periods.
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  // The cue of the task, from the 1 kHz force and position the hand feels:
  //  probe: felt stiffness, N/mm: mean over complete presses of peak force
  //         over indentation at that peak (for Hertzian contact this grows as
  //         c_e^(2/3) at a fixed peak force, eq. 6.12);
  //  drill: penetration rate at the held force, mm/s: least-squares slope of
  //         depth over the second half of the interval (cf. the rig of §8.6).
  double cue = 0.0;
  std::string cue_name;      // "stiffness_n_per_mm" or "penetration_mm_per_s"
  double removed_mm3 = 0.0;  // material removed (drill; 0 for probe)
  std::int64_t steps = 0;    // simulator steps run
  std::int64_t moment_evaluations = 0;  // steps that computed the moments
};

// The largest probe_force_n a probe interval on `material` accepts with burr
// radius radius_mm and voxels of voxel_mm (IntervalOptions::Validate), N:
// 0.9 of the elastic force of the burr buried one voxel short of its diameter,
// 0.9 c_e R^2 ((2R - voxel) / R)^(3/2) (eq. 7.3); 0 when voxel_mm >= 2R.
// Pressing harder can bury the burr, which then feels no net force and sinks
// on. On the discrete moments this happens below the continuum's 2^(3/2)
// c_e R^2, and more so for coarse voxels: measured without impact damping
// (c_i = 0, where sinking is easiest) from 0.82 of it at R = 0.5 mm and
// 0.3 mm voxels, 0.97 at R = 2 mm, and 0.67-0.80 where the voxel reaches
// R; this bound lies below every measured onset (R 0.5-5 mm, voxels
// 0.05-1 mm, 0.1-20 N).
double MaxProbeForceN(const sim::Material& material, double radius_mm,
                      double voxel_mm);

// Runs the interval. Deterministic in `options` (the erosion stream comes from
// options.seed).
Result<IntervalResult> PresentSimulatedInterval(const IntervalOptions& options);

}  // namespace burrlab::stimuli

#endif  // BURRLAB_STIMULI_INTERVAL_H_
