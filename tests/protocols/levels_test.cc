// Levels of tracks: step scales, the rounding of levels, and the property the
// rounding is for: a staircase, an adjustment or a limits series that reaches
// one level many times, by any path, presents (and prints) it the same way
// each time, namely as the closed form start + k x step (or start x 10^(k x
// step)) rounded as levels.h says.
#include "burrlab/protocols/levels.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <string>

#include "burrlab/protocols/adjustment.h"
#include "burrlab/protocols/limits.h"
#include "burrlab/protocols/staircase.h"

namespace burrlab::protocols {
namespace {

// The text a level is exported as (results_schema writes the shortest text
// that reads back as the double).
std::string Printed(double level) { return fmt::format("{}", level); }

// The double a decimal text reads as.
double Decimal(const std::string& text) {
  return std::strtod(text.c_str(), nullptr);
}

// `value` rounded to 12 significant digits, by printf.
double TwelveDigits(double value) {
  return Decimal(fmt::format("{:.11e}", value));
}

TEST(StepScale, StepsMoveLevelsByTheDocumentedFactors) {
  EXPECT_EQ(ApplyStep(2.0, 0.5, StepScale::kLinear), 2.5);
  EXPECT_DOUBLE_EQ(ApplyStep(2.0, 1.0, StepScale::kLog10), 20.0);
  EXPECT_DOUBLE_EQ(ApplyStep(2.0, -20.0, StepScale::kDecibel), 0.2);
  EXPECT_DOUBLE_EQ(ToScaleDomain(100.0, StepScale::kDecibel), 40.0);
  EXPECT_DOUBLE_EQ(
      FromScaleDomain(ToScaleDomain(3.0, StepScale::kLog10), StepScale::kLog10),
      3.0);
  EXPECT_EQ(StepScaleName(StepScale::kDecibel), "db");
}

TEST(Levels, RoundSignificantKeepsTwelveDigits) {
  EXPECT_EQ(Printed(RoundSignificant(0.6000000000000001)), "0.6");
  EXPECT_EQ(Printed(RoundSignificant(0.39810717055349726)), "0.398107170553");
  EXPECT_EQ(Printed(RoundSignificant(1.0000000000000002)), "1");
  EXPECT_EQ(Printed(RoundSignificant(-2.5e-20)), "-2.5e-20");
  EXPECT_EQ(RoundSignificant(0.0), 0.0);
  EXPECT_TRUE(std::isinf(RoundSignificant(INFINITY)));
}

TEST(Levels, RoundToStepKeepsTwelveDigitsOfTheStep) {
  EXPECT_EQ(StepResolution(0.05), 1e-13);
  EXPECT_EQ(StepResolution(2.0), 1e-11);
  EXPECT_EQ(Printed(RoundToStep(0.49999999999999994, 0.05)), "0.5");
  EXPECT_EQ(Printed(RoundToStep(0.15000000000000002, 0.05)), "0.15");
  // 0.3 - 3 x 0.1 is -5.55e-17 in doubles: on a track of 0.1 steps it is 0,
  // and never -0 (which would print as "-0").
  EXPECT_EQ(Printed(RoundToStep(0.3 - 3 * 0.1, 0.1)), "0");
  EXPECT_EQ(Printed(RoundToStep(1234.5678, 100.0)), "1234.5678");
}

// Runs a 1-up/1-down staircase for `trials` random responses (every response
// moves it) and checks each level against truth(k), k the net number of
// steps up from the start; returns the printed texts seen per k.
template <typename Truth>
std::map<int, std::set<std::string>> WalkStaircase(StaircaseOptions o,
                                                   int trials, Truth truth) {
  o.n_down = 1;
  o.n_up = 1;
  o.max_trials = trials;
  Result<Staircase> created = Staircase::Create(o);
  EXPECT_TRUE(created.ok()) << created.error().message;
  Staircase staircase = std::move(created).value();
  boost::random::mt19937 rng(11);
  boost::random::uniform_int_distribution<int> coin(0, 1);
  std::map<int, std::set<std::string>> printed;
  int k = 0;
  for (int i = 0; i < trials; ++i) {
    const double level = staircase.level();
    EXPECT_EQ(level, truth(k)) << "trial " << i << ", " << k << " steps";
    printed[k].insert(Printed(level));
    const bool correct = coin(rng) == 1;
    EXPECT_TRUE(staircase.Update(correct).ok());
    k += correct ? -1 : 1;
  }
  return printed;
}

void ExpectOneTextPerLevel(const std::map<int, std::set<std::string>>& seen) {
  for (const auto& [k, texts] : seen) {
    EXPECT_EQ(texts.size(), 1u) << k << " steps printed as "
                                << fmt::format("{}", fmt::join(texts, ", "));
  }
}

TEST(Levels, LinearStaircaseLevelsAreStartPlusKStepsAsDecimals) {
  StaircaseOptions o;
  o.step_scale = StepScale::kLinear;
  o.start_level = 0.5;
  o.step_down = o.step_up = 0.1;
  // Truth: the decimal (5 + k) / 10, written out and read back.
  const auto seen = WalkStaircase(
      o, 4000, [](int k) { return Decimal(fmt::format("{}e-1", 5 + k)); });
  EXPECT_GT(seen.size(), 40u);  // the walk spans many levels
  ExpectOneTextPerLevel(seen);
  for (const auto& [k, texts] : seen) {
    EXPECT_EQ(*texts.begin(), Printed(Decimal(fmt::format("{}e-1", 5 + k))));
  }
}

TEST(Levels, Log10StaircaseLevelsAreStartTimesTenToTheKStepsRounded) {
  StaircaseOptions o;
  o.step_scale = StepScale::kLog10;
  o.start_level = 0.3;
  o.step_down = o.step_up = 0.05;
  const auto seen = WalkStaircase(o, 4000, [](int k) {
    return TwelveDigits(0.3 * std::pow(10.0, k * 5 / 100.0));
  });
  EXPECT_GT(seen.size(), 40u);
  ExpectOneTextPerLevel(seen);
  EXPECT_EQ(*seen.at(0).begin(), "0.3");
  EXPECT_EQ(*seen.at(20).begin(), "3");
}

TEST(Levels, DecibelStaircaseLevelsAreStartTimesTenToTheKStepsOver20Rounded) {
  StaircaseOptions o;
  o.step_scale = StepScale::kDecibel;
  o.start_level = 0.5;
  o.step_down = o.step_up = 2.0;
  const auto seen = WalkStaircase(o, 4000, [](int k) {
    return TwelveDigits(0.5 * std::pow(10.0, k * 2 / 20.0));
  });
  EXPECT_GT(seen.size(), 40u);
  ExpectOneTextPerLevel(seen);
  EXPECT_EQ(*seen.at(-10).begin(), "0.05");
}

// The example's track: log10 steps of 0.2 that shrink to 0.1, a floor on the
// grid. Every level is 10^(t / 10) for a whole t, the same text each time.
TEST(Levels, ShrinkingStepsAndAFloorKeepOneTextPerLevel) {
  StaircaseOptions o;
  o.step_scale = StepScale::kLog10;
  o.start_level = 1.0;
  o.step_down = o.step_up = 0.2;
  o.step_schedule = {{2, 0.1, 0.1}};
  o.floor_level = 0.01;
  o.ceiling_level = 100.0;
  o.n_down = 3;
  o.n_up = 1;
  o.max_trials = 3000;
  Staircase staircase = Staircase::Create(o).value();
  boost::random::mt19937 rng(5);
  boost::random::uniform_int_distribution<int> draw(0, 3);
  std::map<int, std::set<std::string>> seen;
  int tenths = 0;  // the level is 10^(tenths / 10)
  while (!staircase.finished()) {
    const double level = staircase.level();
    ASSERT_EQ(level, TwelveDigits(std::pow(10.0, tenths / 10.0)))
        << "trial " << staircase.trials().size();
    seen[tenths].insert(Printed(level));
    // Correct at first (down to the floor), then mostly correct or at
    // chance in turns (up to the ceiling and about).
    const std::size_t n = staircase.trials().size();
    const bool correct = n < 100 || draw(rng) >= (n / 500 % 2 == 0 ? 2 : 1);
    const StaircaseTrial t = staircase.Update(correct).value();
    const int step = static_cast<int>(std::lround(t.step_size * 10));
    if (t.move == Move::kDown) tenths = std::max(tenths - step, -20);
    if (t.move == Move::kUp) tenths = std::min(tenths + step, 20);
  }
  EXPECT_TRUE(seen.contains(-20));  // it reached the floor
  EXPECT_TRUE(seen.contains(20));   // and the ceiling
  ExpectOneTextPerLevel(seen);
  EXPECT_EQ(*seen.at(-20).begin(), "0.01");
  EXPECT_EQ(*seen.at(-4).begin(), "0.398107170553");
}

// A ceiling off the grid is presented as itself, and the next move goes one
// step down from it.
TEST(Levels, AnOffGridCeilingIsTheAnchorOfTheNextMove) {
  StaircaseOptions o;
  o.step_scale = StepScale::kLog10;
  o.start_level = 1.0;
  o.step_down = o.step_up = 0.2;
  o.n_down = 1;
  o.ceiling_level = 4.0;
  Staircase staircase = Staircase::Create(o).value();
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(staircase.Update(false).ok());
  EXPECT_EQ(staircase.level(), 4.0);
  ASSERT_TRUE(staircase.Update(true).ok());
  EXPECT_EQ(staircase.level(), TwelveDigits(4.0 * std::pow(10.0, -0.2)));
}

TEST(Levels, AdjustmentPathsPrintEachGridLevelOnce) {
  AdjustmentOptions o;
  o.start_level = 2.0;
  o.step = 0.05;
  o.step_scale = StepScale::kLog10;
  o.max_steps = 2000;
  boost::random::mt19937 jitter(1);
  Adjustment adjustment = Adjustment::Create(o, jitter).value();
  boost::random::mt19937 rng(3);
  boost::random::uniform_int_distribution<int> coin(0, 1);
  for (int i = 0; i < 2000; ++i) {
    ASSERT_TRUE(adjustment.Step(coin(rng) == 1 ? 1 : -1).ok());
  }
  std::map<int, std::set<std::string>> seen;
  int k = 0;
  for (std::size_t i = 0; i < adjustment.path().size(); ++i) {
    if (i > 0) {
      k += adjustment.path()[i] > adjustment.path()[i - 1] ? 1 : -1;
    }
    EXPECT_EQ(adjustment.path()[i],
              TwelveDigits(2.0 * std::pow(10.0, k * 5 / 100.0)));
    seen[k].insert(Printed(adjustment.path()[i]));
  }
  ExpectOneTextPerLevel(seen);
}

// The limits example: steps of 0.05 from jittered starts 0.1 and 0.6. Every
// level is a multiple of 0.05 printed as its decimal (0.5, never
// 0.49999999999999994), and so is every transition point.
TEST(Levels, LimitsSeriesLevelsAreDecimalsOfTheStep) {
  LimitsOptions o;
  o.step = 0.05;
  o.ascending_start = 0.1;
  o.descending_start = 0.6;
  o.start_jitter_steps = 2;
  o.floor_level = 0.0;
  o.ceiling_level = 0.8;
  o.n_series = 40;
  boost::random::mt19937 jitter(7);
  MethodOfLimits limits = MethodOfLimits::Create(o, jitter).value();
  boost::random::mt19937 rng(2);
  boost::random::uniform_int_distribution<int> draw(0, 5);
  while (!limits.finished()) ASSERT_TRUE(limits.Update(draw(rng) == 0).ok());
  for (const LimitsTrial& t : limits.trials()) {
    const long hundredths = std::lround(t.level * 100);
    ASSERT_EQ(hundredths % 5, 0) << t.level;
    EXPECT_EQ(Printed(t.level),
              Printed(Decimal(fmt::format("{}e-2", hundredths))));
  }
  for (const LimitsSeries& s : limits.series()) {
    if (!s.transition_level) continue;
    const long thousandths = std::lround(*s.transition_level * 1000);
    EXPECT_EQ(Printed(*s.transition_level),
              Printed(Decimal(fmt::format("{}e-3", thousandths))));
  }
}

}  // namespace
}  // namespace burrlab::protocols
