// Flag parsing: CLI11 errors as one line, strict number parsing.
#include "cli/flags.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <system_error>
#include <utility>

#include "burrlab/base/spelling.h"
#include "burrlab/results_schema/records.h"

namespace burrlab::runner {
namespace {

// The conversion of a flag that takes a number >= 0 into `value` (a double,
// or an optional that stays unset when the flag is not given).
template <typename Target>
std::function<Status(std::string_view)> NonNegativeInto(const std::string& name,
                                                        std::string_view unit,
                                                        Target* value) {
  return
      [name, unit = std::string(unit), value](std::string_view text) -> Status {
        Result<double> parsed = ParseNonNegative(name, text, unit);
        if (!parsed.ok()) return parsed.error();
        *value = *parsed;
        return {};
      };
}

// " of <unit>" or nothing for a plain number.
std::string OfUnit(std::string_view unit) {
  return unit.empty() ? std::string() : fmt::format(" of {}", unit);
}

// Parses `text` whole with std::from_chars (locale-independent); a leading
// '+' is allowed.
template <typename T>
std::errc ParseWhole(std::string_view text, T* value) {
  if (text.size() > 1 && text.front() == '+' && text[1] != '-') {
    text.remove_prefix(1);
  }
  if (text.empty()) return std::errc::invalid_argument;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, *value);
  if (ec == std::errc() && ptr != end) return std::errc::invalid_argument;
  return ec;
}

// "'a', 'b' or 'c'".
std::string QuotedList(const std::vector<std::string>& words) {
  std::string list;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) list += i + 1 == words.size() ? " or " : ", ";
    list += fmt::format("'{}'", words[i]);
  }
  return list;
}

}  // namespace

Result<double> ParseNumber(std::string_view flag, std::string_view text) {
  double value = 0.0;
  const std::errc ec = ParseWhole(text, &value);
  if (ec == std::errc::result_out_of_range) {
    // from_chars does not say which way; strtod does.
    const std::string copy(text);
    if (std::abs(std::strtod(copy.c_str(), nullptr)) < 1.0) {
      return Error{fmt::format("{} is too close to zero to represent, got '{}'",
                               flag, text)};
    }
  }
  if (ec != std::errc() || !std::isfinite(value)) {
    return Error{
        fmt::format("{} must be a finite number, got '{}'", flag, text)};
  }
  return value;
}

Result<double> ParsePositive(std::string_view flag, std::string_view text,
                             std::string_view unit) {
  Result<double> value = ParseNumber(flag, text);
  if (value.ok() && !(*value > 0.0)) {
    return Error{fmt::format("{} must be a positive number{}, got '{}'", flag,
                             OfUnit(unit), text)};
  }
  return value;
}

Result<double> ParseNonNegative(std::string_view flag, std::string_view text,
                                std::string_view unit) {
  Result<double> value = ParseNumber(flag, text);
  if (value.ok() && !(*value >= 0.0)) {
    return Error{fmt::format("{} must be zero or a positive number{}, got '{}'",
                             flag, OfUnit(unit), text)};
  }
  if (value.ok() && *value == 0.0) return 0.0;  // no "-0" downstream
  return value;
}

Result<std::int64_t> ParseInteger(std::string_view flag, std::string_view text,
                                  std::int64_t min, std::int64_t max) {
  std::int64_t value = 0;
  if (ParseWhole(text, &value) != std::errc() || value < min || value > max) {
    return Error{
        fmt::format("{} must be a whole number from {} to {}, got '{}'", flag,
                    min, max, text)};
  }
  return value;
}

Result<std::uint64_t> ParseUnsigned(std::string_view flag,
                                    std::string_view text) {
  std::uint64_t value = 0;
  if (ParseWhole(text, &value) != std::errc()) {
    return Error{fmt::format("{} must be a whole number from 0 to {}, got '{}'",
                             flag, std::numeric_limits<std::uint64_t>::max(),
                             text)};
  }
  return value;
}

Result<std::uint64_t> ParseSeed(std::string_view flag, std::string_view text) {
  const std::optional<std::uint64_t> seed = results_schema::ParseSeedText(text);
  if (!seed) {
    return Error{fmt::format(
        "{} must be a whole number from 0 to {}, bare or as the exports write "
        "it (seed-N), got '{}'",
        flag, std::numeric_limits<std::uint64_t>::max(), text)};
  }
  return *seed;
}

Result<glm::dvec3> ParseDirection(std::string_view flag,
                                  std::string_view text) {
  std::vector<std::string_view> parts;
  std::string_view rest = text;
  for (;;) {
    const std::size_t comma = rest.find(',');
    parts.push_back(rest.substr(0, comma));
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (parts.size() != 3) {
    return Error{
        fmt::format("{} must be three comma-separated numbers X,Y,Z, got '{}'",
                    flag, text)};
  }
  glm::dvec3 direction(0.0);
  for (int i = 0; i < 3; ++i) {
    double component = 0.0;
    if (ParseWhole(parts[static_cast<std::size_t>(i)], &component) !=
            std::errc() ||
        !std::isfinite(component)) {
      return Error{fmt::format(
          "{} must be three finite numbers X,Y,Z, got '{}'", flag, text)};
    }
    direction[i] = component;
  }
  if (direction == glm::dvec3(0.0)) {
    return Error{
        fmt::format("{} must not be the zero vector, got '{}'", flag, text)};
  }
  return direction;
}

CLI::Option* FlagSet::Add(const std::string& name, const std::string& help,
                          std::string type_name,
                          std::function<Status(std::string_view)> convert) {
  Flag& flag = flags_.emplace_back();
  flag.name = name;
  flag.convert = std::move(convert);
  flag.option = app_->add_option(name, flag.text, help);
  flag.option->type_name(std::move(type_name));
  return flag.option;
}

CLI::Option* FlagSet::AddPositive(const std::string& name,
                                  const std::string& help,
                                  std::string_view unit, double* value,
                                  double max) {
  return Add(
      name, help, "X",
      [name, unit = std::string(unit), value,
       max](std::string_view text) -> Status {
        Result<double> parsed = ParsePositive(name, text, unit);
        if (!parsed.ok()) return parsed.error();
        if (*parsed > max) {
          return Error{fmt::format("{} must be at most {}{}, got '{}'", name,
                                   max, unit.empty() ? "" : " " + unit, text)};
        }
        *value = *parsed;
        return {};
      });
}

CLI::Option* FlagSet::AddNonNegative(const std::string& name,
                                     const std::string& help,
                                     std::string_view unit, double* value) {
  return Add(name, help, "X", NonNegativeInto(name, unit, value));
}

CLI::Option* FlagSet::AddNonNegative(const std::string& name,
                                     const std::string& help,
                                     std::string_view unit,
                                     std::optional<double>* value) {
  return Add(name, help, "X", NonNegativeInto(name, unit, value));
}

CLI::Option* FlagSet::AddInteger(const std::string& name,
                                 const std::string& help, int min, int max,
                                 int* value) {
  return Add(name, help, "N",
             [name, min, max, value](std::string_view text) -> Status {
               Result<std::int64_t> parsed = ParseInteger(name, text, min, max);
               if (!parsed.ok()) return parsed.error();
               *value = static_cast<int>(*parsed);
               return {};
             });
}

CLI::Option* FlagSet::AddUnsigned(const std::string& name,
                                  const std::string& help,
                                  std::uint64_t* value) {
  return Add(name, help, "N", [name, value](std::string_view text) -> Status {
    Result<std::uint64_t> parsed = ParseUnsigned(name, text);
    if (!parsed.ok()) return parsed.error();
    *value = *parsed;
    return {};
  });
}

CLI::Option* FlagSet::AddSeed(const std::string& name, const std::string& help,
                              std::uint64_t* value) {
  return Add(name, help, "N", [name, value](std::string_view text) -> Status {
    Result<std::uint64_t> parsed = ParseSeed(name, text);
    if (!parsed.ok()) return parsed.error();
    *value = *parsed;
    return {};
  });
}

CLI::Option* FlagSet::AddDirection(const std::string& name,
                                   const std::string& help, glm::dvec3* value) {
  return Add(name, help, "X,Y,Z",
             [name, value](std::string_view text) -> Status {
               Result<glm::dvec3> parsed = ParseDirection(name, text);
               if (!parsed.ok()) return parsed.error();
               *value = *parsed;
               return {};
             });
}

CLI::Option* FlagSet::AddChoice(const std::string& name,
                                const std::string& help,
                                std::vector<std::string> choices, int* index) {
  std::string type_name;
  for (const std::string& choice : choices) {
    type_name += (type_name.empty() ? "" : "|") + choice;
  }
  return Add(name, help, type_name,
             [name, choices = std::move(choices),
              index](std::string_view text) -> Status {
               for (std::size_t i = 0; i < choices.size(); ++i) {
                 if (choices[i] == text) {
                   *index = static_cast<int>(i);
                   return {};
                 }
               }
               return Error{fmt::format("{} must be {}, got '{}'", name,
                                        QuotedList(choices), text)};
             });
}

CLI::Option* FlagSet::AddText(const std::string& name, const std::string& help,
                              std::string* value) {
  return Add(name, help, "TEXT", [value](std::string_view text) -> Status {
    *value = std::string(text);
    return {};
  });
}

CLI::Option* FlagSet::AddSwitch(const std::string& name,
                                const std::string& help, bool* value) {
  switches_.push_back(name);
  return app_->add_flag(name, *value, help);
}

bool FlagSet::Given(const std::string& name) const {
  return app_->count(name) > 0;
}

std::optional<int> FlagSet::Parse(const Args& args, std::ostream& out,
                                  std::ostream& err) {
  const std::string& command = app_->get_name();
  // CLI11 would read "--json=5" as a count; a switch takes no value.
  for (const std::string& arg : args) {
    if (arg == "--") break;
    for (const std::string& name : switches_) {
      if (arg.starts_with(name + "=")) {
        return Fail(err, fmt::format("{} takes no value, got '{}'", name, arg));
      }
    }
  }
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app_->parse(reversed);
  } catch (const CLI::CallForHelp&) {
    out << app_->help();
    return 0;
  } catch (const CLI::ExtrasError& e) {
    const std::vector<std::string> extras = app_->remaining(false);
    if (extras.empty()) {
      return Fail(err, fmt::format("{} (see '{} --help')", e.what(), command));
    }
    const std::string& word = extras.front();
    if (!word.starts_with("-")) {
      return Fail(err, fmt::format("unexpected argument '{}' (see '{} --help')",
                                   word, command));
    }
    const std::string flag = word.substr(0, word.find('='));
    std::vector<std::string> names;
    for (const CLI::Option* option : app_->get_options()) {
      for (const std::string& long_name : option->get_lnames()) {
        names.push_back("--" + long_name);
      }
    }
    const std::vector<std::string_view> candidates(names.begin(), names.end());
    if (std::string_view suggestion = DidYouMean(flag, candidates);
        !suggestion.empty()) {
      return Fail(err,
                  fmt::format("unknown flag '{}' for '{}' (did you mean '{}'?)",
                              flag, command, suggestion));
    }
    return Fail(err, fmt::format("unknown flag '{}' for '{}' (see '{} --help')",
                                 flag, command, command));
  } catch (const CLI::ArgumentMismatch& e) {
    // CLI11 says "--x: 1 required X missing" or "--x: At Most 1 required but
    // received 2"; say it in the user's terms.
    const std::string what = e.what();
    const std::string name = what.substr(0, what.find(':'));
    for (const Flag& flag : flags_) {
      if (flag.name != name) continue;
      if (flag.option->count() > 1) {
        return Fail(err, fmt::format("{} given {} times; give it once", name,
                                     flag.option->count()));
      }
      return Fail(err, fmt::format("{} needs a value (see '{} --help')", name,
                                   command));
    }
    return Fail(err, fmt::format("{} (see '{} --help')", what, command));
  } catch (const CLI::ParseError& e) {
    return Fail(err, fmt::format("{} (see '{} --help')", e.what(), command));
  }
  return std::nullopt;
}

Status FlagSet::Convert() const {
  for (const Flag& flag : flags_) {
    if (flag.option->count() == 0) continue;
    if (Status status = flag.convert(flag.text); !status.ok()) return status;
  }
  return {};
}

}  // namespace burrlab::runner
