// Method of constant stimuli: counts per level, full and blocked orders,
// balanced 2AFC intervals, seeded plans, exact validation text.
#include "burrlab/protocols/constant_stimuli.h"

#include <gtest/gtest.h>

#include <boost/random/mersenne_twister.hpp>
#include <limits>
#include <set>
#include <vector>

namespace burrlab::protocols {
namespace {

ConstantStimuliOptions FiveLevels(int repetitions, TrialOrder order,
                                  ResponseMode response) {
  ConstantStimuliOptions o;
  o.levels = {0.8, 0.9, 1.0, 1.1, 1.2};
  o.repetitions = repetitions;
  o.order = order;
  o.response = response;
  return o;
}

std::vector<ConstantStimuliTrial> Plan(const ConstantStimuliOptions& o,
                                       unsigned seed) {
  boost::random::mt19937 rng(seed);
  Result<std::vector<ConstantStimuliTrial>> plan = PlanConstantStimuli(o, rng);
  EXPECT_TRUE(plan.ok()) << plan.error().message;
  return plan.ok() ? *plan : std::vector<ConstantStimuliTrial>{};
}

std::vector<int> LevelOrder(const std::vector<ConstantStimuliTrial>& plan) {
  std::vector<int> out;
  for (const ConstantStimuliTrial& t : plan) out.push_back(t.level_index);
  return out;
}

TEST(ConstantStimuli, EveryLevelAppearsRepetitionsTimes) {
  for (TrialOrder order : {TrialOrder::kFull, TrialOrder::kBlocked}) {
    const ConstantStimuliOptions o = FiveLevels(8, order, ResponseMode::kYesNo);
    for (unsigned seed = 1; seed <= 50; ++seed) {
      const std::vector<ConstantStimuliTrial> plan = Plan(o, seed);
      ASSERT_EQ(plan.size(), 40u);
      std::vector<int> counts(5, 0);
      for (std::size_t i = 0; i < plan.size(); ++i) {
        const ConstantStimuliTrial& t = plan[i];
        EXPECT_EQ(t.index, static_cast<int>(i));
        EXPECT_EQ(t.level, o.levels[t.level_index]);
        EXPECT_EQ(t.repetition, counts[t.level_index]);   // counts up per level
        EXPECT_FALSE(t.comparison_interval.has_value());  // yes/no
        ++counts[t.level_index];
      }
      EXPECT_EQ(counts, (std::vector<int>{8, 8, 8, 8, 8}));
    }
  }
}

TEST(ConstantStimuli, BlockedOrderHoldsEveryLevelOncePerBlock) {
  const ConstantStimuliOptions o =
      FiveLevels(6, TrialOrder::kBlocked, ResponseMode::kYesNo);
  std::set<std::vector<int>> first_blocks;
  for (unsigned seed = 1; seed <= 50; ++seed) {
    const std::vector<ConstantStimuliTrial> plan = Plan(o, seed);
    for (int block = 0; block < 6; ++block) {
      std::set<int> levels;
      for (int j = 0; j < 5; ++j) {
        const ConstantStimuliTrial& t = plan[block * 5 + j];
        EXPECT_EQ(t.repetition, block);
        levels.insert(t.level_index);
      }
      EXPECT_EQ(levels.size(), 5u) << "seed " << seed << " block " << block;
    }
    std::vector<int> order = LevelOrder(plan);
    first_blocks.insert(std::vector<int>(order.begin(), order.begin() + 5));
  }
  EXPECT_GT(first_blocks.size(), 20u);  // shuffled per block, 120 orders
}

TEST(ConstantStimuli, FullOrderIsOnePermutationOfAllTrials) {
  // Unlike blocked order, a full permutation lets a level repeat before
  // every other level has been shown.
  const ConstantStimuliOptions o =
      FiveLevels(6, TrialOrder::kFull, ResponseMode::kYesNo);
  int plans_with_a_repeat_in_the_first_five = 0;
  for (unsigned seed = 1; seed <= 50; ++seed) {
    std::vector<int> order = LevelOrder(Plan(o, seed));
    std::set<int> first(order.begin(), order.begin() + 5);
    if (first.size() < 5) ++plans_with_a_repeat_in_the_first_five;
  }
  // P(five distinct first levels) is about 0.1 for 6 reps of 5 levels.
  EXPECT_GT(plans_with_a_repeat_in_the_first_five, 30);
}

TEST(ConstantStimuli, SameSeedSamePlanAndOtherSeedsDiffer) {
  const ConstantStimuliOptions o =
      FiveLevels(4, TrialOrder::kFull, ResponseMode::kTwoInterval);
  const auto a = Plan(o, 9);
  const auto b = Plan(o, 9);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].level_index, b[i].level_index);
    EXPECT_EQ(a[i].comparison_interval, b[i].comparison_interval);
  }
  EXPECT_NE(LevelOrder(Plan(o, 9)), LevelOrder(Plan(o, 10)));
}

TEST(ConstantStimuli, TwoAfcBalancesTheComparisonIntervalPerLevel) {
  for (TrialOrder order : {TrialOrder::kFull, TrialOrder::kBlocked}) {
    const ConstantStimuliOptions o =
        FiveLevels(10, order, ResponseMode::kTwoInterval);
    std::set<std::vector<int>> patterns;
    for (unsigned seed = 1; seed <= 50; ++seed) {
      std::vector<int> first(5, 0);
      std::vector<int> second(5, 0);
      std::vector<int> pattern;
      for (const ConstantStimuliTrial& t : Plan(o, seed)) {
        ASSERT_TRUE(t.comparison_interval.has_value());
        const int interval = *t.comparison_interval;
        ASSERT_TRUE(interval == 1 || interval == 2);
        ++(interval == 1 ? first : second)[t.level_index];
        pattern.push_back(interval);
      }
      EXPECT_EQ(first, (std::vector<int>{5, 5, 5, 5, 5}));
      EXPECT_EQ(second, (std::vector<int>{5, 5, 5, 5, 5}));
      patterns.insert(pattern);
    }
    EXPECT_EQ(patterns.size(), 50u);  // the positions are random too
  }
}

TEST(ConstantStimuli, TwoAfcWithOddRepetitionsIsOffByAtMostOne) {
  const ConstantStimuliOptions o =
      FiveLevels(5, TrialOrder::kFull, ResponseMode::kTwoInterval);
  for (unsigned seed = 1; seed <= 50; ++seed) {
    std::vector<int> first(5, 0);
    for (const ConstantStimuliTrial& t : Plan(o, seed)) {
      if (*t.comparison_interval == 1) ++first[t.level_index];
    }
    for (int count : first) EXPECT_TRUE(count == 2 || count == 3);
  }
}

TEST(ConstantStimuli, ValidateNamesTheFieldTheValueAndTheRule) {
  ConstantStimuliOptions o;
  EXPECT_EQ(o.Validate().error().message,
            "constant_stimuli: levels must hold at least 1 level, got 0");
  o.levels = {1.0, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_EQ(o.Validate().error().message,
            "constant_stimuli: levels[1] must be a finite number, got nan");
  o.levels = {1.0, 2.0};
  o.repetitions = 0;
  EXPECT_EQ(o.Validate().error().message,
            "constant_stimuli: repetitions must be at least 1, got 0");
  o.repetitions = 60000;
  EXPECT_EQ(o.Validate().error().message,
            "constant_stimuli: 2 levels x 60000 repetitions = 120000 trials, "
            "at most 100000 allowed");
  boost::random::mt19937 rng(1);
  EXPECT_EQ(PlanConstantStimuli(o, rng).error().message,
            o.Validate().error().message);
  o.repetitions = 1;
  EXPECT_TRUE(o.Validate().ok());
}

}  // namespace
}  // namespace burrlab::protocols
