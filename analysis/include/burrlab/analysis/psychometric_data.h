// Psychometric data files for `burrlab analyze fit`: a CSV or TSV of counts
// with the header level,n_correct,n_total, or a burrlab/BIDS _beh.tsv with
// one trial per row (columns stim_level and correct), either pooled by level.
// Parsers take (path, text) so tests need no files; errors read
// "path:line:col: error: message", then the source line and a caret.
#ifndef BURRLAB_ANALYSIS_PSYCHOMETRIC_DATA_H_
#define BURRLAB_ANALYSIS_PSYCHOMETRIC_DATA_H_

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/analysis/psychometric.h"
#include "burrlab/base/result.h"

namespace burrlab::analysis {

struct PsychometricDataFile {
  enum class Format {
    kCounts,  // level,n_correct,n_total: counts per row
    kTrials,  // _beh.tsv: stim_level and correct per trial
  };
  Format format = Format::kCounts;
  // One block per distinct level, the rows at that level pooled, in
  // increasing order of level.
  std::vector<DataBlock> blocks;
  // kCounts: the 1-based line of each block's first row (for diagnostics);
  // kTrials: empty.
  std::vector<int> lines;
  std::size_t rows = 0;  // data rows pooled into blocks (kTrials: trials)
  int skipped_rows = 0;  // kTrials: rows with n/a in stim_level or correct
  // kTrials: practice trials (a `practice` column of 1), left out: a
  // familiarization block is never fitted.
  int practice_rows = 0;
  // kTrials: the first stim_unit that is not n/a (empty: none).
  std::string stim_unit;
  // With a `by` column: the rows of each of its values pooled apart, in
  // order of first appearance (`blocks` still pools them all).
  struct Condition {
    std::string name;
    std::vector<DataBlock> blocks;
    std::vector<int> lines;  // as `lines`
  };
  std::vector<Condition> conditions;
};

// Parses `text` (the whole file). The delimiter is a tab when the header line
// has one, else a comma; cells are trimmed; blank lines, CR line ends and a
// UTF-8 byte-order mark are accepted; other columns are ignored. Counts:
// level a finite number, n_total a whole number >= 1, n_correct a whole
// number in [0, n_total]. Trials: stim_level a finite number or n/a, correct
// 1, 0 or n/a; a row whose `practice` column is 1 is left out (counted in
// practice_rows). The rows of one level may add up to at most INT_MAX trials.
// The error is a formatted diagnostic (up to three lines). A non-empty `by`
// names a column whose values split the rows into conditions (an error when
// the header lacks it, or a cell of it is empty).
Result<PsychometricDataFile> ParsePsychometricData(std::string_view path,
                                                   std::string_view text,
                                                   std::string_view by = {});

// Reads and parses the file at `path`; "cannot read PATH: reason" when it
// cannot be read.
Result<PsychometricDataFile> ReadPsychometricData(const std::string& path,
                                                  std::string_view by = {});

// "path:line:col: error: message", the source line and a caret under the
// column; "path: error: message" when line is 0. No trailing line break.
std::string FormatDataDiagnostic(std::string_view path, std::string_view text,
                                 int line, int column,
                                 std::string_view message);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_PSYCHOMETRIC_DATA_H_
