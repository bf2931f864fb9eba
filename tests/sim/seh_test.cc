// Sample-estimate-hold (§6.4.3): integral matching and energy behaviour on a
// virtual spring.
#include "burrlab/sim/seh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace burrlab::sim {
namespace {

TEST(SampleEstimateHold, HeldValueMatchesTheIntegralOfALinearForce) {
  // F(t) = 3 + 2t sampled at t_k = k T; the exact mean over [t_k, t_k + T] is
  // F(t_k) + T.
  SampleEstimateHold seh;
  const double period = 1e-3;
  for (int k = 0; k < 100; ++k) {
    const double t = k * period;
    const glm::dvec3 held = seh.Update(glm::dvec3(3.0 + 2.0 * t, 0.0, -1.0));
    if (k > 0) {
      EXPECT_NEAR(held.x, 3.0 + 2.0 * t + period, 1e-12);
    }
    EXPECT_EQ(held.z, -1.0);
  }
}

// Work done by a virtual spring on a probe moving through a full sinusoidal
// cycle: zero for the continuous spring; positive (energy injected into the
// hand) under zero-order hold.
double CycleWork(bool use_seh) {
  const double stiffness = 2.0, amplitude = 1.0;
  const int steps = 200;  // 5 Hz motion sampled at 1 kHz
  SampleEstimateHold seh;
  double work = 0.0;
  for (int k = 0; k < steps; ++k) {
    const double x0 = amplitude * std::sin(2 * std::numbers::pi * k / steps);
    const double x1 =
        amplitude * std::sin(2 * std::numbers::pi * (k + 1) / steps);
    const glm::dvec3 sample(-stiffness * x0, 0.0, 0.0);
    const double held = use_seh ? seh.Update(sample).x : sample.x;
    work += held * (x1 - x0);
  }
  return work;
}

TEST(SampleEstimateHold, InjectsFarLessEnergyThanZeroOrderHold) {
  const double zoh = CycleWork(false), seh = CycleWork(true);
  EXPECT_GT(zoh, 0.0);
  EXPECT_LT(std::abs(seh), 0.05 * zoh) << "zoh " << zoh << " seh " << seh;
}

TEST(SampleEstimateHold, ResetForgetsTheHistory) {
  SampleEstimateHold seh;
  seh.Update(glm::dvec3(10.0));
  seh.Reset();
  EXPECT_EQ(seh.Update(glm::dvec3(1.0)).x, 1.0);
}

}  // namespace
}  // namespace burrlab::sim
