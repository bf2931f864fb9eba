// Balanced 2AFC and reference-design trial plans.
#include "burrlab/protocols/two_interval.h"

#include <fmt/format.h>

#include <boost/random/uniform_int_distribution.hpp>
#include <utility>

#include "max_trials.h"
#include "shuffle.h"

namespace burrlab::protocols {
namespace {

// Error unless n_trials is positive, even and at most kMaxTrials.
Status CheckEvenCount(std::string_view method, int n_trials,
                      std::string_view positions) {
  if (n_trials < 1) {
    return Error{
        fmt::format("{}: n_trials must be positive, got {}", method, n_trials)};
  }
  if (n_trials > kMaxTrials) {
    return Error{fmt::format("{}: n_trials must be at most {}, got {}", method,
                             kMaxTrials, n_trials)};
  }
  if (n_trials % 2 != 0) {
    return Error{fmt::format(
        "{}: {} trials cannot be balanced over {} (need a multiple of 2)",
        method, n_trials, positions)};
  }
  return {};
}

MaterialLabel Other(MaterialLabel label) {
  return label == MaterialLabel::kA ? MaterialLabel::kB : MaterialLabel::kA;
}

}  // namespace

std::string_view MaterialLabelName(MaterialLabel label) {
  return label == MaterialLabel::kA ? "A" : "B";
}

Status TwoIntervalOptions::Validate() const {
  return CheckEvenCount("two_interval", n_trials, "intervals 1 and 2");
}

Result<std::vector<TwoIntervalTrial>> PlanTwoInterval(
    const TwoIntervalOptions& options, boost::random::mt19937& order_rng) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  std::vector<int> positions;
  positions.reserve(static_cast<std::size_t>(options.n_trials));
  for (int i = 0; i < options.n_trials; ++i) positions.push_back(1 + i % 2);
  Shuffle(positions, order_rng);
  std::vector<TwoIntervalTrial> trials(positions.size());
  for (std::size_t i = 0; i < trials.size(); ++i) {
    trials[i].index = static_cast<int>(i);
    trials[i].comparison_interval = positions[i];
    trials[i].intervals =
        positions[i] == 1 ? std::array{MaterialLabel::kB, MaterialLabel::kA}
                          : std::array{MaterialLabel::kA, MaterialLabel::kB};
  }
  return trials;
}

Status ReferenceDesignOptions::Validate() const {
  return CheckEvenCount("reference_design", n_trials,
                        "A and B in intervals 2 and 3");
}

Result<std::vector<ReferenceTrial>> PlanReferenceDesign(
    const ReferenceDesignOptions& options, boost::random::mt19937& order_rng) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  std::vector<int> positions;
  positions.reserve(static_cast<std::size_t>(options.n_trials));
  for (int i = 0; i < options.n_trials; ++i) positions.push_back(2 + i % 2);
  Shuffle(positions, order_rng);
  const MaterialLabel match = options.matching_material;
  std::vector<ReferenceTrial> trials(positions.size());
  for (std::size_t i = 0; i < trials.size(); ++i) {
    trials[i].index = static_cast<int>(i);
    trials[i].correct_interval = positions[i];
    trials[i].comparisons = positions[i] == 2 ? std::array{match, Other(match)}
                                              : std::array{Other(match), match};
  }
  return trials;
}

}  // namespace burrlab::protocols
