// A psychometric fit with its 1999-sample parametric bootstrap
// (analysis::AnalyzePsychometric, BCa and percentile intervals, deviance
// p-value) on 6-level data sets; tests/bench/psignifit_time.sh times the
// psignifit 2.5.6 binary on the same data and options and prints the ratio.
// Then what `burrlab analyze fit` does with a large file (parse, pool by
// level, fit): 100,000 count rows at 6 levels, 1,000 to 100,000
// single-trial rows at distinct levels (adaptive methods give one level per
// trial), and 100,000 of them with the bootstrap.
#include <benchmark/benchmark.h>

#include <charconv>
#include <random>
#include <string>
#include <vector>

#include "burrlab/analysis/psychometric.h"
#include "burrlab/analysis/psychometric_data.h"

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

// A counts file of `rows` rows, each 1 trial at its own level in [0.5, 5.5]
// (`distinct`) or 4 trials at level 1 + row % 6, answered by a 2AFC
// logistic observer (alpha 3, beta 0.6, lambda 0.02).
std::string CountsFile(int rows, bool distinct) {
  const PsychometricParams truth{3.0, 0.6, 0.5, 0.02};
  std::mt19937_64 rng(19);
  const auto uniform = [&] {
    return static_cast<double>(rng() >> 11) * 0x1.0p-53;
  };
  std::string text = "level,n_correct,n_total\n";
  for (int row = 0; row < rows; ++row) {
    const double x = distinct ? 0.5 + 5.0 * uniform() : 1.0 + row % 6;
    const int trials = distinct ? 1 : 4;
    int correct = 0;
    for (int t = 0; t < trials; ++t) {
      correct += uniform() < Psi(Sigmoid::kLogistic, truth, x) ? 1 : 0;
    }
    char level[32];
    const auto end = std::to_chars(level, level + sizeof level, x).ptr;
    text += std::string(level, end) + "," + std::to_string(correct) + "," +
            std::to_string(trials) + "\n";
  }
  return text;
}

// Parse, pool and fit as `analyze fit --task 2afc --sigmoid logistic
// --bootstrap B` does.
void FitFile(benchmark::State& state, bool distinct, int bootstrap_samples) {
  const std::string text =
      CountsFile(static_cast<int>(state.range(0)), distinct);
  PsychometricOptions options;
  options.bootstrap_samples = bootstrap_samples;
  std::size_t levels = 0;
  for (auto _ : state) {
    Result<PsychometricDataFile> file = ParsePsychometricData("b.csv", text);
    if (!file.ok()) {
      state.SkipWithError(file.error().message.c_str());
      break;
    }
    Result<PsychometricAnalysis> result =
        AnalyzePsychometric(file->blocks, options);
    if (!result.ok()) {
      state.SkipWithError(result.error().message.c_str());
      break;
    }
    levels = file->blocks.size();
    benchmark::DoNotOptimize(result->thresholds[1].value);
  }
  state.counters["levels"] = static_cast<double>(levels);
  state.SetComplexityN(state.range(0));
}

// 100,000 count rows at 6 levels, with the default 1999-sample bootstrap.
BENCHMARK_CAPTURE(FitFile, count_rows_6_levels, false, 1999)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// One trial per level, the fit without bootstrap: linear in the levels
// (real time: from 8192 levels an evaluation shares them between threads).
BENCHMARK_CAPTURE(FitFile, distinct_levels, true, 0)
    ->RangeMultiplier(10)
    ->Range(1000, 100000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Complexity(benchmark::oN);
// 100,000 single-trial levels with the default 1999-sample bootstrap: each
// refit one or two passes over the levels (Newton steps from the fit), the
// refits shared between the cores.
BENCHMARK_CAPTURE(FitFile, distinct_levels_bootstrap, true, 1999)
    ->Arg(100000)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace burrlab::analysis
