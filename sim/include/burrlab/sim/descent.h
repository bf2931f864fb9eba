// The virtual calibration rig of dissertation ch. 8: a spinning burr descends
// vertically into a flat sample while a PID-style loop holds the contact force
// constant, as on the real robot arm (fig. 8.5). Yields the displacement-time
// trace and the steady penetration velocity, measured once the burr is more
// than a third of its radius inside (§8.6).
#ifndef BURRLAB_SIM_DESCENT_H_
#define BURRLAB_SIM_DESCENT_H_

#include <cstdint>
#include <vector>

#include "burrlab/sim/model.h"
#include "burrlab/sim/result.h"

namespace burrlab::sim {

struct DescentOptions {
  Material material;       // sample material
  Effects effects;         // physical effects beyond the base model (null)
  double force_n = 2.0;    // force held by the controller
  double radius_mm = 3.0;  // burr radius
  double spindle_rad_s =
      2094.0;                 // burr spin (MINICRAFT MB150, about 20 000 rpm)
  double voxel_mm = 0.3;      // voxel size of the virtual sample
  double duration_s = 120.0;  // longest simulated time after contact
  double steady_window_s =
      10.0;                // stop once the burr has been > R/3 inside this long
  std::uint64_t seed = 1;  // erosion random stream
  double dt_s = 1e-3;      // control and simulation period
  double kp_mm_per_n_s = 4.0;   // velocity command per newton of force error
  double ki_mm_per_n_s2 = 8.0;  // integral gain
  double kd_mm_per_n = 0.0;     // derivative gain
  double filter_hz = 100.0;  // force measurement bandwidth (rig: ~100 Hz, §8.5)
  double max_speed_mm_s = 5.0;   // arm speed limit (also the approach speed)
  double trace_period_s = 0.01;  // trace sampling period
  // Depth of the virtual sample below its surface; 0 = 3R + 2 mm. Long
  // descents (slow settling at high speed) need more.
  double sample_depth_mm = 0.0;

  // Names the first bad field.
  Status Validate() const;
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
  double steady_velocity_mm_s = 0.0;  // slope of depth vs time once depth > R/3
  bool steady_reached =
      false;  // depth passed R/3 with enough time left to measure
  double final_depth_mm = 0.0;
  double removed_mm3 = 0.0;
  std::int64_t steps = 0;
  std::vector<DescentSample> trace;
};

Result<DescentResult> RunDescent(const DescentOptions& options);

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_DESCENT_H_
