// The effect library: ids, parameters, null values and their validation.
#include "burrlab/sim/effects.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace burrlab::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

constexpr EffectSpec kLibrary[] = {
    {"motor_power_limit", "max_removal_mm3_per_s", "mm^3/s", kInf,
     &Effects::max_removal_mm3_per_s,
     "the spindle power caps the removal rate at VALUE mm^3/s (null: inf)",
     StrengthMap::kReciprocal, "concave plateau at high force", false,
     "motor_power_limit", "hard cap", &Effects::power_limit_sharpness, kInf},
    {"motor_power_limit_droop", "max_removal_mm3_per_s", "mm^3/s", kInf,
     &Effects::max_removal_mm3_per_s,
     "the motor droops smoothly towards a removal rate of VALUE mm^3/s, "
     "Q = Q_u / (1 + (Q_u/VALUE)^1.5)^(1/1.5) (null: inf)",
     StrengthMap::kReciprocal, "concave, bending early, at high force", false,
     "motor_power_limit", "smooth droop", &Effects::power_limit_sharpness, 1.5},
    {"spindle_slowdown", "stall_force_n", "N", kInf, &Effects::stall_force_n,
     "the spindle slows as 1 - |F_e|/VALUE under load, VALUE the stall "
     "force in N (null: inf)",
     StrengthMap::kReciprocal, "v rises, peaks and falls towards the stall",
     false, "spindle_slowdown", "linear torque line",
     &Effects::slowdown_exponential, 0.0},
    {"spindle_slowdown_exponential", "stall_force_n", "N", kInf,
     &Effects::stall_force_n,
     "the spindle slows as exp(-|F_e|/VALUE) under load (null: inf)",
     StrengthMap::kReciprocal, "v rises, peaks and falls slowly", false,
     "spindle_slowdown", "exponential droop", &Effects::slowdown_exponential,
     1.0},
    {"cutting_threshold", "cutting_threshold_n", "N", 0.0,
     &Effects::cutting_threshold_n,
     "the blades cut only with the contact force above VALUE N (null: 0)",
     StrengthMap::kAboveNull, "v near 0 below F0, steep rise after", false,
     "cutting_threshold", "hard", &Effects::threshold_softness, 0.0},
    {"cutting_threshold_soft", "cutting_threshold_n", "N", 0.0,
     &Effects::cutting_threshold_n,
     "the blades engage gradually around VALUE N, over a width of VALUE/2 "
     "(null: 0)",
     StrengthMap::kAboveNull, "v small at low force, rising smoothly", false,
     "cutting_threshold", "soft", &Effects::threshold_softness, 0.5},
    {"viscous_resistance", "impact_c_i_n_s_per_mm3", "N s/mm^3", 0.0,
     &Effects::impact_c_i_n_s_per_mm3,
     "an impact force c_i R^2 (h/R) v with c_i = VALUE N s/mm^3 takes part "
     "of the held force (null: 0)",
     StrengthMap::kAboveNull, "concave at high force", false,
     "viscous_resistance", "linear in speed", &Effects::viscous_exponent, 1.0},
    {"viscous_resistance_sqrt", "impact_c_i_n_s_per_mm3", "N s/mm^3", 0.0,
     &Effects::impact_c_i_n_s_per_mm3,
     "a resistance c_i R^2 (h/R) (1 mm/s) (v / 1 mm/s)^0.5 with c_i = VALUE "
     "takes part of the held force, shear-thinning (null: 0)",
     StrengthMap::kAboveNull, "concave across the range", false,
     "viscous_resistance", "square root of speed", &Effects::viscous_exponent,
     0.5},
    {"friction_erosion", "friction_erosion_per_n_s", "1/(N s)", 0.0,
     &Effects::friction_erosion_per_n_s,
     "erosion at alpha + VALUE |F_e|, friction-driven wear (null: 0)",
     StrengthMap::kAboveNull, "log-log slope rises at high force", false,
     "friction_erosion", "linear in force", &Effects::friction_erosion_exponent,
     1.0},
    {"friction_erosion_quadratic", "friction_erosion_per_n_s", "1/(N s)", 0.0,
     &Effects::friction_erosion_per_n_s,
     "erosion at alpha + VALUE (|F_e| / 1 N)^2, wear growing with friction "
     "power (null: 0)",
     StrengthMap::kAboveNull, "log-log slope rises steeply at high force",
     false, "friction_erosion", "quadratic in force",
     &Effects::friction_erosion_exponent, 2.0},
    {"contact_exponent", "contact_exponent", "", 1.5,
     &Effects::contact_exponent,
     "F_e = c_e R^2 (h/R)^VALUE, plastic contact below 1.5 (null: 1.5)",
     StrengthMap::kBelowNull, "log-log slope changes everywhere", false,
     "contact_exponent", "softer than Hertz"},
    {"contact_exponent_stiff", "contact_exponent", "", 1.5,
     &Effects::contact_exponent,
     "F_e = c_e R^2 (h/R)^VALUE with VALUE above 1.5: a contact that "
     "stiffens with depth, e.g. a denser layer below the surface (null: 1.5)",
     StrengthMap::kAboveNull, "log-log slope changes everywhere", false,
     "contact_exponent", "stiffer than Hertz", nullptr, 0.0, true},
    {"porosity", "porosity", "", 0.0, &Effects::porosity,
     "void fraction VALUE in [0, 1): c_e (1 - VALUE)^2 (null: 0)",
     StrengthMap::kAboveNull, "none: absorbed by c_e", false},
    {"load_cell_lag", "load_cell_lag_s", "s", 0.0, &Effects::load_cell_lag_s,
     "an extra first-order lag of VALUE s in the load cell; the controller "
     "acts on the lagged force (null: 0; traces only)",
     StrengthMap::kAboveNull,
     "none in steady v(F); overshoot and ringing of the force after contact",
     true},
    {"arm_compliance", "arm_compliance_mm_per_n", "mm/N", 0.0,
     &Effects::arm_compliance_mm_per_n,
     "a series spring of VALUE mm/N between the arm and the burr; the depth "
     "recorded is the arm's (null: 0; traces only)",
     StrengthMap::kAboveNull,
     "none in steady v(F); recorded depth deeper by F x compliance, slower "
     "loading",
     true},
};

}  // namespace

std::span<const EffectSpec> EffectLibrary() { return kLibrary; }

Status Effects::Validate() const {
  if (std::isnan(max_removal_mm3_per_s) || max_removal_mm3_per_s <= 0.0) {
    return Error{fmt::format(
        "motor_power_limit must be a positive removal rate in mm^3/s (inf "
        "for none), got {}",
        max_removal_mm3_per_s)};
  }
  if (!std::isfinite(cutting_threshold_n) || cutting_threshold_n < 0.0) {
    return Error{fmt::format(
        "cutting_threshold must be a finite force of at least 0 N, got {}",
        cutting_threshold_n)};
  }
  if (std::isnan(stall_force_n) || stall_force_n <= 0.0) {
    return Error{fmt::format(
        "spindle_slowdown must be a positive stall force in N (inf for "
        "none), got {}",
        stall_force_n)};
  }
  if (!std::isfinite(impact_c_i_n_s_per_mm3) || impact_c_i_n_s_per_mm3 < 0.0) {
    return Error{fmt::format(
        "viscous_resistance must be a finite c_i of at least 0 N s/mm^3, got "
        "{}",
        impact_c_i_n_s_per_mm3)};
  }
  if (!std::isfinite(friction_erosion_per_n_s) ||
      friction_erosion_per_n_s < 0.0) {
    return Error{fmt::format(
        "friction_erosion must be a finite rate of at least 0 per N s, got {}",
        friction_erosion_per_n_s)};
  }
  if (!(contact_exponent >= 1.0 && contact_exponent <= 2.0)) {
    return Error{
        fmt::format("contact_exponent must lie in [1, 2] (Hertz 1.5), got {}",
                    contact_exponent)};
  }
  if (!(porosity >= 0.0 && porosity < 1.0)) {
    return Error{fmt::format("porosity must lie in [0, 1), got {}", porosity)};
  }
  if (!(power_limit_sharpness >= 1.0)) {
    return Error{fmt::format(
        "the power limit's sharpness must be at least 1 (inf: a hard cap), "
        "got {}",
        power_limit_sharpness)};
  }
  if (!(threshold_softness >= 0.0 && threshold_softness <= 10.0)) {
    return Error{fmt::format(
        "the cutting threshold's softness must lie in [0, 10], got {}",
        threshold_softness)};
  }
  if (!(viscous_exponent > 0.0 && viscous_exponent <= 3.0)) {
    return Error{fmt::format(
        "the viscous resistance's exponent must lie in (0, 3], got {}",
        viscous_exponent)};
  }
  if (slowdown_exponential != 0.0 && slowdown_exponential != 1.0) {
    return Error{fmt::format(
        "the spindle slowdown's shape must be 0 (linear) or 1 (exponential), "
        "got {}",
        slowdown_exponential)};
  }
  if (!(friction_erosion_exponent > 0.0 && friction_erosion_exponent <= 3.0)) {
    return Error{fmt::format(
        "the friction erosion's exponent must lie in (0, 3], got {}",
        friction_erosion_exponent)};
  }
  if (!(load_cell_lag_s >= 0.0 && load_cell_lag_s <= 10.0)) {
    return Error{fmt::format(
        "load_cell_lag must be a time constant in [0, 10] s, got {}",
        load_cell_lag_s)};
  }
  if (!(arm_compliance_mm_per_n >= 0.0 && arm_compliance_mm_per_n <= 100.0)) {
    return Error{fmt::format(
        "arm_compliance must be a compliance in [0, 100] mm/N, got {}",
        arm_compliance_mm_per_n)};
  }
  return {};
}

double ParameterAtStrength(const EffectSpec& spec, double strength) {
  switch (spec.strength) {
    case StrengthMap::kAboveNull:
      return spec.null_value + strength;
    case StrengthMap::kBelowNull:
      return spec.null_value - strength;
    case StrengthMap::kReciprocal:
      return strength > 0.0 ? 1.0 / strength : kInf;
  }
  return spec.null_value;
}

double StrengthOfParameter(const EffectSpec& spec, double value) {
  switch (spec.strength) {
    case StrengthMap::kAboveNull:
      return value - spec.null_value;
    case StrengthMap::kBelowNull:
      return spec.null_value - value;
    case StrengthMap::kReciprocal:
      return std::isfinite(value) ? 1.0 / value : 0.0;
  }
  return 0.0;
}

const EffectSpec* FindEffect(std::string_view id) {
  for (const EffectSpec& spec : kLibrary) {
    if (spec.id == id) return &spec;
  }
  return nullptr;
}

double ErosionRateScale(const Effects& fx, double elastic_n,
                        double alpha_per_s) {
  double scale = 1.0;
  if (fx.cutting_threshold_n > 0.0) {
    const double f0 = fx.cutting_threshold_n;
    if (fx.threshold_softness > 0.0) {
      // The engaged force w ln(1 + exp((F - F0) / w)), a smooth |F - F0|_+.
      const double w = fx.threshold_softness * f0;
      const double z = (elastic_n - f0) / w;
      const double engaged_n = w * (z > 30.0 ? z : std::log1p(std::exp(z)));
      scale = elastic_n > 0.0 ? std::min(1.0, engaged_n / elastic_n) : 0.0;
    } else {
      scale = elastic_n > f0 ? 1.0 - f0 / elastic_n : 0.0;
    }
  }
  if (std::isfinite(fx.stall_force_n)) {
    scale *= fx.slowdown_exponential != 0.0
                 ? std::exp(-elastic_n / fx.stall_force_n)
                 : std::max(0.0, 1.0 - elastic_n / fx.stall_force_n);
  }
  if (fx.friction_erosion_per_n_s > 0.0 && alpha_per_s > 0.0) {
    const double wear = fx.friction_erosion_exponent == 1.0
                            ? elastic_n
                            : std::pow(elastic_n, fx.friction_erosion_exponent);
    scale *= 1.0 + fx.friction_erosion_per_n_s * wear / alpha_per_s;
  }
  return scale;
}

double PowerLimitScale(const Effects& fx, double demand_mm3_per_s) {
  const double cap = fx.max_removal_mm3_per_s;
  if (!std::isfinite(cap) || !(demand_mm3_per_s > 0.0)) return 1.0;
  const double ratio = demand_mm3_per_s / cap;
  if (!std::isfinite(fx.power_limit_sharpness)) {
    return ratio > 1.0 ? 1.0 / ratio : 1.0;
  }
  const double k = fx.power_limit_sharpness;
  return std::pow(1.0 + std::pow(ratio, k), -1.0 / k);
}

void ApplyEffect(const EffectSpec& spec, double value, Effects* effects) {
  effects->*spec.field = value;
  if (spec.shape_field != nullptr)
    effects->*spec.shape_field = spec.shape_value;
}

bool Effects::IsNull() const {
  for (const EffectSpec& spec : kLibrary) {
    if (this->*spec.field != spec.null_value) return false;
  }
  return true;
}

Status SetEffect(std::string_view id, double value, Effects* effects) {
  for (const EffectSpec& spec : kLibrary) {
    if (spec.id != id) continue;
    Effects trial = *effects;
    ApplyEffect(spec, value, &trial);
    if (Status s = trial.Validate(); !s.ok()) return s;
    *effects = trial;
    return {};
  }
  std::string known;
  for (const EffectSpec& spec : kLibrary) {
    known += (known.empty() ? "" : ", ") + std::string(spec.id);
  }
  return Error{
      fmt::format("unknown effect '{}'; known effects: {}", id, known)};
}

}  // namespace burrlab::sim
