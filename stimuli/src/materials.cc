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
#include "burrlab/stimuli/toml_fields.h"
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

constexpr std::string_view kRootKeys[] = {"format", "name", "display_name",
                                          "description", "parameters"};
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

bool IsValid(const toml::source_position& position) {
  return position.line > 0 && position.column > 0;
}

bool Before(const toml::source_position& a, const toml::source_position& b) {
  return a.line < b.line || (a.line == b.line && a.column < b.column);
}

// "path:line:col: <kind>: message" on one line.
std::string LineAt(std::string_view path, const toml::source_position& position,
                   std::string_view kind, std::string_view message) {
  const toml::source_position where =
      IsValid(position) ? position : toml::source_position{1, 1};
  return OneLine(fmt::format("{}:{}:{}: {}: {}", path, where.line, where.column,
                             kind, message));
}

Error ErrorAt(std::string_view path, const toml::source_position& position,
              std::string_view message) {
  return Error{LineAt(path, position, "error", message)};
}

// `prefix.key`, or `key` at the top level.
std::string Dotted(std::string_view prefix, std::string_view key) {
  return prefix.empty() ? std::string(key) : fmt::format("{}.{}", prefix, key);
}

// Validates one parsed file against the schema, reporting the first problem:
// the field readers every file kind shares (burrlab/stimuli/toml_fields.h)
// collect what one step finds, and the step returns the earliest in the file.
class SchemaChecker {
 public:
  explicit SchemaChecker(std::string_view path) : path_(path) {}
  // fields_ reports through this checker: no copies.
  SchemaChecker(const SchemaChecker&) = delete;
  SchemaChecker& operator=(const SchemaChecker&) = delete;

  Result<MaterialSet> Check(const toml::table& root) {
    // The format id first: a file of another format gets that message rather
    // than one about the keys it does not share with this one.
    const toml::node* format = root.get("format");
    if (format == nullptr) {
      return ErrorAt(path_, {1, 1},
                     fmt::format("missing key 'format' (material files start "
                                 "with format = \"{}\")",
                                 kFormat));
    }
    const std::optional<std::string> id =
        fields_.String(root, "format", "format");
    if (!id.has_value()) return First();
    if (*id != kFormat) {
      return ErrorAt(
          path_, PositionOf(*format),
          fmt::format("format must be '{}', got '{}'", kFormat, EchoText(*id)));
    }
    fields_.CheckKeys(root, "the material file", kRootKeys);
    if (!problems_.empty()) return First();

    MaterialSet set;
    std::optional<std::string> name = RequiredString(root, "", "name");
    if (!name.has_value()) return First();
    if (!IsIdentifier(*name)) {
      return ErrorAt(path_, PositionOf(*root.get("name")),
                     fmt::format("name must be lowercase letters, digits and "
                                 "underscores ([a-z0-9_]+), got '{}'",
                                 EchoText(*name)));
    }
    set.name = std::move(*name);
    std::optional<std::string> display_name =
        RequiredString(root, "", "display_name");
    if (!display_name.has_value()) return First();
    set.display_name = std::move(*display_name);
    std::optional<std::string> description =
        fields_.String(root, "description", "description");
    if (!problems_.empty()) return First();
    set.description = description.value_or("");

    if (root.get("parameters") == nullptr) {
      return ErrorAt(path_, {1, 1}, "missing key 'parameters'");
    }
    const toml::table* parameters =
        fields_.Table(root, "parameters", "parameters");
    if (parameters == nullptr) return First();
    std::vector<std::string_view> keys;
    std::vector<TomlRename> renamed;
    for (const MaterialParameterSpelling& spelling :
         kMaterialParameterSpellings) {
      keys.push_back(spelling.key);
      if (!spelling.old_key.empty()) {
        renamed.push_back({spelling.old_key, spelling.key});
      }
    }
    fields_.CheckKeys(*parameters, "[parameters]", keys, {}, {}, renamed);
    if (!problems_.empty()) return First();
    std::vector<std::string> sources;
    for (const MaterialParameterSpelling& spelling :
         kMaterialParameterSpellings) {
      std::optional<Parameter> parameter =
          CheckParameter(*parameters, spelling, set.notes);
      if (!parameter.has_value()) return First();
      set.material.*spelling.field = parameter->value;
      sources.push_back(
          fmt::format("{}: {}", spelling.symbol, parameter->source));
    }
    set.source = fmt::format("{}", fmt::join(sources, "; "));
    // The checks above cover Material::Validate's rules; this catches drift.
    if (Status status = set.material.Validate(); !status.ok()) {
      return ErrorAt(path_, PositionOf(*parameters), status.error().message);
    }
    return set;
  }

 private:
  struct Parameter {
    double value = 0.0;
    std::string source;
  };
  struct Problem {
    toml::source_position where;
    std::string message;
  };

  static bool IsIdentifier(std::string_view text) {
    return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
  }

  // The earliest problem reported (a step reports at least one before it
  // returns this).
  Error First() const {
    const Problem* first = &problems_.front();
    for (const Problem& problem : problems_) {
      if (Before(problem.where, first->where)) first = &problem;
    }
    return ErrorAt(path_, first->where, first->message);
  }

  void Fail(toml::source_position where, std::string message) {
    problems_.push_back({where, std::move(message)});
  }

  // table[key] as a string with something besides white space; nullopt after
  // a report.
  std::optional<std::string> RequiredString(const toml::table& table,
                                            std::string_view prefix,
                                            std::string_view key) {
    const std::string dotted = Dotted(prefix, key);
    const toml::node* node = table.get(key);
    if (node == nullptr) {
      Fail(PositionOf(table), fmt::format("missing key '{}'", dotted));
      return std::nullopt;
    }
    std::optional<std::string> text = fields_.String(table, key, dotted);
    if (text.has_value() &&
        text->find_first_not_of(" \t\r\n") == std::string::npos) {
      Fail(PositionOf(*node), fmt::format("{} must not be empty", dotted));
      return std::nullopt;
    }
    return text;
  }

  // [parameters.<key>] (or its old spelling, with a note): a table of value,
  // source and, optionally, the unit its key spells.
  std::optional<Parameter> CheckParameter(
      const toml::table& parameters, const MaterialParameterSpelling& spelling,
      std::vector<std::string>& notes) {
    std::string_view key = spelling.key;
    if (!spelling.old_key.empty() &&
        parameters.get(spelling.old_key) != nullptr) {
      if (parameters.get(spelling.key) != nullptr) {
        Fail(PositionOf(*parameters.get(spelling.old_key)),
             fmt::format("[parameters.{}] and [parameters.{}] are the same "
                         "parameter; keep [parameters.{}]",
                         spelling.old_key, spelling.key, spelling.key));
        return std::nullopt;
      }
      key = spelling.old_key;
      notes.push_back(
          LineAt(path_, PositionOf(*parameters.get(key)), "note",
                 fmt::format("[parameters.{}] is the old spelling of "
                             "[parameters.{}] (read in {}); rename it, a later "
                             "format will refuse the old spelling",
                             spelling.old_key, spelling.key, spelling.unit)));
    }
    const std::string dotted = Dotted("parameters", key);
    if (parameters.get(key) == nullptr) {
      Fail(PositionOf(parameters),
           fmt::format("missing key '{}'", Dotted("parameters", spelling.key)));
      return std::nullopt;
    }
    const toml::node& node = *parameters.get(key);
    const toml::table* entry = node.as_table();
    if (entry == nullptr) {
      Fail(PositionOf(node), fmt::format("{} must be a table with value and "
                                         "source, got {}",
                                         dotted, TomlTypeName(node)));
      return std::nullopt;
    }
    fields_.CheckKeys(*entry, fmt::format("[{}]", dotted), kEntryKeys);
    if (!problems_.empty()) return std::nullopt;

    if (entry->get("value") == nullptr) {
      Fail(PositionOf(*entry), fmt::format("missing key '{}.value'", dotted));
      return std::nullopt;
    }
    const std::string value_name = fmt::format("{}.value", dotted);
    const std::optional<double> value =
        fields_.Number(*entry, "value", value_name);
    if (!value.has_value()) return std::nullopt;
    const toml::source_position value_at = PositionOf(*entry->get("value"));
    // c_e must be positive: a material with no elastic force cannot be felt
    // (sim::Material::Validate); the others may be 0.
    if (spelling.field == &sim::Material::c_e_n_per_mm2 && *value <= 0.0) {
      Fail(value_at,
           fmt::format("{} must be positive, got {}", value_name, *value));
      return std::nullopt;
    }
    if (*value < 0.0) {
      Fail(value_at, fmt::format("{} must be zero or positive, got {}",
                                 value_name, *value));
      return std::nullopt;
    }
    Parameter parameter;
    parameter.value = *value + 0.0;  // -0 reads as 0

    const std::optional<std::string> unit =
        fields_.String(*entry, "unit", fmt::format("{}.unit", dotted));
    if (!problems_.empty()) return std::nullopt;
    if (unit.has_value() && *unit != spelling.unit) {
      Fail(PositionOf(*entry->get("unit")),
           fmt::format("{}.unit must be '{}', got '{}'", dotted, spelling.unit,
                       EchoText(*unit)));
      return std::nullopt;
    }
    std::optional<std::string> source =
        RequiredString(*entry, dotted, "source");
    if (!source.has_value()) return std::nullopt;
    parameter.source = std::move(*source);
    return parameter;
  }

  std::string_view path_;
  std::vector<Problem> problems_;
  TomlFields fields_{[this](toml::source_position where, std::string message) {
    Fail(where, std::move(message));
  }};
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

Result<MaterialSet> LoadMaterial(const std::string& name_or_path) {
  const bool is_path = name_or_path.ends_with(".toml") ||
                       name_or_path.find('/') != std::string::npos;
  return is_path ? LoadMaterialFile(name_or_path)
                 : LoadBuiltinMaterial(name_or_path);
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
  return Error{OneLine(fmt::format(
      "unknown material '{}': known materials are {}{}", EchoText(name),
      fmt::join(names, ", "), Suggestion(name, names)))};
}

std::vector<std::string> BuiltinMaterialNames() {
  std::vector<std::string> names;
  for (std::string_view name : BuiltinNameViews()) names.emplace_back(name);
  return names;
}

}  // namespace burrlab::stimuli
