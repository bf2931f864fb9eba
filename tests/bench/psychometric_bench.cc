// A psychometric fit with its 1999-sample parametric bootstrap
// (analysis::AnalyzePsychometric, BCa and percentile intervals, deviance
// p-value) on 6-level data sets; tests/bench/psignifit_time.sh times the
// psignifit 2.5.6 binary on the same data and options and prints the ratio.
#include <benchmark/benchmark.h>

#include <vector>

#include "burrlab/analysis/psychometric.h"

namespace burrlab::analysis {
namespace {

// The data of psignifit_time.sh (level, n correct, n total).
const std::vector<DataBlock> kTwoAfc = {{1, 21, 40}, {2, 24, 40}, {3, 29, 40},
                                        {4, 35, 40}, {5, 38, 40}, {6, 40, 40}};
const std::vector<DataBlock> kYesNo = {{1, 2, 40},  {2, 6, 40},  {3, 15, 40},
                                       {4, 28, 40}, {5, 35, 40}, {6, 38, 40}};

void BootstrapFit(benchmark::State& state, Sigmoid sigmoid, int n_intervals) {
  PsychometricOptions options;
  options.sigmoid = sigmoid;
  options.n_intervals = n_intervals;
  options.bootstrap_samples = 1999;
  const std::vector<DataBlock>& data = n_intervals == 1 ? kYesNo : kTwoAfc;
  double threshold = 0.0;
  for (auto _ : state) {
    Result<PsychometricAnalysis> result = AnalyzePsychometric(data, options);
    if (!result.ok()) {
      state.SkipWithError(result.error().message.c_str());
      break;
    }
    threshold = result->thresholds[1].value;
    benchmark::DoNotOptimize(result->thresholds[1].bca.data());
  }
  state.counters["threshold"] = threshold;
}

BENCHMARK_CAPTURE(BootstrapFit, logistic_2afc, Sigmoid::kLogistic, 2)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BootstrapFit, weibull_2afc, Sigmoid::kWeibull, 2)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BootstrapFit, cumnorm_yesno, Sigmoid::kCumulativeNormal, 1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BootstrapFit, gumbel_yesno, Sigmoid::kGumbel, 1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace burrlab::analysis
