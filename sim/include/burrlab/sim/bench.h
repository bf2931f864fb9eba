// The simulator benchmark behind `burrlab sim bench`: the burr slides at 10
// mm/s immersed a quarter of its radius in a solid half-space (drilling erodes
// as it goes), and every step (force + erosion) is timed. Reports median, p99
// and max microseconds per step.
#ifndef BURRLAB_SIM_BENCH_H_
#define BURRLAB_SIM_BENCH_H_

#include <vector>

#include "burrlab/sim/model.h"

namespace burrlab::sim {

struct BenchCase {
  MomentMethod method = MomentMethod::kOctree;
  double radius_mm = 3.0;
  bool drill = false;  // spinning and eroding (true) or probing (false)
  double voxel_mm = 0.3;
  int steps = 3000;  // timed steps (1 kHz: 3 s of sliding)
};

struct BenchCaseResult {
  BenchCase bench_case;
  double median_us = 0.0;
  double p99_us = 0.0;
  double max_us = 0.0;
  double removed_mm3 = 0.0;
};

// The default grid: mono and octree x R = 1, 2, 3, 5 mm x probe and drill.
std::vector<BenchCase> DefaultBenchCases();
BenchCaseResult RunBenchCase(const BenchCase& bench_case);

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_BENCH_H_
