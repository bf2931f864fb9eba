// The simulated observer against the closed forms of its model (2AFC:
// P(correct) = Phi(|ln(S2/S1)| / (sigma sqrt 2)); same-different by the
// differencing rule: F = 2 Phi(-k / (sigma sqrt 2)),
// H = Phi((d' - k) / sqrt 2) + Phi((-d' - k) / sqrt 2), d' = |ln(S2/S1)| /
// sigma), and transformed staircases run by it converging on Levitt's (1971)
// targets.
#include "burrlab/protocols/observer.h"

#include <gtest/gtest.h>

#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <vector>

#include "burrlab/protocols/engine.h"

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
    Result<Response> r = observer.Decide(t, {cues, std::nullopt}, rng);
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
            "weber, weber_stiffness, weber_removal, lapse, criterion, "
            "rt_median_s, always)");
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
      Result<Response> r = observer.Decide(t, {cues, std::nullopt}, rng);
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

}  // namespace
}  // namespace burrlab::protocols
