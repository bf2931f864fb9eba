// How strong a hidden mechanism of the independent truth must be for a design
// to see it: its projected signal-to-noise ratio against the base model, and
// the strength at which that reaches a target. The base model is fitted by
// the product's own fitter (BaseModelRss, discover.h) on the data as parsed
// from the generator's CSV: the truth is independent, the fitter is the one
// under test.
//
// Two definitions of the noncentrality lambda (SNR = sqrt(lambda)):
//  * kNoiseFree: lambda = RSS of the base model fitted to the noise-free
//    velocities / sigma^2. For a base model linear in its parameters this is
//    ||P_perp delta||^2 / sigma^2, the noncentrality of the lack-of-fit
//    statistic exactly; where the base model is curved the fit to noisy data
//    can bend to the noise and the gap looks smaller than this.
//  * kNoiseAveraged: lambda = E[RSS_base - RSS_truth] / sigma^2 + 2 over a
//    fixed set of noise draws (common to every strength, so the SNR is
//    smooth in the strength): RSS_truth is the noise's own sum of squares,
//    and + 2 adds back what the 2 fitted parameters take from the noise
//    (E[RSS_base] = ||P_perp delta||^2 + (n - 2) sigma^2 for a linear model).
//    This is the definition the product's scenario matrix uses, so the rates
//    measured at a given SNR are comparable with its table. (Adding 2 to the
//    noise-free ratio as well would count the parameters' share twice.)
#ifndef BURRLAB_TESTS_ANALYSIS_MODEL_GAP_INDEPENDENT_TRUTH_STRENGTH_AT_SNR_H_
#define BURRLAB_TESTS_ANALYSIS_MODEL_GAP_INDEPENDENT_TRUTH_STRENGTH_AT_SNR_H_

#include <cstdint>
#include <vector>

#include "burrlab/base/result.h"
#include "independent_truth/measured_csv.h"
#include "independent_truth/settled_descent.h"

namespace burrlab::analysis::independent_truth {

enum class SnrDefinition { kNoiseFree, kNoiseAveraged };

struct SnrOptions {
  SnrDefinition definition = SnrDefinition::kNoiseAveraged;
  int draws = 48;                   // kNoiseAveraged: noise draws
  std::uint64_t first_seed = 9001;  // of the draws
};

// The projected SNR of the noise-free velocities `truth_mm_s` (one per force
// level of `design`) against the base model; an error when a level has no
// positive finite velocity or the fit fails.
Result<double> ProjectedSnr(const Design& design,
                            const std::vector<double>& truth_mm_s,
                            const SnrOptions& options = {});

// A strength of the order where `mechanism` changes v(F) visibly in the
// design: where the search for a target SNR starts.
double NaturalStrength(const Design& design, Mechanism mechanism);

struct StrengthAtSnr {
  double strength = 0.0;
  double snr = 0.0;             // under the options' definition
  double snr_noise_free = 0.0;  // the other definitions, for reports
  double snr_noise_averaged = 0.0;
  std::vector<double> truth_mm_s;  // the noise-free velocities there
};

// The smallest strength (to 0.1 %) at which the projected SNR of
// `mechanism` reaches `target`: doubling from NaturalStrength to bracket it,
// then bisection on log strength. An error when the mechanism stops the
// burr (or the SNR stays below the target) before.
Result<StrengthAtSnr> FindStrengthAtSnr(const Design& design,
                                        Mechanism mechanism, double target,
                                        const SnrOptions& options = {});

}  // namespace burrlab::analysis::independent_truth

#endif  // BURRLAB_TESTS_ANALYSIS_MODEL_GAP_INDEPENDENT_TRUTH_STRENGTH_AT_SNR_H_
