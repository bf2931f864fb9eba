// Psychometric functions of several conditions fitted together, and compared
// by likelihood ratios, as Palamedes' PAL_PFLR_ModelComparison does (Kingdom
// & Prins 2016, ch. 9; Prins & Kingdom 2018): the conditions share the lapse
// rate (and a yes/no guess rate) and have
//   separate     their own threshold and slope,
//   shared slope their own threshold and one slope,
//   shared       one threshold and one slope;
// "do the thresholds differ?" is shared against shared slope, "do the slopes
// differ?" shared slope against separate. Each test's likelihood ratio
// statistic LR = 2 (log L fuller - log L lesser) gets a chi-square p-value
// (Wilks; df = conditions - 1) and a parametric-bootstrap p-value from data
// sets simulated from the lesser model's fit and refitted under both.
#ifndef BURRLAB_ANALYSIS_CONDITION_COMPARISON_H_
#define BURRLAB_ANALYSIS_CONDITION_COMPARISON_H_

#include <span>
#include <string>
#include <vector>

#include "burrlab/analysis/psychometric.h"
#include "burrlab/base/result.h"

namespace burrlab::analysis {

struct ConditionData {
  std::string name;
  std::vector<DataBlock> blocks;
};

enum class ConditionModel { kSeparate, kSharedSlope, kShared };
// "separate", "shared slope" or "shared".
std::string ConditionModelName(ConditionModel model);

struct ConditionFit {
  ConditionModel model = ConditionModel::kSeparate;
  // Per condition, in the data's order (shared parameters repeat).
  std::vector<PsychometricParams> params;
  double log_likelihood = 0.0;
  double deviance = 0.0;  // 2 (log L saturated - log L), over all conditions
  int free_parameters = 0;
  bool converged = false;
};

struct LikelihoodRatioTest {
  std::string question;  // "thresholds differ" or "slopes differ"
  ConditionModel lesser = ConditionModel::kShared;
  ConditionModel fuller = ConditionModel::kSharedSlope;
  double lr = 0.0;  // 2 (log L fuller - log L lesser) >= 0
  int df = 0;
  double p_chi_square = 0.0;
  // (1 + #(LR_b >= LR)) / (B + 1) over B data sets simulated from the
  // lesser fit; NaN when B = 0.
  double p_bootstrap = 0.0;
  int bootstrap_samples = 0;
  int bootstrap_failures = 0;  // simulated sets whose refits failed (left out)
};

struct ConditionComparison {
  std::vector<std::string> names;
  std::vector<ConditionFit> fits;          // separate, shared slope, shared
  std::vector<LikelihoodRatioTest> tests;  // thresholds, then slopes
  // Per condition (separate model): the threshold F^-1(cut) at each of
  // options.cuts.
  std::vector<std::vector<double>> thresholds;
  std::vector<std::string> warnings;
};

// Fits `model` to every condition at once. options: sigmoid, n_intervals,
// lambda_max, gamma_max, max_evaluations (per start) as for one data set.
Result<ConditionFit> FitConditions(std::span<const ConditionData> conditions,
                                   const PsychometricOptions& options,
                                   ConditionModel model);

// The three fits and both tests, with options.bootstrap_samples simulated
// data sets (seeded from options.seed) for the bootstrap p-values;
// options.progress, when set, is called after each data set of each test
// (done counting up to bootstrap_samples, once per test). At least two
// conditions, each valid data (ValidateData).
Result<ConditionComparison> CompareConditions(
    std::span<const ConditionData> conditions,
    const PsychometricOptions& options);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_CONDITION_COMPARISON_H_
