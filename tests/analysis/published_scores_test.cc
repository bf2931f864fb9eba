// PublishedScoresProbability against truths computed without it: every
// outcome of a small study enumerated and rounded one by one (brute force),
// and simulated studies of the dissertation's size (Monte Carlo).
#include "burrlab/analysis/published_scores.h"

#include <gtest/gtest.h>

#include <boost/random/discrete_distribution.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace burrlab::analysis {
namespace {

// Mean and SEM (sample SD, divisor n - 1) of `scores`.
std::pair<double, double> MeanAndSemOf(const std::vector<int>& scores) {
  double sum = 0.0;
  for (int k : scores) sum += k;
  const double n = static_cast<double>(scores.size());
  const double mean = sum / n;
  double ss = 0.0;
  for (int k : scores) ss += (k - mean) * (k - mean);
  return {mean, std::sqrt(ss / (n - 1.0)) / std::sqrt(n)};
}

// Kind of truth: brute force. Every outcome of 3 subjects with scores 0..4 is
// enumerated, its mean and SEM rounded to one decimal the ordinary way, and
// the probabilities of each reported pair summed; with n = 3 no mean or SEM
// falls on a rounding boundary (means are thirds; 200 (3Q - S^2) = 9 (2j +
// 1)^2 has no solution), so the rounding is unambiguous.
TEST(PublishedScores, EqualsEveryOutcomeEnumeratedAndRounded) {
  const std::vector<double> p = {0.05, 0.15, 0.2, 0.35, 0.25};
  std::map<std::pair<int, int>, double> reported;  // tenths -> probability
  for (int a = 0; a < 5; ++a) {
    for (int b = 0; b < 5; ++b) {
      for (int c = 0; c < 5; ++c) {
        const auto [mean, sem] = MeanAndSemOf({a, b, c});
        reported[{static_cast<int>(std::lround(mean * 10.0)),
                  static_cast<int>(std::lround(sem * 10.0))}] +=
            p[a] * p[b] * p[c];
      }
    }
  }
  ASSERT_GT(reported.size(), 20u);
  double total = 0.0;
  for (const auto& [tenths, probability] : reported) {
    const PublishedScores published{tenths.first / 10.0, tenths.second / 10.0,
                                    3, 1};
    Result<double> dp = PublishedScoresProbability(p, published);
    ASSERT_TRUE(dp.ok()) << dp.error().message;
    EXPECT_NEAR(*dp, probability, 1e-14)
        << published.mean << " +- " << published.sem;
    total += *dp;
  }
  EXPECT_NEAR(total, 1.0, 1e-12);  // the reported pairs partition the outcomes
  // A pair no outcome reports.
  EXPECT_EQ(*PublishedScoresProbability(p, {2.0, 3.0, 3, 1}), 0.0);
}

// Kind of truth: brute force, an even number of subjects (the computation
// splits the subjects in halves; 3 and 4 split unequally and equally). Every
// outcome of 4 subjects with scores 0..3, rounded to two decimals (means are
// quarters, exact; no SEM lands on a boundary of the rounding, checked by
// the partition summing to 1).
TEST(PublishedScores, EqualsEveryOutcomeOfAnEvenGroup) {
  const std::vector<double> p = {0.1, 0.2, 0.3, 0.4};
  std::map<std::pair<int, int>, double> reported;  // hundredths
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) {
      for (int c = 0; c < 4; ++c) {
        for (int d = 0; d < 4; ++d) {
          const auto [mean, sem] = MeanAndSemOf({a, b, c, d});
          reported[{static_cast<int>(std::lround(mean * 100.0)),
                    static_cast<int>(std::lround(sem * 100.0))}] +=
              p[a] * p[b] * p[c] * p[d];
        }
      }
    }
  }
  double total = 0.0;
  for (const auto& [hundredths, probability] : reported) {
    const PublishedScores published{hundredths.first / 100.0,
                                    hundredths.second / 100.0, 4, 2};
    Result<double> dp = PublishedScoresProbability(p, published);
    ASSERT_TRUE(dp.ok()) << dp.error().message;
    EXPECT_NEAR(*dp, probability, 1e-14)
        << published.mean << " +- " << published.sem;
    total += *dp;
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
}

// Kind of truth: Monte Carlo. 20 subjects scoring out of 12 as a fitted
// population might, 200 000 simulated studies, the fraction reporting the
// dissertation's "9.3 +- 0.4".
TEST(PublishedScores, MatchesSimulatedStudiesOfTheDissertationsSize) {
  std::vector<double> p(13, 0.0);
  const double weights[] = {0.01, 0.01, 0.01, 0.02, 0.02, 0.03, 0.05,
                            0.05, 0.08, 0.12, 0.17, 0.2,  0.23};
  double sum = 0.0;
  for (double w : weights) sum += w;
  for (int k = 0; k < 13; ++k)
    p[static_cast<std::size_t>(k)] = weights[k] / sum;
  const PublishedScores published{9.3, 0.4, 20, 1};
  Result<double> exact = PublishedScoresProbability(p, published);
  ASSERT_TRUE(exact.ok()) << exact.error().message;
  boost::random::mt19937 rng(17);
  boost::random::discrete_distribution<int> score(p.begin(), p.end());
  const int studies = 200000;
  int hits = 0;
  std::vector<int> scores(20);
  for (int i = 0; i < studies; ++i) {
    for (int& k : scores) k = score(rng);
    const auto [mean, sem] = MeanAndSemOf(scores);
    // Sums are integers: a mean of 9.25 or 9.35 is on the boundary (both
    // ends count), so compare the sum itself.
    double total = 0.0;
    for (int k : scores) total += k;
    const bool mean_ok = total >= 185.0 && total <= 187.0;
    const bool sem_ok = sem >= 0.35 - 1e-12 && sem <= 0.45 + 1e-12;
    hits += mean_ok && sem_ok ? 1 : 0;
  }
  const double fraction = static_cast<double>(hits) / studies;
  const double se = std::sqrt(*exact * (1.0 - *exact) / studies);
  RecordProperty("exact", std::to_string(*exact));
  RecordProperty("simulated", std::to_string(fraction));
  EXPECT_GT(*exact, 0.001);  // 0.0041: a test with teeth (0.0042 simulated)
  EXPECT_NEAR(fraction, *exact, 4.0 * se);
}

TEST(PublishedScores, CertainScoresAndBadArguments) {
  std::vector<double> perfect(13, 0.0);
  perfect[12] = 1.0;
  EXPECT_EQ(*PublishedScoresProbability(perfect, {12.0, 0.0, 20, 1}), 1.0);
  EXPECT_EQ(*PublishedScoresProbability(perfect, {11.9, 0.0, 20, 1}), 0.0);
  EXPECT_EQ(
      PublishedScoresProbability(perfect, {12.0, 0.0, 1, 1}).error().message,
      "published scores: n must be in [2, 1000] subjects, got 1");
  EXPECT_EQ(PublishedScoresProbability(std::vector<double>{0.5, 0.4},
                                       {1.0, 0.1, 20, 1})
                .error()
                .message,
            "published scores: the score probabilities must sum to 1, got "
            "0.9");
  EXPECT_EQ(PublishedScoresProbability(std::vector<double>{1.5, -0.5},
                                       {1.0, 0.1, 20, 1})
                .error()
                .message,
            "published scores: a score probability must be in [0, 1], got "
            "1.5");
}

}  // namespace
}  // namespace burrlab::analysis
