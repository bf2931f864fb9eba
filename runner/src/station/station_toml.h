// What station files and station scripts read alike: the document (nesting
// limit, syntax, unknown top-level keys, the format line), where a node or key
// starts, and the field readers every burrlab file kind shares, each problem
// as a diagnostic (file:line:col, printed as `burrlab validate` prints them).
#ifndef BURRLAB_RUNNER_STATION_STATION_TOML_H_
#define BURRLAB_RUNNER_STATION_STATION_TOML_H_

#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/protocols/protocol.h"
#include "burrlab/stimuli/toml_fields.h"

namespace burrlab::runner {

inline protocols::SourceLocation At(const toml::node& node) {
  return {static_cast<int>(node.source().begin.line),
          static_cast<int>(node.source().begin.column)};
}

inline protocols::SourceLocation AtKey(const toml::key& key) {
  return {static_cast<int>(key.source().begin.line),
          static_cast<int>(key.source().begin.column)};
}

// The root table of a station file or script `what` names ("station file"),
// with "unknown key" diagnostics for top-level keys outside `known` and one
// for a format line missing or other than `format`; nullopt with a diagnostic
// when the text is not TOML or nests too deep (64 dots).
std::optional<toml::table> ReadStationToml(
    std::string_view path, std::string_view text, std::string_view what,
    std::string_view format, stimuli::TomlKeys known,
    std::vector<protocols::Diagnostic>* d);

// The shared TOML field readers (burrlab/stimuli/toml_fields.h) reporting
// into `d`, which must outlive them.
stimuli::TomlFields StationFields(std::vector<protocols::Diagnostic>* d);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_TOML_H_
