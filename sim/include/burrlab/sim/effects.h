// Physical effects the base burr model (c_e, alpha) lacks, for the model-gap
// workflow: each below with the equation of the dissertation it changes (eqs.
// 6.4, 7.3, 7.12, 7.14). Each effect has one parameter and a null value at
// which it vanishes; the simulator applies every effect whose parameter is not
// null, so a hidden effect changes the rig's physics, not its output.
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
  // spindle_slowdown: the motor's torque line tau = tau_s (1 - omega/omega_0)
  // against the load torque mu |F_e| R slows the spindle to
  // omega_0 (1 - |F_e| / F_stall); erosion (eq. 7.12) scales with omega.
  // infinity = an ideal spindle.
  double stall_force_n = std::numeric_limits<double>::infinity();
  // cutting_threshold: the blades engage only with the part of the contact
  // force above F0, so erosion runs at alpha (1 - F0/|F_e|), none below F0.
  double cutting_threshold_n = 0.0;
  // viscous_resistance: the impact/rate force F_i = -c_i R^2 (h/R) V of eq.
  // 7.14 with c_i in N s/mm^3, added to the material's c_i; in a held-force
  // descent it takes part of the applied force.
  double impact_c_i_n_s_per_mm3 = 0.0;
  // friction_erosion: removal driven by friction power (Archard/Reye wear, a
  // rate proportional to the contact force): eq. 7.12 runs at
  // alpha + k |F_e|, k in 1/(N s).
  double friction_erosion_per_n_s = 0.0;
  // contact_exponent: F_e = c_e R^2 (h/R)^n instead of Hertz's n = 3/2 of eq.
  // 7.3; plastic (Meyer) contact lowers n towards 1.
  double contact_exponent = 1.5;
  // porosity: void fraction phi of a uniformly porous sample. The solid
  // skeleton of an open-cell foam is softer by (1 - phi)^2 (Gibson-Ashby), so
  // eq. 7.3 runs at c_e (1 - phi)^2; the relative erosion rate of eq. 7.12 is
  // unchanged. v(F) cannot tell it from a lower c_e.
  double porosity = 0.0;
  // load_cell_lag (trace only): an extra first-order lag of the load cell
  // with this time constant, in series with the rig's own filter; the
  // controller acts on the lagged force and the rig records it. Changes the
  // loading transient, not the steady v(F).
  double load_cell_lag_s = 0.0;
  // arm_compliance (trace only): a massless series spring between the arm
  // and the burr. The rig records the arm's position; the burr tip lags it by
  // the contact force times this compliance. Shifts the recorded depth by
  // F C at steady state and slows the loading, not the steady v(F).
  double arm_compliance_mm_per_n = 0.0;

  // Names the first parameter out of its range.
  Status Validate() const;
  // Whether every parameter holds its null value.
  bool IsNull() const;
};

// How a fitter's strength s >= 0 (0 = the null) maps to the parameter.
enum class StrengthMap {
  kAboveNull,   // value = null + s
  kBelowNull,   // value = null - s
  kReciprocal,  // value = 1 / s (the null is infinity)
};

// One entry of the effect library.
struct EffectSpec {
  std::string_view id;         // e.g. "motor_power_limit"
  std::string_view parameter;  // e.g. "max_removal_mm3_per_s"
  std::string_view unit;       // e.g. "mm^3/s"
  double null_value;           // where the effect vanishes
  double Effects::*field;      // the parameter in Effects
  std::string_view help;       // one line for usage texts
  StrengthMap strength;        // the parameter as a strength >= 0
  std::string_view signature;  // the shape it gives steady v(F), for reports
  // Visible only in time traces (the measurement chain): steady-state code
  // (the surrogate, the v(F) attribution) skips it;
  // analysis/model_gap/trace_gap.h tests it.
  bool trace_only = false;
};

// The parameter of `spec` at strength s >= 0, and back.
double ParameterAtStrength(const EffectSpec& spec, double strength);
double StrengthOfParameter(const EffectSpec& spec, double value);

// The spec of effect `id`, or nullptr.
const EffectSpec* FindEffect(std::string_view id);

// The implemented effects, in a fixed order.
std::span<const EffectSpec> EffectLibrary();

// Sets effect `id` to `value` in `effects`: an unknown id gets the list of
// known ones, a value out of range names the rule.
Status SetEffect(std::string_view id, double value, Effects* effects);

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_EFFECTS_H_
