// participants.tsv and participants.json: the experimenter's table read,
// checked for personal columns, and merged into the dataset's.
#include "burrlab/results_schema/participants.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <system_error>

#include "burrlab/base/file_text.h"
#include "burrlab/results_schema/records.h"
#include "file_writes.h"
#include "text.h"

namespace burrlab::results_schema {
namespace fs = std::filesystem;
namespace {

using OrderedJson = nlohmann::ordered_json;

constexpr std::string_view kIdColumn = "participant_id";

// Why a column named `name` would hold personal data, or empty.
std::string_view PersonalColumnReason(std::string_view name) {
  std::string letters;  // lower-case letters only: "First Name" -> firstname
  std::vector<std::string> words;
  std::string word;
  for (char c : name) {
    const char lower =
        (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
    if (lower >= 'a' && lower <= 'z') {
      letters += lower;
      word += lower;
    } else if (!word.empty()) {
      words.push_back(std::move(word));
      word.clear();
    }
  }
  if (!word.empty()) words.push_back(std::move(word));
  if (letters.find("name") != std::string::npos ||
      letters.find("initials") != std::string::npos) {
    return "a personal name";
  }
  if (letters.find("birth") != std::string::npos ||
      std::find(words.begin(), words.end(), "dob") != words.end()) {
    return "a date of birth";
  }
  return {};
}

// A participants table as read: its columns (without participant_id) in
// order and its rows (values in column order).
struct Table {
  std::vector<std::string> columns;
  std::vector<ParticipantRow> rows;
};

// One cell of a line and its 0-based byte offset.
struct TableCell {
  std::string text;
  std::size_t offset = 0;
};

std::string Trimmed(std::string_view text) {
  const std::size_t first = text.find_first_not_of(' ');
  if (first == std::string_view::npos) return {};
  const std::size_t last = text.find_last_not_of(' ');
  return std::string(text.substr(first, last - first + 1));
}

// Splits `line` at `delimiter`; with a comma or semicolon a cell may be
// quoted ("a, b", "say ""hi"""). Surrounding spaces are dropped. The error
// names the 0-based offset where the problem starts.
Result<std::vector<TableCell>> SplitLine(std::string_view line, char delimiter,
                                         std::size_t* error_offset) {
  std::vector<TableCell> cells;
  std::size_t i = 0;
  while (true) {
    TableCell cell;
    cell.offset = i;
    std::size_t start = i;
    while (start < line.size() && line[start] == ' ') ++start;
    if (delimiter != '\t' && start < line.size() && line[start] == '"') {
      std::string text;
      std::size_t k = start + 1;
      bool closed = false;
      while (k < line.size()) {
        if (line[k] == '"') {
          if (k + 1 < line.size() && line[k + 1] == '"') {
            text += '"';
            k += 2;
            continue;
          }
          closed = true;
          ++k;
          break;
        }
        text += line[k++];
      }
      if (!closed) {
        *error_offset = start;
        return Error{
            "a quoted cell runs past the end of the line (a cell is one "
            "line)"};
      }
      while (k < line.size() && line[k] == ' ') ++k;
      if (k < line.size() && line[k] != delimiter) {
        *error_offset = k;
        return Error{
            "text after the closing quote of a cell; put the whole cell in "
            "quotes, with \"\" for a quote inside"};
      }
      cell.text = std::move(text);
      cells.push_back(std::move(cell));
      if (k >= line.size()) break;
      i = k + 1;
      continue;
    }
    const std::size_t end = line.find(delimiter, i);
    cell.text = Trimmed(line.substr(i, end - i));
    cells.push_back(std::move(cell));
    if (end == std::string_view::npos) break;
    i = end + 1;
  }
  return cells;
}

Result<Table> ParseTable(std::string_view path, std::string_view text) {
  const auto fail = [&](std::size_t line, std::size_t offset,
                        std::string_view what) {
    return Error{line > 0 ? fmt::format("{}:{}:{}: error: {}", path, line,
                                        offset + 1, what)
                          : fmt::format("{}: error: {}", path, what)};
  };
  const std::vector<std::string_view> lines = TextLines(text);
  if (lines.empty() || Trimmed(lines[0]).empty()) {
    return fail(0, 0,
                "the file is empty; expected a header line naming the "
                "columns, participant_id first");
  }
  const std::string_view header_line = lines[0];
  const char delimiter = header_line.find('\t') != std::string_view::npos ? '\t'
                         : header_line.find(',') == std::string_view::npos &&
                                 header_line.find(';') != std::string_view::npos
                             ? ';'
                             : ',';
  std::size_t offset = 0;
  Result<std::vector<TableCell>> header =
      SplitLine(header_line, delimiter, &offset);
  if (!header) return fail(1, offset, header.error().message);
  std::optional<std::size_t> id;
  Table table;
  std::vector<std::size_t> value_cells;  // header index of each column
  for (std::size_t k = 0; k < header->size(); ++k) {
    const TableCell& cell = (*header)[k];
    if (cell.text == kIdColumn) {
      if (id) {
        return fail(1, cell.offset, "participant_id is named twice");
      }
      id = k;
      continue;
    }
    if (cell.text.empty()) {
      return fail(1, cell.offset, fmt::format("column {} has no name", k + 1));
    }
    if (Status s = CheckParticipantColumn(cell.text); !s) {
      return fail(1, cell.offset, s.error().message);
    }
    if (std::find(table.columns.begin(), table.columns.end(), cell.text) !=
        table.columns.end()) {
      return fail(1, cell.offset,
                  fmt::format("column {} is named twice", Quoted(cell.text)));
    }
    table.columns.push_back(cell.text);
    value_cells.push_back(k);
  }
  if (!id) {
    return fail(1, 0,
                "the header has no participant_id column (the subjects' "
                "labels, e.g. sub-01 or 01)");
  }
  std::map<std::string, std::size_t> first_line;  // label -> line
  for (std::size_t n = 1; n < lines.size(); ++n) {
    const std::size_t line = n + 1;
    Result<std::vector<TableCell>> cells =
        SplitLine(lines[n], delimiter, &offset);
    if (!cells) return fail(line, offset, cells.error().message);
    if (std::all_of(cells->begin(), cells->end(),
                    [](const TableCell& c) { return c.text.empty(); })) {
      continue;  // a blank line, or a spreadsheet's empty row
    }
    if (cells->size() != header->size()) {
      return fail(line, 0,
                  fmt::format("{} cells, but the header has {} columns",
                              cells->size(), header->size()));
    }
    const TableCell& id_cell = (*cells)[*id];
    std::string label = id_cell.text;
    if (label.starts_with("sub-")) label.erase(0, 4);
    if (Status s = ValidateSubjectLabel(label); !s) {
      return fail(line, id_cell.offset,
                  fmt::format("participant_id {}: {}", Quoted(id_cell.text),
                              s.error().message));
    }
    if (const auto [it, added] = first_line.emplace(label, line); !added) {
      return fail(line, id_cell.offset,
                  fmt::format("participant_id sub-{} appears twice (lines {} "
                              "and {}); give each subject one row",
                              label, it->second, line));
    }
    ParticipantRow row;
    row.subject = label;
    for (std::size_t c = 0; c < value_cells.size(); ++c) {
      const TableCell& cell = (*cells)[value_cells[c]];
      std::string value = cell.text.empty() ? std::string(kNa) : cell.text;
      if (Status s = CheckParticipantValue(table.columns[c], value); !s) {
        return fail(line, cell.offset, s.error().message);
      }
      row.values.push_back({table.columns[c], std::move(value)});
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

// Reads DIR/participants.tsv (an empty table when absent).
Result<Table> ReadParticipantsTsv(const fs::path& dir) {
  const fs::path path = dir / "participants.tsv";
  std::error_code ec;
  if (fs::symlink_status(path, ec).type() == fs::file_type::not_found) {
    return Table{};
  }
  Result<std::string> text = ReadTextFile(path.string(), kMaxParticipantsBytes);
  if (!text) return text.error();
  return ParseTable(path.string(), *text);
}

// Reads DIR/participants.json (an empty object when absent).
Result<OrderedJson> ReadParticipantsJson(const fs::path& dir) {
  const fs::path path = dir / "participants.json";
  std::error_code ec;
  if (fs::symlink_status(path, ec).type() == fs::file_type::not_found) {
    return OrderedJson::object();
  }
  Result<std::string> text = ReadTextFile(path.string(), kMaxParticipantsBytes);
  if (!text) return text.error();
  OrderedJson json = OrderedJson::parse(*text, nullptr, false);
  if (json.is_discarded() || !json.is_object()) {
    return Error{fmt::format(
        "{}: error: not a JSON object (BIDS: one description per column of "
        "participants.tsv); fix or remove the file",
        path.string())};
  }
  return json;
}

OrderedJson Describe(const ParticipantColumn& column) {
  OrderedJson j;
  j["Description"] = column.description;
  if (!column.units.empty()) j["Units"] = column.units;
  for (const auto& [value, meaning] : column.levels) {
    j["Levels"][value] = meaning;
  }
  return j;
}

// Holds an exclusive flock on a folder (released on destruction).
class FolderLock {
 public:
  static Result<FolderLock> Take(const fs::path& dir) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) {
      return Error{fmt::format("cannot open folder {}: {}", dir.string(),
                               std::strerror(errno))};
    }
    int rc = 0;
    do {
      rc = ::flock(fd, LOCK_EX);
    } while (rc != 0 && errno == EINTR);
    if (rc != 0) {
      const int err = errno;
      ::close(fd);
      return Error{fmt::format("cannot lock folder {}: {}", dir.string(),
                               std::strerror(err))};
    }
    return FolderLock(fd);
  }
  FolderLock(FolderLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  FolderLock& operator=(FolderLock&&) = delete;
  ~FolderLock() {
    if (fd_ >= 0) ::close(fd_);
  }

 private:
  explicit FolderLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

Status Update(const fs::path& dir, std::span<const ParticipantRow> rows,
              std::span<const ParticipantColumn> columns) {
  for (const ParticipantRow& row : rows) {
    if (Status s = ValidateSubjectLabel(row.subject); !s) return s;
    for (const ParticipantValue& v : row.values) {
      if (Status s = CheckParticipantColumn(v.column); !s) return s;
      if (Status s = CheckParticipantValue(v.column, v.value); !s) return s;
    }
  }
  Result<FolderLock> lock = FolderLock::Take(dir);
  if (!lock) return lock.error();
  RemoveStaleTempFiles(dir);
  Result<Table> table = ReadParticipantsTsv(dir);
  if (!table) return table.error();
  Result<OrderedJson> kept = ReadParticipantsJson(dir);
  if (!kept) return kept.error();

  // label -> column -> value
  std::map<std::string, std::map<std::string, std::string>> cells;
  for (const ParticipantRow& row : table->rows) {
    for (const ParticipantValue& v : row.values) {
      cells[row.subject][v.column] = v.value;
    }
  }
  std::vector<std::string>& order = table->columns;
  for (const ParticipantRow& row : rows) {
    auto& mine = cells[row.subject];  // a new subject gets a row
    for (const ParticipantValue& v : row.values) {
      if (std::find(order.begin(), order.end(), v.column) == order.end()) {
        order.push_back(v.column);
      }
      mine[v.column] = v.value;
    }
  }
  std::string tsv(kIdColumn);
  for (const std::string& column : order) tsv += "\t" + column;
  tsv += '\n';
  for (const auto& [label, values] : cells) {
    tsv += "sub-" + label;
    for (const std::string& column : order) {
      const auto it = values.find(column);
      tsv += '\t';
      tsv += it != values.end() ? it->second : std::string(kNa);
    }
    tsv += '\n';
  }

  OrderedJson json;
  std::vector<std::string> described = {std::string(kIdColumn)};
  described.insert(described.end(), order.begin(), order.end());
  for (const std::string& column : described) {
    if (kept->contains(column)) {
      json[column] = (*kept)[column];
      continue;
    }
    const auto given = std::find_if(
        columns.begin(), columns.end(),
        [&](const ParticipantColumn& c) { return c.name == column; });
    const auto& known = KnownParticipantColumns();
    const auto builtin = std::find_if(
        known.begin(), known.end(),
        [&](const ParticipantColumn& c) { return c.name == column; });
    if (given != columns.end()) {
      json[column] = Describe(*given);
    } else if (builtin != known.end()) {
      json[column] = Describe(*builtin);
    } else {
      json[column] = Describe(
          {column,
           fmt::format("{}, as the experimenter recorded it for the subject "
                       "(burrlab run --participant {}=VALUE, or a column of "
                       "the --participants table)",
                       column, column),
           "",
           {}});
    }
  }
  for (const auto& [key, value] : kept->items()) {
    if (!json.contains(key)) json[key] = value;  // kept as the file had it
  }
  if (Status s = ReplaceFile(dir / "participants.tsv", tsv); !s) return s;
  return ReplaceFile(
      dir / "participants.json",
      json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
          "\n");
}

}  // namespace

Status CheckParticipantColumn(std::string_view name) {
  if (name.empty()) return Error{"a column name is empty"};
  if (const std::string_view why = PersonalColumnReason(name); !why.empty()) {
    return Error{fmt::format(
        "column {} looks like {}; burrlab keeps subjects pseudonymous "
        "(sub-<label>) and stores no names or dates of birth: leave the "
        "column out{}",
        Quoted(name), why,
        why == "a date of birth" ? " (age in years is fine)" : "")};
  }
  if (name == kIdColumn) {
    return Error{
        "column \"participant_id\" is the subject's label, which burrlab "
        "writes itself"};
  }
  if (!IsSnakeCase(name)) {
    return Error{fmt::format(
        "column {} is not snake_case; use lower-case letters, digits and "
        "underscores, starting with a letter (e.g. age, years_of_practice)",
        Quoted(name))};
  }
  return {};
}

Status CheckParticipantValue(std::string_view column, std::string_view value) {
  if (value.empty()) {
    return Error{
        fmt::format("the value of {} is empty (write n/a for none)", column)};
  }
  if (!IsValidUtf8(value)) {
    return Error{fmt::format("the value of {} {} is not valid UTF-8", column,
                             Quoted(value))};
  }
  if (value.find_first_of("\t\r\n") != std::string_view::npos) {
    return Error{fmt::format("the value of {} {} has a tab or line break",
                             column, Quoted(value))};
  }
  return {};
}

Result<ParticipantValue> ParseParticipantPair(std::string_view text) {
  const auto fail = [&](std::string_view what) {
    return Error{fmt::format("--participant {}: {}", Quoted(text), what)};
  };
  const std::size_t equals = text.find('=');
  if (equals == std::string_view::npos) {
    return fail("expected key=value, e.g. age=34");
  }
  ParticipantValue v{std::string(text.substr(0, equals)),
                     std::string(text.substr(equals + 1))};
  if (Status s = CheckParticipantColumn(v.column); !s) {
    return fail(s.error().message);
  }
  if (Status s = CheckParticipantValue(v.column, v.value); !s) {
    return fail(s.error().message);
  }
  return v;
}

Result<std::vector<ParticipantRow>> ParseParticipantsTable(
    std::string_view path, std::string_view text) {
  try {
    Result<Table> table = ParseTable(path, text);
    if (!table) return table.error();
    return std::move(table->rows);
  } catch (const std::exception& e) {
    return Error{fmt::format("{}: error: internal error: {}", path, e.what())};
  }
}

const std::vector<ParticipantColumn>& KnownParticipantColumns() {
  static const std::vector<ParticipantColumn> kColumns = {
      {"participant_id",
       "The subject's label, sub-<label>, as in the subject's folder name "
       "(pseudonymous: letters and digits only)",
       "",
       {}},
      {"age", "Age of the participant", "year", {}},
      {"sex",
       "Sex of the participant as reported by the participant (BIDS: M or "
       "male, F or female, O or other)",
       "",
       {}},
      {"handedness",
       "Handedness of the participant as reported by the participant (BIDS: "
       "R or right, L or left, A or ambidextrous)",
       "",
       {}},
      {"group",
       "Group the participant belongs to in the study design (e.g. expert, "
       "novice)",
       "",
       {}},
  };
  return kColumns;
}

Status CheckParticipantsFiles(const fs::path& dir) {
  try {
    if (Result<Table> table = ReadParticipantsTsv(dir); !table) {
      return table.error();
    }
    if (Result<OrderedJson> json = ReadParticipantsJson(dir); !json) {
      return json.error();
    }
    return {};
  } catch (const std::exception& e) {
    return Error{
        fmt::format("cannot read the participants of {}: internal "
                    "error: {}",
                    dir.string(), e.what())};
  }
}

Status UpdateParticipants(const fs::path& dir,
                          std::span<const ParticipantRow> rows,
                          std::span<const ParticipantColumn> columns) {
  try {
    return Update(dir, rows, columns);
  } catch (const std::exception& e) {
    return Error{
        fmt::format("cannot update the participants of {}: internal "
                    "error: {}",
                    dir.string(), e.what())};
  }
}

}  // namespace burrlab::results_schema
