// Balanced same-different sequences (dissertation §13.5.1): each trial shows
// material A or B in each of two intervals, and the subject says "same" or
// "different". A block has exactly n/4 trials of each pair AA, AB, BA, BB in
// a random order drawn from the caller's stream (12 trials: 3 of each).
#ifndef BURRLAB_PROTOCOLS_SAME_DIFFERENT_H_
#define BURRLAB_PROTOCOLS_SAME_DIFFERENT_H_

#include <array>
#include <boost/random/mersenne_twister.hpp>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/two_interval.h"

namespace burrlab::protocols {

// The materials of a trial's two intervals.
enum class Pair { kAA, kAB, kBA, kBB };

// "AA", "AB", "BA" or "BB".
std::string_view PairName(Pair pair);

// The answer a same-different trial asks for.
enum class SameDifferentAnswer { kSame, kDifferent };

// "same" or "different".
std::string_view SameDifferentAnswerName(SameDifferentAnswer answer);

// Settings of a same-different block.
struct SameDifferentOptions {
  int n_trials = 12;  // trials in the block; a multiple of 4, at most 100000

  // Names the field, its value and the rule broken, e.g. "same_different: 14
  // trials cannot be balanced over AA, AB, BA, BB (need a multiple of 4)".
  Status Validate() const;
};

// One planned same-different trial.
struct SameDifferentTrial {
  int index = 0;          // 0-based trial number in the block
  Pair pair = Pair::kAA;  // which materials the intervals show
  std::array<MaterialLabel, 2> intervals = {
      MaterialLabel::kA, MaterialLabel::kA};  // material of interval 1 and 2
  SameDifferentAnswer correct_answer =
      SameDifferentAnswer::kSame;  // same for AA and BB, different otherwise
};

// n_trials trials, n_trials/4 of each pair, in random order (one
// Fisher-Yates shuffle of AA..AB..BA..BB.. drawn from order_rng).
Result<std::vector<SameDifferentTrial>> PlanSameDifferent(
    const SameDifferentOptions& options, boost::random::mt19937& order_rng);

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_SAME_DIFFERENT_H_
