// Group statistics of dissertation §13.5: mean score +- SEM over subjects, a
// one-sample t-test against chance, and an exact binomial test of pooled
// correct answers, numerically as R's t.test and binom.test report them.
#ifndef BURRLAB_ANALYSIS_GROUP_STATS_H_
#define BURRLAB_ANALYSIS_GROUP_STATS_H_

#include <span>

#include "burrlab/base/result.h"

namespace burrlab::analysis {

struct MeanSem {
  int n = 0;
  double mean = 0.0;
  double sd = 0.0;   // sample standard deviation (n - 1)
  double sem = 0.0;  // sd / sqrt(n)
};
// At least 2 finite values.
Result<MeanSem> MeanAndSem(std::span<const double> values);

// One-sample Student t-test of mean(values) = mu (R: t.test(values, mu = mu,
// conf.level = conf_level), its three alternatives).
struct TTestResult {
  int n = 0;
  double mean = 0.0;
  double mu = 0.0;
  double sem = 0.0;
  double t = 0.0;            // (mean - mu) / sem
  double df = 0.0;           // n - 1
  double p_two_sided = 0.0;  // alternative "two.sided"
  double p_greater = 0.0;    // alternative "greater": mean > mu
  double p_less = 0.0;       // alternative "less"
  double conf_level = 0.95;
  double ci_low = 0.0;  // two-sided interval for the mean
  double ci_high = 0.0;
};
// At least 2 finite values, not all equal; conf_level in (0, 1).
Result<TTestResult> OneSampleTTest(std::span<const double> values, double mu,
                                   double conf_level = 0.95);

// Exact binomial test of `successes` in `trials` against probability p
// (R: binom.test(successes, trials, p, conf.level = conf_level)). The
// two-sided p-value sums the probabilities of every outcome no more likely
// than the observed one (relative tolerance 1e-7, as R); the interval is
// Clopper-Pearson.
struct BinomialTestResult {
  int successes = 0;
  int trials = 0;
  double p = 0.5;
  double estimate = 0.0;  // successes / trials
  double p_two_sided = 0.0;
  double p_greater = 0.0;  // P(X >= successes)
  double p_less = 0.0;     // P(X <= successes)
  double conf_level = 0.95;
  double ci_low = 0.0;
  double ci_high = 0.0;
};
// trials >= 1, 0 <= successes <= trials, p in [0, 1], conf_level in (0, 1).
Result<BinomialTestResult> ExactBinomialTest(int successes, int trials,
                                             double p,
                                             double conf_level = 0.95);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_GROUP_STATS_H_
