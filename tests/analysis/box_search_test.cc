// Tests of the bounded BOBYQA search: minima against closed forms, the box
// respected, fixed coordinates held, and the best point evaluated returned
// even where the objective has failures.
#include "burrlab/analysis/box_search.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <span>

namespace burrlab::analysis {
namespace {

// Closed form: Rosenbrock's valley has its minimum 0 at (1, 1).
TEST(BoxSearch, FindsRosenbrocksMinimum) {
  BoxSearch box;
  box.lower = {-2.0, -2.0};
  box.upper = {2.0, 2.0};
  box.initial_step = {0.5, 0.5};
  box.xtol_abs = 1e-9;
  box.max_evaluations = 2000;
  int calls = 0;
  const BoxMinimum m = MinimiseInBox(
      [&](std::span<const double> x) {
        ++calls;
        const double a = 1.0 - x[0], b = x[1] - x[0] * x[0];
        return a * a + 100.0 * b * b;
      },
      box, {-1.2, 1.0});
  EXPECT_NEAR(m.x[0], 1.0, 1e-4);
  EXPECT_NEAR(m.x[1], 1.0, 1e-4);
  EXPECT_LT(m.value, 1e-8);
  EXPECT_LE(calls, 2000);
}

// Closed form: a paraboloid centred outside the box has its constrained
// minimum on the nearest face; a coordinate with equal bounds stays put; a
// start outside the box is clamped into it.
TEST(BoxSearch, StaysInTheBoxAndHoldsFixedCoordinates) {
  BoxSearch box;
  box.lower = {0.0, 0.5};
  box.upper = {1.0, 0.5};
  box.initial_step = {0.2, 0.0};
  box.xtol_abs = 1e-9;
  const BoxMinimum m = MinimiseInBox(
      [](std::span<const double> x) {
        EXPECT_GE(x[0], 0.0);
        EXPECT_LE(x[0], 1.0);
        EXPECT_EQ(x[1], 0.5);
        return (x[0] - 3.0) * (x[0] - 3.0) + (x[1] - 2.0) * (x[1] - 2.0);
      },
      box, {5.0, 0.5});
  EXPECT_NEAR(m.x[0], 1.0, 1e-6);
  EXPECT_EQ(m.x[1], 0.5);
  EXPECT_NEAR(m.value, 4.0 + 2.25, 1e-9);
}

// An objective that fails (NaN) on half the line: the best finite point is
// returned, never a failed one.
TEST(BoxSearch, KeepsTheBestFiniteEvaluation) {
  BoxSearch box;
  box.lower = {-1.0};
  box.upper = {1.0};
  box.initial_step = {0.3};
  box.xtol_abs = 1e-8;
  const BoxMinimum m = MinimiseInBox(
      [](std::span<const double> x) {
        if (x[0] < 0.25) return std::numeric_limits<double>::quiet_NaN();
        return (x[0] - 0.25) * (x[0] - 0.25) + 1.0;
      },
      box, {0.9});
  ASSERT_EQ(m.x.size(), 1u);
  EXPECT_GE(m.x[0], 0.25);
  EXPECT_NEAR(m.x[0], 0.25, 1e-3);
  EXPECT_TRUE(std::isfinite(m.value));
  EXPECT_NEAR(m.value, 1.0, 1e-6);
}

}  // namespace
}  // namespace burrlab::analysis
