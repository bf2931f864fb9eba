// Trial plans for the method of constant stimuli: fixed levels along a
// stimulus axis, each repeated a set number of times, in full random order
// (one permutation of all trials) or blocked random order (each block holds
// every level once, shuffled per block); yes/no or 2AFC, where 2AFC also
// places the comparison in interval 1 or 2, balanced per level.
#ifndef BURRLAB_PROTOCOLS_CONSTANT_STIMULI_H_
#define BURRLAB_PROTOCOLS_CONSTANT_STIMULI_H_

#include <boost/random/mersenne_twister.hpp>
#include <optional>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::protocols {

// How the trials of a block are ordered.
enum class TrialOrder {
  kFull,     // one random permutation of all levels x repetitions
  kBlocked,  // repetition r is block r: every level once, shuffled per block
};

// "full" or "blocked".
std::string_view TrialOrderName(TrialOrder order);

// What the subject is asked.
enum class ResponseMode {
  kYesNo,        // one interval; did the subject detect / judge it so
  kTwoInterval,  // 2AFC: standard and comparison in random interval order
};

// "yes_no" or "2afc".
std::string_view ResponseModeName(ResponseMode mode);

// Settings of a constant-stimuli block (plain data with defaults).
struct ConstantStimuliOptions {
  std::vector<double> levels;            // stimulus levels (axis units), finite
  int repetitions = 10;                  // presentations of each level, >= 1
  TrialOrder order = TrialOrder::kFull;  // randomization scheme
  ResponseMode response = ResponseMode::kYesNo;  // yes/no or 2AFC

  // Names the first bad field, its value and the rule broken, e.g.
  // "constant_stimuli: repetitions must be at least 1, got 0". At most
  // 100000 trials in all.
  Status Validate() const;
};

// One planned trial.
struct ConstantStimuliTrial {
  int index = 0;        // 0-based trial number in the block
  int level_index = 0;  // index into options.levels
  double level = 0.0;   // options.levels[level_index]
  int repetition = 0;   // 0-based presentation count of this level so far;
                        // in blocked order also the block number
  std::optional<int> comparison_interval;  // 2AFC: 1 or 2; yes/no: none
};

// The trials of one block. Draws from order_rng, in this order: the trial
// order (one Fisher-Yates shuffle of all trials, or one per block); then, for
// 2AFC, for each level in index order one draw for the odd extra trial's
// interval (only when repetitions is odd) and one shuffle of that level's
// intervals, assigned to its trials in plan order. With an even repetition
// count every level has exactly repetitions/2 trials with the comparison in
// each interval.
Result<std::vector<ConstantStimuliTrial>> PlanConstantStimuli(
    const ConstantStimuliOptions& options, boost::random::mt19937& order_rng);

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_CONSTANT_STIMULI_H_
