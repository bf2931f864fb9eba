// Whether a fit's intervals can be trusted for a design: studies simulated
// from a known population are published as a paper would give them (mean and
// SEM of n subjects, rounded) and fitted back exactly as the observed result
// was (a parametric bootstrap of the intervals' coverage, as psignifit and
// Palamedes check theirs). A 95 % interval should hold the truth in about 95 %
// of the studies; much less means the intervals are too narrow for the design.
// `analyze fit-observers --recovery N` runs it with the fitted population as
// the truth.
#ifndef BURRLAB_RUNNER_STUDIES_FIT_RECOVERY_H_
#define BURRLAB_RUNNER_STUDIES_FIT_RECOVERY_H_

#include <cstdint>
#include <functional>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/protocol.h"
#include "studies/observer_fit.h"
#include "studies/virtual_study.h"

namespace burrlab::runner {

struct RecoveryOptions {
  int studies = 20;        // simulated published results
  std::uint64_t seed = 1;  // of the simulated studies and their fits
  // Renderings per stimulus of each simulated study's own pool: the
  // published studies feel renderings of their own, never the fit's.
  int renderings = 2;
};

// How often the intervals held the truth.
struct Recovery {
  std::string block;
  double weber = 0.0;   // the truth: W of the block's cue
  double spread = 0.0;  // and its spread (SD of ln W)
  bool fit_spread = true;
  int studies = 0;
  int weber_covered = 0;
  int spread_covered = 0;  // = studies when the spread is not fitted
  int both_covered = 0;
  // Intervals that stopped at a search limit (the fit's "not identified").
  int weber_at_limit = 0;
  int spread_at_limit = 0;
  std::vector<ObserverFit> fits;  // one per study, in order
};

// The published result of a virtual block's scores, as a paper gives it: the
// mean and the SEM (sample SD, divisor n - 1, over sqrt n) rounded to
// `decimals`; an SEM that rounds to 0 is given as one unit of the last
// decimal (papers do not print 0).
ObservedGroup PublishedResult(const std::vector<int>& correct,
                              const std::string& block, int decimals);

// Simulates options.studies published results of observed.n subjects of the
// population `truth` describes (its block's W and spread, over
// fit_options.base), published as `observed` is (each subject's score where
// it gives scores, else the mean and SEM rounded to its decimals), and fits
// each back with `fit_options` (its own seed per study) on renderings of
// `fit_pool`; fit_options.jobs studies at once.
// `progress` (may be empty) is told the studies done.
Result<Recovery> CheckRecovery(const protocols::Protocol& protocol,
                               const ObservedGroup& observed,
                               const ObserverFit& truth,
                               const ObserverFitOptions& fit_options,
                               CuePool& fit_pool,
                               const RecoveryOptions& options,
                               const std::function<void(int)>& progress = {});

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_FIT_RECOVERY_H_
