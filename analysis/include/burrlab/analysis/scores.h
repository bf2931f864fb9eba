// Scores and their significance per block (dissertation §13.5): each
// subject's correct answers out of n, the group mean +- SEM, a one-sample
// t-test of the proportions correct against chance, an exact binomial test of
// the pooled answers, and for same-different blocks hit and false-alarm rates
// with d' under the differencing and independent-observation models, per
// subject and pooled, and the block's response times per condition. Reads
// the trials of burrlab's BIDS exports; practice trials (the
// familiarization of §13.5.1) are never scored, and answers after a
// block's response deadline are counted (they are scored).
#ifndef BURRLAB_ANALYSIS_SCORES_H_
#define BURRLAB_ANALYSIS_SCORES_H_

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "burrlab/analysis/group_stats.h"
#include "burrlab/analysis/plot.h"
#include "burrlab/analysis/response_times.h"
#include "burrlab/base/result.h"
#include "burrlab/results_schema/bids_read.h"

namespace burrlab::analysis {

// Same-different answers: a hit is "different" on an AB/BA trial, a false
// alarm "different" on an AA/BB trial. Missed answers are left out of the
// rates. A rate of 0 or 1 is moved to 1/(2N) or 1 - 1/(2N) for d' (Macmillan
// & Kaplan 1985), and `corrected` says so.
struct SameDifferentRates {
  int hits = 0;
  int different_trials = 0;  // answered AB/BA trials
  int false_alarms = 0;
  int same_trials = 0;            // answered AA/BB trials
  double hit_rate = 0.0;          // hits / different_trials (uncorrected)
  double false_alarm_rate = 0.0;  // false_alarms / same_trials (uncorrected)
  bool corrected = false;         // a rate was 0 or 1 and moved for d'
  // d' of the (corrected) rates; none when undefined (the differencing model
  // has no d' for H < F), with the reason in `note`.
  std::optional<double> dprime_differencing;
  std::optional<double> dprime_independent_observation;
  std::string note;
};

struct SubjectScore {
  std::string subject;  // label without "sub-"
  int correct = 0;      // correct answers (a missed answer counts as wrong)
  int trials = 0;       // trials with a correct answer
  double proportion = 0.0;
  int late_answers = 0;  // of those, answered after the block's deadline
  std::optional<SameDifferentRates> rates;  // same-different blocks
};

struct BlockScores {
  std::string block;       // block name from the protocol
  std::string task_label;  // BIDS task label of its files
  std::string method;      // e.g. "same_different"
  std::string task;        // "probe" or "drill"
  // Probability correct by guessing; none when the design has no fixed
  // chance level (adaptive tracks, yes/no), then no test is made and
  // `no_test_reason` says why.
  std::optional<double> chance;
  std::string no_test_reason;
  std::vector<SubjectScore> subjects;  // in subject-label order
  // Trials per subject when every subject has the same number, else none
  // (then mean_score is none and the statistics use proportions).
  std::optional<int> trials_per_subject;
  std::optional<MeanSem> mean_score;       // correct answers per subject
  std::optional<MeanSem> mean_proportion;  // proportions correct
  // One-sample t-test of the proportions against chance (>= 2 subjects whose
  // proportions are not all equal).
  std::optional<TTestResult> t_test;
  std::optional<BinomialTestResult> binomial;  // pooled answers vs chance
  std::optional<SameDifferentRates> pooled_rates;
  // Response times of every subject's trials in the block: "all", then per
  // condition (SummarizeResponseTimes).
  std::vector<ResponseTimeSummary> response_times;
  // Scored trials whose block has a response deadline (their `late` is
  // known), and those answered after it (kept and scored).
  int answers_with_deadline = 0;
  int late_answers = 0;
  std::vector<std::string> warnings;
};

// Practice trials of one block, which the scores leave out.
struct PracticeLeftOut {
  std::string block;  // block name from the protocol
  int trials = 0;     // over every subject
};

// The practice trials of `files` per block, in the order the first subject
// ran them (empty when there are none).
std::vector<PracticeLeftOut> PracticeTrials(
    std::span<const results_schema::BehFile> files);

// Scores of every block with correct answers, in the order the first subject
// ran them; practice trials and blocks without correct answers (adjustment,
// limits) are left out. An error when no block has scored trials.
Result<std::vector<BlockScores>> ScoreBlocks(
    std::span<const results_schema::BehFile> files);

// Probability correct by guessing in a block of `method` (as the results
// name it, e.g. "same_different") whose trials have `trial_type`; none with
// the reason when the design has no fixed chance level.
struct ChanceLevel {
  std::optional<double> p;
  std::string reason;  // when p is none
};
ChanceLevel ChanceOf(const std::string& method, const std::string& trial_type);

// Rates and d' of same-different counts (see SameDifferentRates).
SameDifferentRates RatesFromCounts(int hits, int different_trials,
                                   int false_alarms, int same_trials);

// The histogram of a block's scores (Fig. 13.1-13.2): subjects per score
// from 0 to n (or per 5 % of proportion correct when n differs), with the
// chance level as a labelled dashed reference line.
LinePlot ScoreHistogram(const BlockScores& block);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_SCORES_H_
