// Simulated intervals: a virtual hand probes or drills a block of one material
// on the real step function (sim::Step) in virtual time, 1 kHz ticks; the
// trace is block-averaged to trace_hz and the cue is read off the 1 kHz stream
// the hand feels (the recorded rows are its block means), never off the
// material's parameters.
//
// World frame: mm, z up, z = 0 on the original surface of the block, the burr
// centre on the vertical axis at height z. Indentation (depth) = -(z - R), the
// depth of the burr's lowest point below the original surface.
#include "burrlab/stimuli/interval.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <glm/vec3.hpp>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "burrlab/sim/descent.h"
#include "burrlab/sim/step.h"
#include "burrlab/sim/volume.h"

namespace burrlab::stimuli {
namespace {

constexpr int kTickHz = 1000;  // the haptic loop; dt = 1 ms
constexpr double kDtS = 1.0 / kTickHz;
constexpr double kStartGapMm = 0.2;  // burr bottom above the surface at t = 0
constexpr double kLateralMarginMm = 1.0;  // block beyond the burr, each side

// Probe hand (see PressingVelocity).
constexpr double kProbeBandwidthRadS = 150.0;  // force-loop crossover, 24 Hz
constexpr double kProbeMaxSpeedMmS = 50.0;     // hand speed limit (brisk)
constexpr double kMinStiffnessNPerMm = 0.05;   // stiffness assumed off contact

// ---------------------------------------------------------------------------
// Validation.

// "interval: <field> must be <rule>, got <value>" unless `ok`.
Status Check(bool ok, std::string_view field, std::string_view rule,
             double value) {
  if (ok) return {};
  return Error{
      fmt::format("interval: {} must be {}, got {}", field, rule, value)};
}

// ---------------------------------------------------------------------------
// The block of material.

std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// The scene is a half-space of the interval's material below z = 0. Only a
// window of it around the burr is held: lateral size 2R + 2 mm, height
// 2R + 2S + guards. When the burr comes within a guard band of the window's
// bottom or top, the window moves by S layers (a "treadmill", so memory does
// not grow with the travel: a 600 s drill at the hand's speed limit would
// otherwise need metres of block): layers still inside keep their erosion, new
// layers below are pristine solid, new layers above continue the window's top
// layer (the bore) up to the original surface, air above it. S is a multiple
// of the largest octree block the moment integration may accept whole, so
// every such block keeps its place relative to the material and the force does
// not jump at a shift. Each window is a fresh sim::State: its erosion stream is
// seeded from (seed, window index) and its output filter restarts, so the
// first step after a shift lacks the half-step extrapolation of §6.4.3 (a
// change of half of one step's force change). A window shift is the only
// allocation inside the loop; the probe's presses normally never trigger one.
class MaterialWindow {
 public:
  static Result<MaterialWindow> Create(const sim::Model& model, double voxel_mm,
                                       std::uint64_t seed) {
    MaterialWindow w;
    w.model_ = &model;
    w.seed_ = seed;
    w.voxel_mm_ = voxel_mm;
    const double radius = model.radius_mm;
    w.nxy_ = static_cast<int>(std::ceil(
                 (2.0 * radius + 2.0 * kLateralMarginMm) / voxel_mm)) +
             2;
    // Largest power of two A with a block of A voxels able to lie inside the
    // burr sphere ((A - 1) sqrt(3) v <= 2R), and at least 4 (the erosion's
    // thinning blocks); S is the smallest multiple of A of at least 1 mm.
    int align = 4;
    while (2 * align - 1 <= 2.0 * radius / (std::numbers::sqrt3 * voxel_mm)) {
      align *= 2;
    }
    w.shift_ =
        align *
        std::max(1, static_cast<int>(std::ceil(1.0 / (align * voxel_mm))));
    const int span = static_cast<int>(std::ceil(2.0 * radius / voxel_mm)) + 2;
    w.nz_ = 2 * kGuard + 2 * w.shift_ + span;
    // Off the voxel symmetry lines, as on the rig.
    w.centre_x_mm_ = (0.5 * w.nxy_ + 0.137) * voxel_mm;
    w.centre_y_mm_ = (0.5 * w.nxy_ + 0.071) * voxel_mm;
    // Room S below the burr's bottom and about S above its top at the start.
    if (Status s = w.MoveTo(-(kGuard + w.shift_)); !s.ok()) return s.error();
    return w;
  }

  // One simulator step with the burr centre at height z_mm; velocity_down
  // positive moving down (impact force, eq. 7.14).
  Status Step(double z_mm, double velocity_down_mm_s, double spindle_rad_s,
              sim::Output* out) {
    const double radius = model_->radius_mm;
    const auto layer = [this](double world_z_mm) {
      return static_cast<int>(std::floor(world_z_mm / voxel_mm_)) - base_;
    };
    if (layer(z_mm - radius) < kGuard) {
      if (Status s = MoveTo(base_ - shift_); !s.ok()) return s;
    } else if (layer(z_mm + radius) >= nz_ - kGuard) {
      if (Status s = MoveTo(base_ + shift_); !s.ok()) return s;
    }
    input_.position_mm =
        glm::dvec3(centre_x_mm_, centre_y_mm_, z_mm - base_ * voxel_mm_);
    input_.velocity_mm_s = glm::dvec3(0.0, 0.0, -velocity_down_mm_s);
    input_.spindle_rad_s = glm::dvec3(0.0, 0.0, spindle_rad_s);
    sim::Step(*model_, state_, input_, out);
    return {};
  }

  // Steps that computed the moments afresh, over every window.
  std::int64_t MomentEvaluations() const {
    return evaluations_before_ +
           (has_state_ ? state_.counters().moment_evaluations : 0);
  }

  // Material removed so far, from the volume change of every window.
  double RemovedMm3() const {
    return removed_before_mm3_ + (initial_mm3_ - state_.volume().MaterialMm3());
  }

 private:
  static constexpr int kGuard = 4;  // layers kept between burr and window edge

  // Rebuilds the window with world layer `base` as its layer 0 (world layer
  // kw spans z in [kw v, (kw + 1) v); solid where kw < 0).
  Status MoveTo(int base) {
    Result<sim::Volume> volume =
        sim::Volume::Create(nxy_, nxy_, nz_, voxel_mm_);
    if (!volume.ok()) {
      return Error{
          fmt::format("interval: material block: {}", volume.error().message)};
    }
    const std::size_t layer_size = static_cast<std::size_t>(nxy_) * nxy_;
    const std::uint8_t* old =
        has_state_ ? state_.volume().occupancy() : nullptr;
    for (int k = 0; k < nz_; ++k) {
      const int world = base + k;
      std::uint8_t* to = volume->occupancy() + k * layer_size;
      const int old_k = world - base_;
      if (old != nullptr && old_k >= 0 && old_k < nz_) {
        std::memcpy(to, old + old_k * layer_size, layer_size);
      } else if (world >= 0) {
        // Air above the original surface (the volume starts empty).
      } else if (old != nullptr && old_k >= nz_) {
        std::memcpy(to, old + (nz_ - 1) * layer_size, layer_size);
      } else {
        std::memset(to, sim::kSolidOccupancy, layer_size);
      }
    }
    if (has_state_) {
      removed_before_mm3_ = RemovedMm3();
      evaluations_before_ = MomentEvaluations();
    }
    initial_mm3_ = volume->MaterialMm3();
    const std::uint64_t seed =
        windows_ == 0
            ? seed_
            : SplitMix64(seed_ ^
                         SplitMix64(static_cast<std::uint64_t>(windows_)));
    Result<sim::State> state =
        sim::State::Create(*model_, std::move(*volume), seed);
    if (!state.ok()) {
      return Error{fmt::format("interval: {}", state.error().message)};
    }
    state_ = std::move(*state);
    has_state_ = true;
    base_ = base;
    ++windows_;
    return {};
  }

  const sim::Model* model_ = nullptr;
  std::uint64_t seed_ = 0;
  double voxel_mm_ = 0.3;
  int nxy_ = 0, nz_ = 0;
  int shift_ = 0;  // S, layers the window moves at a time
  int base_ = 0;   // world layer of the window's layer 0
  double centre_x_mm_ = 0.0, centre_y_mm_ = 0.0;
  sim::State state_;
  bool has_state_ = false;
  std::uint64_t windows_ = 0;
  double initial_mm3_ = 0.0;             // material of this window when built
  double removed_before_mm3_ = 0.0;      // removed in earlier windows
  std::int64_t evaluations_before_ = 0;  // moment evaluations of earlier ones
  sim::Input input_;
};

// ---------------------------------------------------------------------------
// The hands.

// The hand's force reading: the felt vertical force through a first-order
// low-pass at the rig's measurement bandwidth (~100 Hz, §8.5).
class ForceSensor {
 public:
  explicit ForceSensor(double bandwidth_hz)
      : smoothing_(kDtS /
                   (1.0 / (2.0 * std::numbers::pi * bandwidth_hz) + kDtS)) {}
  double Update(double force_n) {
    value_ += smoothing_ * (force_n - value_);
    return value_;
  }

 private:
  double smoothing_;
  double value_ = 0.0;
};

// Probe: the hand presses with a triangular force target, 0 -> F -> 0 over
// each press period. Its force loop linearises the contact with its own
// stiffness estimate k^ and anticipates the ramp:
//   v_down = (dF*/dt + w_c (F* - F_measured)) / k^,
// so that with k^ = dF/dh the force error decays as exp(-w_c t) and follows a
// ramp without lag. k^ is the tangent stiffness of a Hertzian contact read off
// the trace, 3 F / (2 h) (from F ∝ h^(3/2)), with h the indentation, and
// kMinStiffnessNPerMm off contact; the hand never uses c_e. The contact
// stiffness spans 30x over the built-in materials, 0.1-20 N and R = 0.5-5 mm:
// a fixed gain would lag by a different amount on each material and so let
// c_e into the peak force. Tracking error while loading: < 0.01 N at 2 N.
double PressingVelocity(double target_n, double ramp_n_per_s, double measured_n,
                        double indentation_mm) {
  double stiffness = kMinStiffnessNPerMm;
  if (indentation_mm > 0.0) {
    stiffness = std::max(stiffness, 1.5 * measured_n / indentation_mm);
  }
  const double v =
      (ramp_n_per_s + kProbeBandwidthRadS * (target_n - measured_n)) /
      stiffness;
  return std::clamp(v, -kProbeMaxSpeedMmS, kProbeMaxSpeedMmS);
}

// Drill: the loop of the virtual calibration rig (sim::RunDescent, §8.6) with
// its gains, filter and speed limit, so that the drill cue is the rig's steady
// penetration velocity: v_down = kp e + ki ∫e dt (the integral runs once the
// reading passes 5 % of the force).
class HoldingHand {
 public:
  explicit HoldingHand(double force_n) : force_n_(force_n) {}
  double Velocity(double measured_n) {
    if (!contact_ && measured_n > 0.05 * force_n_) contact_ = true;
    const double error = force_n_ - measured_n;
    if (contact_) integral_ += error * kDtS;
    const double derivative = (measured_n - previous_n_) / kDtS;
    previous_n_ = measured_n;
    const double v = rig_.kp_mm_per_n_s * error +
                     rig_.ki_mm_per_n_s2 * integral_ -
                     rig_.kd_mm_per_n * derivative;
    return std::clamp(v, -rig_.max_speed_mm_s, rig_.max_speed_mm_s);
  }

 private:
  const sim::DescentOptions rig_;
  double force_n_;
  bool contact_ = false;
  double integral_ = 0.0;
  double previous_n_ = 0.0;
};

// ---------------------------------------------------------------------------
// Trace and cues.

constexpr std::size_t kColumns = 5;

// Block means of the 1 kHz ticks, one row per trace period; every row is
// allocated before the loop. The last row averages the ticks left when the
// duration is not a whole number of trace periods.
class TraceRows {
 public:
  TraceRows(int ticks_per_row, std::int64_t ticks)
      : ticks_per_row_(ticks_per_row),
        rows_(static_cast<std::size_t>((ticks + ticks_per_row - 1) /
                                       ticks_per_row),
              std::vector<double>(kColumns, 0.0)) {}
  void Add(const std::array<double, kColumns>& values) {
    for (std::size_t c = 0; c < kColumns; ++c) sums_[c] += values[c];
    if (++count_ == ticks_per_row_) Flush();
  }
  std::vector<std::vector<double>> Finish() {
    if (count_ > 0) Flush();
    return std::move(rows_);
  }

 private:
  void Flush() {
    std::vector<double>& row = rows_[next_++];
    for (std::size_t c = 0; c < kColumns; ++c) row[c] = sums_[c] / count_;
    sums_ = {};
    count_ = 0;
  }
  int ticks_per_row_;
  int count_ = 0;
  std::size_t next_ = 0;
  std::array<double, kColumns> sums_{};
  std::vector<std::vector<double>> rows_;
};

// Least-squares line; times are taken relative to the first one.
class LineFit {
 public:
  void Add(double t, double y) {
    if (n_ == 0) t0_ = t;
    t -= t0_;
    n_ += 1.0;
    st_ += t;
    sy_ += y;
    stt_ += t * t;
    sty_ += t * y;
  }
  double Slope() const {
    const double d = n_ * stt_ - st_ * st_;
    return n_ >= 2.0 && d > 0.0 ? (n_ * sty_ - st_ * sy_) / d : 0.0;
  }

 private:
  double t0_ = 0.0, n_ = 0.0, st_ = 0.0, sy_ = 0.0, stt_ = 0.0, sty_ = 0.0;
};

}  // namespace

double MaxProbeForceN(const sim::Material& material, double radius_mm,
                      double voxel_mm) {
  const double buried = (2.0 * radius_mm - voxel_mm) / radius_mm;
  if (!(buried > 0.0)) return 0.0;
  return 0.9 * material.c_e_n_per_mm2 * radius_mm * radius_mm * buried *
         std::sqrt(buried);
}

std::string_view TaskName(Task task) {
  switch (task) {
    case Task::kProbe:
      return "probe";
    case Task::kDrill:
      return "drill";
  }
  return "unknown";
}

Status IntervalOptions::Validate() const {
  const sim::Material& m = material;
  // The material rules of the material files (materials.h): c_e positive, the
  // others zero or positive.
  for (const Status& s : {
           Check(std::isfinite(m.c_e_n_per_mm2) && m.c_e_n_per_mm2 > 0.0,
                 "material.c_e", "finite and > 0", m.c_e_n_per_mm2),
           Check(std::isfinite(m.alpha_per_s) && m.alpha_per_s >= 0.0,
                 "material.alpha", "finite and >= 0", m.alpha_per_s),
           Check(std::isfinite(m.c_mu_n_per_mm2) && m.c_mu_n_per_mm2 >= 0.0,
                 "material.c_mu", "finite and >= 0", m.c_mu_n_per_mm2),
           Check(std::isfinite(m.mu) && m.mu >= 0.0, "material.mu",
                 "finite and >= 0", m.mu),
           Check(std::isfinite(m.c_i_n_s_per_mm3) && m.c_i_n_s_per_mm3 >= 0.0,
                 "material.c_i", "finite and >= 0", m.c_i_n_s_per_mm3),
           Check(duration_s > 0.0 && duration_s <= 600.0, "duration_s",
                 "in (0, 600]", duration_s),
           Check(radius_mm >= 0.5 && radius_mm <= 5.0, "radius_mm",
                 "in [0.5, 5]", radius_mm),
           Check(std::isfinite(spindle_rad_s) && spindle_rad_s >= 0.0,
                 "spindle_rad_s", "finite and >= 0", spindle_rad_s),
           Check(probe_force_n > 0.0 && probe_force_n <= 20.0, "probe_force_n",
                 "in (0, 20]", probe_force_n),
           Check(press_period_s >= 0.1 && press_period_s <= duration_s,
                 "press_period_s",
                 fmt::format("in [0.1, duration_s = {}]", duration_s),
                 press_period_s),
           Check(drill_force_n > 0.0 && drill_force_n <= 20.0, "drill_force_n",
                 "in (0, 20]", drill_force_n),
           Check(voxel_mm >= 0.05 && voxel_mm <= 1.0, "voxel_mm",
                 "in [0.05, 1]", voxel_mm),
           Check(probe_moment_reuse_over_h >= 0.0 &&
                     probe_moment_reuse_over_h <= 0.1,
                 "probe_moment_reuse_over_h", "in [0, 0.1]",
                 probe_moment_reuse_over_h),
           Check(drill_moment_reuse_over_h >= 0.0 &&
                     drill_moment_reuse_over_h <= 0.1,
                 "drill_moment_reuse_over_h", "in [0, 0.1]",
                 drill_moment_reuse_over_h),
       }) {
    if (!s.ok()) return s;
  }
  if (trace_hz <= 0 || kTickHz % trace_hz != 0) {
    return Error{fmt::format(
        "interval: trace_hz must be a positive divisor of 1000, got {}",
        trace_hz)};
  }
  if (task == Task::kProbe) {
    const double max_n = MaxProbeForceN(material, radius_mm, voxel_mm);
    if (!(probe_force_n <= max_n)) {
      return Error{fmt::format(
          "interval: probe_force_n = {} N is more than material c_e = {:.6g} "
          "N/mm^2 holds with radius_mm = {} and voxel_mm = {} (at most {:.3g} "
          "N)",
          probe_force_n, material.c_e_n_per_mm2, radius_mm, voxel_mm, max_n)};
    }
  }
  return {};
}

Result<IntervalResult> PresentSimulatedInterval(const IntervalOptions& o) {
  if (Status s = o.Validate(); !s.ok()) return s.error();
  const bool probe = o.task == Task::kProbe;
  const double radius = o.radius_mm;
  sim::Model model;
  model.material = o.material;
  model.radius_mm = radius;
  model.dt_s = kDtS;
  model.method = sim::MomentMethod::kOctree;  // 2-3x the mono speed at R = 2
  model.moment_reuse_over_h =
      probe ? o.probe_moment_reuse_over_h : o.drill_moment_reuse_over_h;
  Result<MaterialWindow> block =
      MaterialWindow::Create(model, o.voxel_mm, o.seed);
  if (!block.ok()) return block.error();

  const std::int64_t ticks = std::llround(o.duration_s * kTickHz);
  const double press_ticks = o.press_period_s * kTickHz;
  const double ramp_n_per_s = 2.0 * o.probe_force_n / o.press_period_s;
  const double spindle = probe ? 0.0 : o.spindle_rad_s;
  TraceRows rows(kTickHz / o.trace_hz, ticks);
  ForceSensor sensor(sim::DescentOptions{}.filter_hz);
  HoldingHand holding(o.drill_force_n);

  // Probe cue. Hertz contact (eq. 6.12 / 7.3 on a flat surface):
  //   F = c_e R^(1/2) h^(3/2), so F / h = c_e^(2/3) R^(1/3) F^(1/3):
  // the felt stiffness at a fixed peak force grows as c_e^(2/3). Each complete
  // press contributes its peak felt force over the indentation at that tick.
  double press_stiffness_sum = 0.0;
  int presses = 0;
  std::int64_t press = 0;
  double peak_n = -1.0, peak_depth_mm = 0.0;
  const auto end_press = [&](std::int64_t index) {
    const bool complete = (static_cast<double>(index) + 1.0) * press_ticks <=
                          static_cast<double>(ticks) + 1e-6;
    if (complete && peak_n > 0.0 && peak_depth_mm > 0.0) {
      press_stiffness_sum += peak_n / peak_depth_mm;
      ++presses;
    }
    peak_n = -1.0;
  };
  // Drill cue: least-squares slope of depth against time over the second half
  // of the interval. The rig (§8.6) waits until the burr is R/3 inside; an
  // interval has a fixed length, so when the burr is not that deep by
  // mid-interval the slope still covers the second half and then measures
  // the slow start of the cut rather than a steady rate. The elastic
  // indentation alone reaches R/3 from F = c_e R^2 3^(-3/2) (eq. 7.3): at
  // R = 2 mm 1.65 N on human temporal bone, 0.36 N on PVC K70.
  LineFit depth_fit;

  double z = radius + kStartGapMm;  // burr centre above the original surface
  double velocity_down = 0.0;
  double removed_mm3 = 0.0;  // since the interval began
  sim::Output out;
  for (std::int64_t i = 0; i < ticks; ++i) {
    const double t = static_cast<double>(i) * kDtS;
    double target = o.drill_force_n, ramp = 0.0;
    if (probe) {
      const double u = static_cast<double>(i) / press_ticks;
      const double whole = std::floor(u);
      const double phase = u - whole;
      target =
          o.probe_force_n * (phase < 0.5 ? 2.0 * phase : 2.0 - 2.0 * phase);
      ramp = phase < 0.5 ? ramp_n_per_s : -ramp_n_per_s;
      const auto index = static_cast<std::int64_t>(whole);
      if (index != press) {
        end_press(press);
        press = index;
      }
    }
    if (Status s = block->Step(z, velocity_down, spindle, &out); !s.ok()) {
      return s.error();
    }
    if (out.non_finite) {
      return Error{fmt::format(
          "interval: the simulator produced a non-finite force at t = {} s",
          t)};
    }
    const double force = out.force_n.z;  // felt force, positive pushing up
    const double depth = radius - z;
    if (probe && depth > 2.0 * radius) {
      // Buried, the burr feels no net force (m1 = 0) and the hand would sink
      // on: the material cannot hold the press force, F_e <= 2^(3/2) c_e R^2
      // (eq. 7.3 at h = 2R). Validate refuses such presses before the loop
      // (MaxProbeForceN, with a margin); this stays as the loop's guard.
      return Error{fmt::format(
          "interval: the burr sank into the material at t = {} s: "
          "probe_force_n = {} N is more than it holds with radius_mm = {} "
          "(at most about {:.3g} N)",
          t, o.probe_force_n, radius,
          2.0 * std::numbers::sqrt2 * o.material.c_e_n_per_mm2 * radius *
              radius)};
    }
    removed_mm3 += out.removed_mm3;
    rows.Add({z, force, depth, target, removed_mm3});
    if (probe) {
      if (force > peak_n) {
        peak_n = force;
        peak_depth_mm = depth;
      }
    } else if (2 * i >= ticks) {
      depth_fit.Add(t, depth);
    }
    const double measured = sensor.Update(force);
    velocity_down = probe ? PressingVelocity(target, ramp, measured, depth)
                          : holding.Velocity(measured);
    z -= velocity_down * kDtS;
  }
  if (probe) end_press(press);

  IntervalResult result;
  result.columns = {"position_z_mm", "force_n", "depth_mm", "target_force_n",
                    "removed_mm3"};
  result.rows = rows.Finish();
  if (probe) {
    result.cue = presses > 0 ? press_stiffness_sum / presses : 0.0;
    result.cue_name = "stiffness_n_per_mm";
  } else {
    result.cue = depth_fit.Slope();
    result.cue_name = "penetration_mm_per_s";
  }
  result.removed_mm3 = block->RemovedMm3();
  result.steps = ticks;
  result.moment_evaluations = block->MomentEvaluations();
  return result;
}

}  // namespace burrlab::stimuli
