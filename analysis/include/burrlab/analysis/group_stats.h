// Group statistics of dissertation §13.5: mean score +- SEM over subjects, a
// one-sample t-test against chance, and an exact binomial test of pooled
// correct answers; and two groups compared (experts and trainees, as §12.3
// compares their forces and speeds) by Welch's t-test and the Mann-Whitney U
// test; numerically as R's t.test, binom.test and wilcox.test report them.
#ifndef BURRLAB_ANALYSIS_GROUP_STATS_H_
#define BURRLAB_ANALYSIS_GROUP_STATS_H_

#include <span>
#include <string>

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
// The arithmetic mean; NaN for no values.
double Mean(std::span<const double> values);

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

// Welch's two-sample t-test of mean(x) = mean(y) without assuming equal
// variances (R: t.test(x, y), its default var.equal = FALSE), two-sided.
struct WelchTTestResult {
  int n_x = 0;
  int n_y = 0;
  double mean_x = 0.0;
  double mean_y = 0.0;
  double t = 0.0;   // (mean_x - mean_y) / sqrt(var_x / n_x + var_y / n_y)
  double df = 0.0;  // Welch-Satterthwaite degrees of freedom
  double p_two_sided = 0.0;
};
// At least 2 finite values in each group, not all of both groups constant.
Result<WelchTTestResult> WelchTTest(std::span<const double> x,
                                    std::span<const double> y);

// The Mann-Whitney U test, or Wilcoxon rank-sum test, of x against y
// (R: wilcox.test(x, y) with its defaults), two-sided.
struct MannWhitneyResult {
  int n_x = 0;
  int n_y = 0;
  // R's W: the sum of x's ranks in both groups together (ties get their
  // mean rank) minus n_x (n_x + 1) / 2, i.e. U of x.
  double w = 0.0;
  double p_two_sided = 0.0;
  bool ties = false;  // some value occurs more than once
  // As wilcox.test decides: exact when both groups have fewer than 50 values
  // and there are no ties (p from the exact distribution of W, counted),
  // else the normal approximation with continuity correction and the ties'
  // correction of the variance.
  bool exact = false;
  std::string method;  // "exact" or the approximation, in words
};
// At least 1 finite value in each group; not every value equal.
Result<MannWhitneyResult> MannWhitneyTest(std::span<const double> x,
                                          std::span<const double> y);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_GROUP_STATS_H_
