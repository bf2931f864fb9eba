// An independent truth for the model-gap tests: the settled penetration
// velocity of a spherical burr held at constant force, written from the
// physics here, with hidden mechanisms in shapes the effect library was not
// written in. Nothing here calls the simulator, the effect library or the
// fitter's surrogate; the tests compare with them.
//
// Base model (dissertation eqs. 7.2, 7.3, 7.12), units mm, s, N. A sphere of
// radius R descends at constant speed v into material of density rho0 = 1.
// Inside the sphere the material erodes at d rho/dt = -alpha f(r/R) rho,
// f(u) = 1 - u^2 (eq. 7.12). In the burr's frame the material moves up at v,
// so along the vertical column at distance s from the axis it enters at the
// lower surface and decays as d rho/dz = -(alpha/v) f rho. The mass inside the
// sphere, m0 = int rho dV, fixes the effective indentation h by the cap volume
// m0 = pi h^2 (R - h/3) (eq. 7.2), and the elastic force is
// F_e = c_e R^2 (h/R)^{3/2} (eq. 7.3). In units of R the profile depends on
// kappa = alpha R / v alone.
//
// Numerics (deliberately not the closed form of the column integral): each
// column is an initial-value problem in z for (rho, int rho dz), integrated by
// classical Runge-Kutta with step doubling; the columns are summed over the
// polar angle theta of the entry point (s = R sin theta) by adaptive
// Gauss-Kronrod quadrature; the cap depth and the steady state are found by
// bracketing root finders.
//
// The settled state is solved by one root search over ln kappa: at a given
// kappa the profile gives m0, hence h and F_e; the mechanism gives the erosion
// rate alpha_eff(F_e) (the profile depends only on alpha_eff R / v, so
// v = alpha_eff R / kappa), the removal rate and any force not carried by the
// elastic contact; the search finds the kappa whose total force is the held
// force F.
//
// Mechanisms, each with a strength s >= 0 (0 = the base model) and at least
// two shapes. A hidden mechanism acts through the physics, never as an
// output filter (except the bump, which is a control outside every family).
//
//  * Motor power limit. The spindle's power is the specific cutting energy
//    times the removal rate (eq. 6.4), so a motor of power W_max removes at
//    most Q_max = W_max / k_s. The removal rate is v times the area of the
//    hole, Q = v int (1 - rho_exit) dA. A motor short of power slows, which
//    scales alpha (eq. 7.12) and therefore v at the same profile.
//    (a) kPowerCap: a governor holds the speed until the power runs out, then
//        Q = min(Q_u, Q_max): a kink. s = 1 / Q_max (s/mm^3).
//    (b) kPowerDroop: a motor whose speed sags with its current long before
//        the limit, Q = Q_u / (1 + (Q_u/Q_max)^2)^{1/2}: a smooth plateau.
//        s = 1 / Q_max.
//  * Spindle slowdown. The erosion rate scales with the spindle's speed
//    omega; the load torque grows with the contact force.
//    (a) kSpindleLinear: a DC motor's straight torque line,
//        omega / omega0 = 1 - F_e / F_stall. s = 1 / F_stall (1/N).
//    (b) kSpindleExponential: an air turbine, whose speed falls ever more
//        gently and never stalls, omega / omega0 = exp(-F_e / F_s).
//        s = 1 / F_s (1/N).
//  * Cutting threshold. The flutes need a minimum contact force F0 to bite.
//    (a) kThresholdHard: erosion at alpha (1 - F0/F_e) above F0 (only the
//        force beyond F0 cuts), none below. s = F0 (N).
//    (b) kThresholdSoft: the engaged force is a smooth ramp of F_e - F0 (the
//        flute edges meet asperities of spread-out heights),
//        F_eng = w ln(1 + e^{(F_e - F0)/w}) - w ln(1 + e^{-F0/w}),
//        w = F0 / 3, and erosion runs at alpha F_eng / F_e: a little rubbing
//        removal below F0, alpha (1 - F0'/F_e) well above. s = F0 (N).
//    (c) kThresholdOffset: a part F0 of the held force never reaches the
//        contact (a guide's Coulomb friction, a blunt shoulder bearing on the
//        rim): F_e = F - F0 with the base erosion rate. s = F0 (N).
//  * Viscous resistance. Debris paste and coolant between burr and material
//    resist the descent; the resistance grows with the wetted cap (h/R) and
//    the speed and takes part of the held force (eq. 7.14's impact term).
//    (a) kViscousLinear: Newtonian, F_r = c R^2 (h/R) v. s = c (N s/mm^3).
//    (b) kViscousSqrt: shear-thinning paste, F_r = c R^2 (h/R) v^{1/2}.
//        s = c (N s^0.5 / mm^2.5).
//  * Friction-driven erosion. Wear proportional to the friction power (the
//    sliding speed is the spindle's, constant), so the rate grows with the
//    contact force.
//    (a) kFrictionLinear: Archard, rate alpha + k F_e. s = k (1/(N s)).
//    (b) kFrictionPower: a severe-wear regime whose wear grows faster than
//        the load, rate alpha + k F_e^{3/2}. s = k (1/(N^1.5 s)).
//  * Contact law. F_e = c_e R^2 (h/R)^n instead of Hertz's n = 3/2 (eq. 7.3).
//    (a) kContactSofter: n = 3/2 - s, plastic (Meyer) contact towards
//        n = 1 (s = 0.3: n = 1.2).
//    (b) kContactStiffer: n = 3/2 + s, a contact that stiffens with depth
//        (material compacted ahead of the burr, a harder layer under a
//        softer one) (s = 0.3: n = 1.8). The library's contact exponent is
//        fitted on the plastic side only (n <= 3/2), so this shape lies
//        outside its allowed range.
//  * Porosity: a void fraction phi softens the skeleton; the relative erosion
//    rate is unchanged. v(F) sees only c_e, so it must be absorbed, never
//    named.
//    (a) kPorositySquare: open-cell foam (Gibson-Ashby), c_e (1 - phi)^2.
//    (b) kPorosityPower15: closed cells, c_e (1 - phi)^{3/2}. s = phi.
//  * kLogBump: a smooth Gaussian bump of height s in log v against log F
//    (centre and width from the design), outside every physical family: it
//    must stay unexplained.
#ifndef BURRLAB_TESTS_ANALYSIS_MODEL_GAP_INDEPENDENT_TRUTH_SETTLED_DESCENT_H_
#define BURRLAB_TESTS_ANALYSIS_MODEL_GAP_INDEPENDENT_TRUTH_SETTLED_DESCENT_H_

#include <span>
#include <string_view>

namespace burrlab::analysis::independent_truth {

// The profile inside the sphere at kappa = alpha R / v, in units of R.
struct SphereProfile {
  double volume = 0.0;        // m0 / R^3: 4 pi / 3 at kappa = 0
  double removal_area = 0.0;  // Q / (v R^2) = int (1 - rho_exit) dA / R^2
};

// The profile by column integration; `with_removal` also integrates the
// removal area (a second quadrature).
SphereProfile ProfileAtKappa(double kappa, bool with_removal = true);

// h / R from m0 / R^3 = pi (h/R)^2 (1 - h/(3R)) (eq. 7.2), m0 in [0, 4 pi/3].
double CapDepthRatio(double volume);

enum class Mechanism {
  kNone,
  kPowerCap,
  kPowerDroop,
  kSpindleLinear,
  kSpindleExponential,
  kThresholdHard,
  kThresholdSoft,
  kThresholdOffset,
  kViscousLinear,
  kViscousSqrt,
  kFrictionLinear,
  kFrictionPower,
  kContactSofter,
  kContactStiffer,
  kPorositySquare,
  kPorosityPower15,
  kLogBump,
};

// The truth: the base material, the burr and one hidden mechanism.
struct Truth {
  double c_e_n_per_mm2 = 2.145;
  double alpha_per_s = 0.087;
  double radius_mm = 1.0;
  Mechanism mechanism = Mechanism::kNone;
  double strength = 0.0;  // 0: the base model; units in the list above
  // kLogBump: centre and width (1/e half-width) in ln F.
  double bump_centre_ln_force = 0.0;
  double bump_width_ln_force = 1.0;
};

// The settled velocity in mm/s at held force `force_n`: 0 when the burr does
// not cut (below a threshold, a stalled spindle), +inf when the force
// exceeds what the fully immersed sphere can carry (the burr falls through),
// NaN for a strength outside the mechanism's range (negative; porosity 1 or
// more; a contact exponent outside [1, 2]).
double SettledVelocityMmS(const Truth& truth, double force_n);

// How the mechanism deforms the base model, for tables and the tests.
struct MechanismInfo {
  Mechanism mechanism;
  std::string_view name;         // short, e.g. "power_cap"
  std::string_view library_id;   // the effect Discover should name ("" none)
  std::string_view description;  // one line with the formula
  bool physical;                 // a mechanism of a library family
};

std::span<const MechanismInfo> Mechanisms();
const MechanismInfo& InfoOf(Mechanism mechanism);

}  // namespace burrlab::analysis::independent_truth

#endif  // BURRLAB_TESTS_ANALYSIS_MODEL_GAP_INDEPENDENT_TRUTH_SETTLED_DESCENT_H_
