// What the haptic loop (devices/haptic_loop.h) counts and measures, as plain
// values: the loop fills them, a session records them with each live interval
// (studies/session.h). A header of its own so studies/ need not include
// devices/ (README.md, "Layout").
#ifndef BURRLAB_RUNNER_COMMON_LOOP_COUNTERS_H_
#define BURRLAB_RUNNER_COMMON_LOOP_COUNTERS_H_

#include <cstdint>

namespace burrlab::runner {

// Counters, MuJoCo style: fixed fields, only ever incremented.
struct LoopCounters {
  std::int64_t ticks = 0;
  std::int64_t missed_deadlines = 0;  // force late: zero force sent instead
  std::int64_t non_finite = 0;        // NaN/inf force: zero force sent instead
  std::int64_t clamped = 0;           // |force| limited to the spec's maximum
  std::int64_t stale_reads = 0;       // the device had no new position
  std::int64_t device_errors = 0;     // a read or write failed
  std::int64_t skipped_ticks = 0;     // deadlines passed while the loop was
                                      // more than a period behind
};

// Period error = when a tick started minus its deadline.
struct LoopStats {
  std::int64_t samples = 0;  // period errors behind the percentiles
  double p50_us = 0.0;
  double p99_us = 0.0;
  double max_us = 0.0;        // over every tick, kept or not
  std::int64_t overruns = 0;  // ticks whose force missed the budget
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_COMMON_LOOP_COUNTERS_H_
