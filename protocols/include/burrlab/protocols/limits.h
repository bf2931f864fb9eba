// The method of limits: ascending and descending series of levels on a fixed
// linear step, alternating, each starting at its direction's start level
// shifted by a random whole number of steps (so the subject cannot count
// steps), and each stopping at the first change of response. A series's
// transition point is the midpoint of its last two levels; the threshold is
// the mean of the transition points. Pure and deterministic: the jitter is
// drawn once, at creation, from the caller's stream.
//
// Rules, stated once:
//  - A change of response is a response that differs from the previous
//    response of the same series (so the first trial of a series never ends
//    it by a change). The responses are booleans of any meaning ("yes,
//    detected", "comparison stiffer").
//  - Series k presents start + i * step (ascending) or start - i * step
//    (descending), i = 0, 1, ..., each computed afresh and rounded to the
//    step (levels.h: 0.6 - 2 x 0.05 is 0.5, not 0.49999999999999994), as
//    are the jittered starts and the transition points. Levels beyond
//    [floor_level, ceiling_level] are never presented (a level within 1e-9
//    steps of a bound is presented as the bound). When the next level would lie
//    beyond the bound, the series ends without a transition ("no transition");
//    it counts as a series but not in the threshold.
#ifndef BURRLAB_PROTOCOLS_LIMITS_H_
#define BURRLAB_PROTOCOLS_LIMITS_H_

#include <boost/random/mersenne_twister.hpp>
#include <optional>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/levels.h"

namespace burrlab::protocols {

// Direction of a series of the method of limits.
enum class SeriesDirection {
  kAscending,   // levels increase
  kDescending,  // levels decrease
};

// "ascending" or "descending".
std::string_view SeriesDirectionName(SeriesDirection direction);

// Settings of a method-of-limits run (plain data with defaults).
struct LimitsOptions {
  SeriesDirection first_direction =
      SeriesDirection::kAscending;  // direction of series 0; then alternating
  int n_series = 4;                 // number of series, 1..1000
  double step = 1.0;                // level change per trial (axis units), > 0
  double ascending_start = 0.0;     // start of ascending series before jitter
  double descending_start = 10.0;   // start of descending series before jitter
  int start_jitter_steps = 0;   // each start moves by a uniform whole number
                                // of steps in [-this, +this]; 0: no jitter
  double floor_level = 0.0;     // lowest level presented, finite
  double ceiling_level = 10.0;  // highest level presented, finite

  // Names the first bad field, its value and the rule broken, e.g.
  // "limits: step must be positive, got 0". Every jittered start must lie
  // within the bounds, and a series may hold at most 100000 levels.
  Status Validate() const;
};

// One series, planned at creation and filled in as responses arrive.
struct LimitsSeries {
  SeriesDirection direction =
      SeriesDirection::kAscending;  // direction of this series
  int jitter_steps = 0;             // whole steps added to the start
  double start_level = 0.0;         // first level, jitter included
  int first_trial = 0;              // index of its first trial in trials()
  int n_trials = 0;                 // trials presented so far
  bool finished = false;            // true once it stopped
  std::optional<double>
      transition_level;  // midpoint of its last two levels; none when it
                         // reached a bound without a change (or is running)
};

// One completed trial.
struct LimitsTrial {
  int index = 0;   // 0-based trial number over all series
  int series = 0;  // index into series()
  SeriesDirection direction =
      SeriesDirection::kAscending;  // the series's direction
  double level = 0.0;               // level presented
  bool response = false;            // the response
  bool ends_series = false;         // the series stopped after this trial
  bool transition = false;          // it stopped on a change of response here
};

// One method-of-limits run: its series in order, fed one response at a time.
class MethodOfLimits {
 public:
  // A run whose start jitters are drawn now from jitter_rng, one draw per
  // series in series order (no draws when start_jitter_steps is 0); or the
  // error of options.Validate().
  static Result<MethodOfLimits> Create(const LimitsOptions& options,
                                       boost::random::mt19937& jitter_rng);

  // Level of the next trial (meaningless once finished()).
  double level() const { return level_; }
  // Index of the running series (n_series once finished()).
  int series_index() const { return current_; }
  // Records the response to the trial at level(); an error once finished().
  Result<LimitsTrial> Update(bool response);
  // True once every series has stopped.
  bool finished() const { return current_ >= options_.n_series; }
  // All series, planned ones included.
  const std::vector<LimitsSeries>& series() const { return series_; }
  // Trials so far, in order.
  const std::vector<LimitsTrial>& trials() const { return trials_; }
  // Mean transition level of the finished series with a transition (only
  // those of one direction when given); an error when there is none.
  Result<double> Threshold(
      std::optional<SeriesDirection> only = std::nullopt) const;
  // The options the run was created with.
  const LimitsOptions& options() const { return options_; }

 private:
  MethodOfLimits(LimitsOptions options, std::vector<LimitsSeries> series);
  // Level i steps into series s, or none beyond its bound.
  std::optional<double> SeriesLevel(const LimitsSeries& s, int i) const;

  LimitsOptions options_;
  std::vector<LimitsSeries> series_;
  std::vector<LimitsTrial> trials_;
  int current_ = 0;
  double level_ = 0.0;
};

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_LIMITS_H_
