// Micro-benchmarks of the simulator kernels (Google Benchmark). `burrlab sim
// bench` reports the per-step distribution the README quotes; these give stable
// means per kernel.
#include <benchmark/benchmark.h>

#include "burrlab/sim/moments.h"
#include "burrlab/sim/octree.h"
#include "burrlab/sim/step.h"
#include "burrlab/sim/volume.h"

namespace burrlab::sim {
namespace {

// 256 x 256 x 128 voxels of 0.3 mm, solid below mid-height.
const Volume& WorkingVolume() {
  static const Volume volume = [] {
    Volume v = Volume::Create(256, 256, 128, 0.3).value();
    for (int k = 0; k < 64; ++k)
      for (int j = 0; j < 256; ++j)
        for (int i = 0; i < 256; ++i) v.Set(i, j, k, kSolidOccupancy);
    return v;
  }();
  return volume;
}

void Moments(benchmark::State& state, MomentMethod method, double radius_mm) {
  const Volume& volume = WorkingVolume();
  static const MomentOctree tree = MomentOctree::Build(WorkingVolume());
  double x = 10.0;
  for (auto _ : state) {
    const glm::dvec3 centre(x, 38.4, 19.2 + 0.75 * radius_mm);
    const sim::Moments m =
        method == MomentMethod::kMono
            ? ComputeMomentsMono(volume, centre, radius_mm)
            : ComputeMomentsOctree(tree, volume, centre, radius_mm,
                                   0.3 * radius_mm);
    benchmark::DoNotOptimize(m);
    x = x > 60.0 ? 10.0 : x + 0.01;
  }
}

void DrillStep(benchmark::State& state, double radius_mm) {
  Model model;
  model.radius_mm = radius_mm;
  State sim_state = State::Create(model, WorkingVolume(), 1).value();
  Input input;
  input.spindle_rad_s = glm::dvec3(0.0, 0.0, 2094.0);
  Output out;
  double x = 10.0;
  for (auto _ : state) {
    input.position_mm = glm::dvec3(x, 38.4, 19.2 + 0.75 * radius_mm);
    Step(model, sim_state, input, &out);
    benchmark::DoNotOptimize(out);
    x = x > 60.0 ? 10.0 : x + 0.01;
  }
}

BENCHMARK_CAPTURE(Moments, MonoR1, MomentMethod::kMono, 1.0);
BENCHMARK_CAPTURE(Moments, OctreeR1, MomentMethod::kOctree, 1.0);
BENCHMARK_CAPTURE(Moments, MonoR5, MomentMethod::kMono, 5.0);
BENCHMARK_CAPTURE(Moments, OctreeR5, MomentMethod::kOctree, 5.0);
BENCHMARK_CAPTURE(DrillStep, OctreeR1, 1.0);
BENCHMARK_CAPTURE(DrillStep, OctreeR5, 5.0);

}  // namespace
}  // namespace burrlab::sim
