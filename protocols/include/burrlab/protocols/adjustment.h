// The method of adjustment: the subject steps a comparison level up or down
// (keys, a knob) until it matches a reference or is just detectable; the
// engine keeps the level on a grid of whole steps from the (optionally
// jittered) start, clamps it to the bounds, records every level visited and
// the final level. Pure and deterministic: the jitter is drawn once, at
// creation, from the caller's stream.
//
// Levels: after k net steps (jitter included) the level is LevelAt(start,
// k * step, step, scale) (levels.h): computed afresh, no accumulated
// rounding, rounded to the step on a linear scale and to 12 significant
// digits on log10 and dB scales, then clamped to [floor_level,
// ceiling_level]. A step up at the ceiling (or down at the floor) leaves the
// level there and is still recorded; the next step the other way returns to
// the grid level below (above) the bound.
#ifndef BURRLAB_PROTOCOLS_ADJUSTMENT_H_
#define BURRLAB_PROTOCOLS_ADJUSTMENT_H_

#include <boost/random/mersenne_twister.hpp>
#include <limits>
#include <optional>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/staircase.h"

namespace burrlab::protocols {

// Settings of one adjustment (plain data with defaults).
struct AdjustmentOptions {
  double start_level = 1.0;    // comparison level before jitter (> 0 for
                               // log10/dB)
  int start_jitter_steps = 0;  // the start moves by a uniform whole number of
                               // steps in [-this, +this]; 0: no jitter
  double step = 0.1;           // one key press, in step-scale units, > 0
  StepScale step_scale = StepScale::kLinear;  // how a step changes the level
  double floor_level =
      -std::numeric_limits<double>::infinity();  // lowest level; -inf: none
  double ceiling_level =
      std::numeric_limits<double>::infinity();  // highest level; +inf: none
  int max_steps = 1000;  // steps allowed before Finish(), 1..100000

  // Names the first bad field, its value and the rule broken, e.g.
  // "adjustment: step must be positive, got 0". The jittered start must lie
  // within the bounds.
  Status Validate() const;
};

// One adjustment: the comparison level, stepped by the subject until Finish().
class Adjustment {
 public:
  // An adjustment at the jittered start (one draw from jitter_rng when
  // start_jitter_steps > 0, none otherwise), or the error of
  // options.Validate().
  static Result<Adjustment> Create(const AdjustmentOptions& options,
                                   boost::random::mt19937& jitter_rng);

  // Current comparison level.
  double level() const { return path_.back(); }
  // First level, jitter included.
  double start_level() const { return path_.front(); }
  // Whole steps the start was moved by.
  int jitter_steps() const { return jitter_steps_; }
  // Moves the level one step up (+1) or down (-1); an error for another
  // direction, after max_steps steps or after Finish().
  Status Step(int direction);
  // Ends the adjustment and returns the final level; an error if already
  // finished.
  Result<double> Finish();
  // True after Finish().
  bool finished() const { return final_level_.has_value(); }
  // The final level, once finished.
  std::optional<double> final_level() const { return final_level_; }
  // Every level, the start first and one entry per step (a step blocked at a
  // bound repeats the level).
  const std::vector<double>& path() const { return path_; }
  // Steps taken so far.
  int steps_taken() const { return static_cast<int>(path_.size()) - 1; }
  // The options it was created with.
  const AdjustmentOptions& options() const { return options_; }

 private:
  Adjustment(AdjustmentOptions options, int jitter_steps);
  // Unclamped grid level k steps from the jittered start.
  double GridLevel(int k) const;

  AdjustmentOptions options_;
  int jitter_steps_ = 0;
  int k_ = 0;  // net steps from the jittered start, kept within the bounds
  std::vector<double> path_;
  std::optional<double> final_level_;
};

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_ADJUSTMENT_H_
