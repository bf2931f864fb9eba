// Mean +- SEM, Student's one-sample t-test and the exact binomial test with
// Boost.Math's distributions.
#include "burrlab/analysis/group_stats.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/math/distributions/beta.hpp>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <exception>
#include <limits>
#include <string>

namespace burrlab::analysis {
namespace {

Status CheckConfLevel(double conf_level) {
  if (!(conf_level > 0.0 && conf_level < 1.0)) {
    return Error{
        fmt::format("conf_level must be in (0, 1), got {}", conf_level)};
  }
  return {};
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

}  // namespace burrlab::analysis
