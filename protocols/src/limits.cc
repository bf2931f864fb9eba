// Method of limits: alternating jittered series, transition points,
// threshold.
#include "burrlab/protocols/limits.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>
#include <string>
#include <utility>

namespace burrlab::protocols {
namespace {

constexpr int kMaxSeries = 1000;
constexpr double kMaxLevelsPerSeries = 100000.0;
// A level this many steps beyond a bound still counts as the bound (rounding).
constexpr double kBoundToleranceSteps = 1e-9;

// Error unless value is finite.
Status CheckFinite(std::string_view name, double value) {
  if (!std::isfinite(value)) {
    return Error{
        fmt::format("limits: {} must be a finite number, got {}", name, value)};
  }
  return {};
}

// Error unless start +- jitter steps stays within the bounds.
Status CheckStart(std::string_view name, double start, const LimitsOptions& o) {
  const double tolerance = kBoundToleranceSteps * o.step;
  const double low = start - o.start_jitter_steps * o.step;
  const double high = start + o.start_jitter_steps * o.step;
  if (low >= o.floor_level - tolerance && high <= o.ceiling_level + tolerance) {
    return {};
  }
  if (o.start_jitter_steps == 0) {
    return Error{fmt::format(
        "limits: {} {} must lie within [floor_level, ceiling_level] = [{}, {}]",
        name, start, o.floor_level, o.ceiling_level)};
  }
  if (low < o.floor_level - tolerance) {
    return Error{fmt::format(
        "limits: {} {} jittered by up to {} steps of {} reaches {}, below "
        "floor_level {}",
        name, start, o.start_jitter_steps, o.step, low, o.floor_level)};
  }
  return Error{fmt::format(
      "limits: {} {} jittered by up to {} steps of {} reaches {}, above "
      "ceiling_level {}",
      name, start, o.start_jitter_steps, o.step, high, o.ceiling_level)};
}

}  // namespace

std::string_view SeriesDirectionName(SeriesDirection direction) {
  return direction == SeriesDirection::kAscending ? "ascending" : "descending";
}

Status LimitsOptions::Validate() const {
  if (n_series < 1 || n_series > kMaxSeries) {
    return Error{fmt::format("limits: n_series must be in [1, {}], got {}",
                             kMaxSeries, n_series)};
  }
  if (Status s = CheckFinite("step", step); !s.ok()) return s;
  if (step <= 0.0) {
    return Error{fmt::format("limits: step must be positive, got {}", step)};
  }
  if (Status s = CheckFinite("floor_level", floor_level); !s.ok()) return s;
  if (Status s = CheckFinite("ceiling_level", ceiling_level); !s.ok()) return s;
  if (!(floor_level < ceiling_level)) {
    return Error{
        fmt::format("limits: floor_level ({}) must be below ceiling_level ({})",
                    floor_level, ceiling_level)};
  }
  const double levels = (ceiling_level - floor_level) / step;
  if (levels > kMaxLevelsPerSeries) {
    return Error{fmt::format(
        "limits: (ceiling_level - floor_level) / step = {} levels per series, "
        "at most {} allowed",
        levels, kMaxLevelsPerSeries)};
  }
  if (start_jitter_steps < 0) {
    return Error{fmt::format(
        "limits: start_jitter_steps must be zero or positive, got {}",
        start_jitter_steps)};
  }
  if (Status s = CheckFinite("ascending_start", ascending_start); !s.ok()) {
    return s;
  }
  if (Status s = CheckFinite("descending_start", descending_start); !s.ok()) {
    return s;
  }
  if (Status s = CheckStart("ascending_start", ascending_start, *this);
      !s.ok()) {
    return s;
  }
  return CheckStart("descending_start", descending_start, *this);
}

MethodOfLimits::MethodOfLimits(LimitsOptions options,
                               std::vector<LimitsSeries> series)
    : options_(std::move(options)), series_(std::move(series)) {
  level_ = series_.front().start_level;
}

Result<MethodOfLimits> MethodOfLimits::Create(
    const LimitsOptions& options, boost::random::mt19937& jitter_rng) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  std::vector<LimitsSeries> series(static_cast<std::size_t>(options.n_series));
  SeriesDirection direction = options.first_direction;
  for (LimitsSeries& s : series) {
    s.direction = direction;
    if (options.start_jitter_steps > 0) {
      boost::random::uniform_int_distribution<int> jitter(
          -options.start_jitter_steps, options.start_jitter_steps);
      s.jitter_steps = jitter(jitter_rng);
    }
    const double start = direction == SeriesDirection::kAscending
                             ? options.ascending_start
                             : options.descending_start;
    s.start_level = std::clamp(
        LevelAt(start, RoundToStep(s.jitter_steps * options.step, options.step),
                options.step, StepScale::kLinear),
        options.floor_level, options.ceiling_level);
    direction = direction == SeriesDirection::kAscending
                    ? SeriesDirection::kDescending
                    : SeriesDirection::kAscending;
  }
  return MethodOfLimits(options, std::move(series));
}

std::optional<double> MethodOfLimits::SeriesLevel(const LimitsSeries& s,
                                                  int i) const {
  const double sign = s.direction == SeriesDirection::kAscending ? 1.0 : -1.0;
  const double raw = LevelAt(
      s.start_level, RoundToStep(sign * i * options_.step, options_.step),
      options_.step, StepScale::kLinear);
  const double tolerance = kBoundToleranceSteps * options_.step;
  if (raw > options_.ceiling_level + tolerance ||
      raw < options_.floor_level - tolerance) {
    return std::nullopt;
  }
  return std::clamp(raw, options_.floor_level, options_.ceiling_level);
}

Result<LimitsTrial> MethodOfLimits::Update(bool response) {
  if (finished()) {
    return Error{
        fmt::format("limits: already finished after {} series and {} trials",
                    series_.size(), trials_.size())};
  }
  LimitsSeries& s = series_[current_];
  LimitsTrial trial;
  trial.index = static_cast<int>(trials_.size());
  trial.series = current_;
  trial.direction = s.direction;
  trial.level = level_;
  trial.response = response;
  if (s.n_trials == 0) s.first_trial = trial.index;

  if (s.n_trials > 0 && trials_.back().response != response) {
    trial.transition = true;
    trial.ends_series = true;
    s.transition_level =
        RoundToStep(0.5 * (trials_.back().level + trial.level), options_.step);
  } else if (std::optional<double> next = SeriesLevel(s, s.n_trials + 1)) {
    level_ = *next;
  } else {
    trial.ends_series = true;
  }
  ++s.n_trials;
  trials_.push_back(trial);

  if (trial.ends_series) {
    s.finished = true;
    ++current_;
    if (!finished()) level_ = series_[current_].start_level;
  }
  return trial;
}

Result<double> MethodOfLimits::Threshold(
    std::optional<SeriesDirection> only) const {
  double sum = 0.0;
  int count = 0;
  for (const LimitsSeries& s : series_) {
    if (!s.finished || !s.transition_level) continue;
    if (only && s.direction != *only) continue;
    sum += *s.transition_level;
    ++count;
  }
  if (count == 0) {
    const int done = static_cast<int>(std::count_if(
        series_.begin(), series_.end(), [&](const LimitsSeries& s) {
          return s.finished && (!only || s.direction == *only);
        }));
    const std::string which =
        only ? fmt::format("{} ", SeriesDirectionName(*only)) : "";
    if (done == 0) {
      return Error{fmt::format("limits: no {}series has finished yet", which)};
    }
    return Error{fmt::format(
        "limits: none of the {} finished {}series had a transition (each "
        "reached a bound without a change of response)",
        done, which)};
  }
  return sum / count;
}

}  // namespace burrlab::protocols
