// The embedded JSON Schemas and the small checker for the subset they use.
#include "burrlab/results_schema/schemas.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <bitset>
#include <cmath>
#include <exception>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>

namespace burrlab::results_schema {
namespace {

using Json = nlohmann::json;

struct EmbeddedSchema {
  std::string_view name;
  std::string_view text;
};

constexpr EmbeddedSchema kSchemas[] = {
#include "schemas.inc"
};

// Deepest $ref chain or nesting followed before giving up.
constexpr int kMaxDepth = 64;

// One element of a compiled pattern: a set of bytes repeated min..max times.
struct PatternAtom {
  std::bitset<256> bytes;
  std::size_t min = 1;
  std::size_t max = 1;
};

constexpr std::size_t kUnbounded = static_cast<std::size_t>(-1);

// The byte an escape stands for (\t, \r, \n or escaped punctuation itself);
// -1 for escapes this checker refuses.
int EscapedByte(char c) {
  if (c == 't') return '\t';
  if (c == 'r') return '\r';
  if (c == 'n') return '\n';
  const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                     (c >= '0' && c <= '9');
  return alnum ? -1 : static_cast<unsigned char>(c);
}

void AddDigits(PatternAtom* atom) {
  for (std::size_t d = '0'; d <= '9'; ++d) atom->bytes.set(d);
}

// Reads "{n}", "{n,}" or "{n,m}" at body[i] (just after '{' is at i).
bool ParseBraces(std::string_view body, std::size_t* i, PatternAtom* atom) {
  const std::size_t close = body.find('}', *i);
  if (close == std::string_view::npos) return false;
  const std::string_view inside = body.substr(*i + 1, close - *i - 1);
  auto number = [](std::string_view digits, std::size_t* out) {
    if (digits.empty() || digits.size() > 6) return false;
    std::size_t value = 0;
    for (char d : digits) {
      if (d < '0' || d > '9') return false;
      value = value * 10 + static_cast<std::size_t>(d - '0');
    }
    *out = value;
    return true;
  };
  const std::size_t comma = inside.find(',');
  if (comma == std::string_view::npos) {
    if (!number(inside, &atom->min)) return false;
    atom->max = atom->min;
  } else {
    if (!number(inside.substr(0, comma), &atom->min)) return false;
    const std::string_view upper = inside.substr(comma + 1);
    if (upper.empty()) {
      atom->max = kUnbounded;
    } else if (!number(upper, &atom->max) || atom->max < atom->min) {
      return false;
    }
  }
  *i = close + 1;
  return true;
}

// Reads a class "[...]" whose '[' was just consumed; false if malformed.
bool ParseClass(std::string_view body, std::size_t* i, PatternAtom* atom) {
  bool negate = false;
  if (*i < body.size() && body[*i] == '^') {
    negate = true;
    ++*i;
  }
  while (*i < body.size()) {
    const char first = body[(*i)++];
    if (first == ']') {
      if (negate) atom->bytes.flip();
      return true;
    }
    int low = static_cast<unsigned char>(first);
    if (first == '\\') {
      if (*i >= body.size()) return false;
      if (body[*i] == 'd') {
        AddDigits(atom);
        ++*i;
        continue;
      }
      low = EscapedByte(body[(*i)++]);
      if (low < 0) return false;
    }
    int high = low;
    if (*i + 1 < body.size() && body[*i] == '-' && body[*i + 1] != ']') {
      const char last = body[*i + 1];
      if (last == '\\' || last == '[') return false;
      high = static_cast<unsigned char>(last);
      *i += 2;
      if (high < low) return false;
    }
    for (int b = low; b <= high; ++b) {
      atom->bytes.set(static_cast<std::size_t>(b));
    }
  }
  return false;
}

// Compiles an anchored pattern "^...$" made of literal bytes, "." (any byte
// but \n), escapes (\t \r \n \d, escaped punctuation), classes [...] with
// ranges and ^ negation, and the quantifiers ? * + {n} {n,} {n,m}. Anything
// else (alternation, groups, look-around, unanchored) is refused. Matching is
// byte-wise, which is exact for the ASCII classes the schemas use.
Result<std::vector<PatternAtom>> CompilePattern(std::string_view pattern) {
  const Error unsupported{fmt::format(
      "unsupported pattern \"{}\" (only anchored ^...$ patterns of literals, "
      "classes and quantifiers)",
      pattern)};
  if (pattern.size() < 2 || pattern.front() != '^' || pattern.back() != '$' ||
      (pattern.size() >= 3 && pattern[pattern.size() - 2] == '\\')) {
    return unsupported;
  }
  const std::string_view body = pattern.substr(1, pattern.size() - 2);
  std::vector<PatternAtom> atoms;
  std::size_t i = 0;
  while (i < body.size()) {
    PatternAtom atom;
    const char c = body[i++];
    if (c == '[') {
      if (!ParseClass(body, &i, &atom)) return unsupported;
    } else if (c == '\\') {
      if (i >= body.size()) return unsupported;
      if (body[i] == 'd') {
        AddDigits(&atom);
        ++i;
      } else {
        const int b = EscapedByte(body[i++]);
        if (b < 0) return unsupported;
        atom.bytes.set(static_cast<std::size_t>(b));
      }
    } else if (c == '.') {
      atom.bytes.set();
      atom.bytes.reset('\n');
    } else if (std::string_view("()|^$*+?{}]").find(c) !=
               std::string_view::npos) {
      return unsupported;
    } else {
      atom.bytes.set(static_cast<unsigned char>(c));
    }
    if (i < body.size()) {
      const char q = body[i];
      if (q == '*' || q == '+' || q == '?') {
        atom.min = q == '+' ? 1 : 0;
        atom.max = q == '?' ? 1 : kUnbounded;
        ++i;
      } else if (q == '{' && !ParseBraces(body, &i, &atom)) {
        return unsupported;
      }
    }
    atoms.push_back(atom);
  }
  return atoms;
}

// Greedy match with backtracking; recursion depth is the number of atoms.
bool MatchAtoms(const std::vector<PatternAtom>& atoms, std::size_t a,
                std::string_view text, std::size_t pos) {
  if (a == atoms.size()) return pos == text.size();
  const PatternAtom& atom = atoms[a];
  std::size_t count = 0;
  while (count < atom.max && pos + count < text.size() &&
         atom.bytes.test(static_cast<unsigned char>(text[pos + count]))) {
    ++count;
  }
  if (count < atom.min) return false;
  for (std::size_t take = count + 1; take-- > atom.min;) {
    if (MatchAtoms(atoms, a + 1, text, pos + take)) return true;
  }
  return false;
}

const std::set<std::string, std::less<>>& Annotations() {
  static const std::set<std::string, std::less<>> kNames = {
      "$schema", "$id",     "$defs",    "$comment",
      "title",   "default", "examples", "description"};
  return kNames;
}

std::string PointerToken(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

std::size_t CodePoints(const std::string& text) {
  return static_cast<std::size_t>(std::count_if(
      text.begin(), text.end(),
      [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

bool HasType(const Json& instance, const std::string& type) {
  if (type == "object") return instance.is_object();
  if (type == "array") return instance.is_array();
  if (type == "string") return instance.is_string();
  if (type == "boolean") return instance.is_boolean();
  if (type == "null") return instance.is_null();
  if (type == "number") return instance.is_number();
  if (type == "integer") {
    if (instance.is_number_integer()) return true;
    if (!instance.is_number_float()) return false;
    const double value = instance.get<double>();
    return std::isfinite(value) && std::floor(value) == value;
  }
  return false;
}

class Checker {
 public:
  explicit Checker(const Json& root) : root_(root) {}

  Status Check(const Json& schema, const Json& instance,
               const std::string& pointer, int depth) const {
    const std::string at = pointer.empty() ? "/" : pointer;
    if (depth > kMaxDepth) {
      return Error{
          fmt::format("{}: schema nesting deeper than {}", at, kMaxDepth)};
    }
    if (schema.is_boolean()) {
      if (schema.get<bool>()) return {};
      return Error{fmt::format("{}: not allowed here", at)};
    }
    if (!schema.is_object()) {
      return Error{fmt::format("{}: the schema here is not an object", at)};
    }
    for (const auto& [keyword, value] : schema.items()) {
      if (Annotations().contains(keyword)) continue;
      Status s =
          CheckKeyword(schema, keyword, value, instance, pointer, at, depth);
      if (!s) return s;
    }
    return {};
  }

 private:
  Status CheckKeyword(const Json& schema, const std::string& keyword,
                      const Json& value, const Json& instance,
                      const std::string& pointer, const std::string& at,
                      int depth) const {
    if (keyword == "$ref") return CheckRef(value, instance, pointer, at, depth);
    if (keyword == "type") return CheckType(value, instance, at);
    if (keyword == "enum") {
      if (!value.is_array()) return BadSchema(at, keyword);
      for (const Json& option : value) {
        if (option == instance) return {};
      }
      return Error{fmt::format("{}: {} is not one of {}", at, instance.dump(),
                               value.dump())};
    }
    if (keyword == "const") {
      if (value == instance) return {};
      return Error{
          fmt::format("{}: {} is not {}", at, instance.dump(), value.dump())};
    }
    if (keyword == "required") {
      if (!value.is_array()) return BadSchema(at, keyword);
      if (!instance.is_object()) return {};
      for (const Json& name : value) {
        if (!name.is_string()) return BadSchema(at, keyword);
        if (!instance.contains(name.get<std::string>())) {
          return Error{
              fmt::format("{}: missing required property {}", at, name.dump())};
        }
      }
      return {};
    }
    if (keyword == "properties") {
      if (!value.is_object()) return BadSchema(at, keyword);
      if (!instance.is_object()) return {};
      for (const auto& [name, item] : instance.items()) {
        if (!value.contains(name)) continue;
        Status s = Check(value.at(name), item,
                         pointer + "/" + PointerToken(name), depth + 1);
        if (!s) return s;
      }
      return {};
    }
    if (keyword == "additionalProperties") {
      if (!instance.is_object()) return {};
      const Json* properties =
          schema.contains("properties") ? &schema.at("properties") : nullptr;
      for (const auto& [name, item] : instance.items()) {
        if (properties != nullptr && properties->is_object() &&
            properties->contains(name)) {
          continue;
        }
        const std::string item_pointer = pointer + "/" + PointerToken(name);
        if (value.is_boolean() && !value.get<bool>()) {
          return Error{fmt::format("{}: property {} is not allowed", at,
                                   Json(name).dump())};
        }
        Status s = Check(value, item, item_pointer, depth + 1);
        if (!s) return s;
      }
      return {};
    }
    if (keyword == "items") {
      if (!instance.is_array()) return {};
      for (std::size_t i = 0; i < instance.size(); ++i) {
        Status s = Check(value, instance[i], fmt::format("{}/{}", pointer, i),
                         depth + 1);
        if (!s) return s;
      }
      return {};
    }
    if (keyword == "minItems") {
      if (!value.is_number_unsigned()) return BadSchema(at, keyword);
      if (instance.is_array() && instance.size() < value.get<std::size_t>()) {
        return Error{fmt::format("{}: {} items, fewer than the {} required", at,
                                 instance.size(), value.get<std::size_t>())};
      }
      return {};
    }
    if (keyword == "minLength") {
      if (!value.is_number_unsigned()) return BadSchema(at, keyword);
      if (instance.is_string() &&
          CodePoints(instance.get<std::string>()) < value.get<std::size_t>()) {
        return Error{fmt::format("{}: {} is shorter than {} characters", at,
                                 instance.dump(), value.get<std::size_t>())};
      }
      return {};
    }
    if (keyword == "minimum" || keyword == "exclusiveMinimum" ||
        keyword == "maximum") {
      if (!value.is_number()) return BadSchema(at, keyword);
      if (!instance.is_number()) return {};
      const double x = instance.get<double>();
      const double bound = value.get<double>();
      const bool ok = keyword == "minimum"   ? x >= bound
                      : keyword == "maximum" ? x <= bound
                                             : x > bound;
      if (ok) return {};
      return Error{fmt::format("{}: {} breaks {} {}", at, instance.dump(),
                               keyword, value.dump())};
    }
    if (keyword == "pattern") {
      if (!value.is_string()) return BadSchema(at, keyword);
      Result<std::vector<PatternAtom>> atoms =
          CompilePattern(value.get_ref<const std::string&>());
      if (!atoms)
        return Error{fmt::format("{}: {}", at, atoms.error().message)};
      if (!instance.is_string()) return {};
      if (MatchAtoms(*atoms, 0, instance.get_ref<const std::string&>(), 0)) {
        return {};
      }
      return Error{fmt::format("{}: {} does not match pattern {}", at,
                               instance.dump(), value.dump())};
    }
    return Error{
        fmt::format("{}: unsupported schema keyword \"{}\"", at, keyword)};
  }

  Status CheckType(const Json& value, const Json& instance,
                   const std::string& at) const {
    std::vector<std::string> types;
    if (value.is_string()) {
      types.push_back(value.get<std::string>());
    } else if (value.is_array()) {
      for (const Json& t : value) {
        if (!t.is_string()) return BadSchema(at, "type");
        types.push_back(t.get<std::string>());
      }
    } else {
      return BadSchema(at, "type");
    }
    for (const std::string& t : types) {
      if (HasType(instance, t)) return {};
    }
    return Error{fmt::format("{}: {} is not of type {}", at, instance.dump(),
                             value.dump())};
  }

  Status CheckRef(const Json& value, const Json& instance,
                  const std::string& pointer, const std::string& at,
                  int depth) const {
    constexpr std::string_view kPrefix = "#/$defs/";
    if (!value.is_string() || !value.get<std::string>().starts_with(kPrefix)) {
      return Error{fmt::format(
          "{}: unsupported $ref {} (only \"#/$defs/name\")", at, value.dump())};
    }
    const std::string name = value.get<std::string>().substr(kPrefix.size());
    if (!root_.contains("$defs") || !root_.at("$defs").is_object() ||
        !root_.at("$defs").contains(name)) {
      return Error{
          fmt::format("{}: $ref {} names no definition", at, value.dump())};
    }
    return Check(root_.at("$defs").at(name), instance, pointer, depth + 1);
  }

  static Status BadSchema(const std::string& at, std::string_view keyword) {
    return Error{
        fmt::format("{}: the schema's \"{}\" is malformed", at, keyword)};
  }

  const Json& root_;
};

}  // namespace

std::vector<std::string_view> SchemaNames() {
  std::vector<std::string_view> names;
  for (const EmbeddedSchema& schema : kSchemas) names.push_back(schema.name);
  std::sort(names.begin(), names.end());
  return names;
}

Result<std::string_view> SchemaText(std::string_view name) {
  for (const EmbeddedSchema& schema : kSchemas) {
    if (schema.name == name) return schema.text;
  }
  try {
    return Error{fmt::format("unknown schema \"{}\"; known: {}", name,
                             fmt::join(SchemaNames(), ", "))};
  } catch (const std::exception& e) {
    return Error{e.what()};
  }
}

Status CheckJson(std::string_view schema, std::string_view instance) {
  try {
    const Json parsed_schema = Json::parse(schema, nullptr, false);
    if (parsed_schema.is_discarded())
      return Error{"the schema is not valid JSON"};
    const Json parsed_instance = Json::parse(instance, nullptr, false);
    if (parsed_instance.is_discarded())
      return Error{"the document is not valid JSON"};
    return Checker(parsed_schema).Check(parsed_schema, parsed_instance, "", 0);
  } catch (const std::exception& e) {
    return Error{fmt::format("cannot check the document: {}", e.what())};
  }
}

Status CheckJsonAgainst(std::string_view name, std::string_view instance) {
  Result<std::string_view> schema = SchemaText(name);
  if (!schema) return schema.error();
  Status s = CheckJson(*schema, instance);
  if (!s)
    return Error{fmt::format("{}.schema.json: {}", name, s.error().message)};
  return {};
}

}  // namespace burrlab::results_schema
