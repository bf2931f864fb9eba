// The haptic-loop benchmark behind `burrlab sim bench --loop`: the real loop
// thread (SCHED_FIFO and mlockall when permitted) drives the simulator at
// 1 kHz with a simulated device whose burr circles a quarter of its radius
// deep in a solid half-space while drilling. Reports how late ticks start
// (period error p50/p99/max) and how many forces missed their deadline.
#ifndef BURRLAB_RUNNER_DEVICES_LOOP_BENCH_H_
#define BURRLAB_RUNNER_DEVICES_LOOP_BENCH_H_

#include <cstdint>
#include <string>

#include "burrlab/base/result.h"
#include "devices/haptic_loop.h"

namespace burrlab::runner {

struct LoopBenchOptions {
  double seconds = 10.0;  // wall-clock length of the run
  double rate_hz = 1000.0;
  bool realtime = true;                          // try SCHED_FIFO and mlockall
  std::string material = "human_temporal_bone";  // built-in material set
  double radius_mm = 3.0;                        // burr radius
};

struct LoopBenchResult {
  LoopBenchOptions options;
  std::int64_t planned_ticks = 0;
  LoopStats stats;
  LoopCounters counters;
  RealtimeSetup realtime;
  double max_force_n = 0.0;  // the simulated device's limit
};

Result<LoopBenchResult> RunLoopBench(const LoopBenchOptions& options);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_LOOP_BENCH_H_
