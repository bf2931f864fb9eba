// Edit distance and "did you mean" suggestions.
#include "burrlab/base/spelling.h"

#include <algorithm>
#include <vector>

namespace burrlab {

// Edits (insert, delete, replace, swap two adjacent characters) turning `a`
// into `b`: optimal string alignment distance.
std::size_t EditDistance(std::string_view a, std::string_view b) {
  const std::size_t n = b.size();
  std::vector<std::size_t> before(n + 1), previous(n + 1), current(n + 1);
  for (std::size_t j = 0; j <= n; ++j) previous[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    current[0] = i;
    for (std::size_t j = 1; j <= n; ++j) {
      const std::size_t replace = a[i - 1] == b[j - 1] ? 0 : 1;
      current[j] = std::min(
          {previous[j] + 1, current[j - 1] + 1, previous[j - 1] + replace});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        current[j] = std::min(current[j], before[j - 2] + 1);
      }
    }
    std::swap(before, previous);
    std::swap(previous, current);
  }
  return previous[n];
}

// The candidate closest to `typed` within two edits (and fewer edits than
// `typed` has characters), else the only candidate starting with `typed`
// (two characters or more); empty when nothing is close.
std::string_view DidYouMean(std::string_view typed,
                            std::span<const std::string_view> candidates) {
  constexpr std::size_t kMaxEdits = 2;
  // Long hostile keys would make the quadratic distance slow for nothing.
  constexpr std::size_t kMaxTypedLength = 64;
  if (typed.size() > kMaxTypedLength) return {};
  std::string_view best;
  std::size_t best_distance = kMaxEdits + 1;
  for (std::string_view candidate : candidates) {
    const std::size_t distance = EditDistance(typed, candidate);
    if (distance < best_distance && distance < typed.size()) {
      best = candidate;
      best_distance = distance;
    }
  }
  if (!best.empty() || typed.size() < 2) return best;
  std::string_view prefixed;
  for (std::string_view candidate : candidates) {
    if (!candidate.starts_with(typed)) continue;
    if (!prefixed.empty()) return {};  // ambiguous
    prefixed = candidate;
  }
  return prefixed;
}

}  // namespace burrlab
