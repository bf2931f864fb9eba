// BIDS-style export of one subject's journal (BIDS 1.9.0 behavioural and
// physiological conventions):
//   DIR/dataset_description.json            written only if absent (authors
//                                           given later are added to it)
//   DIR/.bidsignore                         written only if absent; hides the
//                                           journal files from BIDS validators
//   DIR/sub-<id>/beh/sub-<id>_task-<task>_beh.tsv   one row per trial
//   DIR/sub-<id>/beh/sub-<id>_task-<task>_beh.json  describes every column
//   DIR/sub-<id>/beh/sub-<id>_task-<task>_physio.tsv.gz + _physio.json
//   DIR/sub-<id>/sub-<id>_scans.tsv + .json  one row per data file above:
//                                           filename, session_status
//                                           (complete, incomplete, or n/a for
//                                           a journal older than the
//                                           record), session_trials,
//                                           session_planned_trials (n/a when
//                                           not known ahead)
// with one <task> per protocol block (see TaskLabel). A labelled session's
// files are in DIR/sub-<id>/ses-<session>/ and their names start with
// sub-<id>_ses-<session> (dataset_layout.h): e.g.
// DIR/sub-01/ses-2/beh/sub-01_ses-2_task-<task>_beh.tsv and
// DIR/sub-01/ses-2/sub-01_ses-2_scans.tsv. The dataset's README, code/ and
// participants.tsv come from dataset_files.h and participants.h. Exports are
// derived from the journal and are rewritten whole (temporary file, then
// rename) on every export (temporary files that an export killed before its
// rename left behind are removed by the next export, once their process is
// gone); they carry no wall-clock time, so the same protocol, seed and
// responses give byte-identical files.
#ifndef BURRLAB_RESULTS_SCHEMA_BIDS_EXPORT_H_
#define BURRLAB_RESULTS_SCHEMA_BIDS_EXPORT_H_

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::results_schema {

// BIDS version written to dataset_description.json.
inline constexpr std::string_view kBidsVersion = "1.9.0";

// Columns of every _beh.tsv, in order.
const std::vector<std::string>& BehColumns();

// Columns of every sub-<id>_scans.tsv, in order.
const std::vector<std::string>& ScansColumns();

// Columns that start every _physio.tsv.gz row, before the trace's own columns.
const std::vector<std::string>& PhysioLeadingColumns();

// BIDS-safe task label for a block name: ASCII letters and digits only. Runs
// of other characters separate words; words after the first start upper case
// ("same-different 1" -> "sameDifferent1", "Block_A" -> "BlockA"). A name with
// no letter or digit becomes "block". ExportBids makes labels of distinct
// blocks distinct by appending 2, 3, ... in order of first appearance.
std::string TaskLabel(std::string_view block_name);

// OK when `author` can be one entry of dataset_description.json's Authors:
// a name on one line, valid UTF-8, with at most one comma ("Surname, Given
// names"; BIDS validators take more commas for several people in one
// entry).
Status ValidateAuthor(std::string_view author);

// What an export writes besides the journal's contents.
struct BidsExportOptions {
  std::string session;  // the session's label (ses-<session>); empty: none
  // Authors of the dataset, one name each, for dataset_description.json:
  // written when the file is new, and added to an existing file's Authors
  // when it lacks them. None: no Authors field (BIDS recommends one; the
  // validator warns NO_AUTHORS, and TOO_FEW_AUTHORS for a single one).
  std::vector<std::string> authors;
};

// Writes the BIDS-style files of DIR/sub-<label>/journal.sqlite (see top of
// file), reading the journal in one snapshot so a running session can be
// exported. Traces of a block are concatenated in trial and interval order;
// if a block's traces differ in sampling frequency or columns, each kind gets
// its own file with a _recording-<k> entity (k = 1, 2, ... by first use).
Status ExportBids(const std::filesystem::path& dir,
                  std::string_view subject_label);
// The same for the session and with the authors of `options`.
Status ExportBids(const std::filesystem::path& dir,
                  std::string_view subject_label,
                  const BidsExportOptions& options);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_BIDS_EXPORT_H_
