// "Did you mean ...?" for mistyped command and flag names (Ninja's
// spellcheck idea).
#ifndef BURRLAB_RUNNER_SPELLING_H_
#define BURRLAB_RUNNER_SPELLING_H_

#include <cstddef>
#include <span>
#include <string_view>

namespace burrlab::runner {

// Edits (insert, delete, replace, swap two adjacent characters) turning `a`
// into `b`: optimal string alignment distance.
std::size_t EditDistance(std::string_view a, std::string_view b);

// The candidate closest to `typed` within two edits (and fewer edits than
// `typed` has characters), else the first candidate that starts with `typed`;
// empty when nothing is close.
std::string_view DidYouMean(std::string_view typed,
                            std::span<const std::string_view> candidates);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_SPELLING_H_
