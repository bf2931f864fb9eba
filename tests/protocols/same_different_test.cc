// Balanced same-different sequences (dissertation §13.5.1): exact counts per
// pair for many seeds, seed-dependent order, replay, exact error text.
#include "burrlab/protocols/same_different.h"

#include <gtest/gtest.h>

#include <boost/random/mersenne_twister.hpp>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace burrlab::protocols {
namespace {

std::vector<SameDifferentTrial> Plan(int n_trials, unsigned seed) {
  boost::random::mt19937 rng(seed);
  Result<std::vector<SameDifferentTrial>> plan =
      PlanSameDifferent({.n_trials = n_trials}, rng);
  EXPECT_TRUE(plan.ok()) << plan.error().message;
  return plan.ok() ? *plan : std::vector<SameDifferentTrial>{};
}

std::string Sequence(const std::vector<SameDifferentTrial>& plan) {
  std::string out;
  for (const SameDifferentTrial& t : plan) {
    out += PairName(t.pair);
    out += ' ';
  }
  return out;
}

TEST(SameDifferent, TwelveTrialsHoldExactlyThreeOfEachPairForEverySeed) {
  for (unsigned seed = 1; seed <= 500; ++seed) {
    std::map<Pair, int> counts;
    for (const SameDifferentTrial& t : Plan(12, seed)) ++counts[t.pair];
    EXPECT_EQ(counts[Pair::kAA], 3) << "seed " << seed;
    EXPECT_EQ(counts[Pair::kAB], 3) << "seed " << seed;
    EXPECT_EQ(counts[Pair::kBA], 3) << "seed " << seed;
    EXPECT_EQ(counts[Pair::kBB], 3) << "seed " << seed;
  }
}

TEST(SameDifferent, LongerBlocksHoldAQuarterOfEachPair) {
  std::map<Pair, int> counts;
  for (const SameDifferentTrial& t : Plan(40, 3)) ++counts[t.pair];
  for (Pair pair : {Pair::kAA, Pair::kAB, Pair::kBA, Pair::kBB}) {
    EXPECT_EQ(counts[pair], 10);
  }
}

TEST(SameDifferent, IntervalsAndCorrectAnswerFollowThePair) {
  for (const SameDifferentTrial& t : Plan(12, 7)) {
    const std::string name(PairName(t.pair));
    EXPECT_EQ(std::string(MaterialLabelName(t.intervals[0])) +
                  std::string(MaterialLabelName(t.intervals[1])),
              name);
    EXPECT_EQ(SameDifferentAnswerName(t.correct_answer),
              name[0] == name[1] ? "same" : "different");
  }
}

TEST(SameDifferent, OrderDependsOnTheSeedAndReplaysExactly) {
  EXPECT_EQ(Sequence(Plan(12, 42)), Sequence(Plan(12, 42)));
  std::set<std::string> orders;
  for (unsigned seed = 1; seed <= 200; ++seed) {
    orders.insert(Sequence(Plan(12, seed)));
  }
  // 12! / (3!)^4 = 369600 orders: 200 seeds almost surely all differ.
  EXPECT_GE(orders.size(), 199u);
}

TEST(SameDifferent, IndicesCountFromZero) {
  const std::vector<SameDifferentTrial> plan = Plan(12, 1);
  for (std::size_t i = 0; i < plan.size(); ++i) {
    EXPECT_EQ(plan[i].index, static_cast<int>(i));
  }
}

TEST(SameDifferent, CountThatCannotBeBalancedIsAnError) {
  EXPECT_EQ(SameDifferentOptions{.n_trials = 14}.Validate().error().message,
            "same_different: 14 trials cannot be balanced over AA, AB, BA, BB "
            "(need a multiple of 4)");
  boost::random::mt19937 rng(1);
  EXPECT_EQ(PlanSameDifferent({.n_trials = 14}, rng).error().message,
            "same_different: 14 trials cannot be balanced over AA, AB, BA, BB "
            "(need a multiple of 4)");
  EXPECT_EQ(SameDifferentOptions{.n_trials = 0}.Validate().error().message,
            "same_different: n_trials must be positive, got 0");
  EXPECT_EQ(SameDifferentOptions{.n_trials = 100004}.Validate().error().message,
            "same_different: n_trials must be at most 100000, got 100004");
  EXPECT_TRUE(SameDifferentOptions{}.Validate().ok());
}

}  // namespace
}  // namespace burrlab::protocols
