// A simulated subject's decisions: each interval's percept is the log of the
// cue the simulated hand felt in that interval's force/position trace plus
// Gaussian noise, psi = ln(cue) + eps, eps ~ N(0, sigma^2), with sigma the
// Weber fraction of the task's cue (stiffness for probing, penetration rate for
// drilling). The observer decides by a rule suited to the method, lapses
// (answers at random) at a set rate and takes a log-normal response time. It
// never sees the materials' parameters: only the cues and the levels the
// question is about.
#ifndef BURRLAB_PROTOCOLS_OBSERVER_H_
#define BURRLAB_PROTOCOLS_OBSERVER_H_

#include <boost/random/mersenne_twister.hpp>
#include <optional>
#include <span>
#include <string_view>

#include "burrlab/base/result.h"
#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/protocol.h"

namespace burrlab::protocols {

// Settings of a simulated observer.
// The largest Weber fraction an observer can have (sigma of ln cue: such an
// observer answers at chance for any cue ratio in use).
inline constexpr double kMaxWeberFraction = 5.0;

// What a simulated observer's answers follow.
enum class AnswerRule {
  kPercepts,       // its noisy percepts of the cues (the model above)
  kAlwaysCorrect,  // "always=correct": the correct answer whatever it felt;
                   // "yes" where a trial has none; adjustments step up
  kAlwaysWrong,    // "always=wrong": a wrong answer; "no" where a trial has
                   // none; adjustments step down
};

struct ObserverParams {
  double weber_stiffness = 0.20;  // sigma of ln(stiffness) (probe)
  double weber_removal = 0.30;    // sigma of ln(penetration rate) (drill)
  double lapse = 0.02;            // probability of a random answer
  double criterion = 1.0;         // same-different and limits: "different" when
                                  // |psi1 - psi2| > criterion x sigma x sqrt(2)
  double rt_median_s = 1.0;       // response time median
  double rt_log_sd = 0.35;        // response time spread (sd of ln rt)
  double match_tolerance = 0.5;   // adjustment: stop when the percepts differ
                                  // by less than this x sigma
  // kPercepts, or a fixed answer for checking that a protocol runs to its
  // end at the edges of its levels (no lapses then; a trial with neither a
  // correct answer nor "yes" gets the percepts' answer).
  AnswerRule answers = AnswerRule::kPercepts;

  // Names the first bad field, its value and the rule broken.
  Status Validate() const;
};

// The protocol's [observer] defaults as parameters.
ObserverParams ObserverParamsFrom(const ObserverDefaults& defaults);

// Parses "simulated" or "simulated:key=value,..." (keys: weber (both cues),
// weber_stiffness, weber_removal, lapse, criterion, rt_median_s, and
// always=correct|wrong) over `base`.
Result<ObserverParams> ParseObserverSpec(std::string_view spec,
                                         ObserverParams base);

// Cues of one trial's intervals, as the simulated hand felt them.
struct TrialCues {
  std::span<const double> cues;        // one per interval (same order), > 0
  std::optional<double> standard_cue;  // yes/no trials: the remembered
                                       // standard's cue
};

class SimulatedObserver {
 public:
  explicit SimulatedObserver(ObserverParams params) : params_(params) {}

  // Perceptual noise of the task's cue.
  double Sigma(Task task) const;
  // The answer to a (non-adjustment) trial and a response time; draws from
  // `rng` in a fixed order (lapse, one noise draw per percept, the lapse
  // answer, the response time). An error when a cue is missing or not > 0.
  Result<Response> Decide(const TrialSpec& trial, const TrialCues& cues,
                          boost::random::mt19937& rng) const;
  // One adjustment step: '+' to raise the comparison level, '-' to lower
  // it, '=' when it matches. `direction` is +1 when the cue grows with the
  // level and -1 when it shrinks.
  char AdjustStep(Task task, double standard_cue, double comparison_cue,
                  int direction, boost::random::mt19937& rng) const;
  // A response time drawn from the log-normal.
  double ResponseTime(boost::random::mt19937& rng) const;

  const ObserverParams& params() const { return params_; }

 private:
  ObserverParams params_;
};

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_OBSERVER_H_
