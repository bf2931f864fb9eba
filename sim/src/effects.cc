// The effect library: ids, parameters, null values and their validation.
#include "burrlab/sim/effects.h"

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace burrlab::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

constexpr EffectSpec kLibrary[] = {
    {"motor_power_limit", "max_removal_mm3_per_s", "mm^3/s", kInf,
     &Effects::max_removal_mm3_per_s,
     "the spindle power caps the removal rate at VALUE mm^3/s (null: inf)",
     StrengthMap::kReciprocal, "concave plateau at high force", false},
    {"spindle_slowdown", "stall_force_n", "N", kInf, &Effects::stall_force_n,
     "the spindle slows as 1 - |F_e|/VALUE under load, VALUE the stall "
     "force in N (null: inf)",
     StrengthMap::kReciprocal, "v rises, peaks and falls towards the stall",
     false},
    {"cutting_threshold", "cutting_threshold_n", "N", 0.0,
     &Effects::cutting_threshold_n,
     "the blades cut only with the contact force above VALUE N (null: 0)",
     StrengthMap::kAboveNull, "v near 0 below F0, steep rise after", false},
    {"viscous_resistance", "impact_c_i_n_s_per_mm3", "N s/mm^3", 0.0,
     &Effects::impact_c_i_n_s_per_mm3,
     "an impact force c_i R^2 (h/R) v with c_i = VALUE N s/mm^3 takes part "
     "of the held force (null: 0)",
     StrengthMap::kAboveNull, "concave at high force", false},
    {"friction_erosion", "friction_erosion_per_n_s", "1/(N s)", 0.0,
     &Effects::friction_erosion_per_n_s,
     "erosion at alpha + VALUE |F_e|, friction-driven wear (null: 0)",
     StrengthMap::kAboveNull, "log-log slope rises at high force", false},
    {"contact_exponent", "contact_exponent", "", 1.5,
     &Effects::contact_exponent,
     "F_e = c_e R^2 (h/R)^VALUE, plastic contact below 1.5 (null: 1.5)",
     StrengthMap::kBelowNull, "log-log slope changes everywhere", false},
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
    trial.*spec.field = value;
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
