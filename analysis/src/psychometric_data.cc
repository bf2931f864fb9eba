// CSV/TSV counts and _beh.tsv trial logs turned into psychometric blocks,
// with a diagnostic naming the line and column of the first problem.
#include "burrlab/analysis/psychometric_data.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "burrlab/base/printable.h"
#include "csv_text.h"

namespace burrlab::analysis {
namespace {

constexpr std::string_view kNa = "n/a";
// The most trials a level can pool (DataBlock counts are int).
constexpr std::int64_t kMaxTrialsPerLevel = std::numeric_limits<int>::max();

// The rows of one level so far.
struct Pool {
  std::int64_t n_correct = 0;
  std::int64_t n_total = 0;
  int first_line = 0;  // 1-based line of the level's first row
};

std::optional<int> ParseWhole(std::string_view text) {
  int value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

}  // namespace

std::string FormatDataDiagnostic(std::string_view path, std::string_view text,
                                 int line, int column,
                                 std::string_view message) {
  // Cells and header names quoted in `message` and the source line are the
  // file's bytes: escaped, so none reaches the terminal as a control.
  if (line <= 0) {
    return fmt::format("{}: error: {}", path, PrintableText(message));
  }
  // The parsers count columns after a UTF-8 byte-order mark, and a terminal
  // shows none: the quoted line starts after it too.
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  std::string_view source;
  for (const Line& l : SplitLines(text)) {
    if (l.number == line) {
      source = l.text;
      break;
    }
  }
  // `column` counts bytes; the caret counts code points.
  int caret_column = 1;
  for (int i = 0; i + 1 < column; ++i) {
    const bool continuation =
        static_cast<std::size_t>(i) < source.size() &&
        (static_cast<unsigned char>(source[static_cast<std::size_t>(i)]) &
         0xc0) == 0x80;
    if (!continuation) ++caret_column;
  }
  return fmt::format("{}:{}:{}: error: {}\n{}", path, line, column,
                     PrintableText(message),
                     QuoteLineWithCaret(source, caret_column));
}

Result<PsychometricDataFile> ParsePsychometricData(std::string_view path,
                                                   std::string_view text,
                                                   std::string_view by) {
  Result<CsvTable> table = CsvTable::Split(
      path, text, CsvTable::Delimiter::kTabOrComma,
      "the file is empty; expected a header line level,n_correct,n_total (CSV "
      "or TSV) or a _beh.tsv with stim_level and correct columns");
  if (!table.ok()) return table.error();
  const auto fail = [&](int line, int column, const std::string& message) {
    return table->Fail(line, column, message);
  };
  const auto find = [&](std::string_view name) { return table->Find(name); };
  const Line& header_line = table->header_line();
  const char delimiter = table->delimiter();
  PsychometricDataFile file;
  const int level_at = find("level"), correct_at = find("n_correct"),
            total_at = find("n_total");
  const int stim_at = find("stim_level"), trial_at = find("correct");
  const int practice_at = find("practice");
  const int unit_at = find("stim_unit");
  const int by_at = by.empty() ? -1 : find(by);
  if (level_at >= 0 && correct_at >= 0 && total_at >= 0) {
    file.format = PsychometricDataFile::Format::kCounts;
  } else if (stim_at >= 0 && trial_at >= 0) {
    file.format = PsychometricDataFile::Format::kTrials;
  } else {
    return fail(header_line.number, 1,
                fmt::format("the header names neither level, n_correct and "
                            "n_total nor stim_level and correct (a _beh.tsv); "
                            "columns are separated by {}",
                            delimiter == '\t' ? "tabs" : "commas"));
  }
  if (!by.empty() && by_at < 0) {
    return fail(header_line.number, 1,
                fmt::format("the header has no column '{}' to split the rows "
                            "by",
                            by));
  }
  // Rows pooled by level: the order of the rows cannot change the fit (the
  // bootstrap draws level by level, in increasing order), and the work after
  // parsing depends on the number of levels, not of rows.
  std::map<double, Pool> pooled;
  // With `by`: per condition, in order of first appearance.
  std::vector<std::pair<std::string, std::map<double, Pool>>> by_condition;
  std::map<double, Pool>* condition = nullptr;
  const auto add = [&](double x, int n_correct, int n_total, const Line& line,
                       const Cell& at) -> std::optional<Error> {
    if (condition != nullptr) {
      Pool& own = (*condition)[x];
      if (own.n_total == 0) own.first_line = line.number;
      own.n_correct += n_correct;
      own.n_total += n_total;
    }
    Pool& pool = pooled[x];
    if (pool.n_total == 0) pool.first_line = line.number;
    pool.n_correct += n_correct;
    pool.n_total += n_total;
    ++file.rows;
    if (pool.n_total > kMaxTrialsPerLevel) {
      return fail(line.number, at.column,
                  fmt::format("the rows with level {} add up to more than {} "
                              "trials",
                              x, kMaxTrialsPerLevel));
    }
    return std::nullopt;
  };
  for (const Line& line : table->rows()) {
    Result<std::vector<Cell>> row = table->Cells(line);
    if (!row.ok()) return row.error();
    const std::vector<Cell>& cells = *row;
    const auto cell = [&](int k) { return cells[static_cast<std::size_t>(k)]; };
    if (by_at >= 0) {
      const Cell name = cell(by_at);
      if (name.text.empty()) {
        return fail(line.number, name.column,
                    fmt::format("the {} cell is empty: every row needs a "
                                "condition",
                                by));
      }
      auto it =
          std::find_if(by_condition.begin(), by_condition.end(),
                       [&](const auto& c) { return c.first == name.text; });
      if (it == by_condition.end()) {
        by_condition.emplace_back(std::string(name.text),
                                  std::map<double, Pool>());
        it = by_condition.end() - 1;
      }
      condition = &it->second;
    }
    if (unit_at >= 0 && file.stim_unit.empty() && cell(unit_at).text != kNa) {
      file.stim_unit = std::string(cell(unit_at).text);
    }
    if (file.format == PsychometricDataFile::Format::kCounts) {
      const Cell level = cell(level_at), r = cell(correct_at),
                 total = cell(total_at);
      const std::optional<double> x = ParseFinite(level.text);
      if (!x) {
        return fail(
            line.number, level.column,
            fmt::format("level '{}' is not a finite number", level.text));
      }
      const std::optional<int> n_total = ParseWhole(total.text);
      if (!n_total || *n_total < 1) {
        return fail(line.number, total.column,
                    fmt::format("n_total '{}' is not a whole number of at "
                                "least 1",
                                total.text));
      }
      const std::optional<int> n_correct = ParseWhole(r.text);
      if (!n_correct || *n_correct < 0) {
        return fail(line.number, r.column,
                    fmt::format("n_correct '{}' is not a whole number of at "
                                "least 0",
                                r.text));
      }
      if (*n_correct > *n_total) {
        return fail(line.number, r.column,
                    fmt::format("n_correct = {} exceeds n_total = {}",
                                *n_correct, *n_total));
      }
      if (std::optional<Error> e = add(*x, *n_correct, *n_total, line, total)) {
        return *e;
      }
      continue;
    }
    const Cell level = cell(stim_at), correct = cell(trial_at);
    if (practice_at >= 0 && cell(practice_at).text == "1") {
      ++file.practice_rows;  // familiarization (§13.5.1): never fitted
      continue;
    }
    if (level.text == kNa || correct.text == kNa) {
      ++file.skipped_rows;
      continue;
    }
    const std::optional<double> x = ParseFinite(level.text);
    if (!x) {
      return fail(line.number, level.column,
                  fmt::format("stim_level '{}' is not a finite number or n/a",
                              level.text));
    }
    if (correct.text != "0" && correct.text != "1") {
      return fail(
          line.number, correct.column,
          fmt::format("correct '{}' must be 1, 0 or n/a", correct.text));
    }
    if (std::optional<Error> e =
            add(*x, correct.text == "1" ? 1 : 0, 1, line, level)) {
      return *e;
    }
  }
  const auto to_blocks = [&](const std::map<double, Pool>& pools,
                             std::vector<DataBlock>& blocks,
                             std::vector<int>& lines) {
    for (const auto& [level, pool] : pools) {
      blocks.push_back({level, static_cast<int>(pool.n_correct),
                        static_cast<int>(pool.n_total)});
      if (file.format == PsychometricDataFile::Format::kCounts) {
        lines.push_back(pool.first_line);
      }
    }
  };
  to_blocks(pooled, file.blocks, file.lines);
  for (const auto& [name, pools] : by_condition) {
    PsychometricDataFile::Condition c;
    c.name = name;
    to_blocks(pools, c.blocks, c.lines);
    file.conditions.push_back(std::move(c));
  }
  if (file.blocks.empty()) {
    return fail(0, 0,
                file.format == PsychometricDataFile::Format::kCounts
                    ? std::string("no data rows after the header")
                    : fmt::format("no trial with a stim_level and a correct "
                                  "answer ({} rows with n/a skipped{})",
                                  file.skipped_rows,
                                  file.practice_rows > 0
                                      ? fmt::format(", {} practice trials "
                                                    "left out",
                                                    file.practice_rows)
                                      : std::string()));
  }
  return file;
}

Result<PsychometricDataFile> ReadPsychometricData(const std::string& path,
                                                  std::string_view by) {
  Result<std::string> text = ReadTextFile(path);
  if (!text.ok()) return text.error();
  return ParsePsychometricData(path, *text, by);
}

}  // namespace burrlab::analysis
