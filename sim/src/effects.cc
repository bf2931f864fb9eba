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
     "the spindle power caps the removal rate at VALUE mm^3/s (null: inf)"},
    {"cutting_threshold", "cutting_threshold_n", "N", 0.0,
     &Effects::cutting_threshold_n,
     "the blades cut only with the contact force above VALUE N (null: 0)"},
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
  return {};
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
