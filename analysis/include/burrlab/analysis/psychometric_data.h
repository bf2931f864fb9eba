// Psychometric data files for `burrlab analyze fit`: a CSV or TSV of counts
// with the header level,n_correct,n_total, or a burrlab/BIDS _beh.tsv with
// one trial per row (columns stim_level and correct), pooled by level.
// Parsers take (path, text) so tests need no files; errors read
// "path:line:col: error: message", then the source line and a caret.
#ifndef BURRLAB_ANALYSIS_PSYCHOMETRIC_DATA_H_
#define BURRLAB_ANALYSIS_PSYCHOMETRIC_DATA_H_

#include <string>
#include <string_view>
#include <vector>

#include "burrlab/analysis/psychometric.h"
#include "burrlab/sim/result.h"

namespace burrlab::analysis {

struct PsychometricDataFile {
  enum class Format {
    kCounts,  // level,n_correct,n_total: one block per row, in file order
    kTrials,  // _beh.tsv: stim_level and correct per trial, pooled by level
  };
  Format format = Format::kCounts;
  std::vector<DataBlock> blocks;  // kTrials: sorted by level
  // kCounts: the 1-based line of each block (for diagnostics); kTrials: 0.
  std::vector<int> lines;
  int skipped_rows = 0;  // kTrials: rows with n/a in stim_level or correct
};

// Parses `text` (the whole file). The delimiter is a tab when the header line
// has one, else a comma; cells are trimmed; blank lines, CR line ends and a
// UTF-8 byte-order mark are accepted; other columns are ignored. Counts:
// level a finite number, n_total a whole number >= 1, n_correct a whole
// number in [0, n_total]. Trials: stim_level a finite number or n/a, correct
// 1, 0 or n/a. The error is a formatted diagnostic (up to three lines).
Result<PsychometricDataFile> ParsePsychometricData(std::string_view path,
                                                   std::string_view text);

// Reads and parses the file at `path`; "cannot read PATH: reason" when it
// cannot be read.
Result<PsychometricDataFile> ReadPsychometricData(const std::string& path);

// "path:line:col: error: message", the source line and a caret under the
// column; "path: error: message" when line is 0. No trailing line break.
std::string FormatDataDiagnostic(std::string_view path, std::string_view text,
                                 int line, int column,
                                 std::string_view message);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_PSYCHOMETRIC_DATA_H_
