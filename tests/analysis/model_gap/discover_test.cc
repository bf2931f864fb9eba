// The model-gap workflow on data with hidden effects (discover_scenarios.h):
// the data come from the synthetic measurement generator's noise model around
// a truth with the effect hidden and reach Discover only as CSV text. Hit
// rates per effect at a projected SNR of 4, the null control, the absorbed
// effect, a distortion outside the library, gross outliers, bad options.
//
// The truth here is the continuum surrogate (the fast tier); a full-rig truth
// costs 5-60 s per force level and runs in `burrlab discover matrix --full-rig`
// (analysis/README.md). Seeds: 10 per effect and 30 null in CI;
// BURRLAB_SLOW_TESTS=1 runs 20 per effect and 100 null; the sanitizer build
// runs 1 per effect (most of a test's 2-3 s there is EffectAtSnr's
// bisection) and 2 null.
#include "burrlab/analysis/model_gap/discover.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/analysis/model_gap/discover_scenarios.h"
#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/sim/effects.h"
#include "discover_fixtures.h"

namespace burrlab::analysis {
namespace {

using testing::BoneDesign;
using testing::kSanitized;
using testing::Slow;

int EffectSeeds() { return kSanitized ? 1 : Slow() ? 20 : 10; }
int NullSeeds() { return kSanitized ? 2 : Slow() ? 100 : 30; }

DiscoverOptions Options(const ScenarioDesign& d) {
  DiscoverOptions o;
  o.radius_mm = d.radius_mm;
  o.definition = ScenarioDesign::kDefinition;
  o.reference = d.material;
  return o;
}

void Print(const std::string& name, const ScenarioOutcome& out) {
  std::string verdicts;
  for (const auto& [verdict, count] : out.verdicts) {
    verdicts +=
        std::string(VerdictName(verdict)) + " " + std::to_string(count) + ", ";
  }
  for (const SeedOutcome& s : out.per_seed) {
    if (s.named.empty()) continue;
    verdicts += "seed " + std::to_string(s.seed) + ":";
    for (const std::string& id : s.named) verdicts += " " + id;
    verdicts += "; ";
  }
  std::printf(
      "%-20s %2d/%2d hits (%s) held-out RMSE log v %.4f -> %.4f, shrank in "
      "%d\n",
      name.c_str(), out.hits, out.seeds, verdicts.c_str(), out.mean_cv_before,
      out.mean_cv_after, out.cv_shrank);
}

ScenarioOutcome RunHidden(const ScenarioDesign& d, const sim::Effects& effects,
                          const Distortion& distortion,
                          const std::string& expected, int seeds) {
  Result<std::vector<double>> truth = TruthVelocitiesMmS(d, effects);
  EXPECT_TRUE(truth.ok()) << truth.error().message;
  if (!truth.ok()) return {};
  Result<ScenarioOutcome> out =
      RunScenario(d, *truth, distortion, expected, 1, seeds, Options(d));
  EXPECT_TRUE(out.ok()) << out.error().message;
  return out.ok() ? *out : ScenarioOutcome{};
}

TEST(DiscoverScenarios, ProjectedSnrIsZeroForTheBaseModelAndPorosity) {
  const ScenarioDesign d = BoneDesign();
  // The base model's own truth: fitting it to noise gains E[RSS_truth -
  // RSS_base] = 2 sigma^2 (its 2 parameters), so lambda ~ 0 up to the 48
  // draws' sampling error (a base model curved in c_e gains a little more
  // or less). Porosity is c_e (1 - phi)^2, which the base fit absorbs.
  EXPECT_LT(ProjectedSnr(d, {}).value(), 1.0);
  sim::Effects porous;
  porous.porosity = 0.3;
  EXPECT_LT(ProjectedSnr(d, porous).value(), 1.0);
  // EffectAtSnr reaches its target.
  const sim::Effects fx = EffectAtSnr(d, "motor_power_limit", 6.0).value();
  EXPECT_NEAR(ProjectedSnr(d, fx).value(), 6.0, 1e-3);
}

class NamesTheHiddenEffect : public ::testing::TestWithParam<const char*> {};

TEST_P(NamesTheHiddenEffect, AtProjectedSnr4) {
  const ScenarioDesign d = BoneDesign();
  const std::string id = GetParam();
  Result<sim::Effects> fx = EffectAtSnr(d, id, 4.0);
  ASSERT_TRUE(fx.ok()) << fx.error().message;
  const int seeds = EffectSeeds();
  const ScenarioOutcome out = RunHidden(d, *fx, {}, id, seeds);
  Print(id, out);
  // The right id, or an alias set holding it, in >= 90 % of the seeds; every
  // find predicts the held-out levels better (step 7's check), and the
  // held-out error over the finds falls on average.
  EXPECT_GE(out.hits, kSanitized ? 1 : (90 * seeds + 99) / 100);
  EXPECT_EQ(out.held_out_better, out.hits);
  EXPECT_LT(out.mean_cv_after, out.mean_cv_before);
}

INSTANTIATE_TEST_SUITE_P(
    Library, NamesTheHiddenEffect,
    ::testing::Values("motor_power_limit", "spindle_slowdown",
                      "cutting_threshold", "viscous_resistance",
                      "friction_erosion", "contact_exponent"));

// Each family's other shapes: the family is named (or in the alias set)
// whichever shape the truth has.
INSTANTIATE_TEST_SUITE_P(
    Shapes, NamesTheHiddenEffect,
    ::testing::Values("motor_power_limit_droop", "spindle_slowdown_exponential",
                      "cutting_threshold_soft", "viscous_resistance_sqrt",
                      "friction_erosion_quadratic", "contact_exponent_stiff"));

TEST(Discover, SaysNoneWithoutAHiddenEffect) {
  const ScenarioDesign d = BoneDesign();
  const int seeds = NullSeeds();
  const ScenarioOutcome out = RunHidden(d, {}, {}, "", seeds);
  Print("none", out);
  EXPECT_GE(
      out.verdicts.count(Verdict::kNone) ? out.verdicts.at(Verdict::kNone) : 0,
      kSanitized ? 1 : (9 * seeds + 9) / 10);
}

// Porosity (c_e (1 - phi)^2) is invisible in v(F) alone: it must never be
// named, in any step's alias set. Against the reference it is `absorbed`,
// unless the reference with porosity misfits by chance (its 5 % test) or the
// noise draws a chance shape that the shape tests name: the truth is the
// base model at c_e x 0.64, that is a null at loads 0.78-2.34, so such names
// come at the null's false-discovery rate (<= 10 %). Seeds 1-40 measured:
// absorbed 36, none 1 (seed 12, reference + porosity p = 0.023), a chance
// shape 3 (seeds 8, 14, 16; 14 and 16 are the null's own at loads 0.5-1.5).
TEST(Discover, ReportsPorosityAsAbsorbedNeverNamed) {
  const ScenarioDesign d = BoneDesign();
  sim::Effects porous;
  porous.porosity = 0.2;  // c_e 36 % lower than the reference's
  const int seeds = kSanitized ? 1 : 40;
  const ScenarioOutcome out = RunHidden(d, porous, {}, "porosity", seeds);
  Print("porosity", out);
  ASSERT_EQ(out.per_seed.size(), static_cast<std::size_t>(seeds));
  for (const SeedOutcome& s : out.per_seed) {
    EXPECT_EQ(std::count(s.named.begin(), s.named.end(), "porosity"), 0)
        << "seed " << s.seed << ": " << VerdictName(s.verdict);
  }
  EXPECT_EQ(out.hits, out.verdicts.count(Verdict::kAbsorbed)
                          ? out.verdicts.at(Verdict::kAbsorbed)
                          : 0);
  EXPECT_GE(out.hits, kSanitized ? 1 : (85 * seeds + 99) / 100);
  EXPECT_LE(out.named_physical, seeds / 10);
}

TEST(Discover, LeavesABumpOutsideTheLibraryUnexplained) {
  const ScenarioDesign d = BoneDesign();
  Distortion bump;
  bump.bump_log_v = 0.5;  // v 65 % high at the middle force, smooth
  const int seeds = kSanitized ? 1 : 5;
  const ScenarioOutcome out = RunHidden(d, {}, bump, "", seeds);
  Print("bump", out);
  EXPECT_EQ(out.verdicts.count(Verdict::kUnexplained)
                ? out.verdicts.at(Verdict::kUnexplained)
                : 0,
            seeds);
  EXPECT_EQ(out.named_physical, 0);
}

// The outliers are drawn on top of the null's noise (same seeds), so any
// seed they name an effect in beyond the null's own chance shapes would be
// the outliers' doing: they must add none.
TEST(Discover, NamesNoEffectWhenFivePercentAreGrossOutliers) {
  const ScenarioDesign d = BoneDesign();
  Distortion outliers;
  outliers.outlier_fraction = 0.05;
  outliers.outlier_factor = 3.0;
  const int seeds = kSanitized ? 2 : 20;
  const ScenarioOutcome null = RunHidden(d, {}, {}, "", seeds);
  const ScenarioOutcome out = RunHidden(d, {}, outliers, "", seeds);
  Print("outliers", out);
  EXPECT_EQ(NamedBeyond(out, null), std::vector<std::uint64_t>{});
  EXPECT_GE(
      out.verdicts.count(Verdict::kNone) ? out.verdicts.at(Verdict::kNone) : 0,
      kSanitized ? 1 : (9 * seeds + 9) / 10);
}

// Friction erosion at the truth's alpha is a small k; the base fit of these
// data sits at the end of the c_e box with alpha ~ 1e6. A strength scaled by
// that alpha (k = u alpha_base / F_max) put the truth many decades below the
// refit's ladder, and the refit stopped in the friction-dominated basin (k ~
// 1e5, RSS above the truth's). k is now relative to the point's own alpha.
TEST(Discover, FitsFrictionErosionWhenTheBaseFitSitsAtTheEndOfTheCeBox) {
  const ScenarioDesign d = BoneDesign();
  const sim::Effects fx = EffectAtSnr(d, "friction_erosion", 4.0).value();
  const std::vector<double> truth = TruthVelocitiesMmS(d, fx).value();
  const Result<MeasuredData> data =
      ParseMeasuredData("seed-34.csv", ScenarioCsv(d, truth, {}, 34));
  ASSERT_TRUE(data.ok()) << data.error().message;
  const Result<DiscoverReport> report = Discover(*data, Options(d));
  ASSERT_TRUE(report.ok()) << report.error().message;
  EXPECT_GT(report->baseline.c_e_n_per_mm2, 999.0);
  EXPECT_GT(report->baseline.alpha_per_s, 1e4);
  ASSERT_FALSE(report->rounds.empty());
  double fitted = 0.0;
  for (const EffectAttribution& a : report->rounds[0]) {
    if (a.id == "friction_erosion") fitted = a.value;
  }
  EXPECT_NEAR(fitted / fx.friction_erosion_per_n_s, 1.0, 0.4)
      << "fitted k " << fitted << " 1/(N s), truth "
      << fx.friction_erosion_per_n_s;
  EXPECT_EQ(VerdictName(report->verdict), "ambiguous") << report->summary;
  EXPECT_NE(std::find(report->alias_set.begin(), report->alias_set.end(),
                      "friction_erosion"),
            report->alias_set.end())
      << report->summary;
}

// Two effects hidden together, on a design with enough levels to check a
// model with both (8 levels: lack of fit keeps 8 - 4 = 4 dof): the cutting
// threshold (low forces) and the power limit (high forces), each at
// projected SNR 8. One alone may not predict a held-out end level better, so
// the first step is taken on AICc and the final model must lower the
// held-out error against the base model. Measured: 6 of seeds 1-8 add two
// effects (the threshold's set first, then the power limit or its alias
// spindle slowdown on this design); 2 end unexplained.
TEST(Discover, AddsTwoHiddenEffectsOneAtATime) {
  ScenarioDesign d = BoneDesign();
  d.loads = {0.3, 0.5, 0.7, 0.9, 1.2, 1.5, 1.9, 2.4};
  d.replicates = 6;
#if defined(__SANITIZE_ADDRESS__)
  // The sanitizer build (5 s, mostly the two searches; EffectAtSnr runs there
  // in NamesTheHiddenEffect) takes the strengths they find, to 17 digits.
  sim::Effects fx;
  ASSERT_TRUE(
      sim::SetEffect("cutting_threshold", 0.23914570648223166, &fx).ok());
  fx.max_removal_mm3_per_s = 0.073664650139295088;
#else
  sim::Effects fx = EffectAtSnr(d, "cutting_threshold", 8.0).value();
  fx.max_removal_mm3_per_s =
      EffectAtSnr(d, "motor_power_limit", 8.0).value().max_removal_mm3_per_s;
#endif
  const std::vector<double> truth = TruthVelocitiesMmS(d, fx).value();
  const int seeds = kSanitized ? 1 : 8;
  int both = 0, power_second = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    const Result<MeasuredData> data = ParseMeasuredData(
        "two.csv", ScenarioCsv(d, truth, {}, static_cast<std::uint64_t>(seed)));
    ASSERT_TRUE(data.ok()) << data.error().message;
    const Result<DiscoverReport> report = Discover(*data, Options(d));
    ASSERT_TRUE(report.ok()) << report.error().message;
    std::printf("seed %d %s: %s\n", seed,
                std::string(VerdictName(report->verdict)).c_str(),
                report->summary.c_str());
    if (report->effects.size() != 2) continue;
    // Each step reports the effect it added first in its alias set. The
    // first set holds the threshold. The second step names the power limit
    // or spindle slowdown: the design separates them in expectation (the
    // remainder is >= 6.2 sigma^2), but the noise can rank them wrongly
    // (seeds 1 and 6: slowdown by 6.9 and 3.7 AICc), so the power limit must be
    // in the second set in most seeds, not all.
    ASSERT_EQ(report->alias_sets.size(), 2u);
    EXPECT_EQ(report->alias_sets[0], report->alias_set);
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_EQ(report->alias_sets[k].front(), report->effects[k]);
    }
    const auto holds = [&](std::size_t k, const char* id) {
      const auto& set = report->alias_sets[k];
      return std::find(set.begin(), set.end(), id) != set.end();
    };
    EXPECT_TRUE(holds(0, "cutting_threshold")) << report->summary;
    const std::string& second = report->effects[1];
    EXPECT_TRUE(second == "motor_power_limit" || second == "spindle_slowdown")
        << report->summary;
    power_second += holds(1, "motor_power_limit");
    const bool ambiguous =
        report->alias_sets[0].size() > 1 || report->alias_sets[1].size() > 1;
    EXPECT_EQ(VerdictName(report->verdict), ambiguous ? "ambiguous" : "named");
    EXPECT_LT(report->augmented.cv_rmse_log_v, report->baseline.cv_rmse_log_v);
    EXPECT_FALSE(report->gap_after.detected);
    both += 1;
  }
  EXPECT_GE(both, kSanitized ? 1 : 5);
  EXPECT_GE(power_second, kSanitized ? 0 : 4);
}

TEST(DiscoverScenarios, OutcomeIsTheSameForAnyNumberOfJobs) {
  const ScenarioDesign d = BoneDesign();
#if defined(__SANITIZE_ADDRESS__)
  // The sanitizer build (4.5 s, 1.5 s of it the search; EffectAtSnr runs
  // there in NamesTheHiddenEffect) takes the strength it finds, to 17 digits.
  sim::Effects fx;
  ASSERT_TRUE(sim::SetEffect("spindle_slowdown", 8.8242374569833011, &fx).ok());
#else
  const sim::Effects fx = EffectAtSnr(d, "spindle_slowdown", 4.0).value();
#endif
  const std::vector<double> truth = TruthVelocitiesMmS(d, fx).value();
  const ScenarioOutcome one =
      RunScenario(d, truth, {}, "spindle_slowdown", 3, 2, Options(d), 1)
          .value();
  const ScenarioOutcome two =
      RunScenario(d, truth, {}, "spindle_slowdown", 3, 2, Options(d), 2)
          .value();
  EXPECT_EQ(one.seeds, 2);
  EXPECT_EQ(two.seeds, one.seeds);
  EXPECT_EQ(two.verdicts, one.verdicts);
  EXPECT_EQ(two.hits, one.hits);
  EXPECT_EQ(two.named_physical, one.named_physical);
  EXPECT_EQ(two.cv_shrank, one.cv_shrank);
  EXPECT_EQ(two.held_out_better, one.held_out_better);
  EXPECT_EQ(two.mean_cv_before, one.mean_cv_before);
  EXPECT_EQ(two.mean_cv_after, one.mean_cv_after);
}

// Step 7's held-out check on hand-made numbers: the pooled error lower, or
// more than half of the levels better; a tie at half is not enough.
TEST(Discover, HeldOutCheckTakesThePooledErrorOrMostLevels) {
  ModelFit before;
  before.cv_rmse_log_v = 0.10;
  before.cv_level_rmse_log_v = {0.1, 0.1, 0.1, 0.1, 0.1, 0.1};
  ModelFit after = before;
  after.cv_rmse_log_v = 0.09;
  after.cv_level_rmse_log_v = {0.2, 0.2, 0.2, 0.2, 0.2, 0.2};
  EXPECT_TRUE(PredictsHeldOutBetter(after, before));  // pooled lower
  after.cv_rmse_log_v = 0.11;
  EXPECT_FALSE(PredictsHeldOutBetter(after, before));  // 0 of 6 better
  after.cv_level_rmse_log_v = {0.09, 0.09, 0.09, 0.09, 0.2, 0.1};
  EXPECT_TRUE(PredictsHeldOutBetter(after, before));  // 4 of 6
  after.cv_level_rmse_log_v = {0.09, 0.09, 0.09, 0.1, 0.2, 0.1};
  EXPECT_FALSE(PredictsHeldOutBetter(after, before));  // 3 of 6 (equal: no)
  after.cv_level_rmse_log_v = {0.09, 0.09, 0.09, 0.09};
  EXPECT_FALSE(PredictsHeldOutBetter(after, before));  // levels differ
  after.cv_rmse_log_v = std::nan("");
  EXPECT_TRUE(PredictsHeldOutBetter(after, before));  // fewer than 3 levels
}

TEST(Discover, RefusesBadOptionsAndTooLittleData) {
  MeasuredData data =
      ParseMeasuredData("d.csv",
                        "force_n,velocity_mm_s\n1,0.01\n2,0.05\n3,0.2\n")
          .value();
  DiscoverOptions options;
  EXPECT_EQ(Discover(data, options).error().message,
            "radius_mm must be a positive finite number of mm, got 0");
  options.radius_mm = 1.0;
  options.max_effects = 3;
  EXPECT_EQ(Discover(data, options).error().message,
            "max_effects must lie in [0, 2], got 3");
  options.max_effects = 2;
  options.test_level = 0.7;
  EXPECT_EQ(Discover(data, options).error().message,
            "test_level must lie in (0, 0.5), got 0.7");
  options.test_level = 0.05;
  data.runs.pop_back();
  data.force_levels = 2;
  EXPECT_EQ(Discover(data, options).error().message,
            "discover needs more runs than parameters and at least 2 force "
            "levels, got 2 runs at 2 levels");
  // Data that name their velocities must name the model's.
  MeasuredData named =
      ParseMeasuredData("d.csv",
                        "force_n,velocity_mm_s,velocity_definition\n"
                        "1,0.01,settled\n2,0.05,settled\n3,0.2,settled\n")
          .value();
  options.definition = sim::VelocityDefinition::kInitial;
  EXPECT_EQ(Discover(named, options).error().message,
            "measured data:2: error: the measured velocities are settled "
            "velocities (velocity_definition column) but the model predicts "
            "initial velocities; the two are different quantities (the "
            "initial one is taken before the density in the burr has "
            "settled)");
}

// Not in the sanitizer build: a few hundred rig-loop transients of
// milliseconds each (Calibrate.RecoversTheInitialVelocityNearFullImmersion
// runs calibrate's search of the same kind there).
#if !defined(__SANITIZE_ADDRESS__)
// The base fit of the initial velocity near full immersion (PVC at 0.2-3 N,
// R = 2 mm): the held-factor refits cycle there (the transient factor of the
// top load moves fast with c_e), and the base fit must still land on the
// truth. Truth: the rig-loop surrogate's velocities, three replicates at
// 0.98, 1 and 1.02 of each.
TEST(Discover, FitsTheBaseModelOfTheInitialVelocityNearFullImmersion) {
  MeasuredData data;
  for (const double force_n : {0.2, 0.4, 0.6, 0.8, 1.0, 1.5, 2.0, 2.5, 3.0}) {
    DescentSurrogateInput in;
    in.force_n = force_n;
    in.c_e_n_per_mm2 = 0.462;
    in.alpha_per_s = 0.296;
    in.radius_mm = 2.0;
    const double v = SurrogateVelocityMmS(in, sim::VelocityDefinition::kInitial,
                                          InitialTransientFactor(in));
    for (const double factor : {0.98, 1.0, 1.02}) {
      MeasuredRun run;
      run.force_n = force_n;
      run.velocity_mm_s = v * factor;
      data.runs.push_back(run);
    }
  }
  data.force_levels = 9;
  DiscoverOptions options;
  options.radius_mm = 2.0;
  options.definition = sim::VelocityDefinition::kInitial;
  options.max_effects = 0;
  Result<DiscoverReport> report = Discover(data, options);
  ASSERT_TRUE(report.ok()) << report.error().message;
  EXPECT_NEAR(report->baseline.c_e_n_per_mm2 / 0.462, 1.0, 3e-3);
  EXPECT_NEAR(report->baseline.alpha_per_s / 0.296, 1.0, 3e-3);
  EXPECT_EQ(VerdictName(report->verdict), "none") << report->summary;
}

// Truth: the full rig (not the surrogate), nothing hidden. The fixture is
// `burrlab sim measure --material pvc_k70 --forces
// 0.2,0.4,0.6,0.8,1,1.5,2,2.5,3 --replicates 1 --noise-cv 0 --radius-mm 2
// --velocity-definition initial --seed 1` (the rig's default voxels) with
// three replicates per level drawn as v exp(sigma z), CV 5 % (Python's
// random.Random(7 * 7919 + 50).gauss), the seed of the noise-only matrix
// whose transient factors do not settle (3 N is near full immersion). The
// base fit then computes the factors at every point, the effects' fits hold
// them: compared with the fit under the same held factors, an effect at its
// null strength gains nothing. Compared with the search's fit, each gained a
// likelihood ratio of 3.8 and every family was named as one set.
TEST(Discover, AnEffectAtItsNullGainsNothingWhereTheTransientFactorsCycle) {
  const std::string file =
      "tests/analysis/model_gap/fixtures/pvc_initial_rig_noise_only.csv";
  const std::string text = testing::ReadSourceFile(file);
  ASSERT_FALSE(text.empty()) << file;
  const Result<MeasuredData> data = ParseMeasuredData(file, text);
  ASSERT_TRUE(data.ok()) << data.error().message;
  DiscoverOptions options;
  options.radius_mm = 2.0;
  options.definition = sim::VelocityDefinition::kInitial;
  Result<DiscoverReport> report = Discover(*data, options);
  ASSERT_TRUE(report.ok()) << report.error().message;
  EXPECT_EQ(VerdictName(report->verdict), "none") << report->summary;
  ASSERT_FALSE(report->rounds.empty());
  int at_null = 0;
  for (const EffectAttribution& e : report->rounds[0]) {
    if (e.absorbed) continue;
    const sim::EffectSpec* spec =
        sim::FindEffect(e.variant.empty() ? e.id : e.variant);
    ASSERT_NE(spec, nullptr) << e.id;
    if (e.value != spec->null_value) continue;
    ++at_null;
    EXPECT_LT(e.lr, 1e-6) << e.id << " at its null value " << e.value;
  }
  EXPECT_GE(at_null, 2);  // the power limit and spindle slowdown here
}
#endif

}  // namespace
}  // namespace burrlab::analysis
