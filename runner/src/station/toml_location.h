// Where a toml++ node or key starts, as a SourceLocation for the diagnostics
// of station files and station scripts.
#ifndef BURRLAB_RUNNER_STATION_TOML_LOCATION_H_
#define BURRLAB_RUNNER_STATION_TOML_LOCATION_H_

#include <toml++/toml.h>

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

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_TOML_LOCATION_H_
