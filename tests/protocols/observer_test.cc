// The simulated observer against the closed forms of its model (2AFC:
// P(correct) = Phi(|ln(S2/S1)| / (sigma sqrt 2)); same-different by the
// differencing rule: F = 2 Phi(-k / (sigma sqrt 2)),
// H = Phi((d' - k) / sqrt 2) + Phi((-d' - k) / sqrt 2), d' = |ln(S2/S1)| /
// sigma), and transformed staircases run by it converging on Levitt's (1971)
// targets.
#include "burrlab/protocols/observer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <boost/math/distributions/normal.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/streams.h"
#include "burrlab/stimuli/interval.h"
#include "burrlab/stimuli/materials.h"

namespace burrlab::protocols {
namespace {

double Phi(double z) {
  return boost::math::cdf(boost::math::normal_distribution<double>(), z);
}

TrialSpec TwoIntervalSpec(Method method, double level1, double level2) {
  TrialSpec t;
  t.method = method;
  t.task = Task::kProbe;
  PlannedInterval a;
  a.role = "standard";
  a.level = level1;
  PlannedInterval b;
  b.role = "comparison";
  b.level = level2;
  t.intervals = {a, b};
  if (method == Method::kSameDifferent) {
    t.response_options = {"same", "different"};
  } else {
    t.response_options = {"1", "2"};
  }
  return t;
}

ObserverParams NoLapse(double sigma) {
  ObserverParams p;
  p.weber_stiffness = sigma;
  p.weber_removal = sigma;
  p.lapse = 0.0;
  return p;
}

// Fraction of `n` decisions equal to `answer`.
double Rate(const SimulatedObserver& observer, const TrialSpec& t,
            const std::vector<double>& cues, const std::string& answer, int n,
            std::uint64_t seed) {
  boost::random::mt19937 rng(static_cast<std::uint32_t>(seed));
  int hits = 0;
  for (int i = 0; i < n; ++i) {
    Result<Response> r =
        observer.Decide(t, {cues, std::nullopt, std::nullopt}, rng);
    EXPECT_TRUE(r.ok());
    hits += r->answer == answer ? 1 : 0;
  }
  return static_cast<double>(hits) / n;
}

TEST(SimulatedObserver,
     TwoAfcProportionCorrectIsPhiOfLogRatioOverSigmaRootTwo) {
  const double sigma = 0.2;
  SimulatedObserver observer(NoLapse(sigma));
  const int n = 20000;
  for (double ratio : {1.05, 1.2, 1.5}) {
    const TrialSpec t = TwoIntervalSpec(Method::kTwoInterval, 1.0, ratio);
    const double expected = Phi(std::log(ratio) / (sigma * std::sqrt(2.0)));
    const double se = std::sqrt(expected * (1 - expected) / n);
    EXPECT_NEAR(Rate(observer, t, {1.0, ratio}, "2", n, 7), expected,
                3.5 * se + 1e-9)
        << ratio;
    // The cue may fall with the level (drilling a stiffer material): the
    // observer still picks the interval higher on the axis.
    EXPECT_NEAR(Rate(observer, t, {ratio, 1.0}, "2", n, 8), expected,
                3.5 * se + 1e-9)
        << ratio;
  }
}

TEST(SimulatedObserver, SameDifferentRatesFollowTheDifferencingRule) {
  const double sigma = 0.3;
  ObserverParams params = NoLapse(sigma);
  params.criterion = 1.2;
  SimulatedObserver observer(params);
  const int n = 20000;
  const TrialSpec t = TwoIntervalSpec(Method::kSameDifferent, 0.0, 0.0);
  // False alarms: F = 2 Phi(-k / (sigma sqrt 2)) with k = c sigma sqrt 2.
  const double f = 2.0 * Phi(-params.criterion);
  EXPECT_NEAR(Rate(observer, t, {1.0, 1.0}, "different", n, 3), f,
              3.5 * std::sqrt(f * (1 - f) / n));
  // Hits: H = Phi((d' - k') / sqrt 2) + Phi((-d' - k') / sqrt 2), d' =
  // |ln(S2/S1)| / sigma, k' = k / sigma.
  const double ratio = 1.6;
  const double d = std::log(ratio) / sigma;
  const double kp = params.criterion * std::sqrt(2.0);
  const double h =
      Phi((d - kp) / std::sqrt(2.0)) + Phi((-d - kp) / std::sqrt(2.0));
  EXPECT_NEAR(Rate(observer, t, {1.0, ratio}, "different", n, 4), h,
              3.5 * std::sqrt(h * (1 - h) / n));
}

// The differencing rule's log odds against its closed form. With equal
// total variances v (both materials' renderings spread alike), a different
// pair's D = psi1 - psi2 is N(+-delta, 2v) and a same pair's N(0, 2v), so
// ln P(diff | D) / P(same | D) = ln cosh(D delta / (2v)) - delta^2 / (4v),
// zero at the optimal criterion |D| = (2v / delta) acosh(exp(delta^2 / (4v)))
// (kind of truth: closed form, derived by hand).
TEST(SameDifferentRules, DifferencingLogOddsFollowTheClosedForm) {
  const FeltMaterial a{std::log(2.0), 0.01};
  const FeltMaterial b{std::log(2.0) - 0.5, 0.01};
  const double sigma = 0.2;
  const double v = 0.01 + sigma * sigma;
  const double delta = 0.5;
  for (double d : {-0.9, -0.2, 0.0, 0.1, 0.35, 0.7}) {
    const double expected =
        std::log(std::cosh(d * delta / (2 * v))) - delta * delta / (4 * v);
    EXPECT_NEAR(SameDifferentLogOdds(SameDifferentRule::kDifferencing, 1.0 + d,
                                     1.0, a, b, sigma),
                expected, 1e-12)
        << d;
  }
  const double k =
      2 * v / delta * std::acosh(std::exp(delta * delta / (4 * v)));
  EXPECT_NEAR(k, 0.384393, 1e-6);
  for (double sign : {-1.0, 1.0}) {
    EXPECT_LT(SameDifferentLogOdds(SameDifferentRule::kDifferencing,
                                   sign * (k - 1e-6), 0.0, a, b, sigma),
              0.0);
    EXPECT_GT(SameDifferentLogOdds(SameDifferentRule::kDifferencing,
                                   sign * (k + 1e-6), 0.0, a, b, sigma),
              0.0);
  }
}

// The likelihood-ratio (independent-observation) rule with equal variances
// says "different" exactly when the two percepts fall on opposite sides of
// the materials' midpoint (Macmillan & Creelman 2005, ch. 9), and its log
// odds are ln cosh(delta (x1 - x2) / (2v)) - ln cosh(delta (x1 + x2) / (2v)),
// x = psi - midpoint (kind of truth: closed form).
TEST(SameDifferentRules,
     LikelihoodRuleSaysDifferentOnOppositeSidesOfTheMidpoint) {
  const double mid = std::log(0.8);
  const double delta = 0.6;
  const FeltMaterial a{mid + delta / 2, 0.02};
  const FeltMaterial b{mid - delta / 2, 0.02};
  const double sigma = 0.3;
  const double v = 0.02 + sigma * sigma;
  for (double x1 : {-0.7, -0.25, -0.01, 0.02, 0.3, 0.9}) {
    for (double x2 : {-0.5, -0.05, 0.04, 0.6}) {
      const double odds = SameDifferentLogOdds(SameDifferentRule::kLikelihood,
                                               mid + x1, mid + x2, a, b, sigma);
      EXPECT_EQ(odds > 0.0, x1 * x2 < 0.0) << x1 << " " << x2;
      EXPECT_NEAR(odds,
                  std::log(std::cosh(delta * (x1 - x2) / (2 * v))) -
                      std::log(std::cosh(delta * (x1 + x2) / (2 * v))),
                  1e-12)
          << x1 << " " << x2;
    }
  }
}

// Unequal variances: the rules against the mixture densities written out
// directly (kind of truth: the definition, computed without logs).
TEST(SameDifferentRules, UnequalVariancesMatchTheMixturesWrittenOut) {
  const FeltMaterial a{0.4, 0.05};
  const FeltMaterial b{-0.1, 0.002};
  const double sigma = 0.15;
  const double va = 0.05 + sigma * sigma, vb = 0.002 + sigma * sigma;
  auto n = [](double x, double m, double var) {
    return std::exp(-(x - m) * (x - m) / (2 * var)) /
           std::sqrt(2 * std::numbers::pi * var);
  };
  for (double p1 : {-0.3, 0.0, 0.35, 0.6}) {
    for (double p2 : {-0.2, 0.1, 0.45}) {
      const double d = p1 - p2, delta = 0.5;
      const double differencing =
          std::log((n(d, delta, va + vb) + n(d, -delta, va + vb)) /
                   (n(d, 0, 2 * va) + n(d, 0, 2 * vb)));
      EXPECT_NEAR(SameDifferentLogOdds(SameDifferentRule::kDifferencing, p1, p2,
                                       a, b, sigma),
                  differencing, 1e-12);
      const double likelihood = std::log((n(p1, 0.4, va) * n(p2, -0.1, vb) +
                                          n(p1, -0.1, vb) * n(p2, 0.4, va)) /
                                         (n(p1, 0.4, va) * n(p2, 0.4, va) +
                                          n(p1, -0.1, vb) * n(p2, -0.1, vb)));
      EXPECT_NEAR(SameDifferentLogOdds(SameDifferentRule::kLikelihood, p1, p2,
                                       a, b, sigma),
                  likelihood, 1e-12);
    }
  }
}

TEST(SameDifferentRules, FeltMaterialIsTheMeanAndVarianceOfTheLogCues) {
  const std::vector<double> cues = {1.0, std::exp(0.2), std::exp(-0.1),
                                    std::exp(0.3)};
  const FeltMaterial m = FeltMaterialOf(cues);
  EXPECT_NEAR(m.mean_ln_cue, 0.1, 1e-15);
  // (0.01 + 0.01 + 0.04 + 0.04) / 3
  EXPECT_NEAR(m.var_ln_cue, 0.1 / 3, 1e-15);
  EXPECT_EQ(FeltMaterialOf(std::vector<double>{2.0}).var_ln_cue, 0.0);
}

TEST(SameDifferentRules, DecideUsesTheRuleAndNeedsTheFeltMaterials) {
  ObserverParams params = NoLapse(0.05);
  params.rule = SameDifferentRule::kLikelihood;
  const SimulatedObserver observer(params);
  const TrialSpec t = TwoIntervalSpec(Method::kSameDifferent, 0.0, 0.0);
  const std::array<FeltMaterial, 2> felt = {FeltMaterial{std::log(2.0), 0.0},
                                            FeltMaterial{std::log(1.0), 0.0}};
  boost::random::mt19937 rng(5);
  const std::vector<double> different = {2.0, 1.0}, same = {1.0, 1.0};
  TrialCues cues{different, std::nullopt, felt};
  EXPECT_EQ(observer.Decide(t, cues, rng)->answer, "different");
  cues.cues = same;
  EXPECT_EQ(observer.Decide(t, cues, rng)->answer, "same");
  // 1.2 against 1.0: the likelihood rule, knowing the materials are a factor
  // 2 apart, calls them the same material (both below the midpoint, sqrt 2);
  // the fixed rule calls them different (|ln 1.2| = 0.18 > 1 x 0.05 x sqrt 2).
  const std::vector<double> near = {1.2, 1.0};
  cues.cues = near;
  EXPECT_EQ(observer.Decide(t, cues, rng)->answer, "same");
  params.rule = SameDifferentRule::kFixed;
  EXPECT_EQ(SimulatedObserver(params).Decide(t, cues, rng)->answer,
            "different");
  params.rule = SameDifferentRule::kDifferencing;
  cues.materials.reset();
  EXPECT_EQ(SimulatedObserver(params).Decide(t, cues, rng).error().message,
            "observer: the differencing rule needs the block's two materials "
            "as the observer felt them");
}

// Bias: "different" exactly when the percepts' log odds exceed it, under both
// rules; a keen observer's percepts are its cues (noise 1e-6 against a margin
// of 0.01 in log odds).
TEST(SameDifferentRules, BiasIsTheLogOddsTheObserverNeedsToSayDifferent) {
  const TrialSpec t = TwoIntervalSpec(Method::kSameDifferent, 0.0, 0.0);
  const std::array<FeltMaterial, 2> felt = {FeltMaterial{0.0, 0.04},
                                            FeltMaterial{1.0, 0.09}};
  const std::vector<double> cues = {std::exp(0.3), std::exp(0.8)};
  const TrialCues trial_cues{cues, std::nullopt, felt};
  for (SameDifferentRule rule :
       {SameDifferentRule::kDifferencing, SameDifferentRule::kLikelihood}) {
    const double log_odds =
        SameDifferentLogOdds(rule, 0.3, 0.8, felt[0], felt[1], 1e-6);
    ObserverParams params = NoLapse(1e-6);
    params.rule = rule;
    boost::random::mt19937 rng(5);
    params.bias = log_odds - 0.01;
    EXPECT_EQ(SimulatedObserver(params).Decide(t, trial_cues, rng)->answer,
              "different");
    params.bias = log_odds + 0.01;
    EXPECT_EQ(SimulatedObserver(params).Decide(t, trial_cues, rng)->answer,
              "same");
  }
  // The fixed rule's criterion is its bias: bias does not move it.
  ObserverParams fixed = NoLapse(0.05);
  fixed.bias = 5.0;
  boost::random::mt19937 rng(5);
  EXPECT_EQ(SimulatedObserver(fixed).Decide(t, trial_cues, rng)->answer,
            "different");
  EXPECT_EQ(ParseObserverSpec("simulated:bias=0.7", ObserverParams{})->bias,
            0.7);
  EXPECT_EQ(
      ParseObserverSpec("simulated:bias=-6", ObserverParams{}).error().message,
      "observer: bias must be in [-5, 5], got -6");
}

// A PVC vs bone same-different protocol whose [observer] table holds
// `observer` (TOML lines).
ParseOutcome ParseWithObserver(const std::string& observer) {
  return ParseProtocol("p.toml", R"(
format = "burrlab-protocol/1"
[study]
name = "t"
[materials.pvc]
builtin = "pvc_k70"
[materials.bone]
builtin = "human_temporal_bone"
[observer]
)" + observer + R"(
[[blocks]]
method = "same_different"
task = "drill"
a = "pvc"
b = "bone"
)");
}

TEST(SameDifferentRules, ReadFromTheProtocolsObserverTable) {
  const ParseOutcome outcome = ParseWithObserver("rule = \"likelihood\"");
  ASSERT_TRUE(outcome.protocol.has_value());
  EXPECT_EQ(ObserverParamsFrom(outcome.protocol->observer).rule,
            SameDifferentRule::kLikelihood);
}

TEST(SameDifferentRules, ParsedFromTheFlag) {
  EXPECT_EQ(ParseObserverSpec("simulated", ObserverParams{})->rule,
            SameDifferentRule::kFixed);
  EXPECT_EQ(
      ParseObserverSpec("simulated:rule=likelihood", ObserverParams{})->rule,
      SameDifferentRule::kLikelihood);
  EXPECT_EQ(
      ParseObserverSpec("simulated:rule=differencing", ObserverParams{})->rule,
      SameDifferentRule::kDifferencing);
  EXPECT_EQ(ParseObserverSpec("simulated:rule=optimal", ObserverParams{})
                .error()
                .message,
            "observer: rule must be fixed, differencing or likelihood, got "
            "\"optimal\"");
  EXPECT_EQ(SameDifferentRuleName(SameDifferentRule::kDifferencing),
            "differencing");
}

TEST(SimulatedObserver, LapsesAnswerAtRandom) {
  ObserverParams params = NoLapse(0.01);
  params.lapse = 0.2;
  SimulatedObserver observer(params);
  const TrialSpec t = TwoIntervalSpec(Method::kTwoInterval, 1.0, 3.0);
  // Perfect discrimination except lapses, half of which land right.
  const double expected = 1.0 - params.lapse / 2;
  const int n = 20000;
  EXPECT_NEAR(Rate(observer, t, {1.0, 3.0}, "2", n, 9), expected,
              3.5 * std::sqrt(expected * (1 - expected) / n));
}

TEST(SimulatedObserver, ParsesTheObserverFlag) {
  Result<ObserverParams> p =
      ParseObserverSpec("simulated:weber=0.3,lapse=0.05", ObserverParams{});
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p->weber_stiffness, 0.3);
  EXPECT_EQ(p->weber_removal, 0.3);
  EXPECT_EQ(p->lapse, 0.05);
  EXPECT_TRUE(ParseObserverSpec("simulated", ObserverParams{}).ok());
  EXPECT_EQ(ParseObserverSpec("simulated:webber=0.3", ObserverParams{})
                .error()
                .message,
            "observer: unknown key \"webber\" (did you mean \"weber\"?) (keys: "
            "weber, weber_stiffness, weber_removal, lapse, criterion, bias, "
            "rt_median_s, rule, always, exploration, force_spread, "
            "speed_spread, subject_force_spread, subject_speed_spread)");
  EXPECT_EQ(ParseObserverSpec("simulated:lapse=0.7", ObserverParams{})
                .error()
                .message,
            "observer: lapse must be in [0, 0.5), got 0.7");
  EXPECT_EQ(ParseObserverSpec("human", ObserverParams{}).error().message,
            "--observer must be 'simulated' or 'simulated:key=value,...', got "
            "\"human\"");
}

TEST(SimulatedObserver, ParsesAlwaysCorrectAndAlwaysWrong) {
  EXPECT_EQ(ParseObserverSpec("simulated", ObserverParams{})->answers,
            AnswerRule::kPercepts);
  EXPECT_EQ(
      ParseObserverSpec("simulated:always=correct", ObserverParams{})->answers,
      AnswerRule::kAlwaysCorrect);
  Result<ObserverParams> wrong =
      ParseObserverSpec("simulated:weber=0.3,always=wrong", ObserverParams{});
  ASSERT_TRUE(wrong.ok());
  EXPECT_EQ(wrong->answers, AnswerRule::kAlwaysWrong);
  EXPECT_EQ(wrong->weber_stiffness, 0.3);
  EXPECT_EQ(ParseObserverSpec("simulated:always=right", ObserverParams{})
                .error()
                .message,
            "observer: always must be correct or wrong, got \"right\"");
}

TEST(SimulatedObserver, AlwaysCorrectAndAlwaysWrongIgnoreCuesAndLapses) {
  // The answer key decides, not the percept: cues that point the other way
  // and lapses at 40 % change nothing over 1000 trials.
  ObserverParams params = NoLapse(0.2);
  params.lapse = 0.4;
  TrialSpec t = TwoIntervalSpec(Method::kTwoInterval, 1.0, 3.0);
  t.correct_answer = "2";
  params.answers = AnswerRule::kAlwaysCorrect;
  EXPECT_EQ(Rate(SimulatedObserver(params), t, {3.0, 1.0}, "2", 1000, 5), 1.0);
  params.answers = AnswerRule::kAlwaysWrong;
  EXPECT_EQ(Rate(SimulatedObserver(params), t, {1.0, 3.0}, "1", 1000, 6), 1.0);
  // Without a correct answer (limits): "yes" and "no".
  TrialSpec limits = TwoIntervalSpec(Method::kLimits, 1.0, 3.0);
  limits.response_options = {"yes", "no"};
  params.answers = AnswerRule::kAlwaysCorrect;
  EXPECT_EQ(Rate(SimulatedObserver(params), limits, {1.0, 1.0}, "yes", 100, 7),
            1.0);
  params.answers = AnswerRule::kAlwaysWrong;
  EXPECT_EQ(Rate(SimulatedObserver(params), limits, {1.0, 3.0}, "no", 100, 8),
            1.0);
  // Adjustments step up (correct) or down (wrong) whatever the cues.
  boost::random::mt19937 rng(1);
  params.answers = AnswerRule::kAlwaysCorrect;
  EXPECT_EQ(
      SimulatedObserver(params).AdjustStep(Task::kProbe, 1.0, 1.0, 1, rng),
      '+');
  params.answers = AnswerRule::kAlwaysWrong;
  EXPECT_EQ(
      SimulatedObserver(params).AdjustStep(Task::kProbe, 1.0, 1.0, 1, rng),
      '-');
}

// Runs `runs` staircases (1-up/n-down, log10 steps) with a simulated observer
// whose cue is the level itself, so P(correct | L) = Phi(ln L / (sigma
// sqrt 2)); returns P at the geometric mean of the thresholds.
double StaircaseConvergence(int n_down, int runs) {
  const double sigma = 0.2;
  Protocol p;
  p.format = std::string(kProtocolFormat);
  p.study_name = "convergence";
  stimuli::MaterialSet m;
  m.name = "ref";
  m.material.c_e_n_per_mm2 = 1.0;
  m.material.alpha_per_s = 0.1;
  m.material.c_mu_n_per_mm2 = 0.1;
  m.material.mu = 0.5;
  m.material.c_i_n_s_per_mm3 = 0.01;
  p.materials.push_back({"ref", "", m, {}});
  Axis axis;
  axis.id = "ce";
  axis.kind = AxisKind::kRatio;
  axis.reference = "ref";
  p.axes.push_back(axis);
  Block b;
  b.name = "stairs";
  b.method = Method::kStaircase;
  b.axis = "ce";
  b.standard_level = 1.0;
  StaircaseOptions o;
  o.n_down = n_down;
  o.n_up = 1;
  o.step_scale = StepScale::kLog10;
  o.step_down = o.step_up = 0.04;
  o.step_schedule = {{4, 0.01, 0.01}};
  o.start_level = 1.6;
  o.floor_level = 1.0;
  o.max_trials = 150;
  b.staircases = {o};
  b.threshold_reversals = 10;
  p.blocks = {b};
  SimulatedObserver observer(NoLapse(sigma));
  double sum_log = 0.0;
  int counted = 0;
  for (int run = 0; run < runs; ++run) {
    Result<Engine> engine = Engine::Create(p, 0, 1000 + run);
    EXPECT_TRUE(engine.ok());
    boost::random::mt19937 rng(static_cast<std::uint32_t>(run));
    std::optional<double> estimate;
    while (!engine->finished()) {
      const TrialSpec& t = engine->current();
      std::vector<double> cues;
      for (const PlannedInterval& i : t.intervals) cues.push_back(*i.level);
      Result<Response> r =
          observer.Decide(t, {cues, std::nullopt, std::nullopt}, rng);
      EXPECT_TRUE(r.ok());
      Result<Outcome> out = engine->Respond(*r);
      EXPECT_TRUE(out.ok());
      estimate = out->estimate;
    }
    if (estimate.has_value()) {
      sum_log += std::log(*estimate);
      ++counted;
    }
  }
  EXPECT_GE(counted, runs * 9 / 10);
  const double p_correct = Phi(sum_log / counted / (sigma * std::sqrt(2.0)));
  ::testing::Test::RecordProperty("p_correct_at_threshold",
                                  std::to_string(p_correct));
  return p_correct;
}

TEST(SimulatedObserver, OneUpTwoDownConvergesOnSeventyPointSevenPercent) {
  // Levitt (1971): 1-up/2-down tracks p = sqrt(0.5) = 0.707.
  EXPECT_NEAR(StaircaseConvergence(2, 300), std::sqrt(0.5), 0.02);
}

TEST(SimulatedObserver, OneUpThreeDownConvergesOnSeventyNinePointFourPercent) {
  // Levitt (1971): 1-up/3-down tracks p = 0.5^(1/3) = 0.794.
  EXPECT_NEAR(StaircaseConvergence(3, 300), std::cbrt(0.5), 0.02);
}

// --- The simulated subject around the decisions: felt cues, stand-ins for
// real samples, remembered standards, adjustments step by step, population
// draws.

TEST(FeltCue, HoldsCuesAtTheFloor) {
  EXPECT_EQ(FeltCue(2.5), 2.5);
  EXPECT_EQ(FeltCue(kFeltCueFloor), kFeltCueFloor);
  EXPECT_EQ(FeltCue(0.0), 1e-3);
  EXPECT_EQ(FeltCue(-4.0), 1e-3);
}

TEST(ReferenceStandIn, IsTheMaterialTheReferenceIsModelledOn) {
  Protocol p;
  p.materials.push_back({"bone", "", {}, {}});
  p.materials.push_back({"pvc", "", {}, {}});
  Block block;
  block.material_a = "bone";
  block.material_b = "pvc";
  block.reference.matching_material = MaterialLabel::kA;
  Result<const ProtocolMaterial*> a = ReferenceStandIn(p, block);
  ASSERT_TRUE(a.ok());
  EXPECT_EQ((*a)->id, "bone");
  block.reference.matching_material = MaterialLabel::kB;
  Result<const ProtocolMaterial*> b = ReferenceStandIn(p, block);
  ASSERT_TRUE(b.ok());
  EXPECT_EQ((*b)->id, "pvc");
  block.material_b = "cork";
  Result<const ProtocolMaterial*> missing = ReferenceStandIn(p, block);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message, "reference stand-in material is missing");
}

TEST(ReferenceStandIn, IsFeltAsLongAsTheFirstComparison) {
  TrialSpec t;
  t.intervals.resize(3);
  t.intervals[0].duration_s = 0.0;  // the real reference: subject-paced
  t.intervals[1].duration_s = 7.5;
  t.intervals[2].duration_s = 9.0;
  EXPECT_EQ(ReferenceStandInDuration(t), 7.5);
  t.intervals.resize(1);
  EXPECT_EQ(ReferenceStandInDuration(t), 10.0);
}

TEST(RememberedStandards, FeelsEachBlocksStandardOnce) {
  RememberedStandards standards;
  int felt = 0;
  double next = 1.5;
  const auto feel = [&]() -> Result<double> {
    ++felt;
    return next;
  };
  TrialSpec yes_no;
  yes_no.block_index = 2;
  yes_no.intervals.resize(1);
  const std::vector<double> one = {3.0};
  Result<TrialCues> first = standards.CuesFor(yes_no, one, feel);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first->cues.data(), one.data());
  EXPECT_EQ(first->standard_cue, 1.5);
  next = 9.0;  // later feelings of the standard are not asked for
  Result<TrialCues> again = standards.CuesFor(yes_no, one, feel);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->standard_cue, 1.5);
  EXPECT_EQ(felt, 1);
  yes_no.block_index = 3;  // another block: its own standard
  Result<TrialCues> other = standards.CuesFor(yes_no, one, feel);
  ASSERT_TRUE(other.ok());
  EXPECT_EQ(other->standard_cue, 9.0);
  EXPECT_EQ(felt, 2);
  // Two intervals: no standard is felt.
  TrialSpec two;
  two.block_index = 4;
  two.intervals.resize(2);
  const std::vector<double> cues = {1.0, 2.0};
  Result<TrialCues> pair = standards.CuesFor(two, cues, feel);
  ASSERT_TRUE(pair.ok());
  EXPECT_FALSE(pair->standard_cue.has_value());
  EXPECT_EQ(pair->cues.size(), 2u);
  EXPECT_EQ(felt, 2);
}

TEST(RememberedStandards, AStandardThatCannotBeFeltIsAnErrorAndNotKept) {
  RememberedStandards standards;
  TrialSpec yes_no;
  yes_no.intervals.resize(1);
  const std::vector<double> one = {3.0};
  Result<TrialCues> failed = standards.CuesFor(
      yes_no, one, []() -> Result<double> { return Error{"no standard"}; });
  ASSERT_FALSE(failed.ok());
  EXPECT_EQ(failed.error().message, "no standard");
  Result<TrialCues> later =
      standards.CuesFor(yes_no, one, []() -> Result<double> { return 2.0; });
  ASSERT_TRUE(later.ok());
  EXPECT_EQ(later->standard_cue, 2.0);
}

// An adjustment trial of the probe task at `level` against a standard at 1.
TrialSpec AdjustmentSpec(double level) {
  TrialSpec t;
  t.method = Method::kAdjustment;
  t.task = Task::kProbe;
  t.level = level;
  t.standard_level = 1.0;
  t.intervals.resize(2);
  return t;
}

// An observer whose percepts are practically the cues (sigma 1e-4), taking
// exactly `rt` s per step.
ObserverParams Keen(double rt) {
  ObserverParams p = NoLapse(1e-4);
  p.rt_median_s = rt;
  p.rt_log_sd = 0.0;
  return p;
}

// The first step of a walk far from a match (max_steps 1: the walk ends
// after it).
std::string FirstStep(const SimulatedObserver& observer, double level,
                      double start_cue, std::vector<std::string>* asked) {
  boost::random::mt19937 rng(3);
  Result<Response> r = observer.Adjust(
      AdjustmentSpec(level), 1.0, start_cue, 1, rng,
      [&](const std::string& path) -> Result<std::optional<double>> {
        asked->push_back(path);
        return std::optional<double>(1.0);
      });
  EXPECT_TRUE(r.ok());
  return r.ok() ? r->answer : "";
}

TEST(SimulatedObserverAdjust, StepsAgainstTheFeltDifferenceInTheCuesDirection) {
  const SimulatedObserver observer(Keen(0.5));
  std::vector<std::string> asked;
  // The comparison feels stronger and its level is above the standard's:
  // the cue grows with the level, so the level goes down.
  EXPECT_EQ(FirstStep(observer, 2.0, 2.0, &asked), "-=");
  EXPECT_EQ(asked, (std::vector<std::string>{"-"}));
  // Stronger below the standard's level: the cue falls with the level, so
  // the level goes up.
  asked.clear();
  EXPECT_EQ(FirstStep(observer, 0.5, 2.0, &asked), "+=");
  EXPECT_EQ(asked, (std::vector<std::string>{"+"}));
  // Weaker above: the cue falls with the level; down.
  EXPECT_EQ(FirstStep(observer, 2.0, 0.5, &asked), "-=");
  // At the standard's level the cue is taken to grow with it: weaker, up.
  EXPECT_EQ(FirstStep(observer, 1.0, 0.5, &asked), "+=");
}

// With the cues alike the observer matches at random (percepts closer than
// match_tolerance x sigma); the walk ends at the first '=', having felt
// every step before it and taken one response time per step.
TEST(SimulatedObserverAdjust, StopsAtAMatch) {
  const SimulatedObserver observer(Keen(0.5));
  bool at_once = false;
  for (std::uint32_t seed = 1; seed <= 50; ++seed) {
    boost::random::mt19937 rng(seed);
    int felt = 0;
    Result<Response> r = observer.Adjust(
        AdjustmentSpec(2.0), 1.0, 1.0, 1000, rng,
        [&](const std::string&) -> Result<std::optional<double>> {
          ++felt;
          return std::optional<double>(1.0);
        });
    ASSERT_TRUE(r.ok());
    ASSERT_EQ(r->answer.size(), static_cast<std::size_t>(felt) + 1) << seed;
    EXPECT_LT(felt, 1000) << seed;
    EXPECT_EQ(r->answer.back(), '=');
    EXPECT_EQ(r->response_time_s, 0.5 * (felt + 1)) << seed;
    at_once = at_once || r->answer == "=";
  }
  EXPECT_TRUE(at_once);
}

TEST(SimulatedObserverAdjust, StopsAtAStepBeyondTheLimitOrAfterMaxSteps) {
  const SimulatedObserver observer(Keen(0.25));
  boost::random::mt19937 rng(5);
  std::vector<std::string> asked;
  // The cue never comes closer; the third step is beyond the limit.
  const AdjustedCue limited =
      [&](const std::string& path) -> Result<std::optional<double>> {
    asked.push_back(path);
    if (path.size() == 3) return std::optional<double>();
    return std::optional<double>(2.0);
  };
  Result<Response> r =
      observer.Adjust(AdjustmentSpec(2.0), 1.0, 2.0, 10, rng, limited);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->answer, "--=");
  EXPECT_EQ(asked, (std::vector<std::string>{"-", "--", "---"}));
  EXPECT_EQ(r->response_time_s, 0.75);  // three steps, the last refused
  // Without a limit: max_steps steps, each with its response time.
  Result<Response> capped =
      observer.Adjust(AdjustmentSpec(2.0), 1.0, 2.0, 4, rng,
                      [](const std::string&) -> Result<std::optional<double>> {
                        return std::optional<double>(2.0);
                      });
  ASSERT_TRUE(capped.ok());
  EXPECT_EQ(capped->answer, "----=");
  EXPECT_EQ(capped->response_time_s, 1.0);
}

TEST(SimulatedObserverAdjust, AStepThatCannotBeFeltIsAnError) {
  const SimulatedObserver observer(Keen(0.25));
  boost::random::mt19937 rng(6);
  Result<Response> r = observer.Adjust(
      AdjustmentSpec(2.0), 1.0, 2.0, 10, rng,
      [](const std::string& path) -> Result<std::optional<double>> {
        return Error{"cannot render " + path};
      });
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "cannot render -");
}

// Every step draws AdjustStep's two percepts, then a response time: the same
// draws in the same order as a loop over AdjustStep and ResponseTime.
TEST(SimulatedObserverAdjust, DrawsAsAdjustStepThenResponseTimePerStep) {
  ObserverParams params;
  params.weber_stiffness = 0.3;
  const SimulatedObserver observer(params);
  // The comparison's cue at a path: 1.3 x 0.95 per '-', / 0.95 per '+'.
  const auto cue_of = [](const std::string& path) {
    double cue = 1.3;
    for (char c : path) cue *= c == '-' ? 0.95 : 1.0 / 0.95;
    return cue;
  };
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    boost::random::mt19937 rng(seed);
    Result<Response> r = observer.Adjust(
        AdjustmentSpec(1.3), 1.0, 1.3, 15, rng,
        [&](const std::string& path) -> Result<std::optional<double>> {
          return std::optional<double>(cue_of(path));
        });
    ASSERT_TRUE(r.ok());
    boost::random::mt19937 by_hand(seed);
    std::string path;
    double rt = 0.0;
    for (int step = 0; step < 15; ++step) {
      const char c =
          observer.AdjustStep(Task::kProbe, 1.0, cue_of(path), 1, by_hand);
      rt += observer.ResponseTime(by_hand);
      if (c == '=') break;
      path += c;
    }
    EXPECT_EQ(r->answer, path + "=") << seed;
    EXPECT_EQ(r->response_time_s, rt) << seed;
    EXPECT_EQ(rng, by_hand) << seed;
  }
}

TEST(DrawSubjectObserver, WithoutSpreadIsTheTypicalObserver) {
  ObserverParams typical;
  typical.weber_stiffness = 0.25;
  typical.weber_removal = 0.4;
  typical.lapse = 0.03;
  const ObserverParams p = DrawSubjectObserver(typical, {}, 12, 3);
  EXPECT_EQ(p.weber_stiffness, 0.25);
  EXPECT_EQ(p.weber_removal, 0.4);
  EXPECT_EQ(p.lapse, 0.03);
}

// One z from the population stream of (seed, subject) scales both cues.
TEST(DrawSubjectObserver, OneDrawFromThePopulationStreamScalesBothCues) {
  ObserverParams typical;
  typical.weber_stiffness = 0.2;
  typical.weber_removal = 0.4;
  const WeberSpread spread{0.5, 0.25};
  for (int s = 0; s < 10; ++s) {
    boost::random::mt19937 population =
        StreamFor(7, StreamPurpose::kPopulation, static_cast<std::uint64_t>(s));
    boost::random::normal_distribution<double> unit(0.0, 1.0);
    const double z = unit(population);
    const ObserverParams p = DrawSubjectObserver(typical, spread, 7, s);
    EXPECT_EQ(p.weber_stiffness,
              std::min(kMaxWeberFraction, 0.2 * std::exp(z * 0.5)))
        << s;
    EXPECT_EQ(p.weber_removal,
              std::min(kMaxWeberFraction, 0.4 * std::exp(z * 0.25)))
        << s;
    // The same seed and subject, the same draw; another seed, another.
    EXPECT_EQ(DrawSubjectObserver(typical, spread, 7, s).weber_stiffness,
              p.weber_stiffness);
    EXPECT_NE(DrawSubjectObserver(typical, spread, 8, s).weber_stiffness,
              p.weber_stiffness);
  }
}

TEST(DrawSubjectObserver, DrawsBeyondTheLargestWeberFractionAreHeldThere) {
  ObserverParams typical;
  bool held = false;
  for (int s = 0; s < 40; ++s) {
    const ObserverParams p = DrawSubjectObserver(typical, {20.0, 20.0}, 1, s);
    EXPECT_LE(p.weber_stiffness, kMaxWeberFraction);
    EXPECT_LE(p.weber_removal, kMaxWeberFraction);
    held = held || p.weber_stiffness == kMaxWeberFraction;
  }
  EXPECT_TRUE(held);
}

// ---- Exploration: the simulated hand's force and speed vary ----

// A nominal interval of `material` (a built-in name), as the protocol's
// sessions give it.
stimuli::IntervalOptions NominalInterval(const char* material,
                                         stimuli::Task task) {
  stimuli::IntervalOptions o;
  o.material = stimuli::LoadBuiltinMaterial(material).value().material;
  o.task = task;
  o.duration_s = 20.0;
  return o;
}

TEST(Exploration, NominalHandsPerformTheNominalIntervalAndDrawNothing) {
  const stimuli::IntervalOptions nominal =
      NominalInterval("pvc_k70", stimuli::Task::kProbe);
  boost::random::mt19937 stream(5), untouched(5);
  const stimuli::IntervalOptions o =
      ExploredInterval(nominal, Exploration{}, stream);
  EXPECT_EQ(o.probe_force_n, nominal.probe_force_n);
  EXPECT_EQ(o.drill_force_n, nominal.drill_force_n);
  EXPECT_EQ(o.press_period_s, nominal.press_period_s);
  EXPECT_EQ(stream, untouched);
  // Subject spreads vary subjects, not one subject's intervals.
  Exploration population_only;
  population_only.subject_force_spread = 0.3;
  EXPECT_FALSE(population_only.Varies());
}

// Closed form: force = nominal x factor x exp(s z), z ~ N(0, 1), so ln of
// the force ratio has mean ln(factor) and SD s; the pressing speed likewise
// (press period = nominal / speed); z_force and z_speed are independent.
TEST(Exploration, ForceAndSpeedAreLogNormalAroundTheSubjectsFactors) {
  const stimuli::IntervalOptions nominal =
      NominalInterval("human_temporal_bone", stimuli::Task::kDrill);
  Exploration e;
  e.force_factor = 1.2;
  e.speed_factor = 0.8;
  e.force_spread = 0.15;
  e.speed_spread = 0.12;
  boost::random::mt19937 stream = StreamFor(3, StreamPurpose::kExploration);
  const int n = 4000;
  std::vector<double> ln_force, ln_speed;
  for (int i = 0; i < n; ++i) {
    const stimuli::IntervalOptions o = ExploredInterval(nominal, e, stream);
    ASSERT_TRUE(o.Validate().ok()) << i;
    // Probing and drilling forces move together (one draw).
    EXPECT_NEAR(o.probe_force_n / nominal.probe_force_n,
                o.drill_force_n / nominal.drill_force_n, 1e-12);
    ln_force.push_back(std::log(o.drill_force_n / nominal.drill_force_n));
    ln_speed.push_back(std::log(nominal.press_period_s / o.press_period_s));
  }
  auto mean = [](const std::vector<double>& v) {
    double sum = 0.0;
    for (double x : v) sum += x;
    return sum / static_cast<double>(v.size());
  };
  auto sd = [&](const std::vector<double>& v) {
    const double m = mean(v);
    double ss = 0.0;
    for (double x : v) ss += (x - m) * (x - m);
    return std::sqrt(ss / static_cast<double>(v.size() - 1));
  };
  // 4 standard errors: of a mean s / sqrt(n), of an SD s / sqrt(2 n).
  EXPECT_NEAR(mean(ln_force), std::log(1.2), 4 * 0.15 / std::sqrt(n));
  EXPECT_NEAR(mean(ln_speed), std::log(0.8), 4 * 0.12 / std::sqrt(n));
  EXPECT_NEAR(sd(ln_force), 0.15, 4 * 0.15 / std::sqrt(2.0 * n));
  EXPECT_NEAR(sd(ln_speed), 0.12, 4 * 0.12 / std::sqrt(2.0 * n));
  double cov = 0.0;
  for (int i = 0; i < n; ++i) {
    cov += (ln_force[static_cast<std::size_t>(i)] - mean(ln_force)) *
           (ln_speed[static_cast<std::size_t>(i)] - mean(ln_speed));
  }
  const double correlation = cov / (n - 1) / (sd(ln_force) * sd(ln_speed));
  EXPECT_LT(std::abs(correlation), 4 / std::sqrt(n));
}

TEST(Exploration, DrawsAreHeldAtWhatTheIntervalTakes) {
  const stimuli::IntervalOptions nominal =
      NominalInterval("pvc_k70", stimuli::Task::kProbe);
  const double max_probe_n = stimuli::MaxProbeForceN(
      nominal.material, nominal.radius_mm, nominal.voxel_mm);
  Exploration hard;
  hard.force_factor = kMaxExplorationFactor;
  hard.speed_factor = 1.0 / kMaxExplorationFactor;
  hard.force_spread = 1.0;
  hard.speed_spread = 1.0;
  boost::random::mt19937 stream(11);
  bool probe_held = false, drill_held = false, period_held = false;
  for (int i = 0; i < 200; ++i) {
    const stimuli::IntervalOptions o = ExploredInterval(nominal, hard, stream);
    ASSERT_TRUE(o.Validate().ok()) << o.Validate().error().message;
    probe_held = probe_held || o.probe_force_n == max_probe_n;
    drill_held = drill_held || o.drill_force_n == 20.0;
    period_held = period_held || o.press_period_s == o.duration_s;
  }
  EXPECT_TRUE(probe_held);
  EXPECT_TRUE(drill_held);
  EXPECT_TRUE(period_held);
  Exploration fast;
  fast.speed_factor = kMaxExplorationFactor;
  fast.speed_spread = 1.0;
  bool fastest = false;
  for (int i = 0; i < 200; ++i) {
    const stimuli::IntervalOptions o = ExploredInterval(nominal, fast, stream);
    fastest = fastest || o.press_period_s == 0.1;
  }
  EXPECT_TRUE(fastest);
}

// The subject's factors come after the Weber fractions' z in the population
// stream, so adding them changes no subject's Weber fractions.
TEST(Exploration, SubjectFactorsFollowTheWeberDrawInThePopulationStream) {
  ObserverParams typical;
  typical.exploration.subject_force_spread = 0.05;
  typical.exploration.subject_speed_spread = 0.15;
  const WeberSpread weber{0.5, 0.25};
  ObserverParams without = typical;
  without.exploration = Exploration{};
  std::vector<double> ln_force, ln_speed;
  for (int s = 0; s < 2000; ++s) {
    const ObserverParams p = DrawSubjectObserver(typical, weber, 7, s);
    const ObserverParams q = DrawSubjectObserver(without, weber, 7, s);
    ASSERT_EQ(p.weber_stiffness, q.weber_stiffness) << s;
    ASSERT_EQ(p.weber_removal, q.weber_removal) << s;
    boost::random::mt19937 population =
        StreamFor(7, StreamPurpose::kPopulation, static_cast<std::uint64_t>(s));
    boost::random::normal_distribution<double> unit(0.0, 1.0);
    unit(population);  // the Weber fractions' z
    const double z_force = unit(population);
    const double z_speed = unit(population);
    ASSERT_DOUBLE_EQ(p.exploration.force_factor, std::exp(0.05 * z_force));
    ASSERT_DOUBLE_EQ(p.exploration.speed_factor, std::exp(0.15 * z_speed));
    ln_force.push_back(std::log(p.exploration.force_factor));
    ln_speed.push_back(std::log(p.exploration.speed_factor));
  }
  // Without a Weber spread the subjects still differ in how they explore,
  // and keep the typical Weber fractions.
  const ObserverParams only = DrawSubjectObserver(typical, {}, 7, 0);
  EXPECT_EQ(only.weber_stiffness, typical.weber_stiffness);
  EXPECT_NE(only.exploration.force_factor, 1.0);
  double ss = 0.0;
  for (double x : ln_speed) ss += x * x;
  EXPECT_NEAR(std::sqrt(ss / 2000), 0.15, 4 * 0.15 / std::sqrt(4000.0));
}

TEST(Exploration, ReadFromTheProtocolsObserverTable) {
  const auto parse = ParseWithObserver;
  const ParseOutcome varied = parse("exploration = \"varied\"");
  ASSERT_TRUE(varied.protocol.has_value());
  const ObserverParams p = ObserverParamsFrom(varied.protocol->observer);
  EXPECT_EQ(p.exploration.force_spread, 0.15);
  EXPECT_EQ(p.exploration.speed_spread, 0.12);
  EXPECT_EQ(p.exploration.subject_force_spread, 0.05);
  EXPECT_EQ(p.exploration.subject_speed_spread, 0.15);
  EXPECT_EQ(p.exploration.force_factor, 1.0);
  // A spread given one by one overrides the preset, in any order.
  const ParseOutcome own =
      parse("force_spread = 0.3\nexploration = \"varied\"");
  ASSERT_TRUE(own.protocol.has_value());
  EXPECT_EQ(own.protocol->observer.exploration.force, 0.3);
  EXPECT_EQ(own.protocol->observer.exploration.speed, 0.12);
  const ParseOutcome fixed = parse("");
  ASSERT_TRUE(fixed.protocol.has_value());
  EXPECT_FALSE(
      ObserverParamsFrom(fixed.protocol->observer).exploration.Varies());
  const ParseOutcome biased = parse("bias = 0.5");
  ASSERT_TRUE(biased.protocol.has_value());
  EXPECT_EQ(ObserverParamsFrom(biased.protocol->observer).bias, 0.5);
  const ParseOutcome wide = parse("speed_spread = 1.5");
  ASSERT_FALSE(wide.protocol.has_value());
  ASSERT_EQ(wide.diagnostics.size(), 1u);
  EXPECT_EQ(wide.diagnostics[0].message,
            "observer.speed_spread must be in [0, 1], got 1.5");
  const ParseOutcome odd = parse("exploration = \"wild\"");
  ASSERT_FALSE(odd.protocol.has_value());
  EXPECT_EQ(odd.diagnostics.at(0).message,
            "observer.exploration must be one of fixed, varied, got \"wild\"");
}

TEST(Exploration, ParsedFromTheFlagAndValidated) {
  Result<ObserverParams> varied =
      ParseObserverSpec("simulated:exploration=varied", ObserverParams{});
  ASSERT_TRUE(varied.ok());
  EXPECT_EQ(varied->exploration.force_spread, 0.15);
  EXPECT_EQ(varied->exploration.subject_speed_spread, 0.15);
  Result<ObserverParams> own = ParseObserverSpec(
      "simulated:exploration=varied,force_spread=0.25,subject_force_spread=0",
      ObserverParams{});
  ASSERT_TRUE(own.ok());
  EXPECT_EQ(own->exploration.force_spread, 0.25);
  EXPECT_EQ(own->exploration.subject_force_spread, 0.0);
  EXPECT_EQ(own->exploration.speed_spread, 0.12);
  EXPECT_EQ(ParseObserverSpec("simulated:exploration=wild", ObserverParams{})
                .error()
                .message,
            "observer: exploration must be fixed or varied, got \"wild\"");
  EXPECT_EQ(ParseObserverSpec("simulated:force_spread=2", ObserverParams{})
                .error()
                .message,
            "observer: force_spread must be in [0, 1], got 2");
  ObserverParams p;
  p.exploration.force_factor = 0.1;
  EXPECT_EQ(p.Validate().error().message,
            "observer: force_factor must be in [0.2, 5], got 0.1");
}

}  // namespace
}  // namespace burrlab::protocols
