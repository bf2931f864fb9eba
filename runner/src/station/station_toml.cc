// The TOML reading station files and station scripts share.
#include "station/station_toml.h"

#include <fmt/format.h>

#include <variant>

#include "burrlab/stimuli/toml_guard.h"

namespace burrlab::runner {

std::optional<toml::table> ReadStationToml(
    std::string_view path, std::string_view text, std::string_view what,
    std::string_view format, stimuli::TomlKeys known,
    std::vector<protocols::Diagnostic>* d) {
  std::variant<toml::table, stimuli::TomlFailure> document =
      stimuli::ParseTomlDocument(
          path, text, 64,
          fmt::format("too many dotted keys (a {} needs few)", what));
  if (const auto* failure = std::get_if<stimuli::TomlFailure>(&document)) {
    const toml::source_position p =
        failure->where.value_or(toml::source_position{1, 1});
    d->push_back({{static_cast<int>(p.line), static_cast<int>(p.column)},
                  failure->message});
    return std::nullopt;
  }
  toml::table& root = std::get<toml::table>(document);
  StationFields(d).CheckKeys(root, fmt::format("the {}", what), known);
  const toml::node* line = root.get("format");
  if (line == nullptr) {
    d->push_back(
        {{1, 1},
         fmt::format("missing key 'format' (expected \"{}\")", format)});
  } else if (line->value<std::string>() != std::string(format)) {
    d->push_back({At(*line), fmt::format("format must be \"{}\"", format)});
  }
  return std::move(root);
}

stimuli::TomlFields StationFields(std::vector<protocols::Diagnostic>* d) {
  return stimuli::TomlFields([d](toml::source_position p, std::string message) {
    d->push_back({{static_cast<int>(p.line), static_cast<int>(p.column)},
                  std::move(message)});
  });
}

}  // namespace burrlab::runner
