// Reading burrlab's BIDS-style exports back (bids_export.h writes them): the
// _beh.tsv of each subject and block as TrialRecords, and the _physio.tsv.gz
// traces row by row, so analyses work from the files a lab archives and
// shares. Parsers take (path, text) so tests need no files; errors read
// "path:line:col: error: message".
#ifndef BURRLAB_RESULTS_SCHEMA_BIDS_READ_H_
#define BURRLAB_RESULTS_SCHEMA_BIDS_READ_H_

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/results_schema/records.h"

namespace burrlab::results_schema {

// Largest _beh.tsv read (bytes): a million trials of typical rows.
inline constexpr std::uintmax_t kMaxBehBytes = 512ull << 20;

// The trials of one _beh.tsv (header = BehColumns(), in any order; other
// columns are ignored; "source", "practice" and "late" may be absent, as in
// exports before they existed: then no source, not practice, late
// unknown). rng_state is not exported and stays empty; extra is "{}" where
// the file says n/a.
struct BehTable {
  std::uint64_t seed = 0;  // the seed column (the same on every row)
  std::vector<TrialRecord> trials;
};
Result<BehTable> ParseBehTsv(std::string_view path, std::string_view text);

// One subject's traces of one block: the _physio.json sidecar and its data.
struct PhysioFile {
  std::filesystem::path data_path;  // ..._physio.tsv.gz
  double sampling_frequency_hz = 0.0;
  double start_time_s = 0.0;
  // All columns: trial_index, interval_index, time, then the trace's own.
  std::vector<std::string> columns;
};

// One subject's block as exported (of one session).
struct BehFile {
  std::string subject;  // label without "sub-"
  std::string session;  // label without "ses-"; empty: not labelled
  std::string task;     // the task label of the file name
  std::filesystem::path path;
  BehTable table;
  std::vector<PhysioFile> physio;  // one per recording kind (often one)
};

// Every DIR/sub-*/beh/sub-*_task-*_beh.tsv and
// DIR/sub-*/ses-*/beh/sub-*_ses-*_task-*_beh.tsv (a subject with two
// sessions gives the files of both), sorted by subject label, then session
// label, then by the first trial index of the block (the order the subject
// ran them). Files
// that are not burrlab's (other names) are left alone; a malformed burrlab
// file is an error naming it. A folder without any is an error.
Result<std::vector<BehFile>> ReadBidsDataset(const std::filesystem::path& dir);

// A subject whose journal holds trials its exports do not (its run stopped
// before the export, or an export failed).
struct UnexportedTrials {
  std::string subject;  // label without "sub-"
  int journal_trials = 0;
  int exported_trials = 0;  // rows of its _beh.tsv files in `files`
  std::string session;      // label without "ses-"; empty: not labelled
};

// Every DIR/sub-*/journal.sqlite (and DIR/sub-*/ses-*/journal.sqlite) with
// more trials than the session's rows in `files` (ReadBidsDataset's answer
// for DIR, or empty), sorted by label, then session. A journal that cannot be
// read counts as holding trials (-1).
std::vector<UnexportedTrials> FindUnexportedTrials(
    const std::filesystem::path& dir, const std::vector<BehFile>& files);

// A subject whose journal says its session stopped before its end (an
// error, a stop at the station, a kill not yet resumed, or a run still
// going).
struct IncompleteSession {
  std::string subject;                // label without "sub-"
  int trials = 0;                     // trials its journal holds
  std::optional<int> planned_trials;  // when known ahead
  std::string session;  // label without "ses-"; empty: not labelled
};

// Every DIR/sub-*/journal.sqlite (and DIR/sub-*/ses-*/journal.sqlite) whose
// session has not run to its end, sorted by label, then session. Journals older
// than the record (schema version < 3, not resumed since) do not say and are
// not listed; nor are unreadable ones (FindUnexportedTrials lists those).
std::vector<IncompleteSession> FindIncompleteSessions(
    const std::filesystem::path& dir);

// Parses a _physio.json sidecar's text; `json_path` names it in errors and
// gives data_path, the .tsv.gz beside it.
Result<PhysioFile> ParsePhysioSidecar(const std::filesystem::path& json_path,
                                      std::string_view text);
// Reads and parses a _physio.json sidecar.
Result<PhysioFile> ReadPhysioSidecar(const std::filesystem::path& json_path);

// Longest line of a _physio.tsv read (bytes): thousands of columns. A longer
// line is refused before it is held whole (a small .gz can inflate to
// gigabytes without a line break).
inline constexpr std::size_t kMaxPhysioLineBytes = 1 << 20;

// Streams the rows of `file`'s data: `row` gets one value per column (n/a as
// NaN) and returns false to stop early. Errors name the file and line.
Status ForEachPhysioRow(
    const PhysioFile& file,
    const std::function<bool(std::span<const double>)>& row);
// The same for the decompressed text of a data file with `columns`; `path`
// names it in errors.
Status ForEachPhysioRowOfText(
    std::string_view path, std::span<const std::string> columns,
    std::string_view text,
    const std::function<bool(std::span<const double>)>& row);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_BIDS_READ_H_
