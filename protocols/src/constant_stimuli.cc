// Method of constant stimuli: full or blocked random order, balanced 2AFC
// intervals.
#include "burrlab/protocols/constant_stimuli.h"

#include <fmt/format.h>

#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>
#include <cstdint>
#include <utility>

#include "max_trials.h"
#include "shuffle.h"

namespace burrlab::protocols {

std::string_view TrialOrderName(TrialOrder order) {
  return order == TrialOrder::kFull ? "full" : "blocked";
}

std::string_view ResponseModeName(ResponseMode mode) {
  return mode == ResponseMode::kYesNo ? "yes_no" : "2afc";
}

Status ConstantStimuliOptions::Validate() const {
  if (levels.empty()) {
    return Error{"constant_stimuli: levels must hold at least 1 level, got 0"};
  }
  for (std::size_t i = 0; i < levels.size(); ++i) {
    if (!std::isfinite(levels[i])) {
      return Error{fmt::format(
          "constant_stimuli: levels[{}] must be a finite number, got {}", i,
          levels[i])};
    }
  }
  if (repetitions < 1) {
    return Error{
        fmt::format("constant_stimuli: repetitions must be at least 1, got {}",
                    repetitions)};
  }
  const std::int64_t total =
      static_cast<std::int64_t>(levels.size()) * repetitions;
  if (total > kMaxTrials) {
    return Error{fmt::format(
        "constant_stimuli: {} levels x {} repetitions = {} trials, at most {} "
        "allowed",
        levels.size(), repetitions, total, kMaxTrials)};
  }
  return {};
}

Result<std::vector<ConstantStimuliTrial>> PlanConstantStimuli(
    const ConstantStimuliOptions& options, boost::random::mt19937& order_rng) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  const int n_levels = static_cast<int>(options.levels.size());
  const int reps = options.repetitions;
  const int total = n_levels * reps;

  // Level indices in presentation order: repetition-major, then shuffled.
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(total));
  for (int r = 0; r < reps; ++r) {
    for (int l = 0; l < n_levels; ++l) order.push_back(l);
  }
  if (options.order == TrialOrder::kFull) {
    Shuffle(order, 0, total, order_rng);
  } else {
    for (int r = 0; r < reps; ++r) {
      Shuffle(order, r * n_levels, (r + 1) * n_levels, order_rng);
    }
  }

  std::vector<ConstantStimuliTrial> trials(static_cast<std::size_t>(total));
  std::vector<int> seen(static_cast<std::size_t>(n_levels), 0);
  for (int i = 0; i < total; ++i) {
    ConstantStimuliTrial& trial = trials[i];
    trial.index = i;
    trial.level_index = order[i];
    trial.level = options.levels[order[i]];
    trial.repetition = seen[order[i]]++;
  }

  if (options.response == ResponseMode::kTwoInterval) {
    // intervals[l][r]: comparison interval of level l's r-th presentation.
    std::vector<std::vector<int>> intervals(static_cast<std::size_t>(n_levels));
    for (int l = 0; l < n_levels; ++l) {
      std::vector<int>& list = intervals[l];
      list.reserve(static_cast<std::size_t>(reps));
      for (int r = 0; r < reps / 2; ++r) {
        list.push_back(1);
        list.push_back(2);
      }
      if (reps % 2 == 1) {
        boost::random::uniform_int_distribution<int> extra(1, 2);
        list.push_back(extra(order_rng));
      }
      Shuffle(list, 0, reps, order_rng);
    }
    for (ConstantStimuliTrial& trial : trials) {
      trial.comparison_interval =
          intervals[trial.level_index][trial.repetition];
    }
  }
  return trials;
}

}  // namespace burrlab::protocols
