// Material files: the strict "burrlab-material/1" TOML schema, its one-line
// error messages with source positions, file loading and the built-in sets
// embedded at build time (stimuli/CMakeLists.txt).
#include "burrlab/stimuli/materials.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "burrlab/base/file_text.h"
#include "burrlab/base/printable.h"
#include "burrlab/base/spelling.h"
#include "burrlab/stimuli/toml_guard.h"

namespace burrlab::stimuli {
namespace {

constexpr std::string_view kFormat = "burrlab-material/1";
// Material files are a few kB; anything larger is refused before parsing.
constexpr std::size_t kMaxMaterialBytes = std::size_t{1} << 20;
// Every '.' outside strings and comments can nest a table one level deeper
// (dotted keys), and toml++ builds and destroys tables recursively, about
// 250 bytes of stack a level: 100,000 dots overflow an 8 MiB stack. A material
// file needs about twenty; 256 dots plus toml++'s own limit of 256 nested
// arrays and inline tables keep the depth under ~520 levels (~130 kB).
constexpr std::size_t kMaxDots = 256;

struct EmbeddedMaterial {
  std::string_view name;  // file stem, e.g. "human_temporal_bone"
  std::string_view text;  // the file, byte for byte
};

constexpr EmbeddedMaterial kBuiltinMaterials[] = {
#include "builtin_materials.inc"
};

// One parameter of the schema: its key, unit and the sim::Material field.
struct ParameterSpec {
  std::string_view key;
  std::string_view unit;
  bool strictly_positive;
  double sim::Material::*field;
};

constexpr ParameterSpec kParameters[] = {
    {"c_e", "N/mm^2", true, &sim::Material::c_e_n_per_mm2},
    {"alpha", "1/s", false, &sim::Material::alpha_per_s},
    {"c_mu", "N/mm^2", false, &sim::Material::c_mu_n_per_mm2},
    {"mu", "1", false, &sim::Material::mu},
    {"c_i", "N*s/mm^3", false, &sim::Material::c_i_n_s_per_mm3},
};

constexpr std::string_view kRootKeys[] = {"format", "name", "display_name",
                                          "description", "parameters"};
constexpr std::string_view kParameterKeys[] = {"c_e", "alpha", "c_mu", "mu",
                                               "c_i"};
constexpr std::string_view kEntryKeys[] = {"value", "unit", "source"};

std::string Suggestion(std::string_view typed,
                       std::span<const std::string_view> candidates) {
  const std::string_view suggestion = DidYouMean(typed, candidates);
  if (suggestion.empty()) return {};
  return fmt::format(" (did you mean '{}'?)", suggestion);
}

// `text` with control characters escaped, so that a message stays one line
// whatever a hostile file puts in a key or a string: line breaks and tabs by
// name (\n, \r, \t), everything else as PrintableText escapes it.
std::string OneLine(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  while (!text.empty()) {
    const std::size_t special =
        std::min(text.find_first_of("\n\r\t"), text.size());
    out += PrintableText(text.substr(0, special));
    if (special == text.size()) break;
    out += text[special] == '\n'   ? "\\n"
           : text[special] == '\r' ? "\\r"
                                   : "\\t";
    text.remove_prefix(special + 1);
  }
  return out;
}

// `text` as quoted in a message: at most 64 bytes, cut on a UTF-8 boundary,
// escaped by OneLine.
std::string Echo(std::string_view text) {
  constexpr std::size_t kMaxEcho = 64;
  if (text.size() <= kMaxEcho) return OneLine(text);
  std::size_t cut = kMaxEcho;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xc0) == 0x80) {
    --cut;
  }
  return fmt::format("{}...", OneLine(text.substr(0, cut)));
}

bool IsValid(const toml::source_position& position) {
  return position.line > 0 && position.column > 0;
}

// "path:line:col: error: message" on one line.
Error ErrorAt(std::string_view path, const toml::source_position& position,
              std::string_view message) {
  const toml::source_position where =
      IsValid(position) ? position : toml::source_position{1, 1};
  return Error{OneLine(fmt::format("{}:{}:{}: error: {}", path, where.line,
                                   where.column, message))};
}

// Where a table entry starts: the header of a [table], else its key.
toml::source_position EntryPosition(const toml::key& key,
                                    const toml::node& node,
                                    const toml::source_position& fallback) {
  const toml::table* table = node.as_table();
  if (table != nullptr && !table->is_inline() && IsValid(node.source().begin)) {
    return node.source().begin;
  }
  if (IsValid(key.source().begin)) return key.source().begin;
  if (IsValid(node.source().begin)) return node.source().begin;
  return fallback;
}

toml::source_position TablePosition(const toml::table& table,
                                    const toml::source_position& fallback) {
  return IsValid(table.source().begin) ? table.source().begin : fallback;
}

toml::source_position NodePosition(const toml::node& node,
                                   const toml::source_position& fallback) {
  return IsValid(node.source().begin) ? node.source().begin : fallback;
}

std::string_view TypeName(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::table:
      return "table";
    case toml::node_type::array:
      return "array";
    case toml::node_type::string:
      return "string";
    case toml::node_type::integer:
      return "integer";
    case toml::node_type::floating_point:
      return "float";
    case toml::node_type::boolean:
      return "boolean";
    case toml::node_type::date:
      return "date";
    case toml::node_type::time:
      return "time";
    case toml::node_type::date_time:
      return "date-time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

// `prefix.key`, or `key` at the top level.
std::string Dotted(std::string_view prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : fmt::format("{}.{}", prefix, key);
}

// Validates one parsed file against the schema, reporting the first problem.
class SchemaChecker {
 public:
  explicit SchemaChecker(std::string_view path) : path_(path) {}

  Result<MaterialSet> Check(const toml::table& root) const {
    const toml::source_position root_at = TablePosition(root, {1, 1});

    // The format id first: a file of another format gets that message rather
    // than one about the keys it does not share with this one.
    const toml::node* format = root.get("format");
    if (format == nullptr) {
      return ErrorAt(path_, root_at,
                     fmt::format("missing key 'format' (material files start "
                                 "with format = \"{}\")",
                                 kFormat));
    }
    if (!format->is_string()) {
      return ErrorAt(
          path_, NodePosition(*format, root_at),
          fmt::format("format must be a string, got {}", TypeName(*format)));
    }
    if (const std::string& id = format->as_string()->get(); id != kFormat) {
      return ErrorAt(
          path_, NodePosition(*format, root_at),
          fmt::format("format must be '{}', got '{}'", kFormat, Echo(id)));
    }
    if (auto error = UnknownKey(root, "", kRootKeys, root_at)) return *error;

    MaterialSet set;
    Result<std::string> name = RequiredString(root, "", "name", root_at);
    if (!name.ok()) return name.error();
    const toml::node& name_node = *root.get("name");
    if (!IsIdentifier(*name)) {
      return ErrorAt(path_, NodePosition(name_node, root_at),
                     fmt::format("name must be lowercase letters, digits and "
                                 "underscores ([a-z0-9_]+), got '{}'",
                                 Echo(*name)));
    }
    set.name = std::move(*name);

    Result<std::string> display_name =
        RequiredString(root, "", "display_name", root_at);
    if (!display_name.ok()) return display_name.error();
    set.display_name = std::move(*display_name);

    if (const toml::node* description = root.get("description");
        description != nullptr) {
      if (!description->is_string()) {
        return ErrorAt(path_, NodePosition(*description, root_at),
                       fmt::format("description must be a string, got {}",
                                   TypeName(*description)));
      }
      set.description = description->as_string()->get();
    }

    const toml::node* parameters_node = root.get("parameters");
    if (parameters_node == nullptr) {
      return ErrorAt(path_, root_at, "missing key 'parameters'");
    }
    const toml::table* parameters = parameters_node->as_table();
    if (parameters == nullptr) {
      return ErrorAt(path_, NodePosition(*parameters_node, root_at),
                     fmt::format("parameters must be a table, got {}",
                                 TypeName(*parameters_node)));
    }
    const toml::source_position parameters_at =
        TablePosition(*parameters, root_at);
    if (auto error =
            UnknownKey(*parameters, "parameters", kParameterKeys, root_at)) {
      return *error;
    }
    std::vector<std::string> sources;
    for (const ParameterSpec& spec : kParameters) {
      Result<Parameter> parameter =
          CheckParameter(*parameters, spec, parameters_at);
      if (!parameter.ok()) return parameter.error();
      set.material.*spec.field = parameter->value;
      sources.push_back(fmt::format("{}: {}", spec.key, parameter->source));
    }
    set.source = fmt::format("{}", fmt::join(sources, "; "));
    // The checks above cover Material::Validate's rules; this catches drift.
    if (Status status = set.material.Validate(); !status.ok()) {
      return ErrorAt(path_, parameters_at, status.error().message);
    }
    return set;
  }

 private:
  struct Parameter {
    double value = 0.0;
    std::string source;
  };

  static bool IsIdentifier(std::string_view text) {
    return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
  }

  // The first key of `table` (in file order) not in `allowed`, as an error.
  std::optional<Error> UnknownKey(const toml::table& table,
                                  std::string_view prefix,
                                  std::span<const std::string_view> allowed,
                                  const toml::source_position& fallback) const {
    const toml::key* first_key = nullptr;
    toml::source_position first_at{};
    for (auto&& [key, node] : table) {
      if (std::find(allowed.begin(), allowed.end(), key.str()) !=
          allowed.end()) {
        continue;
      }
      const toml::source_position at = EntryPosition(key, node, fallback);
      if (first_key == nullptr || at.line < first_at.line ||
          (at.line == first_at.line && at.column < first_at.column)) {
        first_key = &key;
        first_at = at;
      }
    }
    if (first_key == nullptr) return std::nullopt;
    return ErrorAt(path_, first_at,
                   fmt::format("unknown key '{}'{}",
                               Dotted(prefix, Echo(first_key->str())),
                               Suggestion(first_key->str(), allowed)));
  }

  // table[key] as a non-empty string.
  Result<std::string> RequiredString(
      const toml::table& table, std::string_view prefix, std::string_view key,
      const toml::source_position& table_at) const {
    const std::string dotted = Dotted(prefix, key);
    const toml::node* node = table.get(key);
    if (node == nullptr) {
      return ErrorAt(path_, table_at, fmt::format("missing key '{}'", dotted));
    }
    const toml::source_position at = NodePosition(*node, table_at);
    if (!node->is_string()) {
      return ErrorAt(
          path_, at,
          fmt::format("{} must be a string, got {}", dotted, TypeName(*node)));
    }
    const std::string& text = node->as_string()->get();
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
      return ErrorAt(path_, at, fmt::format("{} must not be empty", dotted));
    }
    return text;
  }

  // parameters.<spec.key>: a table of value, unit and source.
  Result<Parameter> CheckParameter(
      const toml::table& parameters, const ParameterSpec& spec,
      const toml::source_position& parameters_at) const {
    const std::string dotted = Dotted("parameters", spec.key);
    const toml::node* node = parameters.get(spec.key);
    if (node == nullptr) {
      return ErrorAt(path_, parameters_at,
                     fmt::format("missing key '{}'", dotted));
    }
    const toml::table* entry = node->as_table();
    if (entry == nullptr) {
      return ErrorAt(path_, NodePosition(*node, parameters_at),
                     fmt::format("{} must be a table with value, unit and "
                                 "source, got {}",
                                 dotted, TypeName(*node)));
    }
    const toml::source_position entry_at = TablePosition(*entry, parameters_at);
    if (auto error = UnknownKey(*entry, dotted, kEntryKeys, entry_at)) {
      return *error;
    }

    Parameter parameter;
    const toml::node* value = entry->get("value");
    if (value == nullptr) {
      return ErrorAt(path_, entry_at,
                     fmt::format("missing key '{}.value'", dotted));
    }
    const toml::source_position value_at = NodePosition(*value, entry_at);
    if (const auto* integer = value->as_integer()) {
      parameter.value = static_cast<double>(integer->get());
    } else if (const auto* floating = value->as_floating_point()) {
      parameter.value = floating->get();
    } else {
      return ErrorAt(path_, value_at,
                     fmt::format("{}.value must be a number, got {}", dotted,
                                 TypeName(*value)));
    }
    if (!std::isfinite(parameter.value)) {
      return ErrorAt(path_, value_at,
                     fmt::format("{}.value must be finite, got {}", dotted,
                                 parameter.value));
    }
    if (spec.strictly_positive && parameter.value <= 0.0) {
      return ErrorAt(path_, value_at,
                     fmt::format("{}.value must be positive, got {}", dotted,
                                 parameter.value));
    }
    if (parameter.value < 0.0) {
      return ErrorAt(path_, value_at,
                     fmt::format("{}.value must be zero or positive, got {}",
                                 dotted, parameter.value));
    }
    parameter.value += 0.0;  // -0 reads as 0

    const toml::node* unit = entry->get("unit");
    if (unit == nullptr) {
      return ErrorAt(path_, entry_at,
                     fmt::format("missing key '{}.unit' (expected unit = "
                                 "\"{}\")",
                                 dotted, spec.unit));
    }
    const toml::source_position unit_at = NodePosition(*unit, entry_at);
    if (!unit->is_string()) {
      return ErrorAt(path_, unit_at,
                     fmt::format("{}.unit must be the string '{}', got {}",
                                 dotted, spec.unit, TypeName(*unit)));
    }
    if (const std::string& text = unit->as_string()->get(); text != spec.unit) {
      return ErrorAt(path_, unit_at,
                     fmt::format("{}.unit must be '{}', got '{}'", dotted,
                                 spec.unit, Echo(text)));
    }

    Result<std::string> source =
        RequiredString(*entry, dotted, "source", entry_at);
    if (!source.ok()) return source.error();
    parameter.source = std::move(*source);
    return parameter;
  }

  std::string_view path_;
};

// The built-in names in the order of kBuiltinMaterials (sorted by CMake).
std::vector<std::string_view> BuiltinNameViews() {
  std::vector<std::string_view> names;
  for (const EmbeddedMaterial& material : kBuiltinMaterials) {
    names.push_back(material.name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

Result<MaterialSet> ParseMaterial(std::string_view path,
                                  std::string_view text) {
  if (text.size() > kMaxMaterialBytes) {
    return ErrorAt(path, {1, 1},
                   fmt::format("material text is larger than 1 MiB ({} bytes)",
                               text.size()));
  }
  std::variant<toml::table, TomlFailure> root = ParseTomlDocument(
      path, text, kMaxDots,
      fmt::format("more than {} '.' outside strings and comments; nesting "
                  "this deep is refused",
                  kMaxDots));
  if (const auto* failure = std::get_if<TomlFailure>(&root)) {
    return ErrorAt(path, failure->where.value_or(toml::source_position{1, 1}),
                   failure->message);
  }
  try {
    return SchemaChecker(path).Check(std::get<toml::table>(root));
  } catch (const std::exception& error) {
    return ErrorAt(path, {1, 1}, fmt::format("cannot parse: {}", error.what()));
  } catch (...) {
    return ErrorAt(path, {1, 1}, "cannot parse: unknown error");
  }
}

Result<MaterialSet> LoadMaterialFile(const std::string& path) {
  auto cannot_read = [&path](std::string_view reason) {
    return Error{
        OneLine(fmt::format("{}: cannot read file: {}", path, reason))};
  };
  std::variant<std::string, FileReadFailure> read =
      ReadFileBytes(path, kMaxMaterialBytes, FileKinds::kRegularOnly);
  if (const std::string* text = std::get_if<std::string>(&read)) {
    return ParseMaterial(path, *text);
  }
  const FileReadFailure& failure = std::get<FileReadFailure>(read);
  switch (failure.problem) {
    case FileProblem::kDirectory:
      return cannot_read("is a directory");
    case FileProblem::kTooLarge:
      return cannot_read("larger than 1 MiB");
    case FileProblem::kNotRegular:
    case FileProblem::kUnreadable:
      break;
  }
  return cannot_read(failure.reason.empty() ? std::string_view("I/O error")
                                            : failure.reason);
}

Result<MaterialSet> LoadBuiltinMaterial(std::string_view name) {
  for (const EmbeddedMaterial& material : kBuiltinMaterials) {
    if (material.name != name) continue;
    const std::string path = fmt::format("builtin:{}.toml", material.name);
    Result<MaterialSet> set = ParseMaterial(path, material.text);
    if (set.ok() && set->name != material.name) {
      return Error{fmt::format("{}: name '{}' must equal the file name '{}'",
                               path, set->name, material.name)};
    }
    return set;
  }
  const std::vector<std::string_view> names = BuiltinNameViews();
  return Error{OneLine(
      fmt::format("unknown material '{}': known materials are {}{}", Echo(name),
                  fmt::join(names, ", "), Suggestion(name, names)))};
}

std::vector<std::string> BuiltinMaterialNames() {
  std::vector<std::string> names;
  for (std::string_view name : BuiltinNameViews()) names.emplace_back(name);
  return names;
}

}  // namespace burrlab::stimuli
