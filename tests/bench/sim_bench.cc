// placeholder, replaced below
#include <benchmark/benchmark.h>
static void BM_R1(benchmark::State& state) { for (auto _ : state) benchmark::DoNotOptimize(1); }
BENCHMARK(BM_R1);
