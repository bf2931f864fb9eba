// 2AFC and three-interval reference-design plans: balanced positions,
// materials consistent with the answer, seeded order, exact error text.
#include "burrlab/protocols/two_interval.h"

#include <gtest/gtest.h>

#include <boost/random/mersenne_twister.hpp>
#include <set>
#include <vector>

namespace burrlab::protocols {
namespace {

TEST(TwoInterval, HalfTheTrialsHoldTheComparisonInEachInterval) {
  for (unsigned seed = 1; seed <= 100; ++seed) {
    boost::random::mt19937 rng(seed);
    auto plan = PlanTwoInterval({.n_trials = 12}, rng);
    ASSERT_TRUE(plan.ok());
    ASSERT_EQ(plan->size(), 12u);
    int first = 0;
    for (std::size_t i = 0; i < plan->size(); ++i) {
      const TwoIntervalTrial& t = (*plan)[i];
      EXPECT_EQ(t.index, static_cast<int>(i));
      ASSERT_TRUE(t.comparison_interval == 1 || t.comparison_interval == 2);
      // B, the comparison, sits in the named interval; A in the other.
      EXPECT_EQ(t.intervals[t.comparison_interval - 1], MaterialLabel::kB);
      EXPECT_EQ(t.intervals[2 - t.comparison_interval], MaterialLabel::kA);
      if (t.comparison_interval == 1) ++first;
    }
    EXPECT_EQ(first, 6);
  }
}

TEST(TwoInterval, OrderDependsOnTheSeedAndReplaysExactly) {
  auto positions = [](unsigned seed) {
    boost::random::mt19937 rng(seed);
    const std::vector<TwoIntervalTrial> plan =
        PlanTwoInterval({.n_trials = 20}, rng).value();
    std::vector<int> out;
    for (const TwoIntervalTrial& t : plan) {
      out.push_back(t.comparison_interval);
    }
    return out;
  };
  EXPECT_EQ(positions(4), positions(4));
  std::set<std::vector<int>> orders;
  for (unsigned seed = 1; seed <= 50; ++seed) orders.insert(positions(seed));
  EXPECT_EQ(orders.size(), 50u);
}

TEST(TwoInterval, OddCountCannotBeBalanced) {
  EXPECT_EQ(TwoIntervalOptions{.n_trials = 13}.Validate().error().message,
            "two_interval: 13 trials cannot be balanced over intervals 1 and 2 "
            "(need a multiple of 2)");
  EXPECT_EQ(TwoIntervalOptions{.n_trials = 0}.Validate().error().message,
            "two_interval: n_trials must be positive, got 0");
}

TEST(ReferenceDesign, MatchingMaterialIsInIntervalTwoOrThreeEquallyOften) {
  for (MaterialLabel match : {MaterialLabel::kA, MaterialLabel::kB}) {
    for (unsigned seed = 1; seed <= 100; ++seed) {
      boost::random::mt19937 rng(seed);
      auto plan = PlanReferenceDesign(
          {.n_trials = 10, .matching_material = match}, rng);
      ASSERT_TRUE(plan.ok());
      ASSERT_EQ(plan->size(), 10u);
      int in_second = 0;
      for (const ReferenceTrial& t : *plan) {
        ASSERT_TRUE(t.correct_interval == 2 || t.correct_interval == 3);
        // Intervals 2 and 3 hold A and B once each; the answer names the
        // interval with the material modelled on the reference.
        EXPECT_NE(t.comparisons[0], t.comparisons[1]);
        EXPECT_EQ(t.comparisons[t.correct_interval - 2], match);
        if (t.correct_interval == 2) ++in_second;
      }
      EXPECT_EQ(in_second, 5);
    }
  }
}

TEST(ReferenceDesign, OddCountCannotBeBalanced) {
  EXPECT_EQ(ReferenceDesignOptions{.n_trials = 9}.Validate().error().message,
            "reference_design: 9 trials cannot be balanced over A and B in "
            "intervals 2 and 3 (need a multiple of 2)");
  boost::random::mt19937 rng(1);
  EXPECT_FALSE(PlanReferenceDesign({.n_trials = 9}, rng).ok());
  EXPECT_TRUE(ReferenceDesignOptions{}.Validate().ok());
}

}  // namespace
}  // namespace burrlab::protocols
