// The virtual calibration rig (dissertation ch. 8, fig. 8.5): constant-force
// vertical descent of a spinning burr under the same PID-style force control as
// the robot arm.
#include "burrlab/sim/descent.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

#include "burrlab/sim/step.h"
#include "burrlab/sim/volume.h"

namespace burrlab::sim {
namespace {

constexpr double kInitialDurationS = 3600.0, kSettledDurationS = 36000.0;
// Two consecutive settled windows agree within this fraction.
constexpr double kSettledTolerance = 0.02;
// A trace longer than this is thinned to every other sample.
constexpr std::size_t kMaxTraceSamples = 200000;

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

std::string_view VelocityDefinitionName(VelocityDefinition definition) {
  return definition == VelocityDefinition::kInitial ? "initial" : "settled";
}

std::optional<VelocityDefinition> ParseVelocityDefinition(
    std::string_view name) {
  if (name == "initial") return VelocityDefinition::kInitial;
  if (name == "settled") return VelocityDefinition::kSettled;
  return std::nullopt;
}

std::string_view VelocityDefinitionHelp() {
  return "initial: the plateau after the impact transient, over the first "
         "R/3 cut (dissertation §8.6); settled: once the density in the burr "
         "no longer changes (long runs)";
}

// The skin the burr cuts, over R, goes as about y^0.94 (descent.h).
constexpr double kSkinExponent = 0.94;

double RigVoxelsPerRadius(double load) {
  if (!(load > 0.0) || !std::isfinite(load)) return kRigVoxelsPerRadius;
  const double n =
      kRigVoxelsPerRadius * std::pow(kRigResolvedLoad / load, kSkinExponent);
  return std::clamp(std::round(n), kRigVoxelsPerRadius, kRigMaxVoxelsPerRadius);
}

double RigEllOverR(double load) {
  const double ell = Model{}.ell_over_r;
  if (!(load > 0.0) || !std::isfinite(load)) return ell;
  return std::clamp(ell * std::pow(load / kRigResolvedLoad, kSkinExponent),
                    kRigMinEllOverR, ell);
}

double DescentOptions::EllOverR() const {
  if (ell_over_r) return *ell_over_r;
  return RigEllOverR(force_n /
                     (material.c_e_n_per_mm2 * radius_mm * radius_mm));
}

double DescentOptions::VoxelMm() const {
  if (voxel_mm > 0.0) return voxel_mm;
  return radius_mm / RigVoxelsPerRadius(force_n / (material.c_e_n_per_mm2 *
                                                   radius_mm * radius_mm));
}

double DescentOptions::DurationS() const {
  if (duration_s > 0.0) return duration_s;
  return definition == VelocityDefinition::kInitial ? kInitialDurationS
                                                    : kSettledDurationS;
}

Status DescentOptions::Validate() const {
  if (Status s = material.Validate(); !s.ok()) return s;
  if (Status s = effects.Validate(); !s.ok()) return s;
  for (const Status& s :
       {Positive("force_n", force_n), Positive("radius_mm", radius_mm),
        Positive("dt_s", dt_s), Positive("filter_hz", filter_hz),
        Positive("max_speed_mm_s", max_speed_mm_s),
        Positive("trace_period_s", trace_period_s)}) {
    if (!s.ok()) return s;
  }
  for (const auto& [name, value] :
       {std::pair{"voxel_mm", voxel_mm}, std::pair{"duration_s", duration_s},
        std::pair{"run_on_s", run_on_s}}) {
    if (!std::isfinite(value) || value < 0.0) {
      return Error{fmt::format(
          "{} must be zero (its default) or a positive finite number, got {}",
          name, value)};
    }
  }
  if (ell_over_r && (!std::isfinite(*ell_over_r) || *ell_over_r < 0.0)) {
    return Error{fmt::format(
        "ell_over_r must be zero or a positive finite number, got {}",
        *ell_over_r)};
  }
  if (!(moment_reuse_over_h >= 0.0 && moment_reuse_over_h <= 0.1)) {
    return Error{fmt::format("moment_reuse_over_h must lie in [0, 0.1], got {}",
                             moment_reuse_over_h)};
  }
  if (!(settling_band > 0.0 && settling_band < 1.0)) {
    return Error{
        fmt::format("settling_band must lie in (0, 1), got {}", settling_band)};
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
  if ((DurationS() + run_on_s) / dt_s > 1e9) {
    return Error{
        fmt::format("(duration_s + run_on_s) / dt_s = {} steps is "
                    "too many",
                    (DurationS() + run_on_s) / dt_s)};
  }
  if (radius_mm / VoxelMm() > 200.0) {
    return Error{fmt::format("radius / voxel = {} is too fine a sample",
                             radius_mm / VoxelMm())};
  }
  return {};
}

namespace {

// Least-squares line of depth against time; times relative to the first.
class LineFit {
 public:
  void Reset() { *this = LineFit(); }
  void Add(double t, double y) {
    if (n_ == 0.0) {
      t0_ = t;
      y0_ = y;
    }
    t -= t0_;
    n_ += 1.0;
    st_ += t;
    sy_ += y - y0_;
    stt_ += t * t;
    sty_ += t * (y - y0_);
  }
  bool empty() const { return n_ == 0.0; }
  double t0() const { return t0_; }
  double y0() const { return y0_; }
  double Slope() const {
    const double d = n_ * stt_ - st_ * st_;
    return n_ >= 2.0 && d > 0.0 ? (n_ * sty_ - st_ * sy_) / d : 0.0;
  }

 private:
  double t0_ = 0.0, y0_ = 0.0, n_ = 0.0, st_ = 0.0, sy_ = 0.0, stt_ = 0.0,
         sty_ = 0.0;
};

// The measurement of one definition, fed every tick after contact.
class VelocityWindow {
 public:
  explicit VelocityWindow(const DescentOptions& o) : o_(o) {}

  // Feeds one tick: time, recorded depth, measured force and the burr's
  // effective immersion h (eq. 7.2). True once the velocity is measured.
  bool Add(double t_s, double depth_mm, double measured_n, double h_mm) {
    const bool in_band =
        std::abs(measured_n - o_.force_n) <= o_.settling_band * o_.force_n;
    if (!in_band) {
      // The transient is not over (or the force left its band): start again.
      fit_.Reset();
      previous_.reset();
      settled_ = false;
      last_out_s_ = t_s;
      last_out_n_ = measured_n;
      return false;
    }
    if (!settled_) {
      settled_ = true;
      transient_end_s_ = t_s;
      window_length_s_ = FirstSettledWindowS();
    }
    fit_.Add(t_s, depth_mm);
    last_t_s_ = t_s;
    last_depth_mm_ = depth_mm;
    if (o_.definition == VelocityDefinition::kInitial) {
      if (depth_mm - fit_.y0() < o_.radius_mm / 3.0) return false;
      velocity_ = fit_.Slope();
      return true;
    }
    // A window closes once it spans three residence times h / v at its own
    // slope so far (and the floor); checked every 0.1 s.
    if (t_s - fit_.t0() < window_length_s_ || t_s < next_check_s_) {
      return false;
    }
    next_check_s_ = t_s + 0.1;
    const double v = fit_.Slope();
    if (!(v > 0.0)) return false;
    window_length_s_ = std::max(FirstSettledWindowS(), 3.0 * h_mm / v);
    if (t_s - fit_.t0() < window_length_s_) return false;
    if (previous_ && std::abs(v - *previous_) <= kSettledTolerance * v) {
      velocity_ = v;
      return true;
    }
    previous_ = v;
    window_length_s_ = FirstSettledWindowS();
    fit_.Reset();
    fit_.Add(t_s, depth_mm);
    return false;
  }

  void Fill(DescentResult* r) const {
    r->transient_end_s = settled_ ? transient_end_s_ : 0.0;
    r->window_start_s = fit_.t0();
    r->window_start_depth_mm = fit_.y0();
    r->window_end_s = last_t_s_;
    r->window_end_depth_mm = last_depth_mm_;
    if (velocity_) {
      r->velocity_mm_s = *velocity_;
      return;
    }
    const double duration_s = o_.DurationS();
    if (!settled_) {
      r->no_velocity_reason = fmt::format(
          "the measured force never stayed within {:g} % of {:g} N after "
          "contact (last outside the band at {:.3g} s, at {:.4g} N)",
          100.0 * o_.settling_band, o_.force_n, last_out_s_, last_out_n_);
      return;
    }
    const double elapsed_s = last_t_s_ - fit_.t0();
    const double cut_mm = last_depth_mm_ - fit_.y0();
    const double v = fit_.Slope();
    // Not cutting is only a finding after several erosion times 1 / alpha.
    const double erosion_s = 1.0 / std::max(o_.material.alpha_per_s, 1e-9);
    const bool no_cut = !(v > 0.0) || cut_mm < 1e-3 * o_.radius_mm;
    if (no_cut && elapsed_s >= 5.0 * erosion_s) {
      r->no_velocity_reason = fmt::format(
          "the burr did not cut: it moved {:.3g} mm in the {:.4g} s after the "
          "impact transient",
          cut_mm, elapsed_s);
      return;
    }
    if (no_cut) {
      r->needed_duration_s = transient_end_s_ - contact_s_ + 5.0 * erosion_s;
      r->no_velocity_reason = fmt::format(
          "the burr cut {:.3g} mm in the {:.4g} s after the impact transient, "
          "too short a time to measure (the erosion time 1/alpha is {:.3g} s)",
          cut_mm, elapsed_s, erosion_s);
      return;
    }
    if (o_.definition == VelocityDefinition::kInitial) {
      r->needed_duration_s =
          transient_end_s_ - contact_s_ + (o_.radius_mm / 3.0) / v * 1.2;
      r->no_velocity_reason = fmt::format(
          "the burr cut {:.3g} mm of the R/3 = {:.3g} mm window in the {:g} s "
          "after contact (about {:.3g} mm/s; the window needs about {:.0f} s)",
          cut_mm, o_.radius_mm / 3.0, duration_s, v, r->needed_duration_s);
    } else {
      // At least the window in progress and one more to confirm it.
      r->needed_duration_s = fit_.t0() - contact_s_ + 2.0 * window_length_s_;
      r->no_velocity_reason =
          previous_
              ? fmt::format(
                    "the velocity had not settled within {:g} s after contact "
                    "(the last whole window gave {:.4g} mm/s, the one in "
                    "progress {:.4g} mm/s; windows of {:.4g} s)",
                    duration_s, *previous_, v, window_length_s_)
              : fmt::format(
                    "the velocity had not settled within {:g} s after contact "
                    "(its first window of {:.4g} s had not closed)",
                    duration_s, window_length_s_);
    }
  }

  void set_contact_s(double t_s) { contact_s_ = t_s; }

 private:
  // The settled windows span at least 10 s and four erosion times 1 / alpha.
  double FirstSettledWindowS() const {
    return std::max(10.0, 4.0 / std::max(o_.material.alpha_per_s, 1e-6));
  }

  const DescentOptions& o_;
  LineFit fit_;
  bool settled_ = false;
  double contact_s_ = 0.0, transient_end_s_ = 0.0;
  double last_out_s_ = 0.0, last_out_n_ = 0.0;
  double last_t_s_ = 0.0, last_depth_mm_ = 0.0;
  double window_length_s_ = 0.0;  // the current window's length so far
  double next_check_s_ = 0.0;
  std::optional<double> previous_;  // the last settled window's slope
  std::optional<double> velocity_;
};

}  // namespace

Result<DescentResult> RunDescent(const DescentOptions& o) {
  if (Status s = o.Validate(); !s.ok()) return s.error();
  const double radius = o.radius_mm;
  const double v = o.VoxelMm();
  // A flat sample: solid below a surface that lies on a voxel boundary, air
  // above. It follows the burr down (ShiftContentUp below), so its height
  // only has to hold the burr with room to shift.
  const double room_below_mm = 3.0 * radius + 2.0;
  const double room_above_mm = radius + 1.0;
  const int nxy = static_cast<int>(std::ceil((2.0 * radius + 2.0) / v)) + 2;
  const int below = static_cast<int>(std::ceil(room_below_mm / v));
  const int nz = below + static_cast<int>(std::ceil(room_above_mm / v));
  Result<Volume> volume = Volume::Create(nxy, nxy, nz, v);
  if (!volume.ok()) return volume.error();
  for (int k = 0; k < below; ++k)
    for (int j = 0; j < nxy; ++j)
      for (int i = 0; i < nxy; ++i) volume->Set(i, j, k, kSolidOccupancy);
  double surface_z = below * v;
  Model model;
  model.material = o.material;
  model.effects = o.effects;
  model.radius_mm = radius;
  model.dt_s = o.dt_s;
  model.ell_over_r = o.EllOverR();
  model.moment_reuse_over_h = o.moment_reuse_over_h;
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
  // The sample shifts up when the burr's lowest point comes within R/2 + 2
  // voxels of its bottom, as far as keeps 1 mm of sample above the burr.
  const double shift_trigger_mm = 0.5 * radius + 2.0 * v;
  const double approach_limit_s =
      0.2 / std::min(o.max_speed_mm_s, o.kp_mm_per_n_s * o.force_n) + 5.0;
  DescentResult result;
  result.definition = o.definition;
  VelocityWindow window(o);
  double next_trace = 0.0, trace_period_s = o.trace_period_s;
  double next_progress_s = 1.0;
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
      t_end = t + o.DurationS();
      result.contact_s = t;
      window.set_contact_s(t);
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
      next_trace += trace_period_s;
      if (result.trace.size() >= kMaxTraceSamples) {
        // A long run keeps every other sample at twice the period.
        for (std::size_t i = 1; 2 * i < result.trace.size(); ++i) {
          result.trace[i] = result.trace[2 * i];
        }
        result.trace.resize((result.trace.size() + 1) / 2);
        trace_period_s *= 2.0;
        next_trace = result.trace.back().t_s + trace_period_s;
      }
    }
    if (contact && o.progress && t - result.contact_s >= next_progress_s) {
      o.progress(t - result.contact_s, depth);
      next_progress_s += 1.0;
    }
    if (contact && !result.velocity_mm_s &&
        window.Add(t, depth, measured, out.h_mm)) {
      window.Fill(&result);
      t_end = std::min(t_end, t + o.run_on_s);
    }
    // Follow the burr down: move the sample's content up under it.
    const double burr_bottom_mm = z + deflection - radius;
    if (burr_bottom_mm < shift_trigger_mm) {
      const double top_mm = state->volume().nz() * v;
      const int layers = static_cast<int>(
          std::floor((top_mm - (burr_bottom_mm + 2.0 * radius) - 1.0) / v));
      if (layers < 1) {
        return Error{fmt::format(
            "descent: the sample of {} voxel layers is too short to follow "
            "the burr",
            state->volume().nz())};
      }
      state->ShiftContentUp(layers, kSolidOccupancy);
      z += layers * v;
      surface_z += layers * v;
      ++result.sample_shifts;
    }
    z -= velocity * o.dt_s;
    t += o.dt_s;
  }
  if (!result.velocity_mm_s) window.Fill(&result);
  result.final_depth_mm = surface_z - (z - radius);
  result.removed_mm3 = state->counters().removed_mm3;
  return result;
}

}  // namespace burrlab::sim
