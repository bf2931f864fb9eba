// Trial plans for two-interval forced choice (2AFC/2IFC: which of two
// intervals holds the comparison) and for the three-interval reference design
// of dissertation §13.5.2 (a reference, then materials A and B in random
// order; the subject says which of the two felt more like the reference).
// Both are balanced: every position holds the comparison (or the matching
// material) equally often, in a random order drawn from the caller's stream.
#ifndef BURRLAB_PROTOCOLS_TWO_INTERVAL_H_
#define BURRLAB_PROTOCOLS_TWO_INTERVAL_H_

#include <array>
#include <boost/random/mersenne_twister.hpp>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::protocols {

// One of the two materials of a block (A and B, as in §13.5).
enum class MaterialLabel {
  kA,  // material A
  kB,  // material B
};

// "A" or "B".
std::string_view MaterialLabelName(MaterialLabel label);

// Settings of a 2AFC block.
struct TwoIntervalOptions {
  int n_trials = 12;  // trials in the block; even, at most 100000

  // Names the field, its value and the rule broken, e.g. "two_interval: 13
  // trials cannot be balanced over intervals 1 and 2 (need a multiple of 2)".
  Status Validate() const;
};

// One planned 2AFC trial: A is the standard, B the comparison.
struct TwoIntervalTrial {
  int index = 0;                // 0-based trial number in the block
  int comparison_interval = 1;  // 1 or 2: the interval holding B
  std::array<MaterialLabel, 2> intervals = {
      MaterialLabel::kA, MaterialLabel::kB};  // material of interval 1 and 2
};

// n_trials trials, exactly half with the comparison in interval 1, in random
// order (one Fisher-Yates shuffle drawn from order_rng).
Result<std::vector<TwoIntervalTrial>> PlanTwoInterval(
    const TwoIntervalOptions& options, boost::random::mt19937& order_rng);

// Settings of a three-interval reference-design block (§13.5.2).
struct ReferenceDesignOptions {
  int n_trials = 10;  // trials in the block; even, at most 100000 (§13.5.2: 10)
  MaterialLabel matching_material =
      MaterialLabel::kA;  // the simulated material modelled on the reference

  // Names the field, its value and the rule broken.
  Status Validate() const;
};

// One planned trial of the reference design. Interval 1 is the reference (a
// real sample outside the computer, or a simulated material); intervals 2
// and 3 hold A and B in either order.
struct ReferenceTrial {
  int index = 0;  // 0-based trial number in the block
  std::array<MaterialLabel, 2> comparisons = {
      MaterialLabel::kA, MaterialLabel::kB};  // material of interval 2 and 3
  int correct_interval = 2;  // 2 or 3: the interval holding matching_material
};

// n_trials trials, exactly half with the matching material in interval 2, in
// random order (one Fisher-Yates shuffle drawn from order_rng).
Result<std::vector<ReferenceTrial>> PlanReferenceDesign(
    const ReferenceDesignOptions& options, boost::random::mt19937& order_rng);

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_TWO_INTERVAL_H_
