// Reading untrusted TOML (material, protocol and station files): a lexical
// limit on nesting checked before toml++ sees the text (toml++ builds and
// destroys nested tables recursively, so 100,000 dotted keys overflow the
// stack), the position of a byte offset as toml++ counts it, toml++'s parse
// errors reworded as one line, and the document read with all three
// (ParseTomlDocument), which every file kind's parser starts with.
#ifndef BURRLAB_STIMULI_TOML_GUARD_H_
#define BURRLAB_STIMULI_TOML_GUARD_H_

#include <toml++/toml.h>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

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

// Why a TOML document could not be read: where (none for a failure of no
// place, e.g. out of memory) and a one-line message.
struct TomlFailure {
  std::optional<toml::source_position> where;
  std::string message;
};

// The root table of `text` (named `path` in toml++'s records), or the first
// failure: a '.' beyond `max_dots` outside strings and comments (at that dot,
// with `too_deep_message`), a syntax error (where toml++ found it, with
// SyntaxMessage), anything else toml++ throws ("cannot parse: ...").
std::variant<toml::table, TomlFailure> ParseTomlDocument(
    std::string_view path, std::string_view text, std::size_t max_dots,
    std::string_view too_deep_message);

}  // namespace burrlab::stimuli

#endif  // BURRLAB_STIMULI_TOML_GUARD_H_
