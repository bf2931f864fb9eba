// participants.tsv and participants.json at a dataset's root (BIDS): one row
// per subject, participant_id (sub-<label>) first, then what the experimenter
// records of the subject (age, sex, handedness, group, ...) and, for
// simulated subjects, the simulated observer's true parameters; the JSON file
// describes every column. Runs merge their subject's row into the table: a
// later run updates its subject's cells and keeps the other rows and cells;
// columns are the union of all runs' (n/a where a subject has no value).
// Labels are pseudonymous: a column whose name looks like a personal name or
// a date of birth is refused, wherever it comes from.
#ifndef BURRLAB_RESULTS_SCHEMA_PARTICIPANTS_H_
#define BURRLAB_RESULTS_SCHEMA_PARTICIPANTS_H_

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::results_schema {

// Largest participants table read (bytes): a million subjects of typical
// rows.
inline constexpr std::uintmax_t kMaxParticipantsBytes = 64ull << 20;

// One cell of a subject's row.
struct ParticipantValue {
  std::string column;  // snake_case (CheckParticipantColumn)
  std::string value;   // one line; "n/a" for none

  // Field-by-field equality.
  bool operator==(const ParticipantValue&) const = default;
};

// A subject's row, without participant_id.
struct ParticipantRow {
  std::string subject;                   // label without "sub-"
  std::vector<ParticipantValue> values;  // in the order given; names distinct

  // Field-by-field equality.
  bool operator==(const ParticipantRow&) const = default;
};

// How participants.json describes a column (BIDS column description).
struct ParticipantColumn {
  std::string name;
  std::string description;
  std::string units;                                        // empty: none
  std::vector<std::pair<std::string, std::string>> levels;  // value, meaning
};

// OK when `name` can head a participants.tsv column: snake_case
// ([a-z][a-z0-9_]*), not participant_id (the subject's label), and not a
// name that looks like a personal name or a date of birth (name, first_name,
// surname, full_name, dob, birth_date, date_of_birth, birthday, ...): 'column
// "first_name" looks like a personal name; burrlab keeps subjects
// pseudonymous (sub-<label>) and stores no names or dates of birth: leave the
// column out'.
Status CheckParticipantColumn(std::string_view name);

// OK when `value` can be a cell of column `column`: non-empty, valid UTF-8,
// one line without tabs.
Status CheckParticipantValue(std::string_view column, std::string_view value);

// "age=34" (`burrlab run --participant age=34`) -> {"age", "34"}; the column
// is checked as above, the value as a cell.
Result<ParticipantValue> ParseParticipantPair(std::string_view text);

// The rows of a participants table the experimenter keeps, as a spreadsheet
// saves it: CSV (comma or, without a comma in the header, semicolon; cells
// may be quoted with "") or TSV (a tab in the header), with or without a
// UTF-8 byte order mark, lines ending in LF or CRLF. The header names the
// columns (checked as above, surrounding spaces dropped); participant_id
// holds each subject's label (sub-01 or 01); empty cells become n/a; blank
// lines are skipped. Errors read "path:line:col: error: ...", e.g. a
// participant_id that appears twice.
Result<std::vector<ParticipantRow>> ParseParticipantsTable(
    std::string_view path, std::string_view text);

// The columns burrlab describes itself (participant_id, age, sex,
// handedness, group), as participants.json gives them.
const std::vector<ParticipantColumn>& KnownParticipantColumns();

// OK when DIR/participants.tsv (and participants.json) are absent or can be
// merged into: the checks UpdateParticipants makes before it writes, so a run
// can refuse a bad table before its session starts.
Status CheckParticipantsFiles(const std::filesystem::path& dir);

// Merges `rows` into DIR/participants.tsv (written when absent): each row's
// values replace its subject's cells, other cells and rows stay; new columns
// are added after the existing ones in the order first given; rows are sorted
// by label. Then writes DIR/participants.json: every column described, by the
// entry the file had for it (kept as it was), else by `columns`, else by
// KnownParticipantColumns(), else generically. One process at a time (an
// exclusive flock on DIR); files are replaced whole. Same table in, same
// bytes out.
Status UpdateParticipants(const std::filesystem::path& dir,
                          std::span<const ParticipantRow> rows,
                          std::span<const ParticipantColumn> columns);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_PARTICIPANTS_H_
