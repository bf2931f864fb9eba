// Transformed up-down staircases: validation, the up-down rule, reversals,
// step schedule, bounds, thresholds, random interleaving.
#include "burrlab/protocols/staircase.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/random/uniform_int_distribution.hpp>
#include <cassert>
#include <cmath>
#include <utility>

namespace burrlab::protocols {
namespace {

// Error unless the step size `value` is finite and > 0.
Status CheckStepSize(std::string_view name, double value) {
  if (!std::isfinite(value)) {
    return Error{fmt::format("staircase: {} must be a finite number, got {}",
                             name, value)};
  }
  if (value <= 0.0) {
    return Error{
        fmt::format("staircase: {} must be positive, got {}", name, value)};
  }
  return {};
}

}  // namespace

std::string_view MoveName(Move move) {
  switch (move) {
    case Move::kNone:
      return "none";
    case Move::kDown:
      return "down";
    case Move::kUp:
      return "up";
  }
  return "?";
}

Status StaircaseOptions::Validate() const {
  if (n_down < 1) {
    return Error{
        fmt::format("staircase: n_down must be at least 1, got {}", n_down)};
  }
  if (n_up < 1) {
    return Error{
        fmt::format("staircase: n_up must be at least 1, got {}", n_up)};
  }
  if (Status s = CheckStepSize("step_down", step_down); !s.ok()) return s;
  if (Status s = CheckStepSize("step_up", step_up); !s.ok()) return s;
  for (std::size_t i = 0; i < step_schedule.size(); ++i) {
    const StepChange& change = step_schedule[i];
    if (change.after_reversals < 1) {
      return Error{fmt::format(
          "staircase: step_schedule[{}].after_reversals must be at least 1, "
          "got {}",
          i, change.after_reversals)};
    }
    if (i > 0 &&
        change.after_reversals <= step_schedule[i - 1].after_reversals) {
      return Error{fmt::format(
          "staircase: step_schedule[{}].after_reversals must be greater than "
          "step_schedule[{}].after_reversals ({}), got {}",
          i, i - 1, step_schedule[i - 1].after_reversals,
          change.after_reversals)};
    }
    if (Status s = CheckStepSize(fmt::format("step_schedule[{}].step_down", i),
                                 change.step_down);
        !s.ok()) {
      return s;
    }
    if (Status s = CheckStepSize(fmt::format("step_schedule[{}].step_up", i),
                                 change.step_up);
        !s.ok()) {
      return s;
    }
  }
  if (!std::isfinite(start_level)) {
    return Error{fmt::format(
        "staircase: start_level must be a finite number, got {}", start_level)};
  }
  if (step_scale != StepScale::kLinear && start_level <= 0.0) {
    return Error{fmt::format(
        "staircase: start_level must be positive for a {} step scale, got {}",
        StepScaleName(step_scale), start_level)};
  }
  if (std::isnan(floor_level) || std::isnan(ceiling_level)) {
    return Error{
        fmt::format("staircase: {} must be a number, got nan",
                    std::isnan(floor_level) ? "floor_level" : "ceiling_level")};
  }
  if (!(floor_level < ceiling_level)) {
    return Error{fmt::format(
        "staircase: floor_level ({}) must be below ceiling_level ({})",
        floor_level, ceiling_level)};
  }
  if (start_level < floor_level || start_level > ceiling_level) {
    return Error{
        fmt::format("staircase: start_level {} must lie within [floor_level, "
                    "ceiling_level] = [{}, {}]",
                    start_level, floor_level, ceiling_level)};
  }
  if (max_trials < 0) {
    return Error{fmt::format(
        "staircase: max_trials must be zero (no limit) or positive, got {}",
        max_trials)};
  }
  if (max_reversals < 0) {
    return Error{fmt::format(
        "staircase: max_reversals must be zero (no limit) or positive, got {}",
        max_reversals)};
  }
  if (max_trials == 0 && max_reversals == 0) {
    return Error{
        "staircase: can never stop: set max_trials or max_reversals (both "
        "are 0)"};
  }
  return {};
}

Staircase::Staircase(StaircaseOptions options)
    : options_(std::move(options)), anchor_(options_.start_level) {
  smallest_step_ = std::min(options_.step_down, options_.step_up);
  for (const StepChange& change : options_.step_schedule) {
    smallest_step_ =
        std::min({smallest_step_, change.step_down, change.step_up});
  }
  level_ =
      std::clamp(LevelAt(anchor_, 0.0, smallest_step_, options_.step_scale),
                 options_.floor_level, options_.ceiling_level);
}

void Staircase::StopAt(double bound) {
  level_ = bound;
  // The bound stays on the track's grid when its offset from the anchor is
  // a decimal of the step's resolution up to rounding error (a floor of 0.01
  // under a start of 1 in log10 steps: offset -2); otherwise (a ceiling of 4
  // in log10 steps: offset 0.60206...) the bound becomes the anchor, so the
  // next move goes one step from it.
  const double exact = ToScaleDomain(bound, options_.step_scale) -
                       ToScaleDomain(anchor_, options_.step_scale);
  const double offset = RoundToStep(exact, smallest_step_);
  if (std::fabs(exact - offset) <= 0.01 * StepResolution(smallest_step_)) {
    offset_ = offset;
  } else {
    anchor_ = bound;
    offset_ = 0.0;
  }
}

Result<Staircase> Staircase::Create(StaircaseOptions options) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  return Staircase(std::move(options));
}

bool Staircase::finished() const {
  return (options_.max_trials > 0 &&
          static_cast<int>(trials_.size()) >= options_.max_trials) ||
         (options_.max_reversals > 0 &&
          static_cast<int>(reversals_.size()) >= options_.max_reversals);
}

Result<StaircaseTrial> Staircase::Update(bool correct) {
  if (finished()) {
    return Error{fmt::format(
        "staircase: already finished after {} trial{} and {} reversal{}",
        trials_.size(), trials_.size() == 1 ? "" : "s", reversals_.size(),
        reversals_.size() == 1 ? "" : "s")};
  }
  StaircaseTrial trial;
  trial.index = static_cast<int>(trials_.size());
  trial.level = level_;
  trial.correct = correct;

  if (correct) {
    ++correct_run_;
    incorrect_run_ = 0;
  } else {
    ++incorrect_run_;
    correct_run_ = 0;
  }
  if (correct_run_ >= options_.n_down) {
    trial.move = Move::kDown;
  } else if (incorrect_run_ >= options_.n_up) {
    trial.move = Move::kUp;
  }

  if (trial.move != Move::kNone) {
    correct_run_ = 0;
    incorrect_run_ = 0;
    trial.reversal = last_move_ != Move::kNone && trial.move != last_move_;
    if (trial.reversal) reversals_.push_back({trial.index, trial.level});
    last_move_ = trial.move;

    // Sizes in force from the move making the r-th reversal on.
    const int reversal_count = static_cast<int>(reversals_.size());
    double step_down = options_.step_down;
    double step_up = options_.step_up;
    for (const StepChange& change : options_.step_schedule) {
      if (change.after_reversals > reversal_count) break;
      step_down = change.step_down;
      step_up = change.step_up;
    }
    trial.step_size = trial.move == Move::kDown ? step_down : step_up;

    const double signed_step =
        trial.move == Move::kDown ? -trial.step_size : trial.step_size;
    const double offset = RoundToStep(offset_ + signed_step, smallest_step_);
    const double next =
        LevelAt(anchor_, offset, smallest_step_, options_.step_scale);
    if (next < options_.floor_level) {
      StopAt(options_.floor_level);
      trial.clamped = true;
    } else if (next > options_.ceiling_level) {
      StopAt(options_.ceiling_level);
      trial.clamped = true;
    } else {
      offset_ = offset;
      level_ = next;
    }
  }
  trials_.push_back(trial);
  return trial;
}

Result<double> Staircase::Threshold(int last_k) const {
  if (last_k < 1) {
    return Error{fmt::format(
        "staircase: threshold needs at least 1 reversal, asked for {}",
        last_k)};
  }
  const int count = static_cast<int>(reversals_.size());
  if (count < last_k) {
    return Error{fmt::format(
        "staircase: threshold needs the last {} reversals, only {} happened",
        last_k, count)};
  }
  double sum = 0.0;
  for (int i = count - last_k; i < count; ++i) {
    sum += ToScaleDomain(reversals_[i].level, options_.step_scale);
  }
  return FromScaleDomain(sum / last_k, options_.step_scale);
}

Result<InterleavedStaircases> InterleavedStaircases::Create(
    const std::vector<StaircaseOptions>& options) {
  if (options.empty()) {
    return Error{"staircases: need at least one staircase, got 0"};
  }
  std::vector<Staircase> staircases;
  staircases.reserve(options.size());
  for (std::size_t i = 0; i < options.size(); ++i) {
    Result<Staircase> staircase = Staircase::Create(options[i]);
    if (!staircase.ok()) {
      return Error{
          fmt::format("staircases[{}]: {}", i, staircase.error().message)};
    }
    staircases.push_back(std::move(staircase).value());
  }
  return InterleavedStaircases(std::move(staircases));
}

Result<int> InterleavedStaircases::NextIndex(
    boost::random::mt19937& order_rng) const {
  std::vector<int> open;
  for (int i = 0; i < size(); ++i) {
    if (!staircases_[i].finished()) open.push_back(i);
  }
  if (open.empty()) {
    return Error{
        fmt::format("staircases: all {} staircases have finished", size())};
  }
  if (open.size() == 1) return open.front();
  boost::random::uniform_int_distribution<int> pick(
      0, static_cast<int>(open.size()) - 1);
  return open[pick(order_rng)];
}

Result<StaircaseTrial> InterleavedStaircases::Update(int index, bool correct) {
  if (index < 0 || index >= size()) {
    return Error{fmt::format("staircases: index {} is outside [0, {}]", index,
                             size() - 1)};
  }
  Result<StaircaseTrial> trial = staircases_[index].Update(correct);
  if (!trial.ok()) {
    return Error{
        fmt::format("staircases[{}]: {}", index, trial.error().message)};
  }
  return trial;
}

bool InterleavedStaircases::finished() const {
  return std::all_of(staircases_.begin(), staircases_.end(),
                     [](const Staircase& s) { return s.finished(); });
}

const Staircase& InterleavedStaircases::staircase(int index) const {
  assert(index >= 0 && index < size());
  return staircases_[index];
}

}  // namespace burrlab::protocols
