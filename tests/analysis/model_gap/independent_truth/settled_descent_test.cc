// The independent truth's physics (settled_descent.h): its limits in closed
// form, derived here; each mechanism against what its formula says of the
// base model's state; and agreement with the product's surrogate, which is
// another implementation of the same physics, so it checks both (the base
// model, and the mechanisms whose shape is the effect library's own).
#include "independent_truth/settled_descent.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/sim/effects.h"

namespace burrlab::analysis::independent_truth {
namespace {

constexpr double kPi = std::numbers::pi;

Truth Bone() { return Truth{}; }

Truth Pvc() {
  Truth t;
  t.c_e_n_per_mm2 = 0.462;
  t.alpha_per_s = 0.296;
  return t;
}

Truth With(Truth t, Mechanism mechanism, double strength) {
  t.mechanism = mechanism;
  t.strength = strength;
  return t;
}

double ProductVelocity(const Truth& t, double force_n,
                       const sim::Effects& effects = {}) {
  DescentSurrogateInput in;
  in.force_n = force_n;
  in.c_e_n_per_mm2 = t.c_e_n_per_mm2;
  in.alpha_per_s = t.alpha_per_s;
  in.radius_mm = t.radius_mm;
  in.effects = effects;
  return SteadyVelocityMmS(in);
}

// Truth: another implementation of the same physics. The product's surrogate
// integrates the same continuum model (eqs. 7.2, 7.3, 7.12) by the closed
// form of the column integral, a table and an interpolated inverse; this one
// by Runge-Kutta along each column, adaptive quadrature over the columns and
// a root search. Agreement within 0.2 % at loads 0.05-2.5 on two materials
// and two radii checks both (measured: within 3e-6).
TEST(IndependentTruth, BaseModelAgreesWithTheProductSurrogate) {
  double worst = 0.0;
  for (Truth t : {Bone(), Pvc()}) {
    for (double radius : {1.0, 2.0}) {
      t.radius_mm = radius;
      for (double load : {0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.9, 1.1, 1.3, 1.5,
                          1.8, 2.1, 2.5}) {
        const double f = load * t.c_e_n_per_mm2 * radius * radius;
        const double v = SettledVelocityMmS(t, f);
        const double product = ProductVelocity(t, f);
        EXPECT_NEAR(v / product, 1.0, 2e-3)
            << "load " << load << " c_e " << t.c_e_n_per_mm2 << " R " << radius;
        worst = std::max(worst, std::abs(v / product - 1.0));
      }
    }
  }
  std::printf("largest relative difference from the product: %.2e\n", worst);
}

// kappa -> 0 (v >> alpha R): the sphere is full, m0 -> 4 pi R^3 / 3, h -> 2R.
// To first order rho = 1 - kappa Phi with Phi the erosion integral along the
// column from its entry, int_{-w}^{z} (w^2 - z'^2) dz'. Integrated over the
// column, int_{-w}^{w} Phi dz = int_{-w}^{w} (w^2 - z'^2)(w - z') dz'
// = 4 w^4 / 3, and over the disk, int_0^1 2 pi s (4/3)(1 - s^2)^2 ds
// = 4 pi / 9: m0 / R^3 = 4 pi / 3 - (4 pi / 9) kappa + O(kappa^2). The exit
// density is 1 - kappa (4/3) w^3, so the removal area is
// kappa int_0^1 2 pi s (4/3)(1 - s^2)^{3/2} ds = (8 pi / 15) kappa. Near
// h = 2R the cap volume is 4 pi / 3 - pi (2 - h/R)^2, so
// 2 - h/R = (2/3) sqrt(kappa).
TEST(IndependentTruth, SmallErosionLimit) {
  for (double kappa : {1e-5, 1e-4}) {
    const SphereProfile p = ProfileAtKappa(kappa);
    EXPECT_NEAR((4.0 * kPi / 3.0 - p.volume) / kappa / (4.0 * kPi / 9.0), 1.0,
                2.0 * kappa + 1e-5)
        << kappa;
    EXPECT_NEAR(p.removal_area / kappa / (8.0 * kPi / 15.0), 1.0,
                2.0 * kappa + 1e-5)
        << kappa;
    const double x = CapDepthRatio(p.volume);
    EXPECT_NEAR((2.0 - x) / (2.0 / 3.0 * std::sqrt(kappa)), 1.0, 0.02) << kappa;
  }
  EXPECT_NEAR(ProfileAtKappa(0.0).volume, 4.0 * kPi / 3.0, 1e-9);
  EXPECT_EQ(CapDepthRatio(4.0 * kPi / 3.0), 2.0);
}

// kappa -> inf (v << alpha R): the force is carried by a thin layer at the
// sphere's lower surface. Near the entry f = (w - z)(w + z) ~ 2 w d (d = z + w
// the depth into the column), so rho = exp(-kappa w d^2) and the column holds
// (1/2) sqrt(pi / (kappa w)); with s ds = w dw over the disk,
// m0 / R^3 = pi^{3/2} kappa^{-1/2} int_0^1 w^{1/2} dw
//          = (2/3) pi^{3/2} kappa^{-1/2} (1 + O(kappa^{-1/2})).
// Every column is cut through: the removal area tends to pi R^2. The cap is
// shallow, m0 = pi h^2 R, so the load (h/R)^{3/2} = (m0 / (pi R^3))^{3/4} and
// v = alpha R / kappa with kappa = (4 pi / 9) y^{-8/3} at load y.
TEST(IndependentTruth, ThinLayerLimit) {
  double previous = 1.0;
  for (double kappa : {1e4, 1e6, 1e8}) {
    const SphereProfile p = ProfileAtKappa(kappa);
    const double ratio =
        p.volume * std::sqrt(kappa) / (2.0 / 3.0 * std::pow(kPi, 1.5));
    const double error = std::abs(ratio - 1.0);
    EXPECT_LT(error, 3.0 / std::sqrt(kappa)) << kappa;
    EXPECT_LT(error, 0.2 * previous) << kappa;  // shrinks as kappa^{-1/2}
    previous = error;
    EXPECT_NEAR(p.removal_area / kPi, 1.0, 3.0 / std::cbrt(kappa)) << kappa;
  }
  const Truth t = Bone();
  for (double load : {1e-3, 1e-4}) {
    const double kappa = 4.0 * kPi / 9.0 * std::pow(load, -8.0 / 3.0);
    const double v = SettledVelocityMmS(t, load * t.c_e_n_per_mm2);
    EXPECT_NEAR(v * kappa / (t.alpha_per_s * t.radius_mm), 1.0,
                30.0 * std::pow(load, 2.0 / 3.0))
        << load;
  }
}

TEST(IndependentTruth, FallsThroughBeyondFullImmersion) {
  const Truth t = Bone();
  // The immersed sphere carries c_e R^2 2^{3/2}.
  EXPECT_EQ(SettledVelocityMmS(t, 2.84 * t.c_e_n_per_mm2),
            std::numeric_limits<double>::infinity());
  const double v = SettledVelocityMmS(t, 2.8 * t.c_e_n_per_mm2);
  EXPECT_TRUE(std::isfinite(v) && v > 0.0) << v;
}

// The mechanisms whose shape is the effect library's own (variant (a) of
// each family, and the porosity of (1 - phi)^2) against the product's
// surrogate with that effect: again another implementation of the same
// physics. The other variants have no counterpart there.
TEST(IndependentTruth, LibraryShapedMechanismsAgreeWithTheProductSurrogate) {
  struct Case {
    Mechanism mechanism;
    double strength;
    sim::Effects effects;
  };
  const auto effects = [](double sim::Effects::*field, double value) {
    sim::Effects fx;
    fx.*field = value;
    return fx;
  };
  const Truth t = Bone();
  const Case cases[] = {
      {Mechanism::kPowerCap, 1.0 / 0.01,
       effects(&sim::Effects::max_removal_mm3_per_s, 0.01)},
      {Mechanism::kSpindleLinear, 1.0 / 5.0,
       effects(&sim::Effects::stall_force_n, 5.0)},
      {Mechanism::kThresholdHard, 0.8,
       effects(&sim::Effects::cutting_threshold_n, 0.8)},
      {Mechanism::kViscousLinear, 20.0,
       effects(&sim::Effects::impact_c_i_n_s_per_mm3, 20.0)},
      {Mechanism::kFrictionLinear, 0.05,
       effects(&sim::Effects::friction_erosion_per_n_s, 0.05)},
      {Mechanism::kContactSofter, 0.3,
       effects(&sim::Effects::contact_exponent, 1.2)},
      {Mechanism::kPorositySquare, 0.2, effects(&sim::Effects::porosity, 0.2)},
  };
  double worst = 0.0;
  for (const Case& c : cases) {
    for (double load : {0.5, 0.9, 1.5}) {
      const double f = load * t.c_e_n_per_mm2;
      const double v = SettledVelocityMmS(With(t, c.mechanism, c.strength), f);
      const double product = ProductVelocity(t, f, c.effects);
      EXPECT_NEAR(v / product, 1.0, 2e-3)
          << InfoOf(c.mechanism).name << " at load " << load;
      // The effect itself is not small: v differs from the base model's.
      EXPECT_GT(std::abs(v / SettledVelocityMmS(t, f) - 1.0), 0.02)
          << InfoOf(c.mechanism).name << " at load " << load;
      worst = std::max(worst, std::abs(v / product - 1.0));
    }
  }
  std::printf("largest relative difference from the product: %.2e\n", worst);
}

// Every mechanism does what its formula says to the base model's state,
// checked through the base solver: a rate factor g(F_e) scales v at the
// same force, a load offset shifts the force, porosity and the contact law
// change the force the same depth carries, a resistance adds to the force
// the same state needs, the power limit caps or droops the removal rate.
TEST(IndependentTruth, MechanismsActAsTheirFormulas) {
  const Truth t = Bone();
  const double f = 0.9 * t.c_e_n_per_mm2;  // load 0.9
  const double base = SettledVelocityMmS(t, f);
  const auto v = [&](Mechanism m, double s, double force) {
    return SettledVelocityMmS(With(t, m, s), force);
  };
  constexpr double kTol = 1e-6;
  // Rate factors (F_e = F here).
  EXPECT_NEAR(v(Mechanism::kSpindleLinear, 0.2, f) / base, 1.0 - 0.2 * f, kTol);
  EXPECT_NEAR(v(Mechanism::kSpindleExponential, 0.3, f) / base,
              std::exp(-0.3 * f), kTol);
  EXPECT_NEAR(v(Mechanism::kThresholdHard, 0.5, f) / base, 1.0 - 0.5 / f, kTol);
  const double w = 0.5 / 3.0;
  const double engaged = w * (std::log1p(std::exp((f - 0.5) / w)) -
                              std::log1p(std::exp(-0.5 / w)));
  EXPECT_NEAR(v(Mechanism::kThresholdSoft, 0.5, f) / base, engaged / f, kTol);
  EXPECT_NEAR(v(Mechanism::kFrictionLinear, 0.04, f) / base,
              1.0 + 0.04 * f / t.alpha_per_s, kTol);
  EXPECT_NEAR(v(Mechanism::kFrictionPower, 0.02, f) / base,
              1.0 + 0.02 * std::pow(f, 1.5) / t.alpha_per_s, kTol);
  // Below the hard threshold, and at a stalled spindle, nothing is cut.
  EXPECT_EQ(v(Mechanism::kThresholdHard, 1.1 * f, f), 0.0);
  EXPECT_EQ(v(Mechanism::kSpindleLinear, 1.0 / (0.9 * f), f), 0.0);
  // The soft threshold still rubs a little material away below F0.
  EXPECT_GT(v(Mechanism::kThresholdSoft, 1.5 * f, f), 0.0);
  // A load offset: the contact sees F - F0.
  EXPECT_NEAR(v(Mechanism::kThresholdOffset, 0.4, f + 0.4) / base, 1.0, kTol);
  EXPECT_EQ(v(Mechanism::kThresholdOffset, 0.4, 0.39), 0.0);
  // Porosity: the same depth at c_e (1 - phi)^p carries F (1 - phi)^p.
  EXPECT_NEAR(v(Mechanism::kPorositySquare, 0.2, f * 0.64) / base, 1.0, kTol);
  EXPECT_NEAR(
      v(Mechanism::kPorosityPower15, 0.2, f * std::pow(0.8, 1.5)) / base, 1.0,
      kTol);
  // Contact law: depth x = load^{2/3} carries c_e R^2 x^n.
  const double x = std::pow(0.9, 2.0 / 3.0);
  EXPECT_NEAR(
      v(Mechanism::kContactSofter, 0.3, t.c_e_n_per_mm2 * std::pow(x, 1.2)) /
          base,
      1.0, kTol);
  EXPECT_NEAR(
      v(Mechanism::kContactStiffer, 0.3, t.c_e_n_per_mm2 * std::pow(x, 1.8)) /
          base,
      1.0, kTol);
  // Resistances: the base state at F_e needs F_e + c R^2 x v^p.
  EXPECT_NEAR(v(Mechanism::kViscousLinear, 10.0, f + 10.0 * x * base) / base,
              1.0, kTol);
  EXPECT_NEAR(
      v(Mechanism::kViscousSqrt, 2.0, f + 2.0 * x * std::sqrt(base)) / base,
      1.0, kTol);
  // Power: Q_u = v R^2 A at the base state's kappa = alpha R / v.
  const double area = ProfileAtKappa(t.alpha_per_s / base).removal_area;
  const double q = base * area;
  EXPECT_NEAR(v(Mechanism::kPowerCap, 1.0 / (2.0 * q), f) / base, 1.0, kTol);
  EXPECT_NEAR(v(Mechanism::kPowerCap, 2.0 / q, f) / base, 0.5, kTol);
  EXPECT_NEAR(v(Mechanism::kPowerDroop, 1.0 / q, f) / base, std::sqrt(0.5),
              kTol);
  // The bump: exp(s) at its centre, nothing far from it.
  Truth bump = With(t, Mechanism::kLogBump, 0.3);
  bump.bump_centre_ln_force = std::log(f);
  bump.bump_width_ln_force = 0.2;
  EXPECT_NEAR(SettledVelocityMmS(bump, f) / base, std::exp(0.3), kTol);
  EXPECT_NEAR(
      SettledVelocityMmS(bump, 3.0 * f) / SettledVelocityMmS(t, 3.0 * f), 1.0,
      1e-9);
  // Every mechanism at strength 0 is the base model.
  for (const MechanismInfo& info : Mechanisms()) {
    EXPECT_NEAR(v(info.mechanism, 0.0, f) / base, 1.0, kTol) << info.name;
  }
}

// Each physical mechanism maps to an effect of the library.
TEST(IndependentTruth, MechanismsNameEffectsOfTheLibrary) {
  for (const MechanismInfo& info : Mechanisms()) {
    if (info.library_id.empty()) continue;
    EXPECT_NE(sim::FindEffect(info.library_id), nullptr) << info.name;
  }
}

}  // namespace
}  // namespace burrlab::analysis::independent_truth
