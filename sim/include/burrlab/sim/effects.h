// Physical effects the base burr model (c_e, alpha) lacks, for the model-gap
// workflow (shared/notes/haptics.md, effect table). Each effect has one
// parameter and a null value at which it vanishes; the simulator applies every
// effect whose parameter is not null, so a hidden effect changes the rig's
// physics, not its output.
#ifndef BURRLAB_SIM_EFFECTS_H_
#define BURRLAB_SIM_EFFECTS_H_

#include <limits>
#include <span>
#include <string_view>

#include "burrlab/sim/result.h"

namespace burrlab::sim {

// Parameters of the effects; each default is the effect's null value.
struct Effects {
  // motor_power_limit: the spindle power W_max caps the removal rate at
  // W_max / k_s (k_s the specific cutting energy, eq. 6.4). Parameterised by
  // that rate since k_s is not known; infinity = no limit.
  double max_removal_mm3_per_s = std::numeric_limits<double>::infinity();
  // cutting_threshold: the blades engage only with the part of the contact
  // force above F0, so erosion runs at alpha (1 - F0/|F_e|), none below F0.
  double cutting_threshold_n = 0.0;

  // Names the first parameter out of its range.
  Status Validate() const;
  // Whether every parameter holds its null value.
  bool IsNull() const;
};

// One entry of the effect library.
struct EffectSpec {
  std::string_view id;         // e.g. "motor_power_limit"
  std::string_view parameter;  // e.g. "max_removal_mm3_per_s"
  std::string_view unit;       // e.g. "mm^3/s"
  double null_value;           // where the effect vanishes
  double Effects::*field;      // the parameter in Effects
  std::string_view help;       // one line for usage texts
};

// The implemented effects, in a fixed order.
std::span<const EffectSpec> EffectLibrary();

// Sets effect `id` to `value` in `effects`: an unknown id gets the list of
// known ones, a value out of range names the rule.
Status SetEffect(std::string_view id, double value, Effects* effects);

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_EFFECTS_H_
