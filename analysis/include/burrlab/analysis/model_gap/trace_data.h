// Time traces of the descent rig: for each run of the measured data, the
// recorded force and depth against time, read from one CSV with the header
// run,t_s,force_n,depth_mm (any order; other columns are ignored). The run
// column names the measured CSV's run; a run's rows are consecutive with
// increasing time. Parsers take (path, text); errors read "path:line:col:
// error: message", then the source line and a caret, as in measured_data.h.
#ifndef BURRLAB_ANALYSIS_MODEL_GAP_TRACE_DATA_H_
#define BURRLAB_ANALYSIS_MODEL_GAP_TRACE_DATA_H_

#include <string>
#include <string_view>
#include <vector>

#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/base/result.h"

namespace burrlab::analysis {

// The trace of one run.
struct RunTrace {
  std::string run;               // the run column
  std::vector<double> t_s;       // time, strictly increasing
  std::vector<double> force_n;   // force the rig's load cell recorded
  std::vector<double> depth_mm;  // depth below the original surface the arm
                                 // recorded (negative above it)
  int line = 0;                  // 1-based line of the run's first row
  int run_column = 1;            // 1-based column of its run cell
};

struct TraceData {
  std::vector<RunTrace> runs;  // in file order
};

// Parses `text` (the whole file). Cells are trimmed; blank lines, CR line ends
// and a UTF-8 byte-order mark are accepted. Every value must be a finite
// number, t_s strictly increasing within a run, each run's rows together and
// each run at least 2 samples long.
Result<TraceData> ParseTraceData(std::string_view path, std::string_view text);

// Reads and parses the file at `path`; "cannot read PATH: reason" when it
// cannot be read.
Result<TraceData> ReadTraceData(const std::string& path);

// Reads, parses and matches (MatchTracesToRuns) the file at `path`.
Result<TraceData> ReadTracesOfRuns(const std::string& path,
                                   const MeasuredData& measured);

// Checks that every traced run is a run of `measured` (by its run column);
// `path` and `text` are the trace file's, for the diagnostic.
Status MatchTracesToRuns(const TraceData& traces, const MeasuredData& measured,
                         std::string_view path, std::string_view text);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_MODEL_GAP_TRACE_DATA_H_
