// Response times of a study's trials (the _beh.tsv's response_time: seconds
// from the response prompt to the answer; n/a when none was timed, e.g. an
// answer typed into a pipe): median and quartiles per block and condition,
// over all subjects or per subject. Trials without a time are skipped and
// counted, never guessed.
#ifndef BURRLAB_ANALYSIS_RESPONSE_TIMES_H_
#define BURRLAB_ANALYSIS_RESPONSE_TIMES_H_

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "burrlab/results_schema/bids_read.h"
#include "burrlab/results_schema/records.h"

namespace burrlab::analysis {

// The p-quantile (0 <= p <= 1) of `sorted` (ascending, not empty) by R's
// default definition, quantile(type = 7) (Hyndman & Fan 1996, definition 7):
// with h = 1 + (n - 1) p, j = floor(h) (1-based), the value
// (1 - (h - j)) x[j] + (h - j) x[j + 1].
double QuantileType7(std::span<const double> sorted, double p);

// The response times of some trials.
struct ResponseTimeSummary {
  std::string condition;  // "all", or a condition (ConditionOf)
  int n = 0;              // trials with a response time
  int missing = 0;        // trials without one (n/a), left out
  // Over the n times, R quantile type 7; none when n = 0.
  std::optional<double> median_s;
  std::optional<double> q1_s;   // first quartile
  std::optional<double> q3_s;   // third quartile
  std::optional<double> iqr_s;  // q3_s - q1_s
};

// A trial's condition: in constant-stimuli blocks its level ("level 1.3"),
// else its trial_type (same-different AA/AB/BA/BB, two-interval AB/BA,
// limits ascending/descending, adaptive 2afc/yesno, ...); "n/a" when it has
// none.
std::string ConditionOf(const results_schema::TrialRecord& trial);

// "all" over every trial, then one summary per condition (levels in
// increasing order, then trial types in alphabetical order).
std::vector<ResponseTimeSummary> SummarizeResponseTimes(
    std::span<const results_schema::TrialRecord* const> trials);

// One subject's response times in one block.
struct SubjectBlockResponseTimes {
  std::string subject;                         // label without "sub-"
  std::string block;                           // block name from the protocol
  std::string task_label;                      // BIDS task label of its file
  std::string method;                          // e.g. "same_different"
  std::vector<ResponseTimeSummary> summaries;  // SummarizeResponseTimes
};

// Per subject and block, in the files' order (subjects by label, blocks in
// the order they ran).
std::vector<SubjectBlockResponseTimes> ResponseTimesBySubject(
    std::span<const results_schema::BehFile> files);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_RESPONSE_TIMES_H_
