// The TOML reading station files and station scripts share.
#include "station/station_toml.h"

#include <fmt/format.h>

#include <variant>

#include "burrlab/base/printable.h"
#include "burrlab/stimuli/toml_guard.h"

namespace burrlab::runner {

std::optional<toml::table> ReadStationToml(
    std::string_view path, std::string_view text, std::string_view what,
    std::string_view format, const std::set<std::string_view>& known,
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
  OnlyKeys(root, fmt::format("the {}", what), known, d);
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

void OnlyKeys(const toml::table& table, std::string_view where,
              const std::set<std::string_view>& known,
              std::vector<protocols::Diagnostic>* d) {
  for (const auto& [key, node] : table) {
    if (known.contains(key.str())) continue;
    std::string list;
    for (std::string_view k : known) {
      list += (list.empty() ? "" : ", ") + std::string(k);
    }
    d->push_back(
        {AtKey(key), fmt::format("unknown key '{}' in {} (known: {})",
                                 PrintableText(key.str()), where, list)});
  }
}

std::optional<std::int64_t> Integer(const toml::table& t, std::string_view key,
                                    std::string_view name, std::int64_t lo,
                                    std::int64_t hi,
                                    std::vector<protocols::Diagnostic>* d) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return std::nullopt;
  const auto v = n->value<std::int64_t>();
  if (!v.has_value() || !n->is_integer() || *v < lo || *v > hi) {
    d->push_back({At(*n), fmt::format("{} must be an integer from {} to {}",
                                      name, lo, hi)});
    return std::nullopt;
  }
  return v;
}

}  // namespace burrlab::runner
