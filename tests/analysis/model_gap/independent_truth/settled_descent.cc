// The independent truth's physics: column integration, cap depth, the settled
// state with a hidden mechanism (settled_descent.h).
#include "independent_truth/settled_descent.h"

#include <algorithm>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace burrlab::analysis::independent_truth {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// One column at half-chord w (units of R): the mass int rho dz along it and
// the density with which the material leaves the sphere at the top.
struct Column {
  double mass = 0.0;
  double exit_density = 1.0;
};

// The column as an initial-value problem in d = z + w in [0, 2w] (d = 0 at
// the lower surface, where rho = rho0 = 1): with R = 1 the distance from the
// centre is r^2 = s^2 + z^2 = 1 - w^2 + z^2, so f = 1 - r^2 = w^2 - z^2 =
// d (2w - d), and
//   d rho / dd = -kappa d (2w - d) rho,   d mass / dd = rho   (eq. 7.12).
// Classical Runge-Kutta with step doubling: each step is taken once whole and
// once as two halves; their difference / 15 estimates the error of the
// halves, which must stay below kTolerance of the column's mass scale; the
// accepted value is the Richardson extrapolation of the two. The integration
// stops once the density is negligible (the rest of the column adds less
// than 1e-15 of its length).
Column IntegrateColumn(double kappa, double w) {
  const double length = 2.0 * w;
  if (!(length > 0.0)) return {};
  constexpr double kTolerance = 1e-10;
  constexpr double kNegligible = 1e-15;
  const auto slope = [kappa, w](double d, double rho) {
    return -kappa * d * (2.0 * w - d) * rho;
  };
  // One Runge-Kutta step of length h from (d, rho, mass).
  const auto step = [&slope](double d, double rho, double mass, double h,
                             double* rho_out, double* mass_out) {
    const double r1 = rho;
    const double k1 = slope(d, r1);
    const double r2 = rho + 0.5 * h * k1;
    const double k2 = slope(d + 0.5 * h, r2);
    const double r3 = rho + 0.5 * h * k2;
    const double k3 = slope(d + 0.5 * h, r3);
    const double r4 = rho + h * k3;
    const double k4 = slope(d + h, r4);
    *rho_out = rho + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    *mass_out = mass + h / 6.0 * (r1 + 2.0 * r2 + 2.0 * r3 + r4);
  };
  // The density decays on the shorter of the thin-layer scale near the
  // entry, (kappa w)^{-1/2}, and the rim's kappa^{-1/3}: the column's mass
  // scale; the first step is well inside it.
  double scale = length;
  if (kappa > 0.0) {
    scale = std::min({scale, 1.0 / std::sqrt(kappa * w), std::cbrt(1 / kappa)});
  }
  double h = 0.05 * scale;
  double d = 0.0, rho = 1.0, mass = 0.0;
  bool done = false;
  while (!done && rho > kNegligible) {
    const bool last = h >= length - d;
    if (last) h = length - d;
    double rho_full = 0.0, mass_full = 0.0, rho_mid = 0.0, mass_mid = 0.0;
    double rho_half = 0.0, mass_half = 0.0;
    step(d, rho, mass, h, &rho_full, &mass_full);
    step(d, rho, mass, 0.5 * h, &rho_mid, &mass_mid);
    step(d + 0.5 * h, rho_mid, mass_mid, 0.5 * h, &rho_half, &mass_half);
    // The error estimates of the halves, in units of the column's mass: an
    // error e in rho at d changes the mass by about e times the length over
    // which rho still decays, 1 / max(|rho'/rho|, 1 / 2w). Against a fixed
    // fraction of the column's mass scale the steps per decay length are
    // then the same at every kappa, and the tail takes long steps.
    const double rate = std::max(kappa * d * (2.0 * w - d), 1.0 / length);
    const double ratio = std::max(std::abs(rho_half - rho_full) / rate,
                                  std::abs(mass_half - mass_full)) /
                         (15.0 * kTolerance * scale);
    if (ratio <= 1.0 || h <= 1e-15 * length) {
      rho = rho_half + (rho_half - rho_full) / 15.0;
      mass = mass_half + (mass_half - mass_full) / 15.0;
      d += h;
      done = last;
    }
    // The local error grows as h^5.
    const double factor = ratio > 0.0 ? 0.9 * std::pow(ratio, -0.2) : 4.0;
    h *= std::clamp(factor, 0.2, 4.0);
  }
  return {mass, done ? std::max(rho, 0.0) : 0.0};
}

// int_0^{pi/2} g(theta) d theta by adaptive Gauss-Kronrod (31 points).
template <typename G>
double OverTheta(const G& g) {
  return boost::math::quadrature::gauss_kronrod<double, 31>::integrate(
      g, 0.0, 0.5 * kPi, 12, 1e-9);
}

double Softplus(double u) {
  return u > 0.0 ? u + std::log1p(std::exp(-u)) : std::log1p(std::exp(u));
}

bool NeedsRemoval(Mechanism m) {
  return m == Mechanism::kPowerCap || m == Mechanism::kPowerDroop;
}

// What the rig would see at one kappa.
struct State {
  double total_force_n = 0.0;  // the force the rig must hold
  double velocity_mm_s = 0.0;
};

State AtKappa(const Truth& t, double kappa) {
  const double r = t.radius_mm;
  const double s = t.strength;
  const Mechanism m = t.mechanism;
  const SphereProfile profile = ProfileAtKappa(kappa, NeedsRemoval(m));
  const double x = CapDepthRatio(profile.volume);  // h / R (eq. 7.2)
  // Eq. 7.3 with the contact law and the skeleton's stiffness.
  double c_e = t.c_e_n_per_mm2;
  if (m == Mechanism::kPorositySquare) c_e *= (1.0 - s) * (1.0 - s);
  if (m == Mechanism::kPorosityPower15) c_e *= std::pow(1.0 - s, 1.5);
  double n = 1.5;
  if (m == Mechanism::kContactSofter) n = 1.5 - s;
  if (m == Mechanism::kContactStiffer) n = 1.5 + s;
  const double elastic_n = c_e * r * r * std::pow(x, n);
  // The erosion rate of eq. 7.12 under the mechanism.
  double rate = t.alpha_per_s;
  switch (m) {
    case Mechanism::kSpindleLinear:
      rate *= std::max(0.0, 1.0 - s * elastic_n);
      break;
    case Mechanism::kSpindleExponential:
      rate *= std::exp(-s * elastic_n);
      break;
    case Mechanism::kThresholdHard:
      rate *= elastic_n > s ? 1.0 - s / elastic_n : 0.0;
      break;
    case Mechanism::kThresholdSoft:
      if (s > 0.0) {
        const double width = s / 3.0;
        const double engaged =
            width * (Softplus((elastic_n - s) / width) - Softplus(-s / width));
        rate *= elastic_n > 0.0 ? engaged / elastic_n : 0.0;
      }
      break;
    case Mechanism::kFrictionLinear:
      rate += s * elastic_n;
      break;
    case Mechanism::kFrictionPower:
      rate += s * elastic_n * std::sqrt(elastic_n);
      break;
    default:
      break;
  }
  // The profile fixes kappa_eff = rate R / v.
  double v = rate * r / kappa;
  if (NeedsRemoval(m) && s > 0.0 && v > 0.0) {
    // Q_u / Q_max with Q_u = v R^2 A (eq. 6.4: the power the removal takes).
    const double demand = v * r * r * profile.removal_area * s;
    if (m == Mechanism::kPowerCap && demand > 1.0) v /= demand;
    if (m == Mechanism::kPowerDroop) v /= std::sqrt(1.0 + demand * demand);
  }
  double total = elastic_n;
  if (m == Mechanism::kViscousLinear) total += s * r * r * x * v;
  if (m == Mechanism::kViscousSqrt) total += s * r * r * x * std::sqrt(v);
  if (m == Mechanism::kThresholdOffset) total += s;
  return {total, v};
}

constexpr MechanismInfo kMechanisms[] = {
    {Mechanism::kNone, "none", "", "the base model", false},
    {Mechanism::kPowerCap, "power_cap", "motor_power_limit",
     "Q = min(Q_u, Q_max), s = 1/Q_max", true},
    {Mechanism::kPowerDroop, "power_droop", "motor_power_limit",
     "Q = Q_u / (1 + (Q_u/Q_max)^2)^(1/2), s = 1/Q_max", true},
    {Mechanism::kSpindleLinear, "spindle_linear", "spindle_slowdown",
     "omega/omega0 = 1 - F_e/F_stall, s = 1/F_stall", true},
    {Mechanism::kSpindleExponential, "spindle_exp", "spindle_slowdown",
     "omega/omega0 = exp(-F_e/F_s), s = 1/F_s", true},
    {Mechanism::kThresholdHard, "threshold_hard", "cutting_threshold",
     "rate alpha (1 - F0/F_e) above F0, 0 below, s = F0", true},
    {Mechanism::kThresholdSoft, "threshold_soft", "cutting_threshold",
     "rate alpha softplus_w(F_e - F0) / F_e, w = F0/3, s = F0", true},
    {Mechanism::kThresholdOffset, "threshold_offset", "cutting_threshold",
     "F_e = F - F0, s = F0", true},
    {Mechanism::kViscousLinear, "viscous_linear", "viscous_resistance",
     "F = F_e + c R^2 (h/R) v, s = c", true},
    {Mechanism::kViscousSqrt, "viscous_sqrt", "viscous_resistance",
     "F = F_e + c R^2 (h/R) v^0.5, s = c", true},
    {Mechanism::kFrictionLinear, "friction_linear", "friction_erosion",
     "rate alpha + k F_e, s = k", true},
    {Mechanism::kFrictionPower, "friction_pow1.5", "friction_erosion",
     "rate alpha + k F_e^1.5, s = k", true},
    {Mechanism::kContactSofter, "contact_softer", "contact_exponent",
     "F_e = c_e R^2 (h/R)^(1.5 - s)", true},
    {Mechanism::kContactStiffer, "contact_stiffer", "contact_exponent",
     "F_e = c_e R^2 (h/R)^(1.5 + s)", true},
    {Mechanism::kPorositySquare, "porosity_sq", "porosity",
     "c_e (1 - phi)^2, s = phi", false},
    {Mechanism::kPorosityPower15, "porosity_pow1.5", "porosity",
     "c_e (1 - phi)^1.5, s = phi", false},
    {Mechanism::kLogBump, "bump", "",
     "log v + s exp(-((ln F - c)/w)^2), outside the library", false},
};

}  // namespace

SphereProfile ProfileAtKappa(double kappa, bool with_removal) {
  // Columns at s = sin theta (R = 1) have half-chord w = cos theta and the
  // area element 2 pi s ds = 2 pi sin theta cos theta d theta.
  SphereProfile p;
  p.volume = OverTheta([kappa](double theta) {
    const double w = std::cos(theta);
    return 2.0 * kPi * std::sin(theta) * w * IntegrateColumn(kappa, w).mass;
  });
  if (with_removal) {
    p.removal_area = OverTheta([kappa](double theta) {
      const double w = std::cos(theta);
      return 2.0 * kPi * std::sin(theta) * w *
             (1.0 - IntegrateColumn(kappa, w).exit_density);
    });
  }
  return p;
}

double CapDepthRatio(double volume) {
  if (!(volume > 0.0)) return 0.0;
  if (volume >= 4.0 * kPi / 3.0) return 2.0;
  // pi x^2 (1 - x/3) rises from 0 to 4 pi / 3 on [0, 2].
  const auto excess = [volume](double x) {
    return kPi * x * x * (1.0 - x / 3.0) - volume;
  };
  std::uintmax_t iterations = 200;
  const auto [lo, hi] = boost::math::tools::toms748_solve(
      excess, 0.0, 2.0, -volume, 4.0 * kPi / 3.0 - volume,
      [](double a, double b) { return std::abs(a - b) <= 1e-14; }, iterations);
  return 0.5 * (lo + hi);
}

double SettledVelocityMmS(const Truth& t, double force_n) {
  const Mechanism m = t.mechanism;
  const bool porous =
      m == Mechanism::kPorositySquare || m == Mechanism::kPorosityPower15;
  const bool contact =
      m == Mechanism::kContactSofter || m == Mechanism::kContactStiffer;
  if (!(t.strength >= 0.0) || (porous && t.strength >= 1.0) ||
      (contact && t.strength > 0.5)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  // The total force falls as kappa grows (less material in the sphere,
  // slower cutting): bracket ln kappa and find the held force.
  const double lo = std::log(1e-9), hi = std::log(1e12);
  const auto excess = [&](double ln_kappa) {
    return AtKappa(t, std::exp(ln_kappa)).total_force_n - force_n;
  };
  const double at_lo = excess(lo), at_hi = excess(hi);
  if (at_lo < 0.0) return kInf;  // more than the immersed sphere carries
  if (at_hi > 0.0) return 0.0;   // the contact never reaches the force
  std::uintmax_t iterations = 200;
  const auto [a, b] = boost::math::tools::toms748_solve(
      excess, lo, hi, at_lo, at_hi,
      [](double x, double y) { return std::abs(x - y) <= 1e-10; }, iterations);
  double v = AtKappa(t, std::exp(0.5 * (a + b))).velocity_mm_s;
  if (t.mechanism == Mechanism::kLogBump && v > 0.0) {
    const double z =
        (std::log(force_n) - t.bump_centre_ln_force) / t.bump_width_ln_force;
    v *= std::exp(t.strength * std::exp(-z * z));
  }
  return v;
}

std::span<const MechanismInfo> Mechanisms() { return kMechanisms; }

const MechanismInfo& InfoOf(Mechanism mechanism) {
  for (const MechanismInfo& info : kMechanisms) {
    if (info.mechanism == mechanism) return info;
  }
  return kMechanisms[0];
}

}  // namespace burrlab::analysis::independent_truth
