// Small text helpers shared by the results_schema sources (not public).
#ifndef BURRLAB_RESULTS_SCHEMA_SRC_TEXT_H_
#define BURRLAB_RESULTS_SCHEMA_SRC_TEXT_H_

#include <string>
#include <string_view>
#include <vector>

namespace burrlab::results_schema {

// The text of a missing value in the BIDS-style .tsv tables.
inline constexpr std::string_view kNa = "n/a";

// `text` in double quotes for error messages; bytes that are not printable
// ASCII, quotes and backslashes are escaped (\xC3, \", \\).
std::string Quoted(std::string_view text);

// One character for an error message: '_' or "byte 0xC3".
std::string DescribeChar(char c);

// True when `text` is well-formed UTF-8 (no overlong forms or surrogates).
bool IsValidUtf8(std::string_view text);

// True for [a-z][a-z0-9_]*.
bool IsSnakeCase(std::string_view text);

// The lines of a table file as a spreadsheet may save it: a UTF-8 byte order
// mark at the start is skipped, lines end at '\n' with a '\r' before it
// dropped (CRLF), and no empty line follows a final '\n'.
std::vector<std::string_view> TextLines(std::string_view text);

// Shortest text that reads back as exactly `value` ("0.1", "1", "1e+20").
std::string FormatDouble(double value);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_SRC_TEXT_H_
