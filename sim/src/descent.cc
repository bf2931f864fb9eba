// The virtual calibration rig (dissertation ch. 8, fig. 8.5): constant-force
// vertical descent of a spinning burr under the same PID-style force control as
// the robot arm.
#include "burrlab/sim/descent.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "burrlab/sim/step.h"
#include "burrlab/sim/volume.h"

namespace burrlab::sim {
namespace {

Status Positive(const char* name, double value) {
  if (!std::isfinite(value) || value <= 0.0) {
    return Error{fmt::format("{} must be a positive finite number, got {}",
                             name, value)};
  }
  return {};
}

}  // namespace

LoadCell::LoadCell(double filter_hz, double lag_s, double dt_s) {
  const double tau_s = 1.0 / (2.0 * std::numbers::pi * filter_hz);
  smoothing_ = dt_s / (tau_s + dt_s);
  lagged_ = lag_s > 0.0;
  lag_smoothing_ = dt_s / (lag_s + dt_s);
}

double LoadCell::Read(double force_n) {
  filtered_ += smoothing_ * (force_n - filtered_);
  // Without the lag the measured force is the filtered one, bit for bit.
  measured_ = lagged_ ? measured_ + lag_smoothing_ * (filtered_ - measured_)
                      : filtered_;
  return measured_;
}

Status DescentOptions::Validate() const {
  if (Status s = material.Validate(); !s.ok()) return s;
  if (Status s = effects.Validate(); !s.ok()) return s;
  for (const Status& s :
       {Positive("force_n", force_n), Positive("radius_mm", radius_mm),
        Positive("voxel_mm", voxel_mm), Positive("duration_s", duration_s),
        Positive("dt_s", dt_s), Positive("filter_hz", filter_hz),
        Positive("steady_window_s", steady_window_s),
        Positive("max_speed_mm_s", max_speed_mm_s),
        Positive("trace_period_s", trace_period_s)}) {
    if (!s.ok()) return s;
  }
  if (!std::isfinite(spindle_rad_s) || spindle_rad_s < 0.0) {
    return Error{fmt::format("spindle_rad_s must be zero or positive, got {}",
                             spindle_rad_s)};
  }
  for (double gain : {kp_mm_per_n_s, ki_mm_per_n_s2, kd_mm_per_n}) {
    if (!std::isfinite(gain) || gain < 0.0) {
      return Error{fmt::format(
          "controller gains must be zero or positive, got {}", gain)};
    }
  }
  if (duration_s / dt_s > 1e8) {
    return Error{fmt::format("duration_s / dt_s = {} steps is too many",
                             duration_s / dt_s)};
  }
  if (!std::isfinite(sample_depth_mm) || sample_depth_mm < 0.0 ||
      (sample_depth_mm > 0.0 && sample_depth_mm < 2.0 * radius_mm + 1.0)) {
    return Error{fmt::format(
        "sample_depth_mm must be 0 (automatic) or at least 2 R + 1 mm = {} "
        "mm, got {}",
        2.0 * radius_mm + 1.0, sample_depth_mm)};
  }
  if (sample_depth_mm / voxel_mm > 4096.0) {
    return Error{
        fmt::format("sample_depth_mm / voxel_mm = {} voxels is too "
                    "deep a sample",
                    sample_depth_mm / voxel_mm)};
  }
  if (radius_mm / voxel_mm > 200.0) {
    return Error{fmt::format("radius / voxel = {} is too fine a sample",
                             radius_mm / voxel_mm)};
  }
  return {};
}

Result<DescentResult> RunDescent(const DescentOptions& o) {
  if (Status s = o.Validate(); !s.ok()) return s.error();
  const double radius = o.radius_mm;
  const double v = o.voxel_mm;
  // A flat sample: solid below a surface that lies on a voxel boundary, air
  // above.
  const double room_below_mm =
      o.sample_depth_mm > 0.0 ? o.sample_depth_mm : 3.0 * radius + 2.0;
  const double room_above_mm = radius + 1.0;
  const int nxy = static_cast<int>(std::ceil((2.0 * radius + 2.0) / v)) + 2;
  const int below = static_cast<int>(std::ceil(room_below_mm / v));
  const int nz = below + static_cast<int>(std::ceil(room_above_mm / v));
  Result<Volume> volume = Volume::Create(nxy, nxy, nz, v);
  if (!volume.ok()) return volume.error();
  for (int k = 0; k < below; ++k)
    for (int j = 0; j < nxy; ++j)
      for (int i = 0; i < nxy; ++i) volume->Set(i, j, k, kSolidOccupancy);
  const double surface_z = below * v;
  Model model;
  model.material = o.material;
  model.effects = o.effects;
  model.radius_mm = radius;
  model.dt_s = o.dt_s;
  model.sample_estimate_hold =
      false;  // the rig reads the model force through its load cell
  Result<State> state = State::Create(model, std::move(*volume), o.seed);
  if (!state.ok()) return state.error();

  // Off-grid centre so the burr does not sit on a voxel symmetry line.
  const double cx = 0.5 * nxy * v + 0.137 * v, cy = 0.5 * nxy * v + 0.071 * v;
  double z = surface_z + radius + 0.2;  // start 0.2 mm above the surface
  LoadCell load_cell(o.filter_hz, o.effects.load_cell_lag_s, o.dt_s);
  // arm_compliance: z is the arm; the burr sits `deflection` above it.
  const double compliance = o.effects.arm_compliance_mm_per_n;
  double deflection = 0.0;
  double measured = 0.0, integral = 0.0, previous_measured = 0.0,
         velocity = 0.0;
  bool contact = false;
  double t = 0.0, t_end = std::numeric_limits<double>::infinity();
  double t_inside = -1.0;  // when the burr first got more than R/3 inside
  const double max_depth = room_below_mm - radius - 0.5;
  const double approach_limit_s =
      0.2 / std::min(o.max_speed_mm_s, o.kp_mm_per_n_s * o.force_n) + 5.0;
  DescentResult result;
  double next_trace = 0.0;
  Input input;
  input.spindle_rad_s = glm::dvec3(0.0, 0.0, o.spindle_rad_s);
  Output out;
  while (t < t_end) {
    input.position_mm = glm::dvec3(cx, cy, z + deflection);
    input.velocity_mm_s = glm::dvec3(0.0, 0.0, -velocity);
    Step(model, *state, input, &out);
    ++result.steps;
    if (compliance > 0.0) {
      // The massless spring carries the contact force: deflection = C F at
      // the burr's position, which itself depends on the deflection. One
      // Newton step per tick on d - C F(d) = 0 with the contact stiffness
      // dF/dh = n F_e / h of F_e ~ h^n (eq. 7.3) stays stable for any C k.
      const double force = std::max(out.model_force_n.z, 0.0);
      const double stiffness =
          out.h_mm > 0.0 ? model.effects.contact_exponent *
                               std::max(out.elastic_n.z, 0.0) / out.h_mm
                         : 0.0;
      deflection +=
          (compliance * force - deflection) / (1.0 + compliance * stiffness);
    }
    // Load cell: vertical reaction through a first-order filter of the rig's
    // bandwidth (and the extra lag of a sluggish cell).
    measured = load_cell.Read(out.model_force_n.z);
    if (!contact && measured > 0.05 * o.force_n) {
      contact = true;
      t_end = t + o.duration_s;
    }
    if (!contact && t > approach_limit_s) {
      return Error{"descent: the burr never touched the sample"};
    }
    // PID on the force error; positive velocity moves the burr down.
    const double error = o.force_n - measured;
    if (contact) integral += error * o.dt_s;
    const double derivative = (measured - previous_measured) / o.dt_s;
    previous_measured = measured;
    velocity = o.kp_mm_per_n_s * error + o.ki_mm_per_n_s2 * integral -
               o.kd_mm_per_n * derivative;
    velocity = std::clamp(velocity, -o.max_speed_mm_s, o.max_speed_mm_s);
    const double depth = surface_z - (z - radius);
    if (t >= next_trace) {
      result.trace.push_back(
          {t, depth, measured, velocity, depth - deflection});
      next_trace += o.trace_period_s;
    }
    if (depth > max_depth) break;  // the bottom of the virtual sample
    if (t_inside < 0.0 && depth > radius / 3.0) t_inside = t;
    if (t_inside >= 0.0 && t - t_inside >= o.steady_window_s) break;
    z -= velocity * o.dt_s;
    t += o.dt_s;
  }
  result.final_depth_mm = surface_z - (z - radius);
  result.removed_mm3 = state->counters().removed_mm3;
  // Steady penetration velocity (§8.6): least-squares slope of depth against
  // time once the burr is more than R/3 inside. The first half of that window
  // still carries the settling of the indentation after contact, so the slope
  // is taken over its second half, which must span at least 1 s.
  double t_from = -1.0, t_to = -1.0;
  for (const DescentSample& s : result.trace) {
    if (s.depth_mm <= radius / 3.0) continue;
    if (t_from < 0.0) t_from = s.t_s;
    t_to = s.t_s;
  }
  if (t_from >= 0.0) t_from = 0.5 * (t_from + t_to);
  double n = 0, st = 0, sd = 0, stt = 0, std_ = 0;
  for (const DescentSample& s : result.trace) {
    if (t_from < 0.0 || s.t_s < t_from || s.depth_mm <= radius / 3.0) continue;
    n += 1;
    st += s.t_s;
    sd += s.depth_mm;
    stt += s.t_s * s.t_s;
    std_ += s.t_s * s.depth_mm;
  }
  if (n >= 3 && t_to - t_from >= 1.0) {
    result.steady_velocity_mm_s = (n * std_ - st * sd) / (n * stt - st * st);
    result.steady_reached = true;
  }
  return result;
}

}  // namespace burrlab::sim
