// Mean +- SEM, Student's one-sample t-test, the exact binomial test, Welch's
// t-test and the Mann-Whitney U test with Boost.Math's distributions.
#include "burrlab/analysis/group_stats.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/math/distributions/beta.hpp>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

namespace burrlab::analysis {
namespace {

Status CheckConfLevel(double conf_level) {
  if (!(conf_level > 0.0 && conf_level < 1.0)) {
    return Error{
        fmt::format("conf_level must be in (0, 1), got {}", conf_level)};
  }
  return {};
}

// Every value of `group` finite; an error names the group and the value.
Status CheckGroupFinite(std::span<const double> group, const char* name) {
  for (std::size_t i = 0; i < group.size(); ++i) {
    if (!std::isfinite(group[i])) {
      return Error{fmt::format("{} value {} is not a finite number: {}", name,
                               i + 1, group[i])};
    }
  }
  return {};
}

// Counts of the Mann-Whitney statistic W = U of x under the null hypothesis
// (every assignment of the ranks 1..n_x + n_y to x equally likely): how many
// n_x-subsets of the ranks have each rank sum, by adding one rank at a time.
// count[w] for w = 0 .. n_x n_y. The counts reach C(98, 49) ~ 2.5e28, exact
// to double rounding.
std::vector<double> RankSumCounts(int n_x, int n_y) {
  const int n = n_x + n_y;
  const int max_sum = n_x * (2 * n - n_x + 1) / 2;
  // ways[j][s]: subsets of j of the ranks so far with rank sum s.
  std::vector<std::vector<double>> ways(
      static_cast<std::size_t>(n_x) + 1,
      std::vector<double>(static_cast<std::size_t>(max_sum) + 1, 0.0));
  ways[0][0] = 1.0;
  for (int rank = 1; rank <= n; ++rank) {
    for (int j = std::min(rank, n_x); j >= 1; --j) {
      std::vector<double>& to = ways[static_cast<std::size_t>(j)];
      const std::vector<double>& from = ways[static_cast<std::size_t>(j - 1)];
      for (int sum = max_sum; sum >= rank; --sum) {
        to[static_cast<std::size_t>(sum)] +=
            from[static_cast<std::size_t>(sum - rank)];
      }
    }
  }
  const int lowest = n_x * (n_x + 1) / 2;
  const std::vector<double>& all = ways[static_cast<std::size_t>(n_x)];
  return std::vector<double>(all.begin() + lowest, all.end());
}

}  // namespace

static Result<MeanSem> MeanAndSemUnchecked(std::span<const double> values) {
  if (values.size() < 2) {
    return Error{fmt::format("a mean +- SEM needs at least 2 values, got {}",
                             values.size())};
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      return Error{
          fmt::format("value {} is not a finite number: {}", i + 1, values[i])};
    }
    sum += values[i];
  }
  MeanSem out;
  out.n = static_cast<int>(values.size());
  out.mean = sum / out.n;
  double squares = 0.0;
  for (double v : values) squares += (v - out.mean) * (v - out.mean);
  out.sd = std::sqrt(squares / (out.n - 1));
  out.sem = out.sd / std::sqrt(static_cast<double>(out.n));
  return out;
}

static Result<TTestResult> OneSampleTTestUnchecked(
    std::span<const double> values, double mu, double conf_level) {
  if (Status s = CheckConfLevel(conf_level); !s.ok()) return s.error();
  if (!std::isfinite(mu)) {
    return Error{fmt::format("mu must be a finite number, got {}", mu)};
  }
  Result<MeanSem> m = MeanAndSem(values);
  if (!m.ok()) return m.error();
  if (!(m->sem > 10.0 * std::numeric_limits<double>::epsilon() *
                     std::max(std::abs(m->mean), std::abs(mu)))) {
    return Error{fmt::format(
        "all {} values are equal ({}): the t statistic is undefined", m->n,
        m->mean)};
  }
  TTestResult out;
  out.n = m->n;
  out.mean = m->mean;
  out.mu = mu;
  out.sem = m->sem;
  out.df = out.n - 1;
  out.t = (out.mean - mu) / out.sem;
  out.conf_level = conf_level;
  const boost::math::students_t_distribution<double> t(out.df);
  out.p_less = boost::math::cdf(t, out.t);
  out.p_greater = boost::math::cdf(boost::math::complement(t, out.t));
  out.p_two_sided =
      2.0 * boost::math::cdf(boost::math::complement(t, std::abs(out.t)));
  const double q =
      boost::math::quantile(boost::math::complement(t, (1.0 - conf_level) / 2));
  out.ci_low = out.mean - q * out.sem;
  out.ci_high = out.mean + q * out.sem;
  return out;
}

static Result<BinomialTestResult> ExactBinomialTestUnchecked(
    int successes, int trials, double p, double conf_level) {
  if (Status s = CheckConfLevel(conf_level); !s.ok()) return s.error();
  if (trials < 1) {
    return Error{fmt::format("trials must be at least 1, got {}", trials)};
  }
  if (successes < 0 || successes > trials) {
    return Error{fmt::format("successes must be in [0, trials = {}], got {}",
                             trials, successes)};
  }
  if (!(p >= 0.0 && p <= 1.0)) {
    return Error{fmt::format("p must be in [0, 1], got {}", p)};
  }
  BinomialTestResult out;
  out.successes = successes;
  out.trials = trials;
  out.p = p;
  out.conf_level = conf_level;
  out.estimate = static_cast<double>(successes) / trials;
  const boost::math::binomial_distribution<double> binomial(trials, p);
  const auto pdf = [&](int k) { return boost::math::pdf(binomial, k); };
  const auto cdf = [&](int k) {  // P(X <= k)
    return k < 0 ? 0.0 : boost::math::cdf(binomial, k);
  };
  const auto upper = [&](int k) {  // P(X > k)
    if (k < 0) return 1.0;
    return k >= trials ? 0.0
                       : boost::math::cdf(boost::math::complement(binomial, k));
  };
  out.p_less = cdf(successes);
  out.p_greater = upper(successes - 1);
  // Two-sided: every outcome no more likely than the observed one.
  const double observed = pdf(successes) * (1.0 + 1e-7);
  const double expected = trials * p;
  if (static_cast<double>(successes) == expected) {
    out.p_two_sided = 1.0;
  } else if (successes < expected) {
    int as_unlikely = 0;
    for (int k = static_cast<int>(std::ceil(expected)); k <= trials; ++k) {
      as_unlikely += pdf(k) <= observed;
    }
    out.p_two_sided = cdf(successes) + upper(trials - as_unlikely);
  } else {
    int as_unlikely = 0;
    for (int k = 0; k <= static_cast<int>(std::floor(expected)); ++k) {
      as_unlikely += pdf(k) <= observed;
    }
    out.p_two_sided = cdf(as_unlikely - 1) + upper(successes - 1);
  }
  out.p_two_sided = std::min(1.0, out.p_two_sided);
  const double alpha = 1.0 - conf_level;
  out.ci_low = successes == 0 ? 0.0
                              : boost::math::quantile(
                                    boost::math::beta_distribution<double>(
                                        successes, trials - successes + 1),
                                    alpha / 2);
  out.ci_high =
      successes == trials
          ? 1.0
          : boost::math::quantile(boost::math::beta_distribution<double>(
                                      successes + 1, trials - successes),
                                  1.0 - alpha / 2);
  return out;
}

static Result<WelchTTestResult> WelchTTestUnchecked(std::span<const double> x,
                                                    std::span<const double> y) {
  if (x.size() < 2 || y.size() < 2) {
    return Error{fmt::format(
        "Welch's t-test needs at least 2 values in each group, got {} and {}",
        x.size(), y.size())};
  }
  if (Status s = CheckGroupFinite(x, "x"); !s.ok()) return s.error();
  if (Status s = CheckGroupFinite(y, "y"); !s.ok()) return s.error();
  Result<MeanSem> mx = MeanAndSem(x), my = MeanAndSem(y);
  if (!mx.ok()) return mx.error();
  if (!my.ok()) return my.error();
  const double vx = mx->sem * mx->sem, vy = my->sem * my->sem;  // var / n
  const double se = std::sqrt(vx + vy);
  if (!(se > 10.0 * std::numeric_limits<double>::epsilon() *
                 std::max(std::abs(mx->mean), std::abs(my->mean)))) {
    return Error{fmt::format(
        "both groups are constant ({} and {}): the t statistic is undefined",
        mx->mean, my->mean)};
  }
  WelchTTestResult out;
  out.n_x = mx->n;
  out.n_y = my->n;
  out.mean_x = mx->mean;
  out.mean_y = my->mean;
  out.t = (mx->mean - my->mean) / se;
  out.df = (vx + vy) * (vx + vy) /
           (vx * vx / (out.n_x - 1) + vy * vy / (out.n_y - 1));
  const boost::math::students_t_distribution<double> t(out.df);
  out.p_two_sided = std::min(
      1.0, 2.0 * boost::math::cdf(boost::math::complement(t, std::abs(out.t))));
  return out;
}

static Result<MannWhitneyResult> MannWhitneyTestUnchecked(
    std::span<const double> x, std::span<const double> y) {
  if (x.empty() || y.empty()) {
    return Error{fmt::format(
        "the Mann-Whitney test needs at least 1 value in each group, got {} "
        "and {}",
        x.size(), y.size())};
  }
  if (Status s = CheckGroupFinite(x, "x"); !s.ok()) return s.error();
  if (Status s = CheckGroupFinite(y, "y"); !s.ok()) return s.error();
  MannWhitneyResult out;
  out.n_x = static_cast<int>(x.size());
  out.n_y = static_cast<int>(y.size());
  const int n = out.n_x + out.n_y;
  std::vector<double> values(x.begin(), x.end());
  values.insert(values.end(), y.begin(), y.end());
  std::vector<std::size_t> order(values.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(
      order.begin(), order.end(),
      [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  // Mean ranks of tied runs; sum of t^3 - t over the runs for the variance.
  std::vector<double> rank(values.size());
  double tie_sum = 0.0;
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && values[order[j + 1]] == values[order[i]]) {
      ++j;
    }
    const double mean_rank = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) rank[order[k]] = mean_rank;
    const double t = static_cast<double>(j - i + 1);
    tie_sum += t * t * t - t;
    out.ties = out.ties || j > i;
    i = j + 1;
  }
  double rank_sum_x = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) rank_sum_x += rank[i];
  out.w = rank_sum_x - 0.5 * out.n_x * (out.n_x + 1.0);
  const double centre = 0.5 * out.n_x * out.n_y;
  out.exact = out.n_x < 50 && out.n_y < 50 && !out.ties;
  if (out.exact) {
    out.method = "exact";
    const std::vector<double> counts = RankSumCounts(out.n_x, out.n_y);
    const double total = std::accumulate(counts.begin(), counts.end(), 0.0);
    const auto w = static_cast<std::size_t>(std::llround(out.w));
    // The tail on W's side of the centre, doubled (as R).
    double tail = 0.0;
    if (out.w > centre) {
      for (std::size_t k = w; k < counts.size(); ++k) tail += counts[k];
    } else {
      for (std::size_t k = 0; k <= w; ++k) tail += counts[k];
    }
    out.p_two_sided = std::min(1.0, 2.0 * tail / total);
    return out;
  }
  out.method = fmt::format(
      "normal approximation with continuity correction ({})",
      out.ties ? "ties: no exact p" : "50 or more values in a group");
  const double variance =
      out.n_x * out.n_y / 12.0 *
      ((n + 1.0) - tie_sum / (static_cast<double>(n) * (n - 1.0)));
  if (!(variance > 0.0)) {
    return Error{fmt::format(
        "all {} values are equal ({}): the rank-sum test is undefined", n,
        values[0])};
  }
  const double d = out.w - centre;
  const double correction = d > 0.0 ? 0.5 : d < 0.0 ? -0.5 : 0.0;
  const double z = (d - correction) / std::sqrt(variance);
  const boost::math::normal_distribution<double> normal;
  out.p_two_sided = std::min(
      1.0,
      2.0 * boost::math::cdf(boost::math::complement(normal, std::abs(z))));
  return out;
}

double Mean(std::span<const double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

Result<MeanSem> MeanAndSem(std::span<const double> values) {
  // Boost.Math reports domain errors by throwing; none may leave the library.
  try {
    return MeanAndSemUnchecked(values);
  } catch (const std::exception& e) {
    return Error{std::string("MeanAndSem: ") + e.what()};
  }
}

Result<TTestResult> OneSampleTTest(std::span<const double> values, double mu,
                                   double conf_level) {
  // Boost.Math reports domain errors by throwing; none may leave the library.
  try {
    return OneSampleTTestUnchecked(values, mu, conf_level);
  } catch (const std::exception& e) {
    return Error{std::string("OneSampleTTest: ") + e.what()};
  }
}

Result<BinomialTestResult> ExactBinomialTest(int successes, int trials,
                                             double p, double conf_level) {
  // Boost.Math reports domain errors by throwing; none may leave the library.
  try {
    return ExactBinomialTestUnchecked(successes, trials, p, conf_level);
  } catch (const std::exception& e) {
    return Error{std::string("ExactBinomialTest: ") + e.what()};
  }
}

Result<WelchTTestResult> WelchTTest(std::span<const double> x,
                                    std::span<const double> y) {
  // Boost.Math reports domain errors by throwing; none may leave the library.
  try {
    return WelchTTestUnchecked(x, y);
  } catch (const std::exception& e) {
    return Error{std::string("WelchTTest: ") + e.what()};
  }
}

Result<MannWhitneyResult> MannWhitneyTest(std::span<const double> x,
                                          std::span<const double> y) {
  // Boost.Math reports domain errors by throwing; none may leave the library.
  try {
    return MannWhitneyTestUnchecked(x, y);
  } catch (const std::exception& e) {
    return Error{std::string("MannWhitneyTest: ") + e.what()};
  }
}

}  // namespace burrlab::analysis
