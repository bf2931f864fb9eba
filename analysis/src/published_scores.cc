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
  // The sums of squares a reported (S, Q) can have: [Q_lo(S_lo), Q_hi(S_hi)].
  const auto q_low = [&](long s) {
    const double sd = static_cast<double>(s);
    return std::max(
        0L, static_cast<long>(std::ceil(
                sd * sd / nd + nd * (nd - 1.0) * sem_lo * sem_lo - kSlack)));
  };
  const auto q_high = [&](long s) {
    const double sd = static_cast<double>(s);
    return std::min(
        q_max, static_cast<long>(std::floor(
                   sd * sd / nd + nd * (nd - 1.0) * sem_hi * sem_hi + kSlack)));
  };
  // Meet in the middle: the joint distribution of (sum, sum of squares) of
  // m subjects' scores by a dynamic programme up to m2 = ceil(n / 2), kept
  // at m1 = floor(n / 2) too; the n subjects report (S, Q) when the first m1
  // give (s1, q1) and the other m2 give (S - s1, Q - q1), so the probability
  // is a sum over the first half's states of their probability times the
  // second half's mass in the window. Rows of the table are sums s, columns
  // sums of squares q; a state (s, q) of m subjects has s^2 / m <= q <= s
  // k_max (Cauchy-Schwarz; k^2 <= k k_max), so each row is visited only
  // there.
  const int m1 = n / 2, m2 = n - m1;
  const long s_size = static_cast<long>(m2) * k_max + 1;
  const long q_size = static_cast<long>(m2) * k_max * k_max + 1;
  const auto at = [&](std::vector<double>& table, long s, long q) -> double& {
    return table[static_cast<std::size_t>(s * q_size + q)];
  };
  const auto q_first = [](long s, int m) {
    return m == 0
               ? 0L
               : std::max(
                     0L, static_cast<long>(std::floor(static_cast<double>(s) *
                                                      static_cast<double>(s) /
                                                      static_cast<double>(m))) -
                             1);
  };
  // The tables (up to several MB each) are kept between calls on a thread,
  // so that a fit's thousands of calls neither allocate nor clear them: only
  // the entries a state of m subjects may occupy (rows s <= m k_max, columns
  // q_first(s, m) to s k_max) are ever read, and those are cleared before
  // they are filled.
  thread_local std::vector<double> dp, next, half;  // half: the table at m1
  const std::size_t table_size = static_cast<std::size_t>(s_size * q_size);
  for (std::vector<double>* table : {&dp, &next, &half}) {
    if (table->size() < table_size) table->resize(table_size);
  }
  // Clears the entries of states of m subjects in `table` (copies them from
  // `from` when given).
  const auto clear_band = [&](std::vector<double>& table, int m,
                              const std::vector<double>* from) {
    for (long s = 0; s <= static_cast<long>(m) * k_max; ++s) {
      const std::size_t first = static_cast<std::size_t>(s * q_size +
                                                         q_first(s, m)),
                        last = static_cast<std::size_t>(s * q_size + s * k_max +
                                                        1);
      if (from == nullptr) {
        std::fill(table.begin() + static_cast<std::ptrdiff_t>(first),
                  table.begin() + static_cast<std::ptrdiff_t>(last), 0.0);
      } else {
        std::copy(from->begin() + static_cast<std::ptrdiff_t>(first),
                  from->begin() + static_cast<std::ptrdiff_t>(last),
                  table.begin() + static_cast<std::ptrdiff_t>(first));
      }
    }
  };
  dp[0] = 1.0;  // no subjects: sum 0, sum of squares 0
  if (m1 == 0) clear_band(half, 0, &dp);
  for (int m = 0; m < m2; ++m) {
    const long s_reach = static_cast<long>(m) * k_max;
    clear_band(next, m + 1, nullptr);
    for (long s = 0; s <= s_reach; ++s) {
      const long q_last = s * k_max;
      for (long q = q_first(s, m); q <= q_last; ++q) {
        const double mass = at(dp, s, q);
        if (mass == 0.0) continue;
        for (int k = 0; k <= k_max; ++k) {
          const double pk = score_probabilities[static_cast<std::size_t>(k)];
          if (pk == 0.0) continue;
          at(next, s + k, q + static_cast<long>(k) * k) += mass * pk;
        }
      }
    }
    dp.swap(next);
    if (m + 1 == m1) clear_band(half, m1, &dp);
  }
  // dp: the table at m2; half: at m1.
  double probability = 0.0;
  const long s1_reach = static_cast<long>(m1) * k_max;
  for (long s1 = 0; s1 <= std::min(s1_reach, s_hi); ++s1) {
    for (long q1 = q_first(s1, m1); q1 <= s1 * k_max; ++q1) {
      const double mass = at(half, s1, q1);
      if (mass == 0.0) continue;
      double second = 0.0;
      for (long sum = std::max(s_lo, s1); sum <= s_hi; ++sum) {
        const long s2 = sum - s1;
        if (s2 >= s_size) break;
        const long q2_lo = std::max(q_low(sum) - q1, q_first(s2, m2));
        const long q2_hi = std::min(q_high(sum) - q1, s2 * k_max);
        for (long q2 = q2_lo; q2 <= q2_hi; ++q2) second += at(dp, s2, q2);
      }
      probability += mass * second;
    }
  }
  return std::min(1.0, probability);
}

}  // namespace burrlab::analysis
