// The trace CSV of the model-gap workflow, with a diagnostic naming the line
// and column of the first problem.
#include "burrlab/analysis/model_gap/trace_data.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>
#include <set>

#include "burrlab/analysis/psychometric_data.h"
#include "csv_text.h"

namespace burrlab::analysis {

Result<TraceData> ParseTraceData(std::string_view path, std::string_view text) {
  Result<CsvTable> table =
      CsvTable::Split(path, text, CsvTable::Delimiter::kComma,
                      "the file is empty; expected a header line with the "
                      "columns run,t_s,force_n,depth_mm");
  if (!table.ok()) return table.error();
  const auto fail = [&](int line, int column, const std::string& message) {
    return table->Fail(line, column, message);
  };
  const Line& header_line = table->header_line();
  if (Status distinct = table->CheckDistinctColumns(); !distinct.ok()) {
    return distinct.error();
  }
  const auto find = [&](std::string_view name) { return table->Find(name); };
  constexpr std::string_view kColumns[] = {"run", "t_s", "force_n", "depth_mm"};
  int at[4];
  for (int c = 0; c < 4; ++c) {
    at[c] = find(kColumns[c]);
    if (at[c] < 0) {
      return fail(header_line.number, 1,
                  fmt::format("the header has no {} column; traces need the "
                              "columns run,t_s,force_n,depth_mm "
                              "(comma-separated)",
                              kColumns[c]));
    }
  }
  constexpr std::string_view kUnits[] = {"", "s", "N", "mm"};
  TraceData data;
  std::map<std::string, int, std::less<>> first_line;  // run -> line
  for (const Line& line : table->rows()) {
    Result<std::vector<Cell>> row = table->Cells(line);
    if (!row.ok()) return row.error();
    const std::vector<Cell>& cells = *row;
    const Cell run = cells[static_cast<std::size_t>(at[0])];
    if (run.text.empty()) {
      return fail(line.number, run.column, "the run cell is empty");
    }
    double value[4] = {0.0, 0.0, 0.0, 0.0};
    for (int c = 1; c < 4; ++c) {
      const Cell cell = cells[static_cast<std::size_t>(at[c])];
      const std::optional<double> v = ParseFinite(cell.text);
      if (!v) {
        return fail(line.number, cell.column,
                    fmt::format("{} '{}' is not a finite number of {}",
                                kColumns[c], cell.text, kUnits[c]));
      }
      value[c] = *v;
    }
    if (data.runs.empty() || data.runs.back().run != run.text) {
      if (auto it = first_line.find(run.text); it != first_line.end()) {
        return fail(line.number, run.column,
                    fmt::format("run {} appears again after other runs (it "
                                "started on line {}); keep each run's rows "
                                "together",
                                run.text, it->second));
      }
      if (!data.runs.empty() && data.runs.back().t_s.size() < 2) {
        const RunTrace& last = data.runs.back();
        return fail(last.line, last.run_column,
                    fmt::format("run {} has only 1 sample; a trace needs at "
                                "least 2",
                                last.run));
      }
      first_line.emplace(std::string(run.text), line.number);
      RunTrace trace;
      trace.run = std::string(run.text);
      trace.line = line.number;
      trace.run_column = run.column;
      data.runs.push_back(std::move(trace));
    }
    RunTrace& trace = data.runs.back();
    if (!trace.t_s.empty() && !(value[1] > trace.t_s.back())) {
      const Cell cell = cells[static_cast<std::size_t>(at[1])];
      return fail(line.number, cell.column,
                  fmt::format("t_s {} does not increase within run {} (the "
                              "previous sample is at {} s)",
                              value[1], trace.run, trace.t_s.back()));
    }
    trace.t_s.push_back(value[1]);
    trace.force_n.push_back(value[2]);
    trace.depth_mm.push_back(value[3]);
  }
  if (data.runs.empty()) return fail(0, 0, "no data rows after the header");
  if (data.runs.back().t_s.size() < 2) {
    const RunTrace& last = data.runs.back();
    return fail(last.line, last.run_column,
                fmt::format("run {} has only 1 sample; a trace needs at least "
                            "2",
                            last.run));
  }
  return data;
}

Result<TraceData> ReadTraceData(const std::string& path) {
  Result<std::string> text = ReadTextFile(path);
  if (!text.ok()) return text.error();
  return ParseTraceData(path, *text);
}

Result<TraceData> ReadTracesOfRuns(const std::string& path,
                                   const MeasuredData& measured) {
  Result<std::string> text = ReadTextFile(path);
  if (!text.ok()) return text.error();
  Result<TraceData> traces = ParseTraceData(path, *text);
  if (!traces.ok()) return traces.error();
  if (Status s = MatchTracesToRuns(*traces, measured, path, *text); !s.ok()) {
    return s.error();
  }
  return traces;
}

Status MatchTracesToRuns(const TraceData& traces, const MeasuredData& measured,
                         std::string_view path, std::string_view text) {
  std::set<std::string, std::less<>> runs;
  for (const MeasuredRun& r : measured.runs) {
    if (!r.run.empty()) runs.insert(r.run);
  }
  if (runs.empty()) {
    return Error{FormatDataDiagnostic(
        path, text, 0, 0,
        "the measured data have no run column; traces are matched to runs "
        "by it")};
  }
  for (const RunTrace& t : traces.runs) {
    if (!runs.contains(t.run)) {
      return Error{FormatDataDiagnostic(
          path, text, t.line, t.run_column,
          fmt::format("run {} is not a run of the measured data", t.run))};
    }
  }
  return {};
}

}  // namespace burrlab::analysis
