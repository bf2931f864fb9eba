// A number for the JSON reports: null when it is NaN or infinite, which JSON
// cannot spell.
#ifndef BURRLAB_RUNNER_CLI_JSON_NUMBER_H_
#define BURRLAB_RUNNER_CLI_JSON_NUMBER_H_

#include <cmath>
#include <nlohmann/json.hpp>

namespace burrlab::runner {

inline nlohmann::ordered_json JsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::ordered_json(value)
                              : nlohmann::ordered_json(nullptr);
}

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_JSON_NUMBER_H_
