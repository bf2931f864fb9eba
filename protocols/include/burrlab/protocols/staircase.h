// Transformed up-down staircases (Levitt 1971): n-down/1-up (and generally
// n-down/m-up) tracks with separate up and down step sizes (Kaernbach 1991
// weighted up-down), step sizes that change after given reversal counts,
// linear, log10 or dB steps, floor and ceiling, and stop rules; plus several
// staircases interleaved at random within one block. Pure and deterministic:
// the engines consume responses and yield levels, no I/O, no devices.
//
// Rules, stated once (Staircase follows them exactly):
//  - Levels are easier upward (e.g. a larger material difference): correct
//    responses move the level down, incorrect ones up.
//  - After each response the run counters advance: a correct response adds to
//    the run of correct ones and clears the run of incorrect ones, and vice
//    versa. When n_down correct responses have run in a row the level moves
//    down (harder) by the down step; when n_up incorrect ones have, it moves
//    up (easier) by the up step. A move clears both runs. The rule applies
//    from the first trial (no initial 1-up/1-down phase).
//  - A reversal is a move whose direction is opposite to the direction of the
//    previous move. The first move is never a reversal. The reversal is
//    flagged on the trial whose response triggered the reversing move, and
//    its level (the peak or valley of the track) is the reversal level.
//  - Step sizes: a move that makes the r-th reversal, and every later move,
//    uses the sizes of the last step_schedule entry with after_reversals <= r
//    (the base step_down/step_up before any entry applies). So the step size
//    shrinks on the very move that turns the track (PsychoPy PR #539 fixed
//    the opposite behaviour).
//  - Levels (levels.h): the track keeps an anchor (start_level) and an offset,
//    the sum of its signed moves in step-scale units rounded to the smallest
//    step after each move; the level is LevelAt(anchor, offset), computed
//    afresh, so a level reached twice is the same double. The first level is
//    start_level rounded so too.
//  - Bounds: a move that would leave [floor_level, ceiling_level] stops at the
//    bound; a move at the bound leaves the level there. Such a move still has
//    its direction, so the first move back from the bound is a reversal and
//    its level is the bound. Moves from the bound go on from it: on the same
//    grid when the bound is one of its levels, else from the bound as anchor.
//  - Stop: finished once max_trials trials or max_reversals reversals have
//    happened, whichever comes first (0 = that limit unset).
#ifndef BURRLAB_PROTOCOLS_STAIRCASE_H_
#define BURRLAB_PROTOCOLS_STAIRCASE_H_

#include <boost/random/mersenne_twister.hpp>
#include <limits>
#include <string_view>
#include <utility>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/levels.h"

namespace burrlab::protocols {

// Step sizes that take over from the move making the after_reversals-th
// reversal on.
struct StepChange {
  int after_reversals = 1;  // reversal count from which these sizes apply
  double step_down = 1.0;   // size of a down move, in step-scale units
  double step_up = 1.0;     // size of an up move, in step-scale units
};

// Settings of one staircase (plain data with defaults; levels are easier
// upward: a correct run moves the level down).
struct StaircaseOptions {
  int n_down = 2;  // correct responses in a row that move the level down
  int n_up = 1;    // incorrect responses in a row that move the level up
  double step_down = 1.0;  // initial down step, in step-scale units
  double step_up = 1.0;    // initial up step, in step-scale units
  StepScale step_scale = StepScale::kLinear;  // how steps change the level
  std::vector<StepChange>
      step_schedule;  // later step sizes, after_reversals strictly increasing
  double start_level = 1.0;  // level of the first trial (> 0 for log10/dB)
  double floor_level =
      -std::numeric_limits<double>::infinity();  // lowest level; -inf: none
  double ceiling_level =
      std::numeric_limits<double>::infinity();  // highest level; +inf: none
  int max_trials = 50;    // stop after this many trials; 0: no trial limit
  int max_reversals = 0;  // stop after this many reversals; 0: no limit

  // Names the first bad field, its value and the rule broken, e.g.
  // "staircase: step_down must be positive, got 0".
  Status Validate() const;
};

// What the staircase rule did after a response.
enum class Move {
  kNone,  // the level stays
  kDown,  // harder: the level decreased (or stayed at the floor)
  kUp,    // easier: the level increased (or stayed at the ceiling)
};

// "none", "down" or "up".
std::string_view MoveName(Move move);

// One completed trial of a staircase.
struct StaircaseTrial {
  int index = 0;            // 0-based trial number within this staircase
  double level = 0.0;       // level presented
  bool correct = false;     // the response
  Move move = Move::kNone;  // the rule's decision after this response
  double step_size = 0.0;   // size of that move in step-scale units; 0: none
  bool reversal = false;    // the move reversed the previous move's direction
  bool clamped = false;     // the move would have left the bounds and stopped
                            // at the floor or ceiling
};

// A turning point of the track.
struct Reversal {
  int trial_index = 0;  // the trial whose response triggered the reversal
  double level = 0.0;   // that trial's level
};

// One transformed up-down track.
class Staircase {
 public:
  // A staircase at options.start_level, or the error of options.Validate().
  static Result<Staircase> Create(StaircaseOptions options);

  // Level of the next trial.
  double level() const { return level_; }
  // Records the response to the trial at level() and moves the level; an
  // error once finished().
  Result<StaircaseTrial> Update(bool correct);
  // True once max_trials trials or max_reversals reversals have happened.
  bool finished() const;
  // Reversals so far, in order.
  const std::vector<Reversal>& reversals() const { return reversals_; }
  // Trials so far, in order.
  const std::vector<StaircaseTrial>& trials() const { return trials_; }
  // Mean of the last k reversal levels: arithmetic for a linear scale,
  // geometric (mean in log units) for log10 and dB. Error when k < 1 or fewer
  // than k reversals happened. An even k balances peaks and valleys.
  Result<double> Threshold(int last_k) const;
  // The options the staircase was created with.
  const StaircaseOptions& options() const { return options_; }

 private:
  explicit Staircase(StaircaseOptions options);
  // Puts the level at `bound` (floor or ceiling).
  void StopAt(double bound);

  StaircaseOptions options_;
  double smallest_step_ = 1.0;  // smallest step size of options_, > 0
  double anchor_ = 0.0;         // level the offset counts from
  double offset_ = 0.0;         // sum of moves from anchor_, step-scale units
  double level_ = 0.0;          // LevelAt(anchor_, offset_) or a bound
  int correct_run_ = 0;
  int incorrect_run_ = 0;
  Move last_move_ = Move::kNone;
  std::vector<StaircaseTrial> trials_;
  std::vector<Reversal> reversals_;
};

// Several staircases run in one block, the next one chosen at random per
// trial; each keeps its own state.
class InterleavedStaircases {
 public:
  // One staircase per options entry; errors read "staircases[i]: ...".
  static Result<InterleavedStaircases> Create(
      const std::vector<StaircaseOptions>& options);

  // Index of the staircase for the next trial, uniform among the unfinished
  // ones (one draw from order_rng; no draw when only one is left); an error
  // when all have finished.
  Result<int> NextIndex(boost::random::mt19937& order_rng) const;
  // Records a response for staircase `index`; an error for a bad index or a
  // finished staircase.
  Result<StaircaseTrial> Update(int index, bool correct);
  // True when every staircase has finished.
  bool finished() const;
  // Number of staircases.
  int size() const { return static_cast<int>(staircases_.size()); }
  // Staircase `index` (0 <= index < size()).
  const Staircase& staircase(int index) const;

 private:
  explicit InterleavedStaircases(std::vector<Staircase> staircases)
      : staircases_(std::move(staircases)) {}

  std::vector<Staircase> staircases_;
};

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_STAIRCASE_H_
