// Scores per block and subject, their group statistics and same-different
// d' (dissertation §13.5; Macmillan & Creelman 2005, ch. 9).
#include "burrlab/analysis/scores.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "burrlab/analysis/sdt.h"

namespace burrlab::analysis {
namespace {

using results_schema::BehFile;
using results_schema::TrialRecord;

bool IsDifferentPair(const std::string& type) {
  return type == "AB" || type == "BA";
}
bool IsSamePair(const std::string& type) {
  return type == "AA" || type == "BB";
}

}  // namespace

ChanceLevel ChanceOf(const std::string& method, const std::string& trial_type) {
  if (method == "same_different" || method == "two_interval") return {0.5, ""};
  if (method == "constant_stimuli") {
    if (trial_type == "2afc") return {0.5, ""};
    return {std::nullopt,
            "yes/no answers have no chance level; fit the psychometric "
            "function instead (burrlab analyze thresholds)"};
  }
  if (method == "staircase" || method == "quest") {
    return {std::nullopt,
            "an adaptive track holds accuracy near its target, so its score "
            "says nothing against chance; see burrlab analyze thresholds"};
  }
  return {std::nullopt, fmt::format("method {} has no chance level", method)};
}

SameDifferentRates RatesFromCounts(int hits, int different_trials,
                                   int false_alarms, int same_trials) {
  SameDifferentRates r;
  r.hits = hits;
  r.different_trials = different_trials;
  r.false_alarms = false_alarms;
  r.same_trials = same_trials;
  if (different_trials == 0 || same_trials == 0) {
    r.note = "no answered same or different trials";
    return r;
  }
  r.hit_rate = static_cast<double>(hits) / different_trials;
  r.false_alarm_rate = static_cast<double>(false_alarms) / same_trials;
  // Macmillan & Kaplan (1985): 0 -> 1/(2N), 1 -> 1 - 1/(2N).
  const auto corrected = [&](int k, int n) {
    if (k == 0) {
      r.corrected = true;
      return 0.5 / n;
    }
    if (k == n) {
      r.corrected = true;
      return 1.0 - 0.5 / n;
    }
    return static_cast<double>(k) / n;
  };
  const double h = corrected(hits, different_trials);
  const double f = corrected(false_alarms, same_trials);
  if (Result<double> d =
          DPrimeSameDifferent(h, f, SameDifferentModel::kDifferencing);
      d.ok()) {
    r.dprime_differencing = *d;
  } else {
    r.note = "H < F: the differencing model has no d'";
  }
  if (Result<double> d = DPrimeSameDifferent(
          h, f, SameDifferentModel::kIndependentObservation);
      d.ok()) {
    r.dprime_independent_observation = *d;
  }
  return r;
}

std::vector<PracticeLeftOut> PracticeTrials(std::span<const BehFile> files) {
  std::vector<PracticeLeftOut> out;
  for (const BehFile& file : files) {
    for (const TrialRecord& t : file.table.trials) {
      if (!t.practice) continue;
      auto it = std::find_if(
          out.begin(), out.end(),
          [&](const PracticeLeftOut& p) { return p.block == t.block; });
      if (it == out.end()) it = out.insert(out.end(), {t.block, 0});
      ++it->trials;
    }
  }
  return out;
}

Result<std::vector<BlockScores>> ScoreBlocks(std::span<const BehFile> files) {
  // Blocks in the order they first appear, trials per block and subject.
  std::vector<std::string> order;
  std::map<std::string, BlockScores> blocks;
  std::map<std::string, std::map<std::string, std::vector<const TrialRecord*>>>
      trials;
  int practice = 0;
  for (const BehFile& file : files) {
    for (const TrialRecord& t : file.table.trials) {
      if (t.practice) {  // familiarization (§13.5.1): never scored
        ++practice;
        continue;
      }
      if (!t.correct.has_value()) continue;
      auto [it, added] = blocks.try_emplace(t.block);
      if (added) {
        order.push_back(t.block);
        it->second.block = t.block;
        it->second.task_label = file.task;
        it->second.method = t.method;
        it->second.task = t.task;
        const ChanceLevel chance = ChanceOf(t.method, t.trial_type);
        it->second.chance = chance.p;
        it->second.no_test_reason = chance.reason;
      }
      trials[t.block][file.subject].push_back(&t);
    }
  }
  if (order.empty()) {
    return Error{fmt::format(
        "no block has {}trials with a correct answer (adjustment and limits "
        "blocks have none; see burrlab analyze thresholds){}",
        practice > 0 ? "scored " : "",
        practice > 0
            ? fmt::format("; the {} practice trials are never scored", practice)
            : std::string())};
  }
  std::vector<BlockScores> out;
  for (const std::string& name : order) {
    BlockScores b = std::move(blocks[name]);
    const bool same_different = b.method == "same_different";
    int pooled_correct = 0, pooled_trials = 0;
    int hits = 0, different = 0, false_alarms = 0, same = 0;
    std::vector<double> scores, proportions;
    std::vector<const TrialRecord*> block_trials;
    for (const auto& [subject, list] : trials[name]) {
      block_trials.insert(block_trials.end(), list.begin(), list.end());
      SubjectScore s;
      s.subject = subject;
      int h = 0, nd = 0, fa = 0, ns = 0;
      for (const TrialRecord* t : list) {
        ++s.trials;
        s.correct += *t->correct ? 1 : 0;
        if (t->late.has_value()) {
          ++b.answers_with_deadline;
          if (*t->late) {
            ++s.late_answers;
            ++b.late_answers;
          }
        }
        if (!same_different || t->response.empty()) continue;
        const bool said_different = t->response == "different";
        if (IsDifferentPair(t->trial_type)) {
          ++nd;
          h += said_different ? 1 : 0;
        } else if (IsSamePair(t->trial_type)) {
          ++ns;
          fa += said_different ? 1 : 0;
        }
      }
      s.proportion = static_cast<double>(s.correct) / s.trials;
      if (same_different) {
        s.rates = RatesFromCounts(h, nd, fa, ns);
        hits += h;
        different += nd;
        false_alarms += fa;
        same += ns;
      }
      pooled_correct += s.correct;
      pooled_trials += s.trials;
      scores.push_back(s.correct);
      proportions.push_back(s.proportion);
      b.subjects.push_back(std::move(s));
    }
    const bool equal_n = std::all_of(
        b.subjects.begin(), b.subjects.end(), [&](const SubjectScore& s) {
          return s.trials == b.subjects.front().trials;
        });
    if (equal_n) {
      b.trials_per_subject = b.subjects.front().trials;
    } else {
      b.warnings.push_back(
          "subjects have different numbers of trials (an unfinished "
          "session?): statistics use proportions correct");
    }
    if (b.subjects.size() >= 2) {
      if (equal_n) {
        if (Result<MeanSem> m = MeanAndSem(scores); m.ok()) b.mean_score = *m;
      }
      if (Result<MeanSem> m = MeanAndSem(proportions); m.ok()) {
        b.mean_proportion = *m;
      }
    } else {
      b.warnings.push_back(
          "one subject: no mean +- SEM or t-test (they need at least 2)");
    }
    if (b.chance.has_value()) {
      if (b.subjects.size() >= 2) {
        if (Result<TTestResult> t = OneSampleTTest(proportions, *b.chance);
            t.ok()) {
          b.t_test = *t;
        } else {
          b.warnings.push_back(
              "every subject has the same proportion correct: the t-test is "
              "undefined (zero variance)");
        }
      }
      if (Result<BinomialTestResult> t =
              ExactBinomialTest(pooled_correct, pooled_trials, *b.chance);
          t.ok()) {
        b.binomial = *t;
      }
    }
    if (same_different) {
      b.pooled_rates = RatesFromCounts(hits, different, false_alarms, same);
    }
    b.response_times = SummarizeResponseTimes(block_trials);
    out.push_back(std::move(b));
  }
  return out;
}

LinePlot ScoreHistogram(const BlockScores& block) {
  LinePlot plot;
  Series bars;
  bars.line = false;
  std::vector<double> counts;
  double width = 1.0;
  if (block.trials_per_subject.has_value()) {
    const int n = *block.trials_per_subject;
    counts.assign(static_cast<std::size_t>(n) + 1, 0.0);
    for (const SubjectScore& s : block.subjects) {
      counts[static_cast<std::size_t>(s.correct)] += 1.0;
    }
    for (int k = 0; k <= n; ++k) bars.x.push_back(k);
    plot.x_label = fmt::format("correct answers out of {}", n);
    plot.x_range = std::pair(-0.5, n + 0.5);
    plot.integer_x = true;
    width = 0.8;
  } else {
    counts.assign(21, 0.0);  // 0 %, 5 %, ..., 100 %
    for (const SubjectScore& s : block.subjects) {
      counts[static_cast<std::size_t>(std::lround(s.proportion * 20.0))] += 1.0;
    }
    for (int k = 0; k <= 20; ++k) bars.x.push_back(5.0 * k);
    plot.x_label = "percent correct";
    plot.x_range = std::pair(-2.5, 102.5);
    width = 4.0;
  }
  bars.y = counts;
  bars.bar_width = width;
  bars.label = fmt::format("{} subjects", block.subjects.size());
  plot.series.push_back(bars);
  if (block.chance.has_value()) {
    const double at = block.trials_per_subject.has_value()
                          ? *block.chance * *block.trials_per_subject
                          : *block.chance * 100.0;
    plot.reference_lines.push_back(
        {true, at,
         block.trials_per_subject.has_value()
             ? fmt::format("chance {:.3g} of {}", at, *block.trials_per_subject)
             : fmt::format("chance {:.3g} %", at)});
  }
  std::string stats;
  if (block.mean_score.has_value()) {
    stats = fmt::format(": mean {:.1f} ± {:.1f} SEM", block.mean_score->mean,
                        block.mean_score->sem);
  } else if (block.mean_proportion.has_value()) {
    stats = fmt::format(": mean {:.1f} ± {:.1f} % (SEM)",
                        100.0 * block.mean_proportion->mean,
                        100.0 * block.mean_proportion->sem);
  }
  if (block.t_test.has_value()) {
    stats += fmt::format(", p = {:.2g}", block.t_test->p_greater);
  }
  plot.title = fmt::format("{} ({}, {}){}", block.block, block.method,
                           block.task, stats);
  plot.y_label = "subjects";
  plot.integer_y = true;
  return plot;
}

}  // namespace burrlab::analysis
