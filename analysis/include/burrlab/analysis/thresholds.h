// Thresholds per subject and block by each method's own estimator, from the
// exported trials: staircases the mean of the last k reversal levels in the
// step scale's domain (Levitt 1971), QUEST the posterior mean (Watson & Pelli
// 1983; King-Smith et al. 1994), limits the mean of the series' transition
// levels, adjustment the mean adjusted level, and constant stimuli a
// maximum-likelihood psychometric fit (psychometric.h) with a bootstrap
// interval.
#ifndef BURRLAB_ANALYSIS_THRESHOLDS_H_
#define BURRLAB_ANALYSIS_THRESHOLDS_H_

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "burrlab/analysis/plot.h"
#include "burrlab/analysis/psychometric.h"
#include "burrlab/base/result.h"
#include "burrlab/results_schema/bids_read.h"

namespace burrlab::analysis {

struct ThresholdOptions {
  // Staircases: reversals averaged; 0 takes each staircase's
  // threshold_reversals from the protocol (recorded with its trials).
  int reversals = 0;
  // Constant stimuli: the psychometric fit.
  Sigmoid sigmoid = Sigmoid::kLogistic;
  double cut = 0.5;             // of F: with 2AFC, 0.5 is 75 % correct
  int bootstrap_samples = 999;  // for the threshold's 95 % BCa interval
  std::uint64_t seed = 1;       // bootstrap seed
};

struct ThresholdEstimate {
  std::string subject;
  std::string session;  // the file's session label; empty: not labelled
  std::string block;
  std::string method;
  std::string task;
  std::optional<int> staircase_id;  // interleaved staircases: which
  std::string estimator;            // how `value` was formed, for people
  std::optional<double> value;      // in stim_unit; none: see `note`
  std::string stim_unit;
  // Spread of the values averaged (sample SD) or the posterior SD; none with
  // fewer than 2 values.
  std::optional<double> spread;
  std::string spread_unit;  // stim_unit, "log10" or "dB"
  int n = 0;                // reversals, transitions, adjustments or trials
  // Constant stimuli: 95 % BCa bootstrap interval of the threshold, and the
  // fit behind it.
  std::optional<double> ci_low, ci_high;
  // "BCa", or "percentile" when BCa gives neither bound.
  std::string ci_method = "BCa";
  // A bound that is a search limit (BootstrapEstimate::bca_at_search_limit):
  // its number is the fit's search range, not the data's; printed as such.
  bool ci_low_at_search_limit = false, ci_high_at_search_limit = false;
  std::optional<PsychometricFit> fit;
  // The x of `fit`: "linear" (the levels) or "log10" (log10 of the levels,
  // on ratio axes; the value and interval are transformed back).
  std::string fit_scale = "linear";
  std::optional<double> deviance_p;
  // Limits: the mean transition of the ascending and of the descending
  // series apart (a difference between them is the error of habituation or
  // of expectation; Gescheider 1997, ch. 3), their counts, and the series
  // that started on their stopping answer ("yes" ascending, "no"
  // descending): their start was already past the threshold, so their
  // transition says only that it lies below (above) the start.
  std::optional<double> ascending_mean, descending_mean;
  int ascending_n = 0, descending_n = 0;
  int started_on_stopping_answer = 0;
  std::string note;  // why there is no value, or a caveat
};

// One estimate per subject, block (and staircase), in the files' order.
// Blocks of same-different and two-interval designs have no threshold and
// are left out, and so are practice trials (a practice block has no
// estimate: familiarization, §13.5.1). An error when no block has one, or for
// bad options.
Result<std::vector<ThresholdEstimate>> EstimateThresholds(
    std::span<const results_schema::BehFile> files,
    const ThresholdOptions& options);

// One block's (and staircase's) thresholds across the subjects of a study:
// the arithmetic mean +- SEM with its 95 % Student t interval, and where
// thresholds are ratios or were averaged on a logarithmic step scale (ratio
// axes; staircases stepping in log10 or dB) also the geometric mean: the
// mean of log thresholds transformed back, with the SD and SEM of the logs
// as factors (x/÷ f) and its t interval transformed back. Thresholds of
// ratio stimuli spread on a log scale (Weber's law); Levitt (1971) averages
// a staircase in the units it steps in, and so does the group.
struct GroupThreshold {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  std::string session;  // as the estimates' (empty: not labelled)
  std::string block;
  std::optional<int> staircase_id;
  std::string method, estimator, stim_unit;
  std::vector<std::string> subjects;  // with a value, in the files' order
  std::vector<double> values;         // theirs, in stim_unit
  // Subjects of the block left out of the group: their estimate has no
  // value; each with the estimate's note.
  std::vector<std::pair<std::string, std::string>> without_value;
  // Subjects (among `subjects`) whose interval has a bound at a search
  // limit: their data do not bound their threshold on that side.
  std::vector<std::string> unbounded;
  int n = 0;  // subjects.size()
  // Arithmetic: the mean needs 1 value, the rest 2 (else kNone).
  double mean = kNone, sd = kNone, sem = kNone, ci_low = kNone, ci_high = kNone;
  // Geometric (only when `geometric`; every value > 0).
  bool geometric = false;
  double geometric_mean = kNone, geometric_sd_factor = kNone,
         geometric_sem_factor = kNone, geometric_ci_low = kNone,
         geometric_ci_high = kNone;
};

// Groups `estimates` by session, block and staircase, in order of first
// appearance.
std::vector<GroupThreshold> GroupThresholds(
    std::span<const ThresholdEstimate> estimates);

// The group's figure: each subject's threshold with its 95 % interval (a
// subject whose interval reaches a search limit drawn apart, without one),
// and the group's mean with its 95 % t interval beside them (the geometric
// mean on a log axis for ratio axes and log staircases). `estimates` are
// those GroupThresholds was given.
LinePlot GroupThresholdPlot(const GroupThreshold& group,
                            std::span<const ThresholdEstimate> estimates);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_THRESHOLDS_H_
