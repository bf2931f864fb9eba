// The haptic-loop benchmark and `burrlab sim bench --loop`: tick counts,
// statistics present and ordered, flag errors. Timing values are reported,
// never asserted.
#include "devices/loop_bench.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "run_cli.h"

namespace burrlab::runner {
namespace {

TEST(LoopBench, RunsThePlannedTicksWithoutFaults) {
  LoopBenchOptions options;
  options.seconds = 0.05;
  options.realtime = false;
  const Result<LoopBenchResult> result = RunLoopBench(options);
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_EQ(result->planned_ticks, 50);
  EXPECT_EQ(result->counters.ticks, 50);
  EXPECT_EQ(result->counters.non_finite, 0);
  EXPECT_EQ(result->counters.device_errors, 0);
  EXPECT_EQ(result->stats.samples, 50);
  EXPECT_LE(result->stats.p50_us, result->stats.p99_us);
  EXPECT_LE(result->stats.p99_us, result->stats.max_us);
  EXPECT_EQ(result->max_force_n, 8.0);
  EXPECT_EQ(result->realtime.note, "real-time scheduling not requested");
}

TEST(LoopBench, UnknownMaterialIsAnError) {
  LoopBenchOptions options;
  options.seconds = 0.01;
  options.material = "granite";
  EXPECT_FALSE(RunLoopBench(options).ok());
}

TEST(LoopBench, CommandReportsPeriodErrorsAsJson) {
  const CliRun run =
      RunBurrlab({"sim", "bench", "--loop", "--seconds", "0.02", "--json"});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["ticks"], 20);
  EXPECT_EQ(j["rate_hz"], 1000.0);
  for (const char* key : {"period_error_p50_us", "period_error_p99_us",
                          "period_error_max_us", "overruns", "skipped_ticks",
                          "sched_fifo", "memory_locked", "realtime_note"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_LE(j["period_error_p50_us"].get<double>(),
            j["period_error_max_us"].get<double>());
}

TEST(LoopBench, CommandFlagErrors) {
  CliRun run = RunBurrlab({"sim", "bench", "--seconds", "2"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: --seconds needs --loop (the step benchmark uses "
            "--steps)\n");
  run = RunBurrlab({"sim", "bench", "--loop", "--steps", "3"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: --steps and --loop are mutually exclusive; the loop runs "
            "for --seconds\n");
  run = RunBurrlab({"sim", "bench", "--loop", "--seconds", "0"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.out, "");
}

}  // namespace
}  // namespace burrlab::runner
