// Lines, cells and strict numbers for the analysis data-file parsers.
#include "csv_text.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "burrlab/analysis/psychometric_data.h"

namespace burrlab::analysis {

std::vector<Cell> SplitRow(std::string_view line, char delimiter) {
  std::vector<Cell> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = line.find(delimiter, start);
    std::string_view cell = line.substr(start, end == std::string_view::npos
                                                   ? std::string_view::npos
                                                   : end - start);
    std::size_t lead = 0;
    while (lead < cell.size() && (cell[lead] == ' ' || cell[lead] == '\t')) {
      ++lead;
    }
    cell.remove_prefix(lead);
    while (!cell.empty() && (cell.back() == ' ' || cell.back() == '\t')) {
      cell.remove_suffix(1);
    }
    cells.push_back({cell, static_cast<int>(start + lead) + 1});
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return cells;
}

std::vector<Line> SplitLines(std::string_view text) {
  std::vector<Line> lines;
  std::size_t start = 0;
  int number = 1;
  while (start < text.size()) {
    // LF (Unix), CR LF (Windows) or a lone CR (old Mac spreadsheets).
    std::size_t end = text.find_first_of("\r\n", start);
    if (end == std::string_view::npos) end = text.size();
    lines.push_back({text.substr(start, end - start), number++});
    start = end + 1;
    if (end + 1 < text.size() && text[end] == '\r' && text[end + 1] == '\n') {
      ++start;
    }
  }
  return lines;
}

bool IsBlank(std::string_view line) {
  return std::all_of(line.begin(), line.end(),
                     [](char c) { return c == ' ' || c == '\t'; });
}

std::optional<double> ParseFinite(std::string_view text) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end ||
      !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

Result<CsvTable> CsvTable::Split(std::string_view path, std::string_view text,
                                 Delimiter delimiter,
                                 std::string_view empty_message) {
  CsvTable table;
  table.path_ = path;
  table.whole_ = text;
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  table.lines_ = SplitLines(text);
  std::erase_if(table.lines_, [](const Line& l) { return IsBlank(l.text); });
  if (table.lines_.empty()) return table.Fail(0, 0, empty_message);
  const std::string_view header = table.lines_.front().text;
  table.delimiter_ = delimiter == Delimiter::kTabOrComma &&
                             header.find('\t') != std::string_view::npos
                         ? '\t'
                         : ',';
  table.header_ = SplitRow(header, table.delimiter_);
  return table;
}

int CsvTable::Find(std::string_view column) const {
  for (std::size_t k = 0; k < header_.size(); ++k) {
    if (header_[k].text == column) return static_cast<int>(k);
  }
  return -1;
}

Status CsvTable::CheckDistinctColumns() const {
  for (std::size_t k = 0; k < header_.size(); ++k) {
    for (std::size_t m = 0; m < k; ++m) {
      if (!header_[k].text.empty() && header_[k].text == header_[m].text) {
        return Fail(header_line().number, header_[k].column,
                    fmt::format("the column {} appears twice in the header",
                                header_[k].text));
      }
    }
  }
  return {};
}

Result<std::vector<Cell>> CsvTable::Cells(const Line& row) const {
  std::vector<Cell> cells = SplitRow(row.text, delimiter_);
  if (cells.size() != header_.size()) {
    return Fail(row.number, 1,
                fmt::format("the row has {} cells, the header {}", cells.size(),
                            header_.size()));
  }
  return cells;
}

Error CsvTable::Fail(int line, int column, std::string_view message) const {
  return Error{FormatDataDiagnostic(path_, whole_, line, column, message)};
}

}  // namespace burrlab::analysis
