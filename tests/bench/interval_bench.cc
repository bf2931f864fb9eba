// One simulated interval of a study (stimuli::PresentSimulatedInterval): 20 s
// of virtual time, R = 2 mm, probing at 2 N and drilling at 3 N, on human
// temporal bone and on PVC (the costliest: drilling, the burr sinks 13 mm and
// meets material over its lower half). A study runs about a thousand of these;
// the budget is 0.2 s each.
#include <benchmark/benchmark.h>

#include "burrlab/stimuli/interval.h"
#include "burrlab/stimuli/materials.h"

namespace burrlab::stimuli {
namespace {

void Interval20s(benchmark::State& state, const char* material, Task task) {
  IntervalOptions options;
  options.material = LoadBuiltinMaterial(material).value().material;
  options.task = task;
  options.duration_s = 20.0;
  options.radius_mm = 2.0;
  options.probe_force_n = 2.0;
  options.drill_force_n = 3.0;
  double cue = 0.0;
  for (auto _ : state) {
    Result<IntervalResult> result = PresentSimulatedInterval(options);
    if (!result.ok()) {
      state.SkipWithError(result.error().message.c_str());
      break;
    }
    cue = result->cue;
    benchmark::DoNotOptimize(result->rows.data());
  }
  state.counters["cue"] = cue;
  state.counters["us_per_step"] = benchmark::Counter(
      20000.0 * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

BENCHMARK_CAPTURE(Interval20s, BoneProbe, "human_temporal_bone", Task::kProbe)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Interval20s, BoneDrill, "human_temporal_bone", Task::kDrill)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Interval20s, PvcProbe, "pvc_k70", Task::kProbe)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(Interval20s, PvcDrill, "pvc_k70", Task::kDrill)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace burrlab::stimuli
