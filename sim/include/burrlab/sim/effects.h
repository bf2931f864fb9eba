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

#include "burrlab/base/result.h"

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
  // Shapes: each effect's mechanism in its physically plausible variants.
  // The library (EffectLibrary) names each variant; the defaults are the
  // first variant of each family.
  //
  // motor_power_limit: the sharpness k of the saturation of the removal rate
  // Q_u the blades ask for: Q = Q_u / (1 + (Q_u / Q_max)^k)^(1/k). inf = a
  // hard cap min(Q_u, Q_max); small k = a motor that droops smoothly long
  // before its limit.
  double power_limit_sharpness = std::numeric_limits<double>::infinity();
  // cutting_threshold: the width of the blades' engagement as a fraction of
  // F0. 0 = hard (erosion at alpha (1 - F0/|F_e|) above F0, none below);
  // w > 0 = soft: the engaged force w F0 ln(1 + exp((|F_e| - F0) / (w F0)))
  // replaces |F_e| - F0, so some cutting starts below F0.
  double threshold_softness = 0.0;
  // viscous_resistance: the exponent m of the resistance in speed,
  // c_i R^2 (h/R) v_ref (v / v_ref)^m with v_ref = 1 mm/s: 1 = Newtonian
  // (eq. 7.14), below 1 shear-thinning (a paste of debris).
  double viscous_exponent = 1.0;
  // spindle_slowdown: 0 = the linear torque line omega / omega_0 =
  // 1 - |F_e| / F_stall; 1 = a motor whose speed droops exponentially,
  // exp(-|F_e| / F_stall) (F_stall then the force of a 1/e drop).
  double slowdown_exponential = 0.0;
  // friction_erosion: the exponent p of the wear rate in the force,
  // alpha + k F_ref (|F_e| / F_ref)^p with F_ref = 1 N: 1 = Archard's
  // linear wear, 2 = wear that grows with friction power at a speed that
  // itself rises with the load.
  double friction_erosion_exponent = 1.0;

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
  // The mechanism this entry is a variant of (the id of the family's first
  // entry; the same as `id` for that one), the variant's name within it, and
  // the shape parameter it sets (none for a family of one).
  std::string_view family = {};
  std::string_view shape = {};
  double Effects::*shape_field = nullptr;
  double shape_value = 0.0;
  // A shape on the other side of the family's null (e.g. a stiffer contact
  // than Hertz where the first shape is softer): the first shape cannot
  // stand in for it, so a fitter tests it in its own right.
  bool own_test = false;

  // `family`, or `id` when it is empty.
  std::string_view Family() const { return family.empty() ? id : family; }
};

// The factor on the erosion rate of eq. 7.12 from the effects that scale it
// with the elastic force |F_e| (cutting threshold, spindle slowdown,
// friction erosion, each in its shape); 1 when none is set.
double ErosionRateScale(const Effects& effects, double elastic_n,
                        double alpha_per_s);

// The factor the power limit puts on a removal rate of `demand_mm3_per_s`
// (the rate the blades ask for): 1 without a limit.
double PowerLimitScale(const Effects& effects, double demand_mm3_per_s);

// Sets the effect of `spec` to `value` in `effects`, and its shape (not
// validated).
void ApplyEffect(const EffectSpec& spec, double value, Effects* effects);

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
