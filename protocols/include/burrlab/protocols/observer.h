// A simulated subject's decisions: each interval's percept is the log of the
// cue the simulated hand felt in that interval's force/position trace plus
// Gaussian noise, psi = ln(cue) + eps, eps ~ N(0, sigma^2), with sigma the
// Weber fraction of the task's cue (stiffness for probing, penetration rate for
// drilling). The observer decides by a rule suited to the method, lapses
// (answers at random) at a set rate and takes a log-normal response time. It
// never sees the materials' parameters: only the cues and the levels the
// question is about.
//
// Everything a simulated subject decides is here; the runner only renders
// the cues it feels: the floor of a felt cue, the stand-in felt for a real
// reference, the standard remembered in a yes/no block, the walk of an
// adjustment and a simulated population's spread of Weber fractions.
#ifndef BURRLAB_PROTOCOLS_OBSERVER_H_
#define BURRLAB_PROTOCOLS_OBSERVER_H_

#include <algorithm>
#include <array>
#include <boost/random/mersenne_twister.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
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

// SameDifferentRule (protocol.h): how a same-different observer decides.

// The rule's name in a spec or protocol ("fixed", "differencing",
// "likelihood").
std::string_view SameDifferentRuleName(SameDifferentRule rule);
// The rule of a name, or an error listing the names.
Result<SameDifferentRule> ParseSameDifferentRule(std::string_view name);

// What an observer has learned of one material by feeling it (familiarization
// or a pool of renderings): the mean and the variance of ln(cue) over its
// renderings. The observer adds its own noise, sigma^2, to the variance.
struct FeltMaterial {
  double mean_ln_cue = 0.0;
  double var_ln_cue = 0.0;  // >= 0
};

// FeltMaterial of a material's rendered cues (each > 0; FeltCue applied):
// their mean ln cue and the variance over renderings (divisor n - 1; 0 for a
// single rendering).
FeltMaterial FeltMaterialOf(std::span<const double> cues);

// ln P(different) - ln P(same) of a same-different trial's percepts (psi1,
// psi2) under `rule` (kDifferencing or kLikelihood), with materials a and b
// as felt and internal noise sigma; equal priors. Exposed for tests and for
// expected scores.
double SameDifferentLogOdds(SameDifferentRule rule, double psi1, double psi2,
                            const FeltMaterial& a, const FeltMaterial& b,
                            double sigma);

// How a simulated subject explores: its typical force and pressing speed,
// relative to the protocol's probe_force_n, drill_force_n and 1 /
// press_period_s, and how they vary from one of its intervals to the next
// (SD of ln; 0: every interval alike).
// A simulated population's subjects differ in their typical force and speed
// by subject_force_spread and subject_speed_spread (SD of ln;
// DrawSubjectObserver draws a subject's factors from them).
struct Exploration {
  double force_factor = 1.0;
  double speed_factor = 1.0;
  double force_spread = 0.0;
  double speed_spread = 0.0;
  double subject_force_spread = 0.0;
  double subject_speed_spread = 0.0;

  // True unless every interval is the protocol's nominal one (the subject
  // spreads do not count: they vary subjects, not this subject's intervals).
  bool Varies() const {
    return force_factor != 1.0 || speed_factor != 1.0 || force_spread > 0.0 ||
           speed_spread > 0.0;
  }
};

// The largest |bias| of an observer (prior odds of e^5 = 148 to 1).
inline constexpr double kMaxBias = 5.0;

// The largest factor of a subject's typical force or speed (and the smallest,
// its inverse).
inline constexpr double kMaxExplorationFactor = 5.0;

struct ObserverParams {
  double weber_stiffness = 0.20;  // sigma of ln(stiffness) (probe)
  double weber_removal = 0.30;    // sigma of ln(penetration rate) (drill)
  double lapse = 0.02;            // probability of a random answer
  double criterion = 1.0;         // same-different (rule fixed) and limits:
                                  // "different" when |psi1 - psi2| >
                                  // criterion x sigma x sqrt(2)
  // Same-different: how the percepts are compared (protocol.h).
  SameDifferentRule rule = SameDifferentRule::kFixed;
  // Same-different under the differencing and likelihood rules: "different"
  // when ln P(different) - ln P(same) of the percepts exceeds bias, i.e. the
  // observer takes the prior odds of a same pair to be e^bias (0: even, the
  // designs' own; > 0 leans to "same"). The fixed rule's criterion is its
  // bias.
  double bias = 0.0;
  double rt_median_s = 1.0;      // response time median
  double rt_log_sd = 0.35;       // response time spread (sd of ln rt)
  double match_tolerance = 0.5;  // adjustment: stop when the percepts differ
                                 // by less than this x sigma
  // kPercepts, or a fixed answer for checking that a protocol runs to its
  // end at the edges of its levels (no lapses then; a trial with neither a
  // correct answer nor "yes" gets the percepts' answer).
  AnswerRule answers = AnswerRule::kPercepts;
  // How the simulated hand presses and drills (nothing varies by default).
  Exploration exploration;

  // Names the first bad field, its value and the rule broken.
  Status Validate() const;
};

// The interval `nominal` (the protocol's, SimulatedIntervalOptions) as a
// subject exploring with `e` performs it: its forces times e.force_factor x
// exp(e.force_spread z1) and its pressing speed times e.speed_factor x
// exp(e.speed_spread z2) (press_period_s divided by it), with z1 and z2 ~
// N(0, 1) drawn from `stream` in that order whenever a spread is > 0 (nothing
// drawn otherwise). What the interval cannot take is held at its bound: the
// press period within [0.1 s, duration_s], the probe force at most
// stimuli::MaxProbeForceN (harder would bury the burr) and 20 N, the drill
// force at most 20 N. A nominal `e` returns `nominal`.
stimuli::IntervalOptions ExploredInterval(
    const stimuli::IntervalOptions& nominal, const Exploration& e,
    boost::random::mt19937& stream);

// The protocol's [observer] defaults as parameters.
ObserverParams ObserverParamsFrom(const ObserverDefaults& defaults);

// Parses "simulated" or "simulated:key=value,..." (keys: weber (both cues),
// weber_stiffness, weber_removal, lapse, criterion, bias, rt_median_s,
// rule=fixed|differencing|likelihood, exploration=fixed|varied, force_spread,
// speed_spread, subject_force_spread, subject_speed_spread and
// always=correct|wrong) over `base`.
Result<ObserverParams> ParseObserverSpec(std::string_view spec,
                                         ObserverParams base);

// The weakest cue an observer distinguishes from none: a drill interval too
// short to cut (the rate over its second half can come out 0 or negative)
// feels like 1 um/s; a probe that barely touches like 0.001 N/mm.
inline constexpr double kFeltCueFloor = 1e-3;

// The cue a simulated observer feels of an interval rendered with cue `cue`:
// at least kFeltCueFloor.
inline double FeltCue(double cue) { return std::max(cue, kFeltCueFloor); }

// A real sample (an interval with no material: a real reference) is felt by
// a simulated observer through a stand-in, the protocol material modelled on
// the sample (an assumption: the model is right): `block`'s material_a or
// material_b, as its reference.matching_material says. The error "reference
// stand-in material is missing" when the protocol has no such material.
Result<const ProtocolMaterial*> ReferenceStandIn(const Protocol& protocol,
                                                 const Block& block);
// How long the stand-in is felt: as long as `trial`'s second interval (the
// first comparison); 10 s when the trial has a single interval.
double ReferenceStandInDuration(const TrialSpec& trial);

// Spread of the Weber fractions across a simulated population (SD of ln W;
// 0: all alike).
struct WeberSpread {
  double stiffness = 0.0;
  double removal = 0.0;
};

// Subject `subject` of a simulated population whose typical observer is
// `typical`, drawn from StreamFor(seed, kPopulation, subject): one z ~ N(0,
// 1) scales both Weber fractions, W_stiffness x exp(z spread.stiffness) and
// W_removal x exp(z spread.removal) (a keen prober is a keen driller); a draw
// beyond kMaxWeberFraction is held there (an observer at chance stays at
// chance). When typical.exploration has a subject spread, two more draws z_f
// and z_s follow and the subject explores with the typical factors times
// exp(z_f subject_force_spread) and exp(z_s subject_speed_spread) (held
// within [1 / kMaxExplorationFactor, kMaxExplorationFactor]). Without any
// spread: `typical`, with nothing drawn.
ObserverParams DrawSubjectObserver(const ObserverParams& typical,
                                   WeberSpread spread, std::uint64_t seed,
                                   int subject);

// DrawSubjectObserver in two steps, for drawing a population once and
// applying it to many typical observers: the subject's standard normal draws
// (z always; z_force and z_speed when `explores`, i.e. the typical observer
// has a subject spread of force or speed), and the observer they make of a
// typical one. DrawSubjectObserver(typical, spread, seed, s) equals
// ApplySubjectDraws(typical, spread, DrawSubject(seed, s, explores)) whenever
// it draws at all.
struct SubjectDraws {
  double z = 0.0;
  double z_force = 0.0;
  double z_speed = 0.0;
  bool explores = false;
};
SubjectDraws DrawSubject(std::uint64_t seed, int subject, bool explores);
ObserverParams ApplySubjectDraws(const ObserverParams& typical,
                                 WeberSpread spread, const SubjectDraws& d);

// Cues of one trial's intervals, as the simulated hand felt them.
struct TrialCues {
  std::span<const double> cues;        // one per interval (same order), > 0
  std::optional<double> standard_cue;  // yes/no trials: the remembered
                                       // standard's cue
  // Same-different trials under the differencing and likelihood rules: the
  // block's materials a and b as the observer felt them.
  std::optional<std::array<FeltMaterial, 2>> materials;
};

// The standards a simulated subject remembers: in a one-interval (yes/no)
// trial it compares the interval with the block's standard, felt once, the
// first time the block needs it, and remembered for the block's other trials.
class RememberedStandards {
 public:
  // The cues `trial` is decided on: `cues` (one per interval; the result
  // refers to them) and, for a one-interval trial, the block's remembered
  // standard, felt through `feel` when the block has none yet (its error is
  // returned).
  Result<TrialCues> CuesFor(const TrialSpec& trial,
                            std::span<const double> cues,
                            const std::function<Result<double>()>& feel);

 private:
  std::map<int, double> by_block_;  // per block index
};

// An adjustment step as the simulated hand feels it: the comparison's cue
// (FeltCue) at the level the path of key presses `path` (this step's press
// last) reaches; none when that step is beyond the limit (it is not taken and
// the adjustment ends there); an error ends the adjustment with it.
using AdjustedCue =
    std::function<Result<std::optional<double>>(const std::string& path)>;

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
  // Decide in two steps, for answering one trial again with other Weber
  // fractions: the draws Decide takes from `rng` for `trial` (they depend on
  // the lapse rate and the trial, never on the Weber fractions), and the
  // decision made with them. Decide(trial, cues, rng) equals
  // DecideWith(trial, cues, DrawNoise(trial, rng)).
  struct Noise {
    bool lapse = false;
    std::array<double, 4> z{};  // standard normal, one per interval (the
                                // first four: more cannot be decided)
    int lapse_answer = 0;       // index into the response options
    double rt_z = 0.0;          // of the response time
  };
  Noise DrawNoise(const TrialSpec& trial, boost::random::mt19937& rng) const;
  Result<Response> DecideWith(const TrialSpec& trial, const TrialCues& cues,
                              const Noise& noise) const;
  // One adjustment step: '+' to raise the comparison level, '-' to lower
  // it, '=' when it matches. `direction` is +1 when the cue grows with the
  // level and -1 when it shrinks.
  char AdjustStep(Task task, double standard_cue, double comparison_cue,
                  int direction, boost::random::mt19937& rng) const;
  // A response time drawn from the log-normal.
  double ResponseTime(boost::random::mt19937& rng) const;
  // An adjustment trial, step by step, from the comparison's start cue: at
  // most `max_steps` steps, each an AdjustStep and a response time (drawn in
  // that order from `rng`); a step other than '=' is felt through `cue_at`.
  // Ends at '=', at a step beyond the limit or after max_steps; the answer is
  // the path of the steps taken and '=', its response time the sum of every
  // step's. The direction is +1 (the cue grows with the level) unless both
  // the start level differs from the standard's and the start cue from the
  // standard's cue, and they differ in opposite senses (-1).
  Result<Response> Adjust(const TrialSpec& trial, double standard_cue,
                          double start_cue, int max_steps,
                          boost::random::mt19937& rng,
                          const AdjustedCue& cue_at) const;

  const ObserverParams& params() const { return params_; }

 private:
  ObserverParams params_;
};

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_OBSERVER_H_
