// Tests of virtual studies against closed forms: probing renders the same cue
// for every erosion seed, so a 2AFC subject is correct with probability pc = (1
// - lapse) Phi(|ln(c2/c1)| / (sigma sqrt 2)) + lapse / 2 on every trial, the
// pooled answers of a study are Binomial(n, pc), and the power of the exact
// binomial test is a binomial tail. The Monte-Carlo power must agree with it.
#include "studies/virtual_study.h"

#include <gtest/gtest.h>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <set>
#include <string>

#include "burrlab/analysis/group_stats.h"
#include "example_protocol.h"

namespace burrlab::runner {
namespace {

TEST(VirtualStudy, BinomialPowerOfATwoAfcBlockMatchesTheClosedForm) {
  const protocols::Protocol protocol =
      ExampleProtocol("two_interval_2afc.toml");
  CuePool pool(4, 2.0, 11);
  VirtualStudyOptions options;
  options.subjects = 5;
  options.observer = protocols::ObserverParamsFrom(protocol.observer);
  options.observer.weber_stiffness = 0.5;
  options.observer.lapse = 0.04;

  // The two probe cues (one pool per material; every rendering alike).
  Result<protocols::Engine> engine = protocols::Engine::Create(protocol, 0, 1);
  ASSERT_TRUE(engine.ok());
  const protocols::TrialSpec& trial = engine->current();
  std::vector<double> cues;
  for (const protocols::PlannedInterval& iv : trial.intervals) {
    Result<const std::vector<double>*> c =
        pool.Cues(protocol, trial, *iv.material, iv.duration_s);
    ASSERT_TRUE(c.ok()) << c.error().message;
    for (double x : **c) EXPECT_EQ(x, (**c)[0]);
    cues.push_back((**c)[0]);
  }
  ASSERT_NE(cues[0], cues[1]);
  const double sigma = 0.5, lapse = 0.04;
  const double pc =
      (1.0 - lapse) * boost::math::cdf(boost::math::normal(),
                                       std::abs(std::log(cues[1] / cues[0])) /
                                           (sigma * std::sqrt(2.0))) +
      lapse / 2.0;
  // Smallest pooled count significant at 0.05 (one-sided), and the tail.
  const int n = 5 * 12;
  int critical = 0;
  while (analysis::ExactBinomialTest(critical, n, 0.5)->p_greater >= 0.05) {
    ++critical;
  }
  const double power = boost::math::cdf(
      boost::math::complement(boost::math::binomial(n, pc), critical - 1));

  const int runs = 400;
  int significant = 0, correct = 0;
  for (int r = 0; r < runs; ++r) {
    options.seed = 1000 + static_cast<std::uint64_t>(r);
    Result<std::vector<VirtualBlock>> study =
        RunVirtualStudy(protocol, options, pool);
    ASSERT_TRUE(study.ok()) << study.error().message;
    ASSERT_EQ(study->size(), 1u);
    int k = 0;
    for (int c : (*study)[0].correct) k += c;
    for (int t : (*study)[0].trials) ASSERT_EQ(t, 12);
    correct += k;
    significant += k >= critical ? 1 : 0;
  }
  const double se = std::sqrt(power * (1.0 - power) / runs);
  EXPECT_NEAR(static_cast<double>(significant) / runs, power, 4.0 * se)
      << "pc " << pc << " critical " << critical;
  const double mean_pc = static_cast<double>(correct) / (runs * n);
  EXPECT_NEAR(mean_pc, pc, 4.0 * std::sqrt(pc * (1.0 - pc) / (runs * n)));
  EXPECT_EQ(pool.rendered(), 8);  // two stimuli, four renderings each
}

TEST(VirtualStudy, SameSeedReplaysTheSameScores) {
  const protocols::Protocol protocol =
      ExampleProtocol("two_interval_2afc.toml");
  CuePool pool(2, 2.0, 3);
  VirtualStudyOptions options;
  options.subjects = 4;
  options.seed = 9;
  options.observer.weber_stiffness = 0.4;
  options.spread_stiffness = 0.3;
  options.spread_removal = 0.3;
  Result<std::vector<VirtualBlock>> a =
      RunVirtualStudy(protocol, options, pool);
  Result<std::vector<VirtualBlock>> b =
      RunVirtualStudy(protocol, options, pool);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ((*a)[0].correct, (*b)[0].correct);
  options.seed = 10;
  Result<std::vector<VirtualBlock>> c =
      RunVirtualStudy(protocol, options, pool);
  ASSERT_TRUE(c.ok());
  EXPECT_NE((*a)[0].correct, (*c)[0].correct);
}

TEST(VirtualStudy, AdjustmentBlocksAreRefused) {
  const protocols::Protocol protocol = ExampleProtocol("adjustment_alpha.toml");
  CuePool pool(1, 2.0, 1);
  VirtualStudyOptions options;
  Result<std::vector<VirtualBlock>> study =
      RunVirtualStudy(protocol, options, pool);
  ASSERT_FALSE(study.ok());
  EXPECT_EQ(study.error().message,
            "block \"adjust\": adjustment blocks cannot be simulated virtually "
            "(no correct answer to score); leave them out of a power "
            "analysis");
}

// A recorded block answered by other populations gives exactly what a
// virtual study run afresh gives (the truth here is RunVirtualStudy itself,
// the engine and observer as every study uses them): 2AFC probing and
// same-different drilling under the likelihood rule with a hand that varies
// between intervals and subjects, over Weber fractions and spreads on both
// sides of the recording's.
TEST(RecordedBlock, AnswersExactlyAsAStudyRunAfresh) {
  struct Case {
    const char* protocol;
    const char* block;
    protocols::ObserverParams observer;
  };
  protocols::ObserverParams likelihood;
  likelihood.rule = protocols::SameDifferentRule::kLikelihood;
  likelihood.bias = 0.3;
  likelihood.lapse = 0.05;
  likelihood.exploration.force_spread = 0.15;
  likelihood.exploration.subject_force_spread = 0.05;
  likelihood.exploration.subject_speed_spread = 0.15;
  const Case cases[] = {
      {"two_interval_2afc.toml", "probe2afc", protocols::ObserverParams{}},
      {"same_different_pvc_vs_bone.toml", "drill", likelihood}};
  RenderingPool renderings(2, 5);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.protocol);
    const protocols::Protocol protocol = ExampleProtocol(c.protocol);
    CuePool pool(renderings, 2.0);
    VirtualStudyOptions options;
    options.subjects = 30;
    options.seed = 17;
    options.only_block = c.block;
    options.observer = c.observer;
    options.observer.weber_stiffness = 0.3;
    options.observer.weber_removal = 0.6;
    options.spread_stiffness = options.spread_removal = 0.2;
    std::vector<VirtualBlock> recorded_study;
    Result<RecordedBlock> record =
        RecordedBlock::Record(protocol, options, pool, &recorded_study);
    ASSERT_TRUE(record.ok()) << record.error().message;
    Result<std::vector<VirtualBlock>> fresh_study =
        RunVirtualStudy(protocol, options, pool);
    ASSERT_TRUE(fresh_study.ok());
    ASSERT_EQ(recorded_study.size(), fresh_study->size());
    EXPECT_EQ(recorded_study[0].correct, (*fresh_study)[0].correct);
    int differing = 0;
    for (const double weber : {0.05, 0.3, 1.2, 4.0}) {
      for (const double spread : {0.0, 0.2, 0.9}) {
        options.observer.weber_stiffness = options.observer.weber_removal =
            weber;
        options.spread_stiffness = options.spread_removal = spread;
        Result<std::vector<VirtualBlock>> fresh =
            RunVirtualStudy(protocol, options, pool);
        ASSERT_TRUE(fresh.ok()) << fresh.error().message;
        const VirtualBlock* b = nullptr;
        for (const VirtualBlock& v : *fresh) {
          if (v.block == c.block) b = &v;
        }
        ASSERT_NE(b, nullptr);
        Result<VirtualBlock> again = record->Answer(options);
        ASSERT_TRUE(again.ok()) << again.error().message;
        EXPECT_EQ(again->block, b->block);
        EXPECT_EQ(again->correct, b->correct) << weber << " " << spread;
        EXPECT_EQ(again->trials, b->trials);
        differing += again->correct != recorded_study[0].correct ? 1 : 0;
      }
    }
    EXPECT_GE(differing, 8);  // the populations do answer differently
  }
}

TEST(RecordedBlock, RefusesAdaptiveBlocksAndOtherObservers) {
  CuePool pool(1, 2.0, 1);
  VirtualStudyOptions options;
  options.subjects = 3;
  // The error recording `block` of `file` gives.
  const auto refusal_of = [&](const char* file, const char* block) {
    options.only_block = block;
    Result<RecordedBlock> r =
        RecordedBlock::Record(ExampleProtocol(file), options, pool, nullptr);
    return r.ok() ? std::string("recorded") : r.error().message;
  };
  EXPECT_EQ(refusal_of("staircase_1up3down.toml", "stairs"),
            "block \"stairs\" (staircase) adapts its trials to the answers: "
            "it cannot be answered again by other observers");
  EXPECT_EQ(refusal_of("two_interval_2afc.toml", ""),
            "recording a virtual study needs the block to record "
            "(only_block)");

  options.only_block = "probe2afc";
  Result<RecordedBlock> record = RecordedBlock::Record(
      ExampleProtocol("two_interval_2afc.toml"), options, pool, nullptr);
  ASSERT_TRUE(record.ok()) << record.error().message;
  const std::string refusal =
      "a recorded virtual study can be answered again only with other Weber "
      "fractions and spreads";
  for (int change = 0; change < 4; ++change) {
    VirtualStudyOptions other = options;
    if (change == 0) other.observer.lapse = 0.1;
    if (change == 1) other.subjects = 4;
    if (change == 2) other.seed = 2;
    if (change == 3) other.observer.exploration.force_spread = 0.1;
    Result<VirtualBlock> b = record->Answer(other);
    ASSERT_FALSE(b.ok()) << change;
    EXPECT_EQ(b.error().message, refusal);
  }
}

}  // namespace
}  // namespace burrlab::runner

namespace burrlab::runner {
namespace {

// One z per subject scales both cues: ln(W / W0) / spread is the same for
// the stiffness and the removal cue; draws beyond the largest Weber fraction
// are held there; explicit subject observers are taken as given.
TEST(SubjectObserver, OneDrawPerSubjectScalesBothCues) {
  VirtualStudyOptions o;
  o.seed = 12;
  o.observer.weber_stiffness = 0.2;
  o.observer.weber_removal = 0.4;
  EXPECT_EQ(SubjectObserver(o, 3).weber_stiffness, 0.2);  // no spread
  o.spread_stiffness = 0.5;
  o.spread_removal = 1.0;
  std::set<double> seen;
  for (int s = 0; s < 20; ++s) {
    const protocols::ObserverParams p = SubjectObserver(o, s);
    const double zs = std::log(p.weber_stiffness / 0.2) / 0.5;
    const double zr = std::log(p.weber_removal / 0.4) / 1.0;
    if (p.weber_removal < protocols::kMaxWeberFraction) {
      EXPECT_NEAR(zs, zr, 1e-12) << s;
    }
    EXPECT_LE(p.weber_removal, protocols::kMaxWeberFraction);
    EXPECT_EQ(p.weber_stiffness, SubjectObserver(o, s).weber_stiffness);
    seen.insert(p.weber_stiffness);
  }
  EXPECT_EQ(seen.size(), 20u);
  o.spread_removal = 20.0;  // draws far beyond 5 are held at 5
  bool held = false;
  for (int s = 0; s < 20; ++s) {
    held = held ||
           SubjectObserver(o, s).weber_removal == protocols::kMaxWeberFraction;
  }
  EXPECT_TRUE(held);
  protocols::ObserverParams own;
  own.weber_stiffness = 0.33;
  o.subject_observers = {own};
  EXPECT_EQ(SubjectObserver(o, 0).weber_stiffness, 0.33);
}

}  // namespace
}  // namespace burrlab::runner
