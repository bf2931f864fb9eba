// Calibration of c_e and alpha: recovery from noise-free data, the
// identifiability verdict, and Monte-Carlo coverage of the profile-likelihood
// intervals on data drawn from the surrogate with log-normal noise. The
// recovery of the built-in materials from the full rig's data is in
// tests/runner/calibrate_command_test.cc.
#include "burrlab/analysis/model_gap/calibration.h"

#include <gtest/gtest.h>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/analysis/model_gap/initial_velocity.h"
#include "burrlab/analysis/model_gap/measured_data.h"
#include "discover_fixtures.h"

namespace burrlab::analysis {
namespace {

struct Truth {
  double c_e_n_per_mm2 = 2.145;
  double alpha_per_s = 0.087;
  double radius_mm = 1.0;
};

// Runs at the given loads F / (c_e R^2), `replicates` each, velocities from
// the surrogate times log-normal noise of coefficient of variation `cv`.
MeasuredData MakeData(const Truth& truth, const std::vector<double>& loads,
                      int replicates, double cv, std::uint64_t seed) {
  boost::random::mt19937_64 rng(seed);
  boost::random::normal_distribution<double> normal;
  const double s = std::sqrt(std::log1p(cv * cv));
  MeasuredData data;
  for (double load : loads) {
    DescentSurrogateInput in;
    in.force_n = load * truth.c_e_n_per_mm2 * truth.radius_mm * truth.radius_mm;
    in.c_e_n_per_mm2 = truth.c_e_n_per_mm2;
    in.alpha_per_s = truth.alpha_per_s;
    in.radius_mm = truth.radius_mm;
    const double v = SteadyVelocityMmS(in);
    for (int k = 0; k < replicates; ++k) {
      MeasuredRun run;
      run.force_n = in.force_n;
      run.velocity_mm_s = v * std::exp(s * normal(rng));
      data.runs.push_back(run);
    }
  }
  data.force_levels = static_cast<int>(loads.size());
  data.velocity_definition = sim::VelocityDefinition::kSettled;
  return data;
}

// Options for a fit of MakeData's settled velocities at burr radius
// `radius_mm`.
CalibrationOptions SettledOptions(double radius_mm) {
  CalibrationOptions options;
  options.radius_mm = radius_mm;
  options.definition = sim::VelocityDefinition::kSettled;
  return options;
}

bool Covers(const std::optional<Interval>& ci, double value) {
  return ci && (*ci)[0] <= value && value <= (*ci)[1];
}

const std::vector<double> kWideLoads = {0.5, 0.7, 0.9, 1.1, 1.3, 1.5};
const std::vector<double> kShallowLoads = {0.01, 0.015, 0.02, 0.03, 0.045};

TEST(Calibrate, RecoversNoiseFreeData) {
  const Truth truth;
  CalibrationOptions options = SettledOptions(truth.radius_mm);
  Result<CalibrationSummary> fit =
      Calibrate(MakeData(truth, kWideLoads, 1, 0.0, 1), options);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  EXPECT_NEAR(fit->c_e_n_per_mm2 / truth.c_e_n_per_mm2, 1.0, 1e-4);
  EXPECT_NEAR(fit->alpha_per_s / truth.alpha_per_s, 1.0, 1e-4);
  EXPECT_LT(fit->rmse_log_v, 1e-5);
}

TEST(Calibrate, RefusesDataThatNameAnotherVelocityThanTheModels) {
  const Truth truth;
  CalibrationOptions options = SettledOptions(truth.radius_mm);
  options.definition = sim::VelocityDefinition::kInitial;
  MeasuredData data = MakeData(truth, kWideLoads, 1, 0.0, 1);
  data.velocity_definition_line = 2;
  EXPECT_EQ(Calibrate(data, options).error().message,
            "measured data:2: error: the measured velocities are settled "
            "velocities (velocity_definition column) but the model predicts "
            "initial velocities; the two are different quantities (the "
            "initial one is taken before the density in the burr has "
            "settled)");
}

// Runs of `data` dealt out level by level (the first run of every level,
// then the second, ...), as a lab's file interleaves its forces.
MeasuredData Interleaved(const MeasuredData& data, int replicates) {
  MeasuredData out = data;
  out.runs.clear();
  const std::size_t levels = data.runs.size() / replicates;
  for (int k = 0; k < replicates; ++k) {
    for (std::size_t g = 0; g < levels; ++g) {
      out.runs.push_back(data.runs[g * replicates + k]);
    }
  }
  return out;
}

// The fit keeps one level per force with its runs' mean and spread. Truths:
// the RSS summed here run by run from the fitted velocities (the identity
// sum_i (y_i - p)^2 = within + sum_g n_g (ybar_g - p_g)^2 checked by the
// definition, not by the code's formula), and the same fit with the runs in
// another order.
TEST(Calibrate, PoolsTheRunsAtAForceWhateverTheirOrder) {
  const Truth truth;
  const int replicates = 40;
  const MeasuredData sorted = MakeData(truth, kWideLoads, replicates, 0.08, 5);
  const MeasuredData mixed = Interleaved(sorted, replicates);
  CalibrationOptions options = SettledOptions(truth.radius_mm);
  options.bootstrap_replicates = 0;  // its draws follow the runs' order
  Result<CalibrationSummary> a = Calibrate(sorted, options);
  Result<CalibrationSummary> b = Calibrate(mixed, options);
  ASSERT_TRUE(a.ok() && b.ok());
  double rss = 0.0;
  for (std::size_t i = 0; i < mixed.runs.size(); ++i) {
    const double r =
        std::log(mixed.runs[i].velocity_mm_s / b->fitted_velocity_mm_s[i]);
    rss += r * r;
  }
  EXPECT_NEAR(b->rss_log_v / rss, 1.0, 1e-12);
  EXPECT_NEAR(a->rss_log_v / b->rss_log_v, 1.0, 1e-12);
  EXPECT_NEAR(a->c_e_n_per_mm2 / b->c_e_n_per_mm2, 1.0, 1e-9);
  EXPECT_NEAR(a->alpha_per_s / b->alpha_per_s, 1.0, 1e-9);
  EXPECT_NEAR(a->condition_number / b->condition_number, 1.0, 1e-9);
  ASSERT_TRUE(a->c_e_ci && b->c_e_ci);
  EXPECT_NEAR((*a->c_e_ci)[0] / (*b->c_e_ci)[0], 1.0, 1e-9);
  EXPECT_NEAR((*a->c_e_ci)[1] / (*b->c_e_ci)[1], 1.0, 1e-9);
  // Fitted velocities follow the runs: run i's is its own level's.
  for (std::size_t i = 0; i < mixed.runs.size(); ++i) {
    const std::size_t g = i % kWideLoads.size();
    EXPECT_DOUBLE_EQ(b->fitted_velocity_mm_s[i], b->fitted_velocity_mm_s[g]);
  }
}

// Options for a fit of initial velocities at burr radius `radius_mm`, point
// estimates only.
CalibrationOptions InitialWithoutBootstrap(double radius_mm) {
  CalibrationOptions options;
  options.radius_mm = radius_mm;
  options.definition = sim::VelocityDefinition::kInitial;
  options.bootstrap_replicates = 0;
  return options;
}

// The initial velocity, truth the surrogate's own rig loop (InitialVelocity
// MmS, transient included): the fit holds each run's transient factor at its
// estimate and refreshes it until it settles, so it must land on the truth.
// (The full rig as the truth: tests/runner/calibrate_command_test.cc.)
TEST(Calibrate, RecoversTheInitialVelocityWithItsTransient) {
  const Truth truth{2.145, 0.087, 2.0};
  MeasuredData data;
  for (const double force_n : {1.0, 2.0, 3.0, 4.0, 5.0}) {
    InitialVelocityInput in;
    in.force_n = in.elastic_n = force_n;
    in.radius_mm = truth.radius_mm;
    in.rate_per_s = truth.alpha_per_s;
    in.depth_ratio = std::cbrt(std::pow(
        force_n / (truth.c_e_n_per_mm2 * truth.radius_mm * truth.radius_mm),
        2.0));
    MeasuredRun run;
    run.force_n = force_n;
    run.velocity_mm_s = InitialVelocityMmS(in);
    data.runs.push_back(run);
  }
  data.force_levels = 5;
  CalibrationOptions options = InitialWithoutBootstrap(truth.radius_mm);
  Result<CalibrationSummary> fit = Calibrate(data, options);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  EXPECT_NEAR(fit->c_e_n_per_mm2 / truth.c_e_n_per_mm2, 1.0, 2e-3);
  EXPECT_NEAR(fit->alpha_per_s / truth.alpha_per_s, 1.0, 3e-3);
  EXPECT_LT(fit->rmse_log_v, 1e-4);
  // Fitted as settled velocities the same data are far off.
  options.definition = sim::VelocityDefinition::kSettled;
  Result<CalibrationSummary> wrong = Calibrate(data, options);
  ASSERT_TRUE(wrong.ok());
  EXPECT_GT(std::abs(std::log(wrong->alpha_per_s / truth.alpha_per_s)), 0.2);
}

// PVC at 0.2-3 N, R = 2 mm: the top load is near full immersion (h/R = 1.38),
// where the transient factor moves fast with c_e (1.34 at the truth, 1.75 at
// c_e 0.42) and the held-factor refits cycle between c_e of about 0.40 and
// 0.54 instead of settling; the fit then searches with the factors computed
// at every point. Truth: the rig-loop surrogate's own velocities (the fit's
// model), so the answer must be the truth.
TEST(Calibrate, RecoversTheInitialVelocityNearFullImmersion) {
  const Truth truth{0.462, 0.296, 2.0};
  MeasuredData data;
#if defined(__SANITIZE_ADDRESS__)
  // The sanitizer build (23 s at nine levels) fits three, the top one still
  // at 3 N, where the refits cycle: 6 s.
  const std::vector<double> forces_n = {0.2, 1.0, 3.0};
#else
  const std::vector<double> forces_n = {0.2, 0.4, 0.6, 0.8, 1.0,
                                        1.5, 2.0, 2.5, 3.0};
#endif
  for (const double force_n : forces_n) {
    DescentSurrogateInput in;
    in.force_n = force_n;
    in.c_e_n_per_mm2 = truth.c_e_n_per_mm2;
    in.alpha_per_s = truth.alpha_per_s;
    in.radius_mm = truth.radius_mm;
    MeasuredRun run;
    run.force_n = force_n;
    run.velocity_mm_s = SurrogateVelocityMmS(
        in, sim::VelocityDefinition::kInitial, InitialTransientFactor(in));
    data.runs.push_back(run);
  }
  data.force_levels = static_cast<int>(forces_n.size());
  CalibrationOptions options = InitialWithoutBootstrap(truth.radius_mm);
  Result<CalibrationSummary> fit = Calibrate(data, options);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  EXPECT_NEAR(fit->c_e_n_per_mm2 / truth.c_e_n_per_mm2, 1.0, 3e-3);
  EXPECT_NEAR(fit->alpha_per_s / truth.alpha_per_s, 1.0, 3e-3);
  EXPECT_LT(fit->rmse_log_v, 1e-3);
}

TEST(Calibrate, SeparatesCeAndAlphaWhenTheLoadsReachDeepImmersion) {
  const Truth truth;
  CalibrationOptions options = SettledOptions(truth.radius_mm);
  Result<CalibrationSummary> fit =
      Calibrate(MakeData(truth, kWideLoads, 3, 0.1, 5), options);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  std::printf("wide: c_e %.4g %s alpha %.4g cond %.3g\n  %s\n",
              fit->c_e_n_per_mm2, fit->c_e_ci ? "ci" : "no ci",
              fit->alpha_per_s, fit->condition_number,
              fit->identifiability.c_str());
  EXPECT_TRUE(fit->identifiable);
  EXPECT_TRUE(Covers(fit->c_e_ci, truth.c_e_n_per_mm2));
  EXPECT_TRUE(Covers(fit->alpha_ci, truth.alpha_per_s));
  EXPECT_NE(fit->identifiability.find("determines c_e and alpha separately"),
            std::string::npos);
}

TEST(Calibrate, ReportsOnlyTheCombinationForShallowImmersion) {
  const Truth truth;
  CalibrationOptions options = SettledOptions(truth.radius_mm);
  Result<CalibrationSummary> fit =
      Calibrate(MakeData(truth, kShallowLoads, 3, 0.1, 5), options);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  std::printf("shallow: c_e %.4g alpha %.4g exponent %.4g cond %.3g\n  %s\n",
              fit->c_e_n_per_mm2, fit->alpha_per_s, fit->combination_exponent,
              fit->condition_number, fit->identifiability.c_str());
  EXPECT_FALSE(fit->identifiable);
  EXPECT_FALSE(fit->c_e_ci.has_value());
  EXPECT_FALSE(fit->alpha_ci.has_value());
  const double b = fit->combination_exponent;
  EXPECT_TRUE(Covers(fit->combination_ci,
                     truth.alpha_per_s * std::pow(truth.c_e_n_per_mm2, b)));
  EXPECT_NE(fit->identifiability.find("determines only the combination alpha "
                                      "* c_e^"),
            std::string::npos);
}

// Coverage of the 95 % profile intervals over seeds, for two designs: loads
// 0.5-1.5 of c_e R^2 with 3 replicates and 10 % noise, and the design of the
// rig-based recovery test (tests/runner/calibrate_command_test.cc): loads
// 0.7-1.45, 4 replicates, 5 % noise. A profile that does not close is the
// unbounded interval and so covers; both designs must identify c_e and alpha
// in at least 95 % of seeds, so that rule moves coverage by at most 5 %. The
// CI tier uses 60 seeds per case and 100 bootstrap replicates per fit;
// BURRLAB_SLOW_TESTS=1 runs 1000 seeds with the command's 200 replicates
// (binomial error of a coverage near 0.92: 0.9 % instead of 3.5 %).
struct Design {
  const char* name;
  std::vector<double> loads;
  int replicates;
  double cv;
};

#if !defined(__SANITIZE_ADDRESS__)
// A committed fixture of tests/analysis/model_gap/fixtures, parsed.
Result<MeasuredData> ParseFixture(const std::string& name) {
  const std::string file = "tests/analysis/model_gap/fixtures/" + name;
  return ParseMeasuredData(file, testing::ReadSourceFile(file));
}

// The initial velocity's profile RSS of log v at c_e with the point's own
// transient factors, computed from the surrogate's public velocity
// (SurrogateVelocityMmS, InitialTransientFactor), alpha in closed form and
// the factors refreshed until they settle, starting from `alpha_per_s`: an
// evaluation of the objective independent of calibrate's search.
double OwnFactorProfileRss(const MeasuredData& data, double radius_mm,
                           double c_e, double alpha_per_s) {
  const int n = static_cast<int>(data.runs.size());
  double ln_alpha = std::log(alpha_per_s);
  double rss = 0.0;
  for (int round = 0; round < 4; ++round) {
    std::vector<double> r(n);
    double mean = 0.0, last_force = 0.0, factor = 1.0;
    for (int i = 0; i < n; ++i) {
      DescentSurrogateInput in;
      in.force_n = data.runs[i].force_n;
      in.c_e_n_per_mm2 = c_e;
      in.alpha_per_s = std::exp(ln_alpha);
      in.radius_mm = radius_mm;
      if (in.force_n != last_force) {  // replicates share their level's
        factor = InitialTransientFactor(in);
        last_force = in.force_n;
      }
      in.alpha_per_s = 1.0;
      r[i] = std::log(data.runs[i].velocity_mm_s) -
             std::log(SurrogateVelocityMmS(
                 in, sim::VelocityDefinition::kInitial, factor));
      mean += r[i] / n;
    }
    ln_alpha = mean;
    rss = 0.0;
    for (double x : r) rss += (x - mean) * (x - mean);
  }
  return rss;
}

// The initial velocity's c_e interval ends where the profile with the end's
// own transient factors crosses the threshold RSS_min (1 + q / (n - 2)), not
// the profile with the fit's factors. Truth: the RSS at each end computed
// here from the surrogate's public velocity with the factors of that point
// (alpha in closed form, the factors refreshed until they settle), on the
// committed full-rig PVC fixture (discover_test.cc gives its command), where
// the fit's factors put the upper end at 0.618 N/mm^2 and the RSS there with
// its own factors is 2.2 times the threshold. Not in the sanitizer build:
// hundreds of rig-loop transients.
TEST(Calibrate, InitialIntervalEndsUseTheirOwnTransientFactors) {
  const Result<MeasuredData> data =
      ParseFixture("pvc_initial_rig_noise_only.csv");
  ASSERT_TRUE(data.ok()) << data.error().message;
  CalibrationOptions options = InitialWithoutBootstrap(2.0);
  const Result<CalibrationSummary> fit = Calibrate(*data, options);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  ASSERT_TRUE(fit->c_e_ci.has_value());
  const int n = fit->runs;
  const double threshold =
      fit->rss_log_v * (1.0 + fit->profile_quantiles[0] / (n - 2));
  const auto own_rss = [&](double c_e) {
    return OwnFactorProfileRss(*data, 2.0, c_e, fit->alpha_per_s);
  };
  std::printf("c_e %.4g [%.4g, %.4g], threshold %.5g\n", fit->c_e_n_per_mm2,
              (*fit->c_e_ci)[0], (*fit->c_e_ci)[1], threshold);
  for (const double end : *fit->c_e_ci) {
    EXPECT_NEAR(own_rss(end) / threshold, 1.0, 0.01) << "c_e " << end;
  }
  // The truth, 0.462, stays inside.
  EXPECT_LE((*fit->c_e_ci)[0], 0.462);
  EXPECT_GE((*fit->c_e_ci)[1], 0.462);
}

// The initial velocity's c_e profile can have two minima whose RSS both lie
// within the threshold: the fit lands in one, and the report names the other
// with its own part of the confidence set. The data: bone (c_e 2.145, alpha
// 0.087), R = 1 mm, loads 0.7-1.45 of c_e R^2, 4 replicates, the surrogate's
// initial velocity times exp(0.05 z), z from std::normal_distribution on
// std::mt19937_64(5014). Truth: the own-factor profile computed here
// (OwnFactorProfileRss), not calibrate's search; on it the minima lie near
// c_e 2.0 (RSS 0.0441) and 6.4 (0.0424) with a ridge near 3 (0.063), above
// the F threshold (0.056), and the truth 2.145 lies in the part around the
// minimum the fit did not land in.
TEST(Calibrate, ReportsASecondMinimumOfTheInitialVelocityProfile) {
  const Result<MeasuredData> data = ParseFixture("bone_initial_two_minima.csv");
  ASSERT_TRUE(data.ok()) << data.error().message;
  const Result<CalibrationSummary> fit =
      Calibrate(*data, InitialWithoutBootstrap(1.0));
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  ASSERT_TRUE(fit->c_e_ci.has_value());
  ASSERT_TRUE(fit->second_minimum.has_value());
  const SecondMinimum& m = *fit->second_minimum;
  const double threshold =
      fit->rss_log_v * (1.0 + fit->profile_quantiles[0] / (fit->runs - 2));
  const auto own_rss = [&](double c_e) {
    return OwnFactorProfileRss(*data, 1.0, c_e, m.alpha_per_s);
  };
  std::printf(
      "fit c_e %.4g [%.4g, %.4g]; second %.4g RSS %.5g, threshold %.5g\n",
      fit->c_e_n_per_mm2, (*fit->c_e_ci)[0], (*fit->c_e_ci)[1], m.c_e_n_per_mm2,
      m.rss_log_v, threshold);
  // A minimum of the independent profile, at the RSS reported, inside the
  // set, and a ridge above the threshold between it and the fit.
  const double at = own_rss(m.c_e_n_per_mm2);
  EXPECT_NEAR(at / m.rss_log_v, 1.0, 0.01);
  EXPECT_LT(at, threshold);
  EXPECT_GT(own_rss(0.97 * m.c_e_n_per_mm2), at);
  EXPECT_GT(own_rss(1.03 * m.c_e_n_per_mm2), at);
  EXPECT_GT(own_rss(std::sqrt(m.c_e_n_per_mm2 * fit->c_e_n_per_mm2)),
            threshold);
  // Its own part of the set ends where the profile crosses the threshold,
  // apart from the fit's, and holds the truth.
  ASSERT_TRUE(m.c_e_ci.has_value());
  for (const double end : *m.c_e_ci) {
    EXPECT_NEAR(own_rss(end) / threshold, 1.0, 0.01) << "c_e " << end;
  }
  EXPECT_LT((*m.c_e_ci)[1], (*fit->c_e_ci)[0]);
  EXPECT_LE((*m.c_e_ci)[0], 2.145);
  EXPECT_GE((*m.c_e_ci)[1], 2.145);
}
#endif  // !defined(__SANITIZE_ADDRESS__)

// Monte-Carlo coverage runs in the optimised build only (the sanitizer build
// runs the same code in the tests above).
#if !defined(__SANITIZE_ADDRESS__)
TEST(Calibrate, ProfileIntervalsCoverTheTruth) {
  const bool slow = std::getenv("BURRLAB_SLOW_TESTS") != nullptr;
  const int seeds = slow ? 1000 : 60;
  CalibrationOptions options = SettledOptions(1.0);
  // The command's 200 bootstrap replicates in the slow tier; 100 in CI.
  options.bootstrap_replicates = slow ? 200 : 100;
  const Design designs[] = {
      {"wide", {0.5, 0.7, 0.9, 1.1, 1.3, 1.5}, 3, 0.1},
      {"rig", {0.7, 0.95, 1.2, 1.45}, 4, 0.05},
  };
  // Loads are relative to c_e R^2, so a second truth needs other seeds to
  // be a second experiment.
  std::uint64_t seed_base = 1000;
  for (const Design& design : designs) {
    for (const Truth& truth :
         {Truth{2.145, 0.087, 1.0}, Truth{0.462, 0.296, 2.0}}) {
      seed_base += 100000;
      int c_e_hits = 0, alpha_hits = 0, identified = 0;
      options.radius_mm = truth.radius_mm;
      for (int seed = 1; seed <= seeds; ++seed) {
        Result<CalibrationSummary> fit =
            Calibrate(MakeData(truth, design.loads, design.replicates,
                               design.cv, seed_base + seed),
                      options);
        ASSERT_TRUE(fit.ok()) << fit.error().message;
        identified += fit->identifiable;
        c_e_hits += !fit->c_e_ci || Covers(fit->c_e_ci, truth.c_e_n_per_mm2);
        alpha_hits +=
            !fit->alpha_ci || Covers(fit->alpha_ci, truth.alpha_per_s);
      }
      const double c_e_coverage = static_cast<double>(c_e_hits) / seeds;
      const double alpha_coverage = static_cast<double>(alpha_hits) / seeds;
      std::printf(
          "%s design, c_e %.3f alpha %.3f: coverage c_e %.3f alpha "
          "%.3f (identified %d of %d)\n",
          design.name, truth.c_e_n_per_mm2, truth.alpha_per_s, c_e_coverage,
          alpha_coverage, identified, seeds);
      EXPECT_GE(identified, seeds * 95 / 100) << design.name;
      EXPECT_GE(c_e_coverage, 0.85) << design.name;
      EXPECT_LE(c_e_coverage, 0.99) << design.name;
      EXPECT_GE(alpha_coverage, 0.85) << design.name;
      EXPECT_LE(alpha_coverage, 0.99) << design.name;
    }
  }
  // Shallow immersion: only alpha * c_e^b is identified; its interval.
  int combination_hits = 0, unidentified = 0;
  const Truth truth;
  options.radius_mm = truth.radius_mm;
  for (int seed = 1; seed <= seeds; ++seed) {
    Result<CalibrationSummary> fit =
        Calibrate(MakeData(truth, kShallowLoads, 3, 0.1, 7000 + seed), options);
    ASSERT_TRUE(fit.ok()) << fit.error().message;
    unidentified += !fit->identifiable;
    combination_hits +=
        Covers(fit->combination_ci,
               truth.alpha_per_s *
                   std::pow(truth.c_e_n_per_mm2, fit->combination_exponent));
  }
  const double coverage = static_cast<double>(combination_hits) / seeds;
  std::printf(
      "shallow: coverage of the combination %.3f (not identifiable "
      "%d of %d)\n",
      coverage, unidentified, seeds);
  EXPECT_GE(coverage, 0.85);
  EXPECT_LE(coverage, 0.99);
  // Now and then the noise bends the curve enough to close the profile.
  EXPECT_GE(unidentified, seeds * 8 / 10);
}
#endif  // !defined(__SANITIZE_ADDRESS__)

}  // namespace
}  // namespace burrlab::analysis
