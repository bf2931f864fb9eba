// What station files and station scripts read alike: the document (nesting
// limit, syntax, unknown top-level keys, the format line), where a node or key
// starts, unknown keys of a table and bounded integers, each problem as a
// diagnostic (file:line:col, printed as `burrlab validate` prints them).
#ifndef BURRLAB_RUNNER_STATION_STATION_TOML_H_
#define BURRLAB_RUNNER_STATION_STATION_TOML_H_

#include <toml++/toml.h>

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/protocols/protocol.h"

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
    std::string_view format, const std::set<std::string_view>& known,
    std::vector<protocols::Diagnostic>* d);

// A diagnostic for every key of `table` outside `known`; `where` names the
// table ("[device]").
void OnlyKeys(const toml::table& table, std::string_view where,
              const std::set<std::string_view>& known,
              std::vector<protocols::Diagnostic>* d);

// The integer at `key` of `t` in [lo, hi]; nullopt when absent, or with a
// diagnostic naming `name` when it is not such an integer.
std::optional<std::int64_t> Integer(const toml::table& t, std::string_view key,
                                    std::string_view name, std::int64_t lo,
                                    std::int64_t hi,
                                    std::vector<protocols::Diagnostic>* d);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_TOML_H_
