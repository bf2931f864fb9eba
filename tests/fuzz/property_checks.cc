// Properties of errors and diagnostics shared by the fuzz targets.
#include "property_checks.h"

#include <algorithm>
#include <charconv>
#include <string>

#include "burrlab/base/printable.h"

namespace burrlab::fuzz {
namespace {

// `text` cut to 80 bytes and escaped, for a violation's line.
std::string Excerpt(std::string_view text) {
  return PrintableText(text.substr(0, 80)) + (text.size() > 80 ? "..." : "");
}

}  // namespace

int CountLines(std::string_view text) {
  int lines = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n' ||
        (text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n'))) {
      ++lines;
    }
  }
  return lines;
}

void Expect(bool condition, std::string_view what, Violations* violations) {
  if (!condition) violations->push_back(std::string(what));
}

void CheckMessageLine(std::string_view message, std::string_view what,
                      Violations* violations) {
  if (message.empty()) {
    violations->push_back(std::string(what) + ": the message is empty");
  } else if (PrintableText(message) != message) {
    violations->push_back(std::string(what) +
                          ": the message holds a control character, a line "
                          "break or malformed UTF-8: " +
                          Excerpt(message));
  }
}

void CheckFormattedError(std::string_view error, std::string_view input,
                         std::string_view what, Violations* violations) {
  if (error.empty()) {
    violations->push_back(std::string(what) + ": the error is empty");
    return;
  }
  const std::string prefix = std::string(kInputPath) + ":";
  if (!error.starts_with(prefix)) {
    violations->push_back(
        std::string(what) +
        ": the error does not start with the file name: " + Excerpt(error));
  }
  // Every line printable; a quoted source line keeps its tabs and the caret
  // line copies them.
  std::size_t start = 0;
  while (start <= error.size()) {
    std::size_t end = error.find('\n', start);
    if (end == std::string_view::npos) end = error.size();
    std::string line(error.substr(start, end - start));
    std::erase(line, '\t');
    if (PrintableText(line) != line) {
      violations->push_back(std::string(what) +
                            ": a line of the error holds a control character "
                            "or malformed UTF-8: " +
                            Excerpt(line));
      break;
    }
    start = end + 1;
  }
  // "input:N:" names a line the input has.
  std::string_view rest = error.substr(std::min(prefix.size(), error.size()));
  int line = 0;
  const auto [end, ec] =
      std::from_chars(rest.data(), rest.data() + rest.size(), line);
  if (ec == std::errc() && end != rest.data() && *end == ':') {
    if (line < 1 || line > CountLines(input)) {
      violations->push_back(std::string(what) + ": the error names line " +
                            std::to_string(line) + " of an input of " +
                            std::to_string(CountLines(input)) +
                            " lines: " + Excerpt(error));
    }
  }
}

void CheckDiagnostics(std::span<const protocols::Diagnostic> diagnostics,
                      std::string_view input, Violations* violations) {
  const int lines = CountLines(input);
  for (const protocols::Diagnostic& d : diagnostics) {
    CheckMessageLine(d.message, "diagnostic", violations);
    if (d.where.line < 0 || d.where.line > lines ||
        (d.where.line > 0 && d.where.column < 1)) {
      violations->push_back(
          "diagnostic at line " + std::to_string(d.where.line) + ", column " +
          std::to_string(d.where.column) + " of an input of " +
          std::to_string(lines) + " lines: " + Excerpt(d.message));
    }
  }
  if (diagnostics.empty()) return;
  const std::string all =
      protocols::FormatDiagnostics(kInputPath, input, diagnostics);
  CheckFormattedError(all, input, "formatted diagnostics", violations);
  // At most kMaxPrintedDiagnostics of three lines each, then a count.
  const auto printed_lines = std::count(all.begin(), all.end(), '\n');
  Expect(printed_lines <= static_cast<std::ptrdiff_t>(
                              3 * protocols::kMaxPrintedDiagnostics + 1),
         "formatted diagnostics: more than 3 lines per printed diagnostic",
         violations);
}

}  // namespace burrlab::fuzz
