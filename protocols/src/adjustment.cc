// Method of adjustment: a clamped grid of steps, the path and the final
// level.
#include "burrlab/protocols/adjustment.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>
#include <string_view>
#include <utility>

namespace burrlab::protocols {
namespace {

constexpr int kMaxSteps = 100000;

}  // namespace

Status AdjustmentOptions::Validate() const {
  if (!std::isfinite(start_level)) {
    return Error{
        fmt::format("adjustment: start_level must be a finite number, got {}",
                    start_level)};
  }
  if (step_scale != StepScale::kLinear && start_level <= 0.0) {
    return Error{fmt::format(
        "adjustment: start_level must be positive for a {} step scale, got {}",
        StepScaleName(step_scale), start_level)};
  }
  if (!std::isfinite(step)) {
    return Error{
        fmt::format("adjustment: step must be a finite number, got {}", step)};
  }
  if (step <= 0.0) {
    return Error{
        fmt::format("adjustment: step must be positive, got {}", step)};
  }
  if (start_jitter_steps < 0) {
    return Error{fmt::format(
        "adjustment: start_jitter_steps must be zero or positive, got {}",
        start_jitter_steps)};
  }
  if (std::isnan(floor_level) || std::isnan(ceiling_level)) {
    return Error{
        fmt::format("adjustment: {} must be a number, got nan",
                    std::isnan(floor_level) ? "floor_level" : "ceiling_level")};
  }
  if (!(floor_level < ceiling_level)) {
    return Error{fmt::format(
        "adjustment: floor_level ({}) must be below ceiling_level ({})",
        floor_level, ceiling_level)};
  }
  const double low =
      ApplyStep(start_level, -start_jitter_steps * step, step_scale);
  const double high =
      ApplyStep(start_level, start_jitter_steps * step, step_scale);
  if (low < floor_level || high > ceiling_level) {
    if (start_jitter_steps == 0) {
      return Error{fmt::format(
          "adjustment: start_level {} must lie within [floor_level, "
          "ceiling_level] = [{}, {}]",
          start_level, floor_level, ceiling_level)};
    }
    return Error{fmt::format(
        "adjustment: start_level {} jittered by up to {} steps of {} ({}) "
        "spans [{}, {}], outside [floor_level, ceiling_level] = [{}, {}]",
        start_level, start_jitter_steps, step, StepScaleName(step_scale), low,
        high, floor_level, ceiling_level)};
  }
  if (max_steps < 1 || max_steps > kMaxSteps) {
    return Error{fmt::format("adjustment: max_steps must be in [1, {}], got {}",
                             kMaxSteps, max_steps)};
  }
  return {};
}

Adjustment::Adjustment(AdjustmentOptions options, int jitter_steps)
    : options_(std::move(options)), jitter_steps_(jitter_steps) {
  path_.reserve(static_cast<std::size_t>(options_.max_steps) + 1);
  path_.push_back(
      std::clamp(GridLevel(0), options_.floor_level, options_.ceiling_level));
}

Result<Adjustment> Adjustment::Create(const AdjustmentOptions& options,
                                      boost::random::mt19937& jitter_rng) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  int jitter = 0;
  if (options.start_jitter_steps > 0) {
    boost::random::uniform_int_distribution<int> draw(
        -options.start_jitter_steps, options.start_jitter_steps);
    jitter = draw(jitter_rng);
  }
  return Adjustment(options, jitter);
}

double Adjustment::GridLevel(int k) const {
  const double offset =
      RoundToStep((jitter_steps_ + k) * options_.step, options_.step);
  return LevelAt(options_.start_level, offset, options_.step,
                 options_.step_scale);
}

Status Adjustment::Step(int direction) {
  if (direction != 1 && direction != -1) {
    return Error{fmt::format("adjustment: direction must be +1 or -1, got {}",
                             direction)};
  }
  if (finished()) {
    return Error{"adjustment: already finished"};
  }
  if (steps_taken() >= options_.max_steps) {
    return Error{
        fmt::format("adjustment: max_steps ({}) reached; finish the adjustment",
                    options_.max_steps)};
  }
  const double raw = GridLevel(k_);
  const bool blocked = direction > 0 ? raw >= options_.ceiling_level
                                     : raw <= options_.floor_level;
  if (!blocked) k_ += direction;
  path_.push_back(
      std::clamp(GridLevel(k_), options_.floor_level, options_.ceiling_level));
  return {};
}

Result<double> Adjustment::Finish() {
  if (finished()) return Error{"adjustment: already finished"};
  final_level_ = level();
  return *final_level_;
}

}  // namespace burrlab::protocols
