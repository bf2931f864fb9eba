// Method of limits: alternating series, stop at the first change of
// response, transition midpoints and their mean against hand computation,
// bounds without a transition, seeded start jitter, exact validation text.
#include "burrlab/protocols/limits.h"

#include <gtest/gtest.h>

#include <boost/random/mersenne_twister.hpp>
#include <functional>
#include <limits>
#include <set>
#include <vector>

namespace burrlab::protocols {
namespace {

LimitsOptions FourSeriesZeroToTen() {
  LimitsOptions o;
  o.first_direction = SeriesDirection::kAscending;
  o.n_series = 4;
  o.step = 1.0;
  o.ascending_start = 0.0;
  o.descending_start = 10.0;
  o.floor_level = 0.0;
  o.ceiling_level = 10.0;
  return o;
}

// Runs to the end answering respond(series, level); every update must work.
MethodOfLimits RunAll(const LimitsOptions& options, unsigned seed,
                      const std::function<bool(int, double)>& respond) {
  boost::random::mt19937 rng(seed);
  Result<MethodOfLimits> created = MethodOfLimits::Create(options, rng);
  EXPECT_TRUE(created.ok()) << created.error().message;
  MethodOfLimits limits = std::move(created).value();
  for (int guard = 0; !limits.finished() && guard < 10000; ++guard) {
    const bool response = respond(limits.series_index(), limits.level());
    EXPECT_TRUE(limits.Update(response).ok());
  }
  return limits;
}

std::vector<double> LevelsOfSeries(const MethodOfLimits& limits, int series) {
  std::vector<double> out;
  for (const LimitsTrial& t : limits.trials()) {
    if (t.series == series) out.push_back(t.level);
  }
  return out;
}

TEST(MethodOfLimits, ThresholdIsTheMeanOfHandComputedTransitionPoints) {
  // The subject says "yes" from 5 up in series 0, from 3 in series 1 (it
  // keeps saying yes while descending), from 6 in series 2, from 4 in 3.
  const std::vector<double> yes_from = {5, 3, 6, 4};
  MethodOfLimits limits = RunAll(
      FourSeriesZeroToTen(), 1,
      [&](int series, double level) { return level >= yes_from[series]; });
  ASSERT_TRUE(limits.finished());
  // Series 0 ascends 0..5 and stops at the first yes: transition (4+5)/2.
  EXPECT_EQ(LevelsOfSeries(limits, 0), (std::vector<double>{0, 1, 2, 3, 4, 5}));
  // Series 1 descends 10..2 and stops at the first no: (3+2)/2.
  EXPECT_EQ(LevelsOfSeries(limits, 1),
            (std::vector<double>{10, 9, 8, 7, 6, 5, 4, 3, 2}));
  EXPECT_EQ(LevelsOfSeries(limits, 2),
            (std::vector<double>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(LevelsOfSeries(limits, 3),
            (std::vector<double>{10, 9, 8, 7, 6, 5, 4, 3}));
  std::vector<double> transitions;
  for (const LimitsSeries& s : limits.series()) {
    ASSERT_TRUE(s.transition_level.has_value());
    transitions.push_back(*s.transition_level);
  }
  EXPECT_EQ(transitions, (std::vector<double>{4.5, 2.5, 5.5, 3.5}));
  EXPECT_EQ(limits.Threshold().value(), (4.5 + 2.5 + 5.5 + 3.5) / 4.0);
  EXPECT_EQ(limits.Threshold(SeriesDirection::kAscending).value(), 5.0);
  EXPECT_EQ(limits.Threshold(SeriesDirection::kDescending).value(), 3.0);
  EXPECT_EQ(limits.trials().size(), 6u + 9u + 7u + 8u);
}

TEST(MethodOfLimits, SeriesAlternateStartingWithTheConfiguredDirection) {
  LimitsOptions o = FourSeriesZeroToTen();
  o.first_direction = SeriesDirection::kDescending;
  o.n_series = 3;
  boost::random::mt19937 rng(1);
  MethodOfLimits limits = MethodOfLimits::Create(o, rng).value();
  ASSERT_EQ(limits.series().size(), 3u);
  EXPECT_EQ(limits.series()[0].direction, SeriesDirection::kDescending);
  EXPECT_EQ(limits.series()[1].direction, SeriesDirection::kAscending);
  EXPECT_EQ(limits.series()[2].direction, SeriesDirection::kDescending);
  EXPECT_EQ(limits.level(), 10.0);
}

TEST(MethodOfLimits, EachSeriesStopsAtTheFirstChangeOfResponse) {
  // A change is relative to the previous response of the same series: an
  // ascending series that starts with "yes" stops at the first "no".
  boost::random::mt19937 rng(1);
  MethodOfLimits limits =
      MethodOfLimits::Create(FourSeriesZeroToTen(), rng).value();
  const LimitsTrial first = limits.Update(true).value();
  EXPECT_FALSE(first.ends_series);
  EXPECT_EQ(limits.level(), 1.0);
  const LimitsTrial second = limits.Update(false).value();
  EXPECT_TRUE(second.ends_series);
  EXPECT_TRUE(second.transition);
  EXPECT_EQ(limits.series()[0].transition_level, 0.5);
  EXPECT_EQ(limits.series_index(), 1);
  EXPECT_EQ(limits.level(), 10.0);  // series 1 starts descending
}

TEST(MethodOfLimits, SeriesThatReachesTheBoundWithoutChangeHasNoTransition) {
  // Series 0 never hears a yes up to the ceiling; series 1 hears yes all the
  // way down to the floor; series 2 and 3 change at 5 and 4.
  MethodOfLimits limits =
      RunAll(FourSeriesZeroToTen(), 1, [](int series, double level) {
        if (series == 0) return false;
        if (series == 1) return true;
        return level >= (series == 2 ? 5.0 : 4.0);
      });
  EXPECT_EQ(LevelsOfSeries(limits, 0).size(), 11u);  // 0..10, bound included
  EXPECT_EQ(LevelsOfSeries(limits, 1).size(), 11u);  // 10..0
  EXPECT_FALSE(limits.series()[0].transition_level.has_value());
  EXPECT_FALSE(limits.series()[1].transition_level.has_value());
  EXPECT_TRUE(limits.trials()[10].ends_series);
  EXPECT_FALSE(limits.trials()[10].transition);
  // Only the series with transitions count: (4.5 + 3.5) / 2.
  EXPECT_EQ(limits.Threshold().value(), 4.0);
}

TEST(MethodOfLimits, LevelsBeyondTheBoundAreNeverPresented) {
  LimitsOptions o = FourSeriesZeroToTen();
  o.ascending_start = 0.5;
  o.n_series = 1;
  MethodOfLimits limits = RunAll(o, 1, [](int, double) { return false; });
  EXPECT_EQ(
      LevelsOfSeries(limits, 0),
      (std::vector<double>{0.5, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5, 9.5}));
  EXPECT_EQ(limits.Threshold().error().message,
            "limits: none of the 1 finished series had a transition (each "
            "reached a bound without a change of response)");
}

TEST(MethodOfLimits, ThresholdBeforeAnySeriesFinishedIsAnError) {
  boost::random::mt19937 rng(1);
  MethodOfLimits limits =
      MethodOfLimits::Create(FourSeriesZeroToTen(), rng).value();
  EXPECT_EQ(limits.Threshold().error().message,
            "limits: no series has finished yet");
  EXPECT_EQ(limits.Threshold(SeriesDirection::kDescending).error().message,
            "limits: no descending series has finished yet");
}

TEST(MethodOfLimits, UpdateAfterTheLastSeriesIsAnError) {
  LimitsOptions o = FourSeriesZeroToTen();
  o.n_series = 1;
  MethodOfLimits limits = RunAll(o, 1, [](int, double l) { return l >= 2; });
  EXPECT_TRUE(limits.finished());
  EXPECT_EQ(limits.Update(true).error().message,
            "limits: already finished after 1 series and 3 trials");
}

TEST(MethodOfLimits, StartJitterIsWholeStepsWithinTheRangeAndSeeded) {
  LimitsOptions o = FourSeriesZeroToTen();
  o.ascending_start = 2.0;
  o.descending_start = 8.0;
  o.start_jitter_steps = 2;
  o.step = 0.5;
  std::set<double> ascending_starts;
  std::set<int> jitters;
  for (unsigned seed = 1; seed <= 200; ++seed) {
    boost::random::mt19937 rng(seed);
    MethodOfLimits limits = MethodOfLimits::Create(o, rng).value();
    for (const LimitsSeries& s : limits.series()) {
      EXPECT_GE(s.jitter_steps, -2);
      EXPECT_LE(s.jitter_steps, 2);
      jitters.insert(s.jitter_steps);
      const double base =
          s.direction == SeriesDirection::kAscending ? 2.0 : 8.0;
      EXPECT_EQ(s.start_level, base + 0.5 * s.jitter_steps);
      if (s.direction == SeriesDirection::kAscending) {
        ascending_starts.insert(s.start_level);
      }
    }
  }
  EXPECT_EQ(jitters, (std::set<int>{-2, -1, 0, 1, 2}));
  EXPECT_EQ(ascending_starts, (std::set<double>{1.0, 1.5, 2.0, 2.5, 3.0}));

  auto starts = [&](unsigned seed) {
    boost::random::mt19937 rng(seed);
    const MethodOfLimits limits = MethodOfLimits::Create(o, rng).value();
    std::vector<double> out;
    for (const LimitsSeries& s : limits.series()) {
      out.push_back(s.start_level);
    }
    return out;
  };
  EXPECT_EQ(starts(5), starts(5));
  int differing = 0;
  for (unsigned seed = 6; seed < 16; ++seed) {
    differing += starts(5) != starts(seed) ? 1 : 0;
  }
  EXPECT_GE(differing, 8);
}

TEST(MethodOfLimits, JitteredSeriesStillStopAtTheMidpointOfTheLastTwoLevels) {
  LimitsOptions o = FourSeriesZeroToTen();
  o.ascending_start = 2.0;
  o.descending_start = 8.0;
  o.start_jitter_steps = 2;
  MethodOfLimits limits = RunAll(o, 42, [](int, double l) { return l >= 5.0; });
  for (const LimitsSeries& s : limits.series()) {
    ASSERT_TRUE(s.transition_level.has_value());
    EXPECT_EQ(*s.transition_level, 4.5);
  }
  EXPECT_EQ(limits.Threshold().value(), 4.5);
}

TEST(MethodOfLimits, DefaultsAreValid) {
  EXPECT_TRUE(LimitsOptions{}.Validate().ok());
}

TEST(MethodOfLimits, ValidateNamesTheFieldTheValueAndTheRule) {
  LimitsOptions o;
  o.step = 0.0;
  EXPECT_EQ(o.Validate().error().message,
            "limits: step must be positive, got 0");
  o = {};
  o.n_series = 0;
  EXPECT_EQ(o.Validate().error().message,
            "limits: n_series must be in [1, 1000], got 0");
  o = {};
  o.ascending_start = 1.0;
  o.start_jitter_steps = 2;
  EXPECT_EQ(o.Validate().error().message,
            "limits: ascending_start 1 jittered by up to 2 steps of 1 reaches "
            "-1, below floor_level 0");
  o = {};
  o.descending_start = 11.0;
  EXPECT_EQ(o.Validate().error().message,
            "limits: descending_start 11 must lie within [floor_level, "
            "ceiling_level] = [0, 10]");
  o = {};
  o.ceiling_level = std::numeric_limits<double>::infinity();
  EXPECT_EQ(o.Validate().error().message,
            "limits: ceiling_level must be a finite number, got inf");
  o = {};
  o.step = 0.0625;
  o.ceiling_level = 10000.0;
  EXPECT_EQ(o.Validate().error().message,
            "limits: (ceiling_level - floor_level) / step = 160000 levels per "
            "series, at most 100000 allowed");
  boost::random::mt19937 rng(1);
  EXPECT_EQ(MethodOfLimits::Create(o, rng).error().message,
            o.Validate().error().message);
}

}  // namespace
}  // namespace burrlab::protocols
