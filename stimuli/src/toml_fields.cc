// The typed TOML field readers every file kind shares.
#include "burrlab/stimuli/toml_fields.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "burrlab/base/printable.h"
#include "burrlab/base/spelling.h"

namespace burrlab::stimuli {

std::string_view TomlTypeName(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "a date or time";
  }
}

std::string EchoText(std::string_view text) {
  constexpr std::size_t kMaxEcho = 60;
  if (text.size() <= kMaxEcho) return PrintableText(text);
  std::size_t cut = kMaxEcho;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xc0) == 0x80) {
    --cut;
  }
  return PrintableText(text.substr(0, cut)) + "...";
}

std::string JoinKeys(TomlKeys keys) {
  std::string out;
  for (std::string_view k : keys) {
    if (!out.empty()) out += ", ";
    out += k;
  }
  return out;
}

void TomlFields::CheckKeys(const toml::table& table, std::string_view name,
                           TomlKeys allowed, TomlKeys elsewhere,
                           std::string_view elsewhere_message,
                           std::span<const TomlRename> renamed) const {
  // Suggestions come from the keys and their old spellings, an old one
  // suggested as its new spelling.
  std::vector<std::string_view> candidates(allowed.begin(), allowed.end());
  for (const TomlRename& rename : renamed) {
    candidates.push_back(rename.old_key);
  }
  for (const auto& [key, node] : table) {
    const std::string_view k = key.str();
    if (std::find(candidates.begin(), candidates.end(), k) !=
        candidates.end()) {
      continue;
    }
    // At the key: the header of a [table], else the key itself.
    const toml::table* sub = node.as_table();
    const toml::source_position at =
        (sub != nullptr && !sub->is_inline()) || key.source().begin.line == 0
            ? PositionOf(node)
            : key.source().begin;
    if (std::find(elsewhere.begin(), elsewhere.end(), k) != elsewhere.end()) {
      Fail(at, fmt::format("key \"{}\" {}", k, elsewhere_message));
      continue;
    }
    std::string_view hint = DidYouMean(k, candidates);
    for (const TomlRename& rename : renamed) {
      if (hint == rename.old_key) hint = rename.key;
    }
    if (!hint.empty()) {
      Fail(at, fmt::format("unknown key \"{}\" in {} (did you mean \"{}\"?)",
                           EchoText(k), name, hint));
    } else {
      Fail(at, fmt::format("unknown key \"{}\" in {}; accepted: {}",
                           EchoText(k), name, JoinKeys(allowed)));
    }
  }
}

const toml::table* TomlFields::Table(const toml::table& parent,
                                     std::string_view key,
                                     std::string_view name) const {
  const toml::node* node = parent.get(key);
  if (node == nullptr) return nullptr;
  if (!node->is_table()) {
    Fail(*node,
         fmt::format("{} must be a table, got {}", name, TomlTypeName(*node)));
    return nullptr;
  }
  return node->as_table();
}

std::optional<std::string> TomlFields::String(const toml::table& t,
                                              std::string_view key,
                                              std::string_view name) const {
  const toml::node* node = t.get(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_string()) {
    Fail(*node,
         fmt::format("{} must be a string, got {}", name, TomlTypeName(*node)));
    return std::nullopt;
  }
  return std::string(node->as_string()->get());
}

std::optional<double> TomlFields::Number(const toml::table& t,
                                         std::string_view key,
                                         std::string_view name) const {
  const toml::node* node = t.get(key);
  if (node == nullptr) return std::nullopt;
  if (node->is_integer()) {
    return static_cast<double>(node->as_integer()->get());
  }
  if (!node->is_floating_point()) {
    Fail(*node,
         fmt::format("{} must be a number, got {}", name, TomlTypeName(*node)));
    return std::nullopt;
  }
  const double v = node->as_floating_point()->get();
  if (!std::isfinite(v)) {
    Fail(*node, fmt::format("{} must be a finite number, got {}", name, v));
    return std::nullopt;
  }
  return v;
}

std::optional<std::int64_t> TomlFields::Integer(const toml::table& t,
                                                std::string_view key,
                                                std::string_view name) const {
  const toml::node* node = t.get(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_integer()) {
    Fail(*node, fmt::format("{} must be an integer, got {}", name,
                            TomlTypeName(*node)));
    return std::nullopt;
  }
  return node->as_integer()->get();
}

std::optional<bool> TomlFields::Boolean(const toml::table& t,
                                        std::string_view key,
                                        std::string_view name) const {
  const toml::node* node = t.get(key);
  if (node == nullptr) return std::nullopt;
  if (!node->is_boolean()) {
    Fail(*node, fmt::format("{} must be true or false, got {}", name,
                            TomlTypeName(*node)));
    return std::nullopt;
  }
  return node->as_boolean()->get();
}

std::optional<int> TomlFields::Choice(const toml::table& t,
                                      std::string_view key,
                                      std::string_view name,
                                      TomlKeys choices) const {
  std::optional<std::string> value = String(t, key, name);
  if (!value.has_value()) return std::nullopt;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    if (choices[i] == *value) return static_cast<int>(i);
  }
  const std::string_view hint = DidYouMean(*value, choices);
  Fail(*t.get(key),
       fmt::format(
           "{} must be one of {}, got \"{}\"{}", name, JoinKeys(choices),
           EchoText(*value),
           hint.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", hint)));
  return std::nullopt;
}

bool TomlFields::Range(const toml::table& t, std::string_view key,
                       std::string_view name, double value, double lo,
                       double hi, bool lo_open, bool hi_open) const {
  const bool ok = (lo_open ? value > lo : value >= lo) &&
                  (hi_open ? value < hi : value <= hi);
  if (ok) return true;
  const std::string lo_text = std::isinf(lo) ? "-inf" : fmt::format("{}", lo);
  const std::string hi_text = std::isinf(hi) ? "inf" : fmt::format("{}", hi);
  Fail(*t.get(key), fmt::format("{} must be in {}{}, {}{}, got {}", name,
                                lo_open ? "(" : "[", lo_text, hi_text,
                                hi_open ? ")" : "]", value));
  return false;
}

std::optional<std::int64_t> TomlFields::IntegerIn(const toml::table& t,
                                                  std::string_view key,
                                                  std::string_view name,
                                                  std::int64_t lo,
                                                  std::int64_t hi) const {
  const std::optional<std::int64_t> v = Integer(t, key, name);
  if (!v.has_value()) return std::nullopt;
  if (*v < lo || *v > hi) {
    Fail(*t.get(key),
         fmt::format("{} must be in [{}, {}], got {}", name, lo, hi, *v));
    return std::nullopt;
  }
  return v;
}

std::optional<double> TomlFields::PositiveNumberUpTo(const toml::table& t,
                                                     std::string_view key,
                                                     std::string_view name,
                                                     double hi) const {
  const std::optional<double> v = Number(t, key, name);
  if (!v.has_value()) return std::nullopt;
  if (!Range(t, key, name, *v, 0.0, hi, true, false)) return std::nullopt;
  return v;
}

}  // namespace burrlab::stimuli
