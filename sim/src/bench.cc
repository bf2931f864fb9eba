// The simulator benchmark cases of `burrlab sim bench` (see bench.h).
#include "burrlab/sim/bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "burrlab/sim/step.h"
#include "burrlab/sim/volume.h"

namespace burrlab::sim {

std::vector<BenchCase> DefaultBenchCases() {
  std::vector<BenchCase> cases;
  for (MomentMethod method : {MomentMethod::kMono, MomentMethod::kOctree}) {
    for (double radius : {1.0, 2.0, 3.0, 5.0}) {
      for (bool drill : {false, true}) {
        BenchCase c;
        c.method = method;
        c.radius_mm = radius;
        c.drill = drill;
        cases.push_back(c);
      }
    }
  }
  return cases;
}

BenchCaseResult RunBenchCase(const BenchCase& bench_case) {
  BenchCaseResult result;
  result.bench_case = bench_case;
  // The dissertation's working volume: 256 x 256 x 128 voxels, solid below
  // mid-height.
  const double v = bench_case.voxel_mm;
  Result<Volume> volume = Volume::Create(256, 256, 128, v);
  if (!volume.ok()) return result;
  const int surface_k = 64;
  for (int k = 0; k < surface_k; ++k)
    for (int j = 0; j < volume->ny(); ++j)
      for (int i = 0; i < volume->nx(); ++i)
        volume->Set(i, j, k, kSolidOccupancy);
  Model model;
  model.radius_mm = bench_case.radius_mm;
  model.method = bench_case.method;
  Result<State> state = State::Create(model, std::move(*volume), /*seed=*/1);
  if (!state.ok()) return result;
  const double radius = bench_case.radius_mm;
  const double speed_mm_s = 10.0;
  Input input;
  input.velocity_mm_s = glm::dvec3(speed_mm_s, 0.0, 0.0);
  input.spindle_rad_s = glm::dvec3(0.0, 0.0, bench_case.drill ? 2094.0 : 0.0);
  // Immersed a quarter of the radius, sliding along x from 8 mm.
  const double z = surface_k * v + radius - 0.25 * radius;
  const double y = 0.5 * 256 * v + 0.071 * v;
  const int warmup = 100;
  std::vector<double> micros;
  micros.reserve(static_cast<std::size_t>(bench_case.steps));
  Output out;
  for (int s = 0; s < warmup + bench_case.steps; ++s) {
    input.position_mm = glm::dvec3(8.0 + speed_mm_s * model.dt_s * s, y, z);
    const auto start = std::chrono::steady_clock::now();
    Step(model, *state, input, &out);
    const auto stop = std::chrono::steady_clock::now();
    if (s >= warmup) {
      micros.push_back(
          std::chrono::duration<double, std::micro>(stop - start).count());
    }
  }
  std::sort(micros.begin(), micros.end());
  if (micros.empty()) return result;
  result.median_us = micros[micros.size() / 2];
  result.p99_us = micros[std::min(micros.size() - 1, micros.size() * 99 / 100)];
  result.max_us = micros.back();
  result.removed_mm3 = state->counters().removed_mm3;
  return result;
}

}  // namespace burrlab::sim
