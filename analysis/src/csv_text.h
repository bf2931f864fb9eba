// Small text helpers shared by the analysis data-file parsers (counts CSV/TSV,
// _beh.tsv, measured descent CSV): lines with their numbers, cells with their
// columns, strict numbers. Private to analysis/.
#ifndef BURRLAB_ANALYSIS_SRC_CSV_TEXT_H_
#define BURRLAB_ANALYSIS_SRC_CSV_TEXT_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::analysis {

// One cell of a row, trimmed of spaces and tabs.
struct Cell {
  std::string_view text;  // trimmed
  int column = 1;         // 1-based column of the cell's first character
};
// The cells of `line` split at `delimiter`.
std::vector<Cell> SplitRow(std::string_view line, char delimiter);

// A line of a file without its line break: LF, CR LF or a lone CR.
struct Line {
  std::string_view text;
  int number = 0;  // 1-based
};
std::vector<Line> SplitLines(std::string_view text);

// Only spaces and tabs.
bool IsBlank(std::string_view line);

// The whole text as a finite number (no NaN, infinity, overflow or trailing
// characters).
std::optional<double> ParseFinite(std::string_view text);

// The whole file; "cannot read PATH: reason" when it cannot be read.
Result<std::string> ReadTextFile(const std::string& path);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_SRC_CSV_TEXT_H_
