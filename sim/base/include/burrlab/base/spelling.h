// "Did you mean ...?" for mistyped names (commands, flags, keys, materials),
// after Ninja's spellcheck. A generic utility kept at the root of the
// dependency graph so every library's error messages can use it.
#ifndef BURRLAB_BASE_SPELLING_H_
#define BURRLAB_BASE_SPELLING_H_

#include <cstddef>
#include <span>
#include <string_view>

namespace burrlab {

// Edits (insert, delete, replace, swap two adjacent characters) turning `a`
// into `b`: the optimal string alignment distance.
std::size_t EditDistance(std::string_view a, std::string_view b);

// The candidate closest to `typed` within two edits (and fewer edits than
// `typed` has characters), else the only candidate starting with `typed` (two
// characters or more); empty when nothing is close or `typed` is longer than 64
// characters.
std::string_view DidYouMean(std::string_view typed,
                            std::span<const std::string_view> candidates);

}  // namespace burrlab

#endif  // BURRLAB_BASE_SPELLING_H_
