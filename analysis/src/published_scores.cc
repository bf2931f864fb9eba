// The probability of a published mean +- SEM (see published_scores.h).
#include "burrlab/analysis/published_scores.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace burrlab::analysis {

Result<double> PublishedScoresProbability(
    std::span<const double> score_probabilities,
    const PublishedScores& published) {
  const int n = published.n;
  if (n < 2 || n > 1000) {
    return Error{fmt::format(
        "published scores: n must be in [2, 1000] subjects, got {}", n)};
  }
  if (published.decimals < 0 || published.decimals > 6) {
    return Error{
        fmt::format("published scores: decimals must be in [0, 6], got {}",
                    published.decimals)};
  }
  if (!(std::isfinite(published.mean) && std::isfinite(published.sem) &&
        published.sem >= 0.0)) {
    return Error{fmt::format(
        "published scores: the mean must be finite and the SEM finite and "
        ">= 0, got {} +- {}",
        published.mean, published.sem)};
  }
  const std::size_t values = score_probabilities.size();
  if (values == 0 || values > 1000) {
    return Error{fmt::format(
        "published scores: 1 to 1000 possible scores, got {}", values)};
  }
  double total = 0.0;
  for (double p : score_probabilities) {
    if (!(p >= 0.0 && p <= 1.0)) {
      return Error{fmt::format(
          "published scores: a score probability must be in [0, 1], got {}",
          p)};
    }
    total += p;
  }
  if (std::abs(total - 1.0) > 1e-9) {
    return Error{fmt::format(
        "published scores: the score probabilities must sum to 1, got {}",
        total)};
  }
  const int k_max = static_cast<int>(values) - 1;
  const double h = 0.5 * std::pow(10.0, -published.decimals);
  // Tolerance of the boundaries (the sums are integers, the bounds are not).
  constexpr double kSlack = 1e-9;
  const double nd = static_cast<double>(n);
  // Sums S whose mean S / n rounds to the published mean.
  const long s_lo = std::max(
      0L, static_cast<long>(std::ceil(nd * (published.mean - h) - kSlack)));
  const long s_hi = std::min(
      static_cast<long>(n) * k_max,
      static_cast<long>(std::floor(nd * (published.mean + h) + kSlack)));
  if (s_lo > s_hi) return 0.0;
  // Sample variance (Q - S^2 / n) / (n - 1) = n sem^2, so for a sum S the
  // sums of squares Q in [S^2 / n + n (n - 1) lo^2, ... hi^2].
  const double sem_lo = std::max(0.0, published.sem - h);
  const double sem_hi = published.sem + h;
  const long q_max = static_cast<long>(n) * k_max * k_max;
  // dp[s][q]: probability of the scores so far summing to s with squares
  // summing to q; only s <= m k_max and q <= m k_max^2 after m subjects.
  const std::size_t q_size = static_cast<std::size_t>(q_max) + 1;
  std::vector<double> dp((static_cast<std::size_t>(n) * k_max + 1) * q_size,
                         0.0);
  std::vector<double> next(dp.size(), 0.0);
  dp[0] = 1.0;
  for (int m = 0; m < n; ++m) {
    std::fill(next.begin(), next.end(), 0.0);
    const long s_reach = static_cast<long>(m) * k_max;
    const long q_reach = static_cast<long>(m) * k_max * k_max;
    for (long s = 0; s <= s_reach; ++s) {
      const double* row = &dp[static_cast<std::size_t>(s) * q_size];
      for (long q = 0; q <= q_reach; ++q) {
        const double mass = row[q];
        if (mass == 0.0) continue;
        for (int k = 0; k <= k_max; ++k) {
          const double pk = score_probabilities[static_cast<std::size_t>(k)];
          if (pk == 0.0) continue;
          next[static_cast<std::size_t>(s + k) * q_size +
               static_cast<std::size_t>(q + static_cast<long>(k) * k)] +=
              mass * pk;
        }
      }
    }
    dp.swap(next);
  }
  double probability = 0.0;
  for (long s = s_lo; s <= s_hi; ++s) {
    const double sd = static_cast<double>(s);
    const double base = sd * sd / nd;
    const long q_lo = std::max(
        0L, static_cast<long>(
                std::ceil(base + nd * (nd - 1.0) * sem_lo * sem_lo - kSlack)));
    const long q_hi = std::min(
        q_max, static_cast<long>(std::floor(
                   base + nd * (nd - 1.0) * sem_hi * sem_hi + kSlack)));
    for (long q = q_lo; q <= q_hi; ++q) {
      probability += dp[static_cast<std::size_t>(s) * q_size +
                        static_cast<std::size_t>(q)];
    }
  }
  return std::min(1.0, probability);
}

}  // namespace burrlab::analysis
