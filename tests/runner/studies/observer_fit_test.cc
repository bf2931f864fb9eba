// Tests of the observer-population fit: group results simulated with a known
// Weber fraction are fitted back with intervals that hold it, and the
// --observed text is parsed strictly.
#include "studies/observer_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "example_protocol.h"

namespace burrlab::runner {
namespace {

// Four published groups in the optimised build; the sanitizer build (several
// times slower) fits one.
#if defined(__SANITIZE_ADDRESS__)
constexpr std::uint64_t kGroups = 1;
#else
constexpr std::uint64_t kGroups = 4;
#endif

// The group result a paper reports of scores `correct`: mean +- SEM (sample
// SD, divisor n - 1, over sqrt(n)), unrounded.
ObservedGroup ReportOf(const std::vector<int>& correct) {
  double sum = 0.0, sum2 = 0.0;
  for (int c : correct) {
    sum += c;
    sum2 += double(c) * c;
  }
  const double n = static_cast<double>(correct.size());
  ObservedGroup g;
  g.n = static_cast<int>(correct.size());
  g.mean = sum / n;
  g.sem = std::sqrt((sum2 - sum * sum / n) / (n - 1.0) / n);
  return g;
}

TEST(ObserverFit, RecoversAKnownWeberFractionWithinItsInterval) {
  const protocols::Protocol protocol =
      ExampleProtocol("two_interval_2afc.toml");
  const double truth = 0.4;
  int covered = 0;
  for (std::uint64_t seed = 1; seed <= kGroups; ++seed) {
    // The "published" result: 20 subjects of Weber 0.4.
    CuePool pool(2, 2.0, seed);
    VirtualStudyOptions study;
    study.subjects = 20;
    study.seed = 100 + seed;
    study.observer.weber_stiffness = truth;
    study.observer.weber_removal = truth;
    Result<std::vector<VirtualBlock>> result =
        RunVirtualStudy(protocol, study, pool);
    ASSERT_TRUE(result.ok()) << result.error().message;
    const ObservedGroup observed = ReportOf((*result)[0].correct);

    ObserverFitOptions options;
    options.virtual_subjects = 300;
    options.seed = 7 + seed;
    options.fit_spread = false;
    options.base = study.observer;
    Result<ObserverFit> fit = FitObservers(protocol, observed, options, pool);
    ASSERT_TRUE(fit.ok()) << fit.error().message;
    EXPECT_EQ(fit->block, "probe2afc");
    EXPECT_EQ(fit->trials_per_subject, 12);
    EXPECT_LT(fit->weber_low, fit->weber);
    EXPECT_LT(fit->weber, fit->weber_high);
    EXPECT_NEAR(fit->fitted_mean, observed.mean, 0.1);
    covered += fit->weber_low <= truth && truth <= fit->weber_high ? 1 : 0;
  }
  EXPECT_GE(covered, kGroups == 4 ? 3 : 1);  // 95 % intervals
}

TEST(ObserverFit, SpreadExplainsAnSdAboveTheBinomial) {
  const protocols::Protocol protocol =
      ExampleProtocol("two_interval_2afc.toml");
  CuePool pool(2, 2.0, 1);
  ObserverFitOptions options;
  // 9 of 12 with SD 2.2 (binomial alone gives about 1.5).
  ObservedGroup observed{9.0, 2.2 / std::sqrt(20.0), 20, ""};
#if defined(__SANITIZE_ADDRESS__)
  // The sanitizer build (ten times slower on this fit: 50 s) runs the spread
  // fit's plumbing on a small population; the optimised build checks what it
  // finds.
  options.virtual_subjects = 40;
  Result<ObserverFit> fit = FitObservers(protocol, observed, options, pool);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  EXPECT_GE(fit->weber_spread, 0.0);
  EXPECT_TRUE(std::isfinite(fit->fitted_sd));
#else
  options.virtual_subjects = 300;
  Result<ObserverFit> fit = FitObservers(protocol, observed, options, pool);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  EXPECT_GT(fit->weber_spread, 0.1);
  EXPECT_NEAR(fit->fitted_sd, 2.2, 0.25);
  EXPECT_NEAR(fit->fitted_mean, 9.0, 0.15);
  // The likelihood tells the models apart: 20 subjects all alike (their SD
  // about 1.5, binomial) rarely report an SD of 2.2 (SEM 0.49); the spread
  // population reports it far more often.
  options.fit_spread = false;
  Result<ObserverFit> alike = FitObservers(protocol, observed, options, pool);
  ASSERT_TRUE(alike.ok()) << alike.error().message;
  RecordProperty("p_spread", std::to_string(fit->published_probability));
  RecordProperty("p_alike", std::to_string(alike->published_probability));
  EXPECT_GT(fit->published_probability, 5.0 * alike->published_probability);
#endif
}

TEST(ObserverFit, ObservedTextIsParsedStrictly) {
  Result<ObservedGroup> g = ParseObservedGroup("n=20,mean=9.3,sem=0.4");
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(g->mean, 9.3);
  EXPECT_EQ(g->sem, 0.4);
  EXPECT_EQ(g->n, 20);
  EXPECT_EQ(g->decimals, 1);  // the rounding of the published numbers
  EXPECT_EQ(ParseObservedGroup("mean=9.25,sem=0.4,n=20")->decimals, 2);
  EXPECT_EQ(ParseObservedGroup("mean=9,sem=1,n=20")->decimals, 0);
  for (const std::string bad :
       {"mean=9.3,sem=0.4", "mean=9.3,sem=0,n=20", "mean=x,sem=0.4,n=20",
        "mean=9.3,sem=0.4,n=2.5", "mean=9.3;sem=0.4;n=20", "",
        "block=,mean=9.3,sem=0.4,n=20",
        "block=a,block=b,mean=9.3,sem=0.4,n=20"}) {
    Result<ObservedGroup> r = ParseObservedGroup(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.error().message,
              "--observed must be [block=NAME,]mean=M,sem=S,n=N (M >= 0, S > "
              "0, N >= 2) or [block=NAME,]scores=S1/S2/... (each subject's "
              "score, at least two), got '" +
                  bad + "'");
  }
}

// Each subject's score: n, mean and SEM are theirs (by hand: 8, 9, 10, 11
// have mean 9.5 and SD sqrt(5/3), SEM sqrt(5/3) / 2), unrounded.
TEST(ObserverFit, ObservedTextMayGiveEachSubjectsScore) {
  Result<ObservedGroup> g = ParseObservedGroup("block=probe,scores=8/9/10/11");
  ASSERT_TRUE(g.ok()) << g.error().message;
  EXPECT_EQ(g->block, "probe");
  EXPECT_EQ(g->scores, (std::vector<int>{8, 9, 10, 11}));
  EXPECT_EQ(g->n, 4);
  EXPECT_DOUBLE_EQ(g->mean, 9.5);
  EXPECT_DOUBLE_EQ(g->sem, std::sqrt(5.0 / 3.0) / 2.0);
  EXPECT_EQ(g->decimals, 6);
  for (const std::string bad :
       {"scores=9", "scores=9/x", "scores=9//10", "scores=9/-1",
        "scores=9/10,n=2", "scores=9/10,mean=9.5", "scores=9/10,scores=9/10",
        "scores="}) {
    Result<ObservedGroup> r = ParseObservedGroup(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.error().message.find("or [block=NAME,]scores=S1/S2/..."),
              std::string::npos);
  }
}

// The likelihood of each subject's score against that of the published mean
// and SEM, at the same population. Truth, combinatorial: two subjects scoring
// 8 and 11 are the only pair with mean 9.5 and SEM 1.5, reached in two orders,
// so P(mean 9.5, SEM 1.5) = 2 p(8) p(11) = 2 P(scores 8, 11): the log
// likelihoods differ by ln 2. The moment fits (same mean and SD) give the
// same population.
TEST(ObserverFit, EachSubjectsScoreIsTheMeanAndSemInOneOrder) {
  const protocols::Protocol protocol =
      ExampleProtocol("two_interval_2afc.toml");
  CuePool pool(2, 2.0, 1);
  ObserverFitOptions options;
  options.virtual_subjects = 200;
  options.maximum_likelihood = false;
  options.fit_spread = false;
  const Result<ObservedGroup> scores = ParseObservedGroup("scores=8/11");
  ASSERT_TRUE(scores.ok());
  Result<ObserverFit> by_scores =
      FitObservers(protocol, *scores, options, pool);
  Result<ObserverFit> by_mean =
      FitObservers(protocol, {9.5, 1.5, 2, "", 1}, options, pool);
  ASSERT_TRUE(by_scores.ok()) << by_scores.error().message;
  ASSERT_TRUE(by_mean.ok()) << by_mean.error().message;
  EXPECT_EQ(by_scores->weber, by_mean->weber);
  EXPECT_NEAR(by_mean->log_likelihood - by_scores->log_likelihood,
              std::log(2.0), 1e-12);
  // A score above the block's trials is refused by name.
  Result<ObserverFit> above =
      FitObservers(protocol, ObservedScores({8, 13}, ""), options, pool);
  ASSERT_FALSE(above.ok());
  EXPECT_EQ(above.error().message,
            "an observed score of 13 is above the 12 trials of block "
            "\"probe2afc\"");
}

TEST(ObserverFit, ObservedTextMayNameItsBlock) {
  Result<ObservedGroup> g =
      ParseObservedGroup("block=drill,mean=9.6,sem=0.5,n=20");
  ASSERT_TRUE(g.ok()) << g.error().message;
  EXPECT_EQ(g->block, "drill");
  EXPECT_EQ(g->mean, 9.6);
  EXPECT_EQ(g->n, 20);
}

// A drill block fits the removal cue: a population of known removal Weber
// fraction (and another stiffness one, which the drill block never feels)
// is recovered within the fit's interval.
TEST(ObserverFit, ADrillBlockFitsTheRemovalCue) {
  const protocols::Protocol protocol =
      ExampleProtocol("same_different_pvc_vs_bone.toml");
  RenderingPool renderings(2, 3);
  CuePool pool(renderings, 2.0);
  VirtualStudyOptions study;
  study.subjects = 20;
  study.seed = 41;
  study.observer.weber_stiffness = 0.05;
  study.observer.weber_removal = 1.5;
  study.only_block = "drill";
  Result<std::vector<VirtualBlock>> result =
      RunVirtualStudy(protocol, study, pool);
  ASSERT_TRUE(result.ok()) << result.error().message;
  const VirtualBlock* drill = nullptr;
  for (const VirtualBlock& b : *result) {
    if (b.block == "drill") drill = &b;
  }
  ASSERT_NE(drill, nullptr);
  ObservedGroup observed = ReportOf(drill->correct);
  observed.block = "drill";
  ObserverFitOptions options;
  options.virtual_subjects = 200;
  options.seed = 5;
  options.fit_spread = false;
  options.base = study.observer;
  Result<ObserverFit> fit = FitObservers(protocol, observed, options, pool);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  EXPECT_EQ(fit->block, "drill");
  EXPECT_EQ(fit->task, protocols::Task::kDrill);
  EXPECT_LE(fit->weber_low, 1.5);
  EXPECT_GE(fit->weber_high, 1.5);
  EXPECT_NEAR(fit->fitted_mean, observed.mean, 0.15);
}

// A lapse shared by the blocks (variant likelihood_lapse) caps every block's
// mean: a subject who answers at random in a fraction l of the trials scores
// at most T (1 - l / 2) of T on average, however keen. Both PVC vs bone
// blocks reported at 11.0 +- 0.15 of 12 (n 40; SD 0.95, about the binomial
// SD of a keen observer lapsing near the cap) put that ceiling at l = 2 (1 -
// 11 / 12) = 0.167: the profile interval's upper end lies beyond it, but by
// no more than the mean's uncertainty allows (11.0 - 3 SEM gives 0.24).
// Truth: the closed-form ceiling of a lapsing observer's mean. Not in the
// sanitizer build (its profile is some fifty fits; the CLI test runs the
// variant there).
#if !defined(__SANITIZE_ADDRESS__)
TEST(ObserverFit, ASharedLapseIsBoundedByTheCeilingOfTheMeans) {
  const protocols::Protocol protocol =
      ExampleProtocol("same_different_pvc_vs_bone.toml");
  const std::vector<ObservedGroup> observed = {{11.0, 0.15, 40, "probe", 2},
                                               {11.0, 0.15, 40, "drill", 2}};
  Result<ObserverVariant> variant = FindObserverVariant("likelihood_lapse");
  ASSERT_TRUE(variant.ok()) << variant.error().message;
  RenderingPool renderings(2, 3);
  CuePool pool(renderings, 2.0);
  ObserverFitOptions options;
  options.virtual_subjects = 100;
  options.seed = 7;
  options.jobs = 2;
  int calls = 0, last = 0;
  Result<std::vector<VariantFit>> fitted =
      CompareObserverVariants(protocol, observed, std::span(&*variant, 1),
                              options, pool, [&](int done, std::string_view) {
                                ++calls;
                                last = done;
                              });
  ASSERT_TRUE(fitted.ok()) << fitted.error().message;
  ASSERT_EQ(fitted->size(), 1u);
  const VariantFit& v = fitted->front();
  const double ceiling = 2.0 * (1.0 - 11.0 / 12.0);
  std::printf("lapse %.4f [%.4f, %.4f], ln L %.3f\n", v.observer.lapse,
              v.lapse_low, v.lapse_high, v.log_likelihood);
  EXPECT_GT(v.lapse_high, ceiling);
  EXPECT_LT(v.lapse_high, 2.0 * (1.0 - (11.0 - 3.0 * 0.15) / 12.0));
  EXPECT_LE(v.lapse_low, v.observer.lapse);
  EXPECT_LE(v.observer.lapse, v.lapse_high);
  // The profile: every lapse tried, the fit at its maximum, and far below it
  // where the ceiling is out of reach (at 0.4 the mean is at most 9.6).
  ASSERT_GE(v.lapse_profile.size(), std::size(kLapseGrid));
  double peak = -1e300, at_04 = 0.0;
  for (const auto& [lapse, ll] : v.lapse_profile) {
    peak = std::max(peak, ll);
    if (lapse == 0.4) at_04 = ll;
  }
  // (The blocks' final fits, with intervals, may find a little more.)
  EXPECT_GE(v.log_likelihood, peak);
  EXPECT_LT(at_04, peak - 10.0);
  // Both blocks are fitted at the shared lapse, with their own W; the lapse
  // counts once.
  ASSERT_EQ(v.fits.size(), 2u);
  EXPECT_EQ(v.parameters, 5);
  EXPECT_DOUBLE_EQ(v.aic, 2.0 * 5 - 2.0 * v.log_likelihood);
  // Progress counts up to FitsToCompare's total.
  EXPECT_EQ(last, FitsToCompare(std::span(&*variant, 1), 2));
  EXPECT_GT(calls, 2);
}
#endif  // !__SANITIZE_ADDRESS__

// Fits on several threads (--jobs) are the fits made one after another, to
// the last bit: each fit draws only from its own seeds, and the threads share
// a cue cache they fill as they go (a fresh one for each run here).
TEST(ObserverFit, FitsOnSeveralThreadsAreTheFitsMadeInTurn) {
  const protocols::Protocol protocol =
      ExampleProtocol("same_different_pvc_vs_bone.toml");
  const std::vector<ObservedGroup> observed = {{9.3, 0.4, 20, "probe"},
                                               {9.6, 0.5, 20, "drill"}};
  std::vector<ObserverVariant> variants;
  for (const char* name : {"fixed", "likelihood_alike"}) {
    Result<ObserverVariant> v = FindObserverVariant(name);
    ASSERT_TRUE(v.ok()) << v.error().message;
    variants.push_back(*v);
  }
  ObserverFitOptions options;
#if defined(__SANITIZE_ADDRESS__)
  options.virtual_subjects = 30;
#else
  options.virtual_subjects = 100;
#endif
  options.seed = 3;
  options.base = protocols::ObserverParamsFrom(protocol.observer);
  RenderingPool renderings(2, 5);
  const auto compare = [&](int jobs, std::vector<int>* progress) {
    CuePool pool(renderings, 2.0);
    ObserverFitOptions o = options;
    o.jobs = jobs;
    return CompareObserverVariants(
        protocol, observed, variants, o, pool,
        [&](int done, std::string_view) { progress->push_back(done); });
  };
  std::vector<int> progress_1, progress_3;
  Result<std::vector<VariantFit>> one = compare(1, &progress_1);
  Result<std::vector<VariantFit>> three = compare(3, &progress_3);
  ASSERT_TRUE(one.ok()) << one.error().message;
  ASSERT_TRUE(three.ok()) << three.error().message;
  EXPECT_EQ(progress_1, (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(progress_3, (std::vector<int>{1, 2, 3, 4}));
  ASSERT_EQ(one->size(), 2u);
  ASSERT_EQ(three->size(), 2u);
  for (std::size_t i = 0; i < one->size(); ++i) {
    const VariantFit& a = (*one)[i];
    const VariantFit& b = (*three)[i];
    EXPECT_EQ(a.variant.name, b.variant.name);
    EXPECT_EQ(a.log_likelihood, b.log_likelihood);
    EXPECT_EQ(a.aic, b.aic);
    ASSERT_EQ(a.fits.size(), 2u);
    ASSERT_EQ(b.fits.size(), 2u);
    for (std::size_t g = 0; g < 2; ++g) {
      EXPECT_EQ(a.fits[g].block, observed[g].block);
      EXPECT_EQ(b.fits[g].block, observed[g].block);
      EXPECT_EQ(a.fits[g].weber, b.fits[g].weber);
      EXPECT_EQ(a.fits[g].weber_low, b.fits[g].weber_low);
      EXPECT_EQ(a.fits[g].weber_high, b.fits[g].weber_high);
      EXPECT_EQ(a.fits[g].weber_spread, b.fits[g].weber_spread);
      EXPECT_EQ(a.fits[g].spread_high, b.fits[g].spread_high);
      EXPECT_EQ(a.fits[g].log_likelihood, b.fits[g].log_likelihood);
    }
  }
  // FitObserverGroups too, and its fits are the variant's.
  CuePool pool(renderings, 2.0);
  ObserverFitOptions o = options;
  o.base = VariantObserver(variants[1], options.base);
  o.fit_spread = false;
  o.jobs = 2;
  Result<std::vector<ObserverFit>> groups =
      FitObserverGroups(protocol, observed, o, pool);
  ASSERT_TRUE(groups.ok()) << groups.error().message;
  const VariantFit& alike =
      (*one)[0].variant.name == "likelihood_alike" ? (*one)[0] : (*one)[1];
  ASSERT_EQ(groups->size(), 2u);
  for (std::size_t g = 0; g < 2; ++g) {
    EXPECT_EQ((*groups)[g].weber, alike.fits[g].weber);
    EXPECT_EQ((*groups)[g].log_likelihood, alike.fits[g].log_likelihood);
  }
  // An error is the first group's, whichever thread met it first.
  const std::vector<ObservedGroup> wrong = {{9.3, 0.4, 20, "nope"},
                                            {13.0, 0.5, 20, "drill"}};
  Result<std::vector<ObserverFit>> refused =
      FitObserverGroups(protocol, wrong, o, pool);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().message,
            "the protocol has no block \"nope\" (blocks: probe, drill)");
}

TEST(ObserverFit, PopulationTakesEachCueFromTheBlockOfItsTask) {
  ObserverFit probe, drill;
  probe.block = "probe";
  probe.task = protocols::Task::kProbe;
  probe.weber = 0.12;
  probe.weber_spread = 1.7;
  drill.block = "drill";
  drill.task = protocols::Task::kDrill;
  drill.weber = 0.9;
  drill.weber_spread = 0.5;
  protocols::ObserverParams base;
  base.lapse = 0.03;
  std::vector<std::string> notes;
  Result<VirtualStudyOptions> both = PopulationOf({probe, drill}, base, &notes);
  ASSERT_TRUE(both.ok());
  EXPECT_EQ(both->observer.weber_stiffness, 0.12);
  EXPECT_EQ(both->observer.weber_removal, 0.9);
  EXPECT_EQ(both->spread_stiffness, 1.7);
  EXPECT_EQ(both->spread_removal, 0.5);
  EXPECT_EQ(both->observer.lapse, 0.03);
  EXPECT_TRUE(notes.empty());

  Result<VirtualStudyOptions> one = PopulationOf({drill}, base, &notes);
  ASSERT_TRUE(one.ok());
  EXPECT_EQ(one->observer.weber_stiffness, 0.9);
  EXPECT_EQ(one->spread_stiffness, 0.5);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0],
            "only the removal cue was fitted (block \"drill\"); the stiffness "
            "cue takes the same Weber fraction and spread");

  ObserverFit drill2 = drill;
  drill2.block = "drill2";
  Result<VirtualStudyOptions> clash =
      PopulationOf({drill, drill2}, base, nullptr);
  ASSERT_FALSE(clash.ok());
  EXPECT_EQ(clash.error().message,
            "blocks \"drill\" and \"drill2\" both fit the removal cue: fit one "
            "block per task");
}

TEST(ObserverFit, AMeanAboveTheTrialsIsRefused) {
  const protocols::Protocol protocol =
      ExampleProtocol("two_interval_2afc.toml");
  CuePool pool(1, 2.0, 1);
  Result<ObserverFit> fit =
      FitObservers(protocol, {13.0, 0.5, 20, ""}, ObserverFitOptions{}, pool);
  ASSERT_FALSE(fit.ok());
  EXPECT_EQ(fit.error().message,
            "the observed mean 13 is above the 12 trials of block "
            "\"probe2afc\"");
}

}  // namespace
}  // namespace burrlab::runner
