// Untrusted TOML: nesting limit, positions, syntax messages.
#include "burrlab/stimuli/toml_guard.h"

#include <fmt/format.h>

#include "burrlab/base/printable.h"

namespace burrlab::stimuli {

// Line and column (in code points, like toml++) of byte `offset` of `text`.
toml::source_position PositionOf(std::string_view text, std::size_t offset) {
  toml::source_position position{1, 1};
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (text[i] == '\n') {
      ++position.line;
      position.column = 1;
    } else if ((byte & 0xc0) != 0x80) {
      ++position.column;
    }
  }
  return position;
}

// The byte offset of the first '.' outside strings and comments beyond
// max_dots, if any. A lexical scan only: malformed TOML is left to toml++.
std::optional<std::size_t> ExcessDotOffset(std::string_view text,
                                           std::size_t max_dots) {
  std::size_t dots = 0;
  std::size_t i = 0;
  const std::size_t n = text.size();
  // Skips the string starting at text[i], as TOML 1.0 delimits it: a
  // multi-line string may end in up to two quotes of its own before the
  // closing three.
  auto skip_string = [&](char quote, bool escapes) {
    auto quote_run = [&](std::size_t at) {
      std::size_t run = 0;
      while (run < 6 && at + run < n && text[at + run] == quote) ++run;
      return run;
    };
    const bool multiline = quote_run(i) >= 3;
    i += multiline ? 3 : 1;
    while (i < n) {
      if (escapes && text[i] == '\\') {
        i += 2;
      } else if (multiline && quote_run(i) >= 3) {
        i += std::min<std::size_t>(quote_run(i), 5);
        return;
      } else if (!multiline && (text[i] == quote || text[i] == '\n')) {
        ++i;
        return;
      } else {
        ++i;
      }
    }
  };
  while (i < n) {
    switch (text[i]) {
      case '#':
        while (i < n && text[i] != '\n') ++i;
        break;
      case '"':
        skip_string('"', /*escapes=*/true);
        break;
      case '\'':
        skip_string('\'', /*escapes=*/false);
        break;
      case '.':
        if (++dots > max_dots) return i;
        ++i;
        break;
      default:
        ++i;
    }
  }
  return std::nullopt;
}

// toml++'s parse error as "invalid TOML ...".
std::string SyntaxMessage(std::string_view description) {
  // toml++ quotes the character it did not expect as it is: a C1 control
  // (U+0085 is a line break to some terminals) is escaped, like every other
  // piece of file text in a message.
  constexpr std::string_view kPrefix = "Error while parsing ";
  if (description.starts_with(kPrefix)) {
    description.remove_prefix(kPrefix.size());
    return fmt::format("invalid TOML in {}", PrintableText(description));
  }
  if (description.empty()) return "invalid TOML";
  std::string message =
      fmt::format("invalid TOML: {}", PrintableText(description));
  constexpr std::size_t kFirst = std::string_view("invalid TOML: ").size();
  if (message[kFirst] >= 'A' && message[kFirst] <= 'Z') {
    message[kFirst] = static_cast<char>(message[kFirst] - 'A' + 'a');
  }
  return message;
}

std::variant<toml::table, TomlFailure> ParseTomlDocument(
    std::string_view path, std::string_view text, std::size_t max_dots,
    std::string_view too_deep_message) {
  if (std::optional<std::size_t> offset = ExcessDotOffset(text, max_dots)) {
    return TomlFailure{PositionOf(text, *offset),
                       std::string(too_deep_message)};
  }
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& error) {
    return TomlFailure{error.source().begin,
                       SyntaxMessage(error.description())};
  } catch (const std::exception& error) {
    return TomlFailure{std::nullopt,
                       fmt::format("cannot parse: {}", error.what())};
  } catch (...) {
    return TomlFailure{std::nullopt, "cannot parse: unknown error"};
  }
}

}  // namespace burrlab::stimuli
