// The trace CSV of discover --traces: what it accepts and the exact
// diagnostics for what it refuses.
#include "burrlab/analysis/model_gap/trace_data.h"

#include <gtest/gtest.h>

#include <string>

namespace burrlab::analysis {
namespace {

std::string TraceErrorOf(std::string_view text) {
  Result<TraceData> data = ParseTraceData("t.csv", text);
  return data.ok() ? std::string("(parsed)") : data.error().message;
}

TEST(ParseTraceData, ReadsRunsWithColumnsInAnyOrder) {
  Result<TraceData> d = ParseTraceData("t.csv",
                                       "\xEF\xBB\xBF"
                                       "depth_mm,run,note,t_s,force_n\r\n"
                                       "-0.2, 1 ,a,0,0\n\n"
                                       "0.1,1,b,0.01,0.5\n"
                                       "-0.2,2,c,0,0\n"
                                       "0.3,2,d,0.01,1.5\n"
                                       "0.4,2,e,0.02,1.9\n");
  ASSERT_TRUE(d.ok()) << d.error().message;
  ASSERT_EQ(d->runs.size(), 2u);
  EXPECT_EQ(d->runs[0].run, "1");
  EXPECT_EQ(d->runs[0].t_s, (std::vector<double>{0.0, 0.01}));
  EXPECT_EQ(d->runs[1].run, "2");
  EXPECT_EQ(d->runs[1].force_n, (std::vector<double>{0.0, 1.5, 1.9}));
  EXPECT_EQ(d->runs[1].depth_mm, (std::vector<double>{-0.2, 0.3, 0.4}));
  EXPECT_EQ(d->runs[1].line, 5);
  EXPECT_EQ(d->runs[1].run_column, 6);
}

TEST(ParseTraceData, RefusesAnEmptyFileOrNoRows) {
  EXPECT_EQ(TraceErrorOf("\n \n"),
            "t.csv: error: the file is empty; expected a header line with "
            "the columns run,t_s,force_n,depth_mm");
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm\n"),
            "t.csv: error: no data rows after the header");
}

TEST(ParseTraceData, NamesAMissingColumn) {
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth\n1,0,0,0\n"),
            "t.csv:1:1: error: the header has no depth_mm column; traces "
            "need the columns run,t_s,force_n,depth_mm (comma-separated)\n"
            "run,t_s,force_n,depth\n^");
  EXPECT_EQ(TraceErrorOf("t_s,force_n,depth_mm\n0,0,0\n"),
            "t.csv:1:1: error: the header has no run column; traces need the "
            "columns run,t_s,force_n,depth_mm (comma-separated)\n"
            "t_s,force_n,depth_mm\n^");
}

TEST(ParseTraceData, RefusesADuplicateColumn) {
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm,t_s\n1,0,0,0,0\n"),
            "t.csv:1:26: error: the column t_s appears twice in the header\n"
            "run,t_s,force_n,depth_mm,t_s\n                         ^");
}

TEST(ParseTraceData, RefusesNonFiniteValues) {
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm\n1,0,nan,0\n"),
            "t.csv:2:5: error: force_n 'nan' is not a finite number of N\n"
            "1,0,nan,0\n    ^");
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm\n1,0,0,inf\n"),
            "t.csv:2:7: error: depth_mm 'inf' is not a finite number of mm\n"
            "1,0,0,inf\n      ^");
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm\n1,x,0,0\n"),
            "t.csv:2:3: error: t_s 'x' is not a finite number of s\n"
            "1,x,0,0\n  ^");
}

TEST(ParseTraceData, RefusesTimeThatDoesNotIncreaseWithinARun) {
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm\n1,0,0,0\n1,0.01,0,0\n"
                         "1,0.01,0,0\n"),
            "t.csv:4:3: error: t_s 0.01 does not increase within run 1 (the "
            "previous sample is at 0.01 s)\n1,0.01,0,0\n  ^");
  // A new run starts its own clock.
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm\n1,0,0,0\n1,1,0,0\n2,0,0,0\n"
                         "2,1,0,0\n"),
            "(parsed)");
}

TEST(ParseTraceData, RefusesSplitRunsShortRunsEmptyRunsAndRaggedRows) {
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm\n1,0,0,0\n1,1,0,0\n2,0,0,0\n"
                         "2,1,0,0\n1,2,0,0\n"),
            "t.csv:6:1: error: run 1 appears again after other runs (it "
            "started on line 2); keep each run's rows together\n1,2,0,0\n^");
  EXPECT_EQ(
      TraceErrorOf("run,t_s,force_n,depth_mm\n1,0,0,0\n2,0,0,0\n2,1,0,0\n"),
      "t.csv:2:1: error: run 1 has only 1 sample; a trace needs at "
      "least 2\n1,0,0,0\n^");
  EXPECT_EQ(
      TraceErrorOf("run,t_s,force_n,depth_mm\n1,0,0,0\n1,1,0,0\n2,0,0,0\n"),
      "t.csv:4:1: error: run 2 has only 1 sample; a trace needs at "
      "least 2\n2,0,0,0\n^");
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm\n ,0,0,0\n"),
            "t.csv:2:2: error: the run cell is empty\n ,0,0,0\n ^");
  EXPECT_EQ(TraceErrorOf("run,t_s,force_n,depth_mm\n1,0,0\n"),
            "t.csv:2:1: error: the row has 3 cells, the header 4\n1,0,0\n^");
}

TEST(MatchTracesToRuns, NamesATracedRunTheMeasuredDataLack) {
  const std::string measured_text =
      "run,force_n,velocity_mm_s\n1,1,0.1\n2,1,0.1\n3,2,0.2\n";
  const MeasuredData measured =
      ParseMeasuredData("m.csv", measured_text).value();
  const std::string text =
      "run,t_s,force_n,depth_mm\n1,0,0,0\n1,1,0,0\n7,0,0,0\n7,1,0,0\n";
  const TraceData traces = ParseTraceData("t.csv", text).value();
  EXPECT_EQ(MatchTracesToRuns(traces, measured, "t.csv", text).error().message,
            "t.csv:4:1: error: run 7 is not a run of the measured data\n"
            "7,0,0,0\n^");
  const TraceData good =
      ParseTraceData("t.csv", "run,t_s,force_n,depth_mm\n3,0,0,0\n3,1,0,0\n")
          .value();
  EXPECT_TRUE(MatchTracesToRuns(good, measured, "t.csv", "").ok());
  const MeasuredData unnamed =
      ParseMeasuredData("m.csv", "force_n,velocity_mm_s\n1,0.1\n1,0.1\n2,0.2\n")
          .value();
  EXPECT_EQ(MatchTracesToRuns(good, unnamed, "t.csv", "").error().message,
            "t.csv: error: the measured data have no run column; traces are "
            "matched to runs by it");
}

}  // namespace
}  // namespace burrlab::analysis
