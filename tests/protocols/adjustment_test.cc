// Method of adjustment: the recorded path on a grid of steps, clamping at
// the bounds, log/dB steps, seeded start jitter, the max_steps guard, exact
// validation text.
#include "burrlab/protocols/adjustment.h"

#include <gtest/gtest.h>

#include <boost/random/mersenne_twister.hpp>
#include <cmath>
#include <set>
#include <vector>

namespace burrlab::protocols {
namespace {

AdjustmentOptions Linear() {
  AdjustmentOptions o;
  o.start_level = 1.0;
  o.step = 0.25;
  o.floor_level = 0.5;
  o.ceiling_level = 1.5;
  return o;
}

Adjustment Make(const AdjustmentOptions& o, unsigned seed = 1) {
  boost::random::mt19937 rng(seed);
  Result<Adjustment> created = Adjustment::Create(o, rng);
  EXPECT_TRUE(created.ok()) << created.error().message;
  return std::move(created).value();
}

void StepAll(Adjustment& a, const std::vector<int>& directions) {
  for (int d : directions) EXPECT_TRUE(a.Step(d).ok());
}

TEST(Adjustment, RecordsEveryLevelVisitedAndTheFinalLevel) {
  Adjustment a = Make(Linear());
  StepAll(a, {+1, +1, +1, -1, -1, -1, -1, -1});
  // Up to the ceiling (the third step is blocked there), down to the floor
  // (the last step is blocked there).
  EXPECT_EQ(a.path(), (std::vector<double>{1.0, 1.25, 1.5, 1.5, 1.25, 1.0, 0.75,
                                           0.5, 0.5}));
  EXPECT_EQ(a.steps_taken(), 8);
  EXPECT_FALSE(a.finished());
  EXPECT_EQ(a.Finish().value(), 0.5);
  EXPECT_TRUE(a.finished());
  EXPECT_EQ(a.final_level(), 0.5);
}

TEST(Adjustment, ClampsToAnOffGridBoundAndReturnsToTheGrid) {
  AdjustmentOptions o = Linear();
  o.ceiling_level = 1.4;
  Adjustment a = Make(o);
  StepAll(a, {+1, +1, +1, -1});
  EXPECT_EQ(a.path(), (std::vector<double>{1.0, 1.25, 1.4, 1.4, 1.25}));
}

TEST(Adjustment, DecibelStepsReturnExactlyToTheStart) {
  AdjustmentOptions o;
  o.start_level = 2.0;
  o.step = 6.0;
  o.step_scale = StepScale::kDecibel;
  Adjustment a = Make(o);
  StepAll(a, {+1, -1, -1});
  ASSERT_EQ(a.path().size(), 4u);
  // 2 x 10^(+-0.3) to 12 significant digits (levels.h).
  EXPECT_EQ(a.path()[1], 3.99052462994);
  EXPECT_EQ(a.path()[2], 2.0);  // computed from the grid, no rounding drift
  EXPECT_EQ(a.path()[3], 1.00237446725);
}

TEST(Adjustment, StartJitterIsWholeStepsAndSeeded) {
  AdjustmentOptions o;
  o.start_level = 1.0;
  o.step = 0.1;
  o.step_scale = StepScale::kLog10;
  o.start_jitter_steps = 3;
  std::set<int> jitters;
  for (unsigned seed = 1; seed <= 100; ++seed) {
    Adjustment a = Make(o, seed);
    EXPECT_GE(a.jitter_steps(), -3);
    EXPECT_LE(a.jitter_steps(), 3);
    // Rounded to 12 significant digits (levels.h).
    EXPECT_NEAR(a.start_level(), std::pow(10.0, 0.1 * a.jitter_steps()),
                5e-12 * a.start_level());
    jitters.insert(a.jitter_steps());
  }
  EXPECT_EQ(jitters.size(), 7u);
  EXPECT_EQ(Make(o, 8).start_level(), Make(o, 8).start_level());
}

TEST(Adjustment, MaxStepsGuardsThePath) {
  AdjustmentOptions o = Linear();
  o.max_steps = 3;
  Adjustment a = Make(o);
  StepAll(a, {+1, -1, +1});
  EXPECT_EQ(a.Step(+1).error().message,
            "adjustment: max_steps (3) reached; finish the adjustment");
  EXPECT_EQ(a.path().size(), 4u);
  EXPECT_EQ(a.Finish().value(), 1.25);
}

TEST(Adjustment, RejectsBadDirectionsAndStepsAfterFinish) {
  Adjustment a = Make(Linear());
  EXPECT_EQ(a.Step(2).error().message,
            "adjustment: direction must be +1 or -1, got 2");
  EXPECT_EQ(a.Step(0).error().message,
            "adjustment: direction must be +1 or -1, got 0");
  ASSERT_TRUE(a.Finish().ok());
  EXPECT_EQ(a.Step(1).error().message, "adjustment: already finished");
  EXPECT_EQ(a.Finish().error().message, "adjustment: already finished");
  EXPECT_EQ(a.path().size(), 1u);
}

TEST(Adjustment, DefaultsAreValid) {
  EXPECT_TRUE(AdjustmentOptions{}.Validate().ok());
}

TEST(Adjustment, ValidateNamesTheFieldTheValueAndTheRule) {
  AdjustmentOptions o;
  o.step = 0.0;
  EXPECT_EQ(o.Validate().error().message,
            "adjustment: step must be positive, got 0");
  o = Linear();
  o.start_jitter_steps = 3;
  EXPECT_EQ(o.Validate().error().message,
            "adjustment: start_level 1 jittered by up to 3 steps of 0.25 "
            "(linear) spans [0.25, 1.75], outside [floor_level, ceiling_level] "
            "= [0.5, 1.5]");
  o = {};
  o.step_scale = StepScale::kLog10;
  o.start_level = -1.0;
  EXPECT_EQ(o.Validate().error().message,
            "adjustment: start_level must be positive for a log10 step scale, "
            "got -1");
  o = {};
  o.max_steps = 0;
  EXPECT_EQ(o.Validate().error().message,
            "adjustment: max_steps must be in [1, 100000], got 0");
  boost::random::mt19937 rng(1);
  EXPECT_EQ(Adjustment::Create(o, rng).error().message,
            "adjustment: max_steps must be in [1, 100000], got 0");
}

}  // namespace
}  // namespace burrlab::protocols
