// Fitting a simulated-observer population to observed group results: the
// Weber fraction W of a block's cue (stiffness when probing, removal rate
// when drilling) whose virtual studies give the observed mean
// score of a block, and the spread of W across subjects that gives the
// observed between-subject SD (SEM x sqrt(n)), with an interval for W from
// the observed mean's uncertainty (mean +- 1.96 SEM mapped through the
// monotone mean-score curve). Virtual studies: virtual_study.h; the same
// subject seeds at every W (common random numbers) keep the curve smooth.
#ifndef BURRLAB_RUNNER_STUDIES_OBSERVER_FIT_H_
#define BURRLAB_RUNNER_STUDIES_OBSERVER_FIT_H_

#include <cstdint>
#include <functional>
#include <iterator>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/protocol.h"
#include "studies/virtual_study.h"

namespace burrlab::runner {

// A group result as papers report it: mean score +- SEM over n subjects.
struct ObservedGroup {
  double mean = 0.0;  // correct answers per subject
  double sem = 0.0;   // standard error of the mean
  int n = 0;          // subjects
  std::string block;  // the block scored; empty: not said
  int decimals = 1;   // the rounding of mean and sem as given (the most
                      // decimals of the two)
  // Each subject's score, where known (raw data, or a histogram such as the
  // dissertation's Fig. 13.1 read off): the likelihood is then that of these
  // scores, and mean, sem and n are theirs (unrounded).
  std::vector<int> scores = {};
};

// Parses "mean=9.3,sem=0.4,n=20" (keys in any order, all three required), or
// "scores=12/11/9/..." (each subject's score, at least two), optionally with
// "block=probe".
Result<ObservedGroup> ParseObservedGroup(std::string_view text);
// The group of these scores: n, mean and SEM (sample SD over sqrt n) theirs,
// unrounded.
ObservedGroup ObservedScores(std::vector<int> scores, std::string block);

struct ObserverFitOptions {
  std::string block;  // the block the scores are of; empty: the first
  // Subjects per virtual study: the likelihood is estimated from their score
  // distribution, so they set its noise. Fitting the dissertation's probing
  // block (likelihood rule) with seeds 1 and 2 gave W 0.484 and 0.448 with
  // 400, 0.449 and 0.446 with 2000.
  int virtual_subjects = 2000;
  std::uint64_t seed = 1;  // of the virtual studies
  bool fit_spread = true;  // also fit the spread of W across subjects
  // Refine the moment fit by maximum likelihood (the probability of the
  // published mean +- SEM to its rounding) with profile-likelihood
  // intervals; false: the moment fit and its interval from mean +- 1.96 SEM.
  bool maximum_likelihood = true;
  protocols::ObserverParams base;  // lapse, criterion, ... (W is replaced)
  // Fits run at once (FitObserverGroups, CompareObserverVariants: each block
  // and variant is its own fit); the results do not depend on it.
  int jobs = 1;
  // Maximum likelihood: also the profile intervals of W and its spread
  // (false: the maximum alone, each interval the point; for profiles over
  // another parameter).
  bool intervals = true;
};

struct ObserverFit {
  std::string block;
  protocols::Task task = protocols::Task::kProbe;  // the block's: its cue is
                                                   // the one fitted
  int trials_per_subject = 0;
  double weber = 0.0;  // fitted typical Weber fraction
  // Its 95 % interval. Maximum likelihood: where the profile log likelihood
  // (the spread re-fitted at each W) falls 1.92 below its maximum. Moments:
  // the W giving mean -+ 1.96 SEM (a larger W gives a lower score). At the
  // search limit where it does not close, with a note.
  double weber_low = 0.0;
  double weber_high = 0.0;
  double weber_spread = 0.0;  // SD of ln W across subjects
  // Its 95 % profile interval (maximum likelihood with a fitted spread; else
  // both equal weber_spread). A lower bound of 0: subjects all alike are not
  // rejected.
  double spread_low = 0.0;
  double spread_high = 0.0;
  bool maximum_likelihood = false;  // how the fit was made
  double fitted_mean = 0.0;         // mean score of the fitted population
  double fitted_sd = 0.0;           // between-subject SD of its scores
  double observed_sd = 0.0;         // sem x sqrt(n)
  // The probability that n subjects of the fitted population report the
  // observed mean +- SEM to its rounding (analysis::PublishedScoresProbability
  // of the population's score distribution): the likelihood of the fit.
  double published_probability = 0.0;
  double log_likelihood = 0.0;  // its log (the smoothed estimate the fit
                                // maximises: kPseudoSubjects)
  int virtual_studies = 0;      // evaluations used
  std::vector<std::string> notes;
};

// Observer models `analyze fit-observers` fits and compares by name
// (--variant, --compare-variants): a same-different decision rule, how the
// simulated hand explores, and whether the Weber fraction spreads across
// subjects. Each fits one Weber fraction per observed block (the block's cue)
// and, with `spread`, its spread; with `lapse`, one lapse rate shared by the
// blocks as well (a profile over the lapse). The rest (the lapse otherwise,
// criterion, bias) stays at the protocol's [observer] values.
struct ObserverVariant {
  std::string_view name;
  protocols::SameDifferentRule rule;
  bool varied_exploration;  // kVariedExploration (§12.3), else every
                            // interval alike
  bool spread;              // fit the spread of W across subjects
  bool lapse;               // fit a lapse rate shared by the blocks
};
inline constexpr ObserverVariant kObserverVariants[] = {
    {"fixed", protocols::SameDifferentRule::kFixed, false, true, false},
    {"differencing", protocols::SameDifferentRule::kDifferencing, false, true,
     false},
    {"likelihood", protocols::SameDifferentRule::kLikelihood, false, true,
     false},
    {"likelihood_varied", protocols::SameDifferentRule::kLikelihood, true, true,
     false},
    {"likelihood_alike", protocols::SameDifferentRule::kLikelihood, false,
     false, false},
    {"likelihood_lapse", protocols::SameDifferentRule::kLikelihood, false, true,
     true},
};
// The variant named `name`, or an error listing the names.
Result<ObserverVariant> FindObserverVariant(std::string_view name);
// `base` with the variant's rule and exploration.
protocols::ObserverParams VariantObserver(const ObserverVariant& variant,
                                          protocols::ObserverParams base);

// Fits of one observer model to every observed block, and how well it does:
// the log likelihood of all the observed results (the blocks' summed),
// with k parameters (a W per block, and its spread where fitted), AIC = 2k -
// 2 ln L and BIC = k ln N - 2 ln L with N the observed subjects over blocks.
struct VariantFit {
  ObserverVariant variant;
  // The variant's observer over the base (with the fitted lapse where it
  // fits one).
  protocols::ObserverParams observer;
  bool fit_spread = true;
  std::vector<ObserverFit> fits;  // one per observed block, in their order
  // variant.lapse: the shared lapse rate's 95 % profile interval (the fit is
  // observer.lapse), and notes on its bounds.
  double lapse_low = 0.0;
  double lapse_high = 0.0;
  // The profile: (lapse, summed log likelihood of the blocks at their
  // maximum) at every lapse tried, in increasing lapse.
  std::vector<std::pair<double, double>> lapse_profile = {};
  std::vector<std::string> notes = {};
  int parameters = 0;
  double log_likelihood = 0.0;
  double aic = 0.0;
  double bic = 0.0;
  double delta_aic = 0.0;  // above the best's
};

// Fits each of `variants` (VariantObserver over options.base; its spread
// fitted where the variant has one and options.fit_spread allows) to every
// observed group, options.jobs fits at once; `progress` (may be empty) is
// told (fits done, of FitsToCompare(variants, groups), the variant of the
// last one done), one call at a time. A variant with a shared lapse fits it
// by profile likelihood: every block fitted (W and spread at their maximum)
// at each lapse of kLapseGrid, the summed log likelihood's maximum refined
// by golden-section steps between the best grid point's neighbours, each end
// of its 95 % interval (1.92 below the maximum) by bisection between the
// lapses that bracket it, then the blocks fitted with their intervals at the
// fitted lapse; k counts the lapse once. Sorted by AIC, best first (stable);
// an error is the first in the order of variants and groups.
Result<std::vector<VariantFit>> CompareObserverVariants(
    const protocols::Protocol& protocol,
    const std::vector<ObservedGroup>& observed,
    std::span<const ObserverVariant> variants,
    const ObserverFitOptions& options, CuePool& pool,
    const std::function<void(int, std::string_view)>& progress);

// Where a shared lapse's profile starts (the observer takes lapses in [0,
// 0.5)), its refinement steps, and the fits per block it makes at most: the
// grid, the golden-section steps, the bisections of each end and the final
// fit.
inline constexpr double kLapseGrid[] = {0.0,  0.02, 0.05, 0.1, 0.15, 0.2,
                                        0.25, 0.3,  0.35, 0.4, 0.45};
inline constexpr int kLapseGoldenSteps = 5;
inline constexpr int kLapseBisections = 4;
inline constexpr int kLapseFitsPerGroup =
    static_cast<int>(std::size(kLapseGrid)) + kLapseGoldenSteps +
    2 * kLapseBisections + 1;
// The fits CompareObserverVariants makes of `groups` observed blocks.
int FitsToCompare(std::span<const ObserverVariant> variants, int groups);

// Search range of W and of its spread (SD of ln W).
inline constexpr double kMinWeber = 0.01;
inline constexpr double kMaxWeber = protocols::kMaxWeberFraction;
inline constexpr double kMaxWeberSpread = 2.0;

// The likelihood of a population is the probability that n of its subjects
// report the published mean +- SEM (analysis::PublishedScoresProbability) of
// the score distribution of its virtual study with this many pseudo-subjects
// added, spread evenly over the scores: N virtual subjects cannot tell a
// score's probability below about 1 / N, and without them a score no virtual
// subject reached would make a publication that needs it impossible.
inline constexpr double kPseudoSubjects = 1.0;

Result<ObserverFit> FitObservers(const protocols::Protocol& protocol,
                                 const ObservedGroup& observed,
                                 const ObserverFitOptions& options,
                                 CuePool& pool);
// FitObservers of each observed group, options.jobs at once, in their order
// (an error is the first group's that failed).
Result<std::vector<ObserverFit>> FitObserverGroups(
    const protocols::Protocol& protocol,
    const std::vector<ObservedGroup>& observed,
    const ObserverFitOptions& options, CuePool& pool);

// The population fitted blocks describe, for virtual or simulated studies:
// each cue takes the Weber fraction and spread of the block of its task
// (probe: stiffness; drill: removal); with only one fit, the other cue takes
// the same values (said in `notes`). Two fits of one task are an error.
Result<VirtualStudyOptions> PopulationOf(const std::vector<ObserverFit>& fits,
                                         const protocols::ObserverParams& base,
                                         std::vector<std::string>* notes);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_OBSERVER_FIT_H_
