// Small text helpers shared by the analysis data-file parsers (counts CSV/TSV,
// _beh.tsv, measured descent CSV, trace CSV): lines with their numbers, cells
// with their columns, strict numbers, and the prologue every one of them
// shares (CsvTable). Private to analysis/.
#ifndef BURRLAB_ANALYSIS_SRC_CSV_TEXT_H_
#define BURRLAB_ANALYSIS_SRC_CSV_TEXT_H_

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/file_text.h"
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

// A data file's text after the prologue every analysis CSV/TSV reader shares:
// a spreadsheet's UTF-8 byte-order mark skipped, the lines split (LF, CR LF or
// CR), blank lines dropped, the first line split as the header. Diagnostics
// name the file, line and column (FormatDataDiagnostic). The table views
// `text`, which must outlive it.
class CsvTable {
 public:
  // How cells are separated: commas, or tabs when the header holds a tab
  // (a _beh.tsv), else commas.
  enum class Delimiter { kComma, kTabOrComma };

  // The table of `text`; an error with `empty_message` when no line holds
  // more than spaces and tabs.
  static Result<CsvTable> Split(std::string_view path, std::string_view text,
                                Delimiter delimiter,
                                std::string_view empty_message);

  const Line& header_line() const { return lines_.front(); }
  const std::vector<Cell>& header() const { return header_; }
  char delimiter() const { return delimiter_; }
  // The lines after the header.
  std::span<const Line> rows() const {
    return std::span<const Line>(lines_).subspan(1);
  }
  // The header's index of `column`, -1 when it has none.
  int Find(std::string_view column) const;
  // The first column the header names a second time, as an error at its
  // second place.
  Status CheckDistinctColumns() const;
  // The cells of `row`; an error when there are more or fewer than the
  // header's.
  Result<std::vector<Cell>> Cells(const Line& row) const;
  // An error at `line` and `column` of the file (line 0: the whole file).
  Error Fail(int line, int column, std::string_view message) const;

 private:
  std::string_view path_, whole_;
  std::vector<Line> lines_;
  std::vector<Cell> header_;
  char delimiter_ = ',';
};

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_SRC_CSV_TEXT_H_
