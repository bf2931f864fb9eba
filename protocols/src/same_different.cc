// Balanced same-different sequences (dissertation §13.5.1).
#include "burrlab/protocols/same_different.h"

#include <fmt/format.h>

#include <boost/random/uniform_int_distribution.hpp>
#include <utility>

#include "max_trials.h"
#include "shuffle.h"

namespace burrlab::protocols {

std::string_view PairName(Pair pair) {
  switch (pair) {
    case Pair::kAA:
      return "AA";
    case Pair::kAB:
      return "AB";
    case Pair::kBA:
      return "BA";
    case Pair::kBB:
      return "BB";
  }
  return "?";
}

std::string_view SameDifferentAnswerName(SameDifferentAnswer answer) {
  return answer == SameDifferentAnswer::kSame ? "same" : "different";
}

Status SameDifferentOptions::Validate() const {
  if (n_trials < 1) {
    return Error{fmt::format(
        "same_different: n_trials must be positive, got {}", n_trials)};
  }
  if (n_trials > kMaxTrials) {
    return Error{
        fmt::format("same_different: n_trials must be at most {}, got {}",
                    kMaxTrials, n_trials)};
  }
  if (n_trials % 4 != 0) {
    return Error{fmt::format(
        "same_different: {} trials cannot be balanced over AA, AB, BA, BB "
        "(need a multiple of 4)",
        n_trials)};
  }
  return {};
}

Result<std::vector<SameDifferentTrial>> PlanSameDifferent(
    const SameDifferentOptions& options, boost::random::mt19937& order_rng) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  std::vector<Pair> pairs;
  pairs.reserve(static_cast<std::size_t>(options.n_trials));
  for (Pair pair : {Pair::kAA, Pair::kAB, Pair::kBA, Pair::kBB}) {
    for (int i = 0; i < options.n_trials / 4; ++i) pairs.push_back(pair);
  }
  Shuffle(pairs, order_rng);
  std::vector<SameDifferentTrial> trials(pairs.size());
  for (std::size_t i = 0; i < trials.size(); ++i) {
    SameDifferentTrial& trial = trials[i];
    trial.index = static_cast<int>(i);
    trial.pair = pairs[i];
    const bool first_a = pairs[i] == Pair::kAA || pairs[i] == Pair::kAB;
    const bool second_a = pairs[i] == Pair::kAA || pairs[i] == Pair::kBA;
    trial.intervals = {first_a ? MaterialLabel::kA : MaterialLabel::kB,
                       second_a ? MaterialLabel::kA : MaterialLabel::kB};
    trial.correct_answer = first_a == second_a
                               ? SameDifferentAnswer::kSame
                               : SameDifferentAnswer::kDifferent;
  }
  return trials;
}

}  // namespace burrlab::protocols
