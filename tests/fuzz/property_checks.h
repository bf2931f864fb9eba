// Properties every fuzz target checks of an error or diagnostic: non-empty,
// printable (no raw control characters or malformed UTF-8, as
// burrlab/base/printable.h escapes them), naming the file, and pointing at a
// line the input has. Each failed check appends one line to a Violations.
#ifndef BURRLAB_TESTS_FUZZ_PROPERTY_CHECKS_H_
#define BURRLAB_TESTS_FUZZ_PROPERTY_CHECKS_H_

#include <span>
#include <string>
#include <string_view>

#include "burrlab/protocols/protocol.h"
#include "fuzz_targets.h"

namespace burrlab::fuzz {

// The file name every target passes to its parser.
inline constexpr std::string_view kInputPath = "input";

// Lines of `text` under the widest reading (LF, CR LF or a lone CR each end a
// line, as the CSV readers split them): no parser may name a line beyond it.
int CountLines(std::string_view text);

// `condition`, or a violation reading `what`.
void Expect(bool condition, std::string_view what, Violations* violations);

// A one-line message: non-empty, no line break, printable.
void CheckMessageLine(std::string_view message, std::string_view what,
                      Violations* violations);

// A formatted error of one or more lines ("path:line:col: error: ...", then
// the source line and a caret): non-empty, starts with "<kInputPath>:",
// every line printable (tabs allowed: a quoted source line keeps them), and
// any "path:N:" names a line 1..CountLines(input).
void CheckFormattedError(std::string_view error, std::string_view input,
                         std::string_view what, Violations* violations);

// Diagnostics of a (path, text) parser: each message a printable line, each
// place 0 (none) or a line of the input with a column >= 1; and what
// protocols::FormatDiagnostics prints of them a well-formed error.
void CheckDiagnostics(std::span<const protocols::Diagnostic> diagnostics,
                      std::string_view input, Violations* violations);

// Runs `body` and turns any exception escaping it into a violation.
template <typename Body>
Violations Guarded(std::string_view target, Body body) {
  Violations violations;
  try {
    body(&violations);
  } catch (const std::exception& e) {
    violations.push_back(std::string(target) +
                         ": an exception escaped: " + e.what());
  } catch (...) {
    violations.push_back(std::string(target) +
                         ": a non-standard exception escaped");
  }
  return violations;
}

}  // namespace burrlab::fuzz

#endif  // BURRLAB_TESTS_FUZZ_PROPERTY_CHECKS_H_
