// Reading untrusted TOML (material and protocol files): a lexical limit on
// nesting checked before toml++ sees the text (toml++ builds and destroys
// nested tables recursively, so 100,000 dotted keys overflow the stack), the
// position of a byte offset as toml++ counts it, and toml++'s parse errors
// reworded as one line.
#ifndef BURRLAB_STIMULI_TOML_GUARD_H_
#define BURRLAB_STIMULI_TOML_GUARD_H_

#include <toml++/toml.h>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace burrlab::stimuli {

// Line and column (in code points, like toml++) of byte `offset` of `text`.
toml::source_position PositionOf(std::string_view text, std::size_t offset);

// The byte offset of the first '.' outside strings and comments beyond
// max_dots, if any. A lexical scan only: malformed TOML is left to toml++.
std::optional<std::size_t> ExcessDotOffset(std::string_view text,
                                           std::size_t max_dots);

// toml++'s parse error as "invalid TOML ...", its quoted text made
// printable (burrlab/base/printable.h).
std::string SyntaxMessage(std::string_view description);

}  // namespace burrlab::stimuli

#endif  // BURRLAB_STIMULI_TOML_GUARD_H_
