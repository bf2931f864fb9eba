// BIDS-style export of one subject's journal (BIDS 1.9.0 behavioural and
// physiological conventions):
//   DIR/dataset_description.json            written only if absent
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
// with one <task> per protocol block (see TaskLabel). Exports are derived from
// the journal and are rewritten whole (temporary file, then rename) on every
// export (temporary files that an export killed before its rename left behind
// are removed by the next export, once their process is gone); they carry no
// wall-clock time, so the same protocol, seed and
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

// Writes the BIDS-style files of DIR/sub-<label>/journal.sqlite (see top of
// file), reading the journal in one snapshot so a running session can be
// exported. Traces of a block are concatenated in trial and interval order;
// if a block's traces differ in sampling frequency or columns, each kind gets
// its own file with a _recording-<k> entity (k = 1, 2, ... by first use).
Status ExportBids(const std::filesystem::path& dir,
                  std::string_view subject_label);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_BIDS_EXPORT_H_
