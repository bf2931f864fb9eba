// Medians and quartiles of response times, R quantile type 7.
#include "burrlab/analysis/response_times.h"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <utility>

namespace burrlab::analysis {
namespace {

using results_schema::TrialRecord;

// Orders conditions: levels by value, then trial types by name.
using ConditionKey = std::pair<std::optional<double>, std::string>;

ConditionKey KeyOf(const TrialRecord& t) {
  if (t.method == "constant_stimuli" && t.stim_level.has_value()) {
    return {t.stim_level, ""};
  }
  return {std::nullopt, t.trial_type.empty() ? "n/a" : t.trial_type};
}

std::string NameOf(const ConditionKey& key) {
  return key.first ? fmt::format("level {}", *key.first) : key.second;
}

ResponseTimeSummary Summarize(std::string condition,
                              std::span<const TrialRecord* const> trials) {
  ResponseTimeSummary s;
  s.condition = std::move(condition);
  std::vector<double> times;
  for (const TrialRecord* t : trials) {
    if (t->response_time_s.has_value() && std::isfinite(*t->response_time_s)) {
      times.push_back(*t->response_time_s);
    } else {
      ++s.missing;
    }
  }
  s.n = static_cast<int>(times.size());
  if (times.empty()) return s;
  std::sort(times.begin(), times.end());
  s.median_s = QuantileType7(times, 0.5);
  s.q1_s = QuantileType7(times, 0.25);
  s.q3_s = QuantileType7(times, 0.75);
  s.iqr_s = *s.q3_s - *s.q1_s;
  return s;
}

}  // namespace

double QuantileType7(std::span<const double> sorted, double p) {
  assert(!sorted.empty() && p >= 0.0 && p <= 1.0);
  // As R's quantile.default: index h = 1 + (n - 1) p, interpolated between
  // x[floor h] and x[ceiling h] (1-based) unless they are equal.
  const double h = 1.0 + static_cast<double>(sorted.size() - 1) * p;
  const double lo = std::floor(h), hi = std::ceil(h);
  const double x_lo = sorted[static_cast<std::size_t>(lo) - 1];
  const double x_hi = sorted[static_cast<std::size_t>(hi) - 1];
  if (!(h > lo) || x_hi == x_lo) return x_lo;
  const double w = h - lo;
  return (1.0 - w) * x_lo + w * x_hi;
}

std::string ConditionOf(const TrialRecord& trial) {
  return NameOf(KeyOf(trial));
}

std::vector<ResponseTimeSummary> SummarizeResponseTimes(
    std::span<const TrialRecord* const> trials) {
  std::vector<ResponseTimeSummary> out;
  out.push_back(Summarize("all", trials));
  std::map<ConditionKey, std::vector<const TrialRecord*>> by_condition;
  for (const TrialRecord* t : trials) by_condition[KeyOf(*t)].push_back(t);
  // std::optional orders none before any value: put the levels first.
  std::vector<std::pair<ConditionKey, std::vector<const TrialRecord*>>> sorted(
      by_condition.begin(), by_condition.end());
  std::stable_partition(sorted.begin(), sorted.end(), [](const auto& c) {
    return c.first.first.has_value();
  });
  for (const auto& [key, list] : sorted) {
    out.push_back(Summarize(NameOf(key), list));
  }
  return out;
}

std::vector<SubjectBlockResponseTimes> ResponseTimesBySubject(
    std::span<const results_schema::BehFile> files) {
  std::vector<SubjectBlockResponseTimes> out;
  for (const results_schema::BehFile& file : files) {
    // A file holds one block (two blocks whose names give one task label
    // would share it): its trials by block name, in the order they ran.
    std::vector<std::pair<std::string, std::vector<const TrialRecord*>>> blocks;
    for (const TrialRecord& t : file.table.trials) {
      auto it = std::find_if(blocks.begin(), blocks.end(),
                             [&](const auto& b) { return b.first == t.block; });
      if (it == blocks.end()) {
        blocks.emplace_back(t.block, std::vector<const TrialRecord*>{});
        it = blocks.end() - 1;
      }
      it->second.push_back(&t);
    }
    for (const auto& [block, trials] : blocks) {
      SubjectBlockResponseTimes s;
      s.subject = file.subject;
      s.block = block;
      s.task_label = file.task;
      s.method = trials.front()->method;
      s.summaries = SummarizeResponseTimes(trials);
      out.push_back(std::move(s));
    }
  }
  return out;
}

}  // namespace burrlab::analysis
