// The trace-gap test of the trace-only effects (load_cell_lag,
// arm_compliance): the lumped rig against closed forms and the surrogate's
// steady state, and detection on traces from the voxel rig (the truth, not
// the lumped model) with the base fit from noisy v(F), as the workflow sees
// them: CSV text through the parsers.
//
// Seeds: 6 per scenario in CI, BURRLAB_SLOW_TESTS=1 runs 40, the sanitizer
// build 1, with 2 replicates and the lumped rig at 5 ms (10 s a test with 2
// seeds, 4 replicates and 1 ms).
#include "burrlab/analysis/model_gap/trace_gap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "burrlab/analysis/model_gap/calibration.h"
#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/analysis/model_gap/discover_scenarios.h"
#include "burrlab/analysis/model_gap/synthetic_measurement.h"
#include "discover_fixtures.h"

namespace burrlab::analysis {
namespace {

using testing::BoneDesign;
using testing::kSanitized;
using testing::Slow;

int Seeds() { return kSanitized ? 1 : Slow() ? 40 : 6; }

// What a user of `sim measure --traces` has for one seed: v(F) from the
// surrogate truth with log-normal noise (trace-only effects do not change
// it), and each level's trace from the voxel rig (R/12, 5 ms) with `effects`
// hidden, through the CSV formats and their parsers.
struct Scenario {
  MeasuredData measured;
  std::vector<TraceRun> runs;
  TraceGapOptions options;
};

Scenario MakeScenario(const sim::Effects& effects, std::uint64_t seed) {
#if defined(__SANITIZE_ADDRESS__)
  ScenarioDesign d = BoneDesign();
  d.replicates = 2;  // half the traces to fit
#else
  const ScenarioDesign d = BoneDesign();
#endif
  const std::vector<double> truth =
      TruthVelocitiesMmS(d, sim::Effects{}).value();
  Scenario s;
  const std::string csv = ScenarioCsv(d, truth, {}, seed);
  s.measured = ParseMeasuredData("m.csv", csv).value();
  CalibrationOptions calibration;
  calibration.radius_mm = d.radius_mm;
  calibration.definition = ScenarioDesign::kDefinition;
  calibration.bootstrap_replicates = 0;
  const CalibrationSummary fit = Calibrate(s.measured, calibration).value();
  SyntheticMeasurementOptions rig;
  rig.material = d.material;
  rig.effects = effects;
  rig.forces_n = d.ForcesN();
  rig.radius_mm = d.radius_mm;
  rig.seed = seed;  // the traces' sensor noise (default size)
  SyntheticMeasurement m;
  for (std::size_t level = 0; level < rig.forces_n.size(); ++level) {
    m.level_traces.push_back(
        RigTransientTrace(rig, rig.forces_n[level], seed * 1000 + level, 4.0)
            .value());
  }
  for (const MeasuredRun& r : s.measured.runs) {
    m.runs.push_back({std::stoi(r.run), r.force_n, r.velocity_mm_s, 0.0});
  }
  const std::string traces_csv = FormatTraceCsv(m, rig);
  const TraceData traces = ParseTraceData("t.csv", traces_csv).value();
  EXPECT_TRUE(MatchTracesToRuns(traces, s.measured, "t.csv", traces_csv).ok());
  s.runs = PairTraces(traces, s.measured);
  s.options.c_e_n_per_mm2 = fit.c_e_n_per_mm2;
  s.options.alpha_per_s = fit.alpha_per_s;
  s.options.radius_mm = d.radius_mm;
#if defined(__SANITIZE_ADDRESS__)
  s.options.rig.dt_s = 5e-3;  // the voxel rig's own period here
#endif
  return s;
}

struct Rates {
  int seeds = 0;
  int named_expected = 0;    // the expected effect named
  int named_any = 0;         // any trace effect named
  double mean_fitted = 0.0;  // the expected effect's fitted value, mean
};

// Seeds 101, 102, ...: each a fresh v(F) noise draw (hence base fit) and
// fresh erosion streams of the rig.
Rates RunSeeds(const sim::Effects& effects, const std::string& expected,
               const char* label) {
  Rates rates;
  for (int seed = 1; seed <= Seeds(); ++seed) {
    const Scenario s = MakeScenario(effects, 100 + seed);
    const TraceGapResult r = TestTraceEffects(s.runs, s.options).value();
    ++rates.seeds;
    rates.named_any += !r.named.empty();
    rates.named_expected += !expected.empty() && r.named == expected;
    for (const TraceEffectTest& e : r.effects) {
      if (e.id == expected) rates.mean_fitted += e.value / Seeds();
    }
  }
  std::printf(
      "%-26s %2d seeds: expected named %2d, any named %2d, mean fit %.4g\n",
      label, rates.seeds, rates.named_expected, rates.named_any,
      rates.mean_fitted);
  return rates;
}

// A run that starts 0.2 mm above the surface (as the rig does) and is
// sampled every 0.1 s for `duration_s`.
RunTrace Timeline(double duration_s) {
  RunTrace t;
  t.run.push_back('1');
  for (int k = 0; k * 0.1 <= duration_s; ++k) {
    t.t_s.push_back(k * 0.1);
    t.force_n.push_back(0.0);
    t.depth_mm.push_back(-0.2);
  }
  return t;
}

TraceGapOptions BoneOptions() {
  TraceGapOptions o;
  o.c_e_n_per_mm2 = 2.145;
  o.alpha_per_s = 0.087;
  o.radius_mm = 1.0;
  return o;
}

// Quasi-steady erosion at the surrogate's rate: once settled, the lumped rig
// holds the force and cuts at SteadyVelocityMmS, so it adds nothing to the
// steady state the v(F) fit uses.
TEST(LumpedRig, SettlesOnTheSurrogatesSteadyState) {
  const TraceGapOptions o = BoneOptions();
  for (double force_n : {1.0, 2.5}) {
    const RunTrace t = Timeline(60.0);
    const LumpedTrace m = SimulateLumpedRig(t, force_n, o, {}, 60.0);
    ASSERT_EQ(m.t_s.size(), t.t_s.size());
    const std::size_t end = m.t_s.size() - 1, mid = end - 100;
    EXPECT_NEAR(m.force_n[end], force_n, 1e-3 * force_n);
    DescentSurrogateInput in;
    in.force_n = force_n;
    in.c_e_n_per_mm2 = o.c_e_n_per_mm2;
    in.alpha_per_s = o.alpha_per_s;
    in.radius_mm = o.radius_mm;
    const double slope_mm_s =
        (m.depth_mm[end] - m.depth_mm[mid]) / (m.t_s[end] - m.t_s[mid]);
    EXPECT_NEAR(slope_mm_s / SteadyVelocityMmS(in), 1.0, 2e-3) << force_n;
    // The immersion below the eroded surface is Hertz's at F (eq. 7.3).
    const double h_mm = m.burr_depth_mm[end] - m.surface_mm[end];
    EXPECT_NEAR(h_mm, std::pow(force_n / o.c_e_n_per_mm2, 2.0 / 3.0), 1e-3);
  }
}

TEST(LumpedRig, ArmComplianceShiftsTheArmByForceTimesCompliance) {
  const TraceGapOptions o = BoneOptions();
  const RunTrace t = Timeline(30.0);
  sim::Effects spring;
  spring.arm_compliance_mm_per_n = 0.2;
  const LumpedTrace m = SimulateLumpedRig(t, 2.0, o, spring, 30.0);
  const std::size_t end = m.t_s.size() - 1;
  EXPECT_NEAR(m.depth_mm[end] - m.burr_depth_mm[end], 0.2 * 2.0, 1e-3);
  // The spring slows the loading: later to reach 90 % of the force.
  const LumpedTrace rigid = SimulateLumpedRig(t, 2.0, o, {}, 30.0);
  const auto rise = [](const LumpedTrace& x) {
    for (std::size_t k = 0; k < x.t_s.size(); ++k) {
      if (x.force_n[k] > 1.8) return x.t_s[k];
    }
    return -1.0;
  };
  EXPECT_GT(rise(m), rise(rigid));
}

TEST(LumpedRig, LoadCellLagMakesTheForceOvershoot) {
  const TraceGapOptions o = BoneOptions();
  const RunTrace t = Timeline(5.0);
  sim::Effects lag;
  lag.load_cell_lag_s = 0.1;
  const auto peak = [&](const sim::Effects& fx) {
    const LumpedTrace m = SimulateLumpedRig(t, 2.0, o, fx, 5.0);
    return *std::max_element(m.force_n.begin(), m.force_n.end());
  };
  // The approach at full speed overshoots a little anyway; the controller
  // that sees the force 0.1 s late drives on much further.
  EXPECT_GT(peak(lag), peak({}) + 0.25 * 2.0) << peak({});
}

TEST(TraceGap, NoEffectNamesNothing) {
  const Rates rates = RunSeeds(sim::Effects{}, "", "no effect");
  EXPECT_LE(rates.named_any, rates.seeds / 10) << rates.seeds;
}

TEST(TraceGap, NamesAVisibleLoadCellLag) {
  sim::Effects lag;
  lag.load_cell_lag_s = 0.05;
  const Rates rates = RunSeeds(lag, "load_cell_lag", "load_cell_lag 0.05 s");
  EXPECT_GE(rates.named_expected, rates.seeds - rates.seeds / 10);
  EXPECT_NEAR(rates.mean_fitted, 0.05, 0.01);
}

TEST(TraceGap, NamesAVisibleArmCompliance) {
  sim::Effects spring;
  spring.arm_compliance_mm_per_n = 0.1;
  const Rates rates =
      RunSeeds(spring, "arm_compliance", "arm_compliance 0.1 mm/N");
  EXPECT_GE(rates.named_expected, rates.seeds - rates.seeds / 10);
  // c_e absorbs part of the spring (both deepen the indentation).
  EXPECT_NEAR(rates.mean_fitted, 0.1, 0.03);
}

// Discover with and without the traces of a hidden lag: v(F) alone never
// names a trace-only effect (the surrogate truth is the same with and
// without it, and the attribution skips them); with the traces the lag is
// named through AddTraceGap.
TEST(TraceGap, DiscoverNamesTheLagOnlyWithTraces) {
  sim::Effects lag;
  lag.load_cell_lag_s = 0.05;
  int named_without = 0, named_with = 0;
  const int seeds = kSanitized ? 1 : std::max(2, Seeds() / 2);
  for (int seed = 1; seed <= seeds; ++seed) {
    const Scenario s = MakeScenario(lag, 200 + seed);
    DiscoverOptions options;
    options.radius_mm = s.options.radius_mm;
    options.definition = ScenarioDesign::kDefinition;
    const DiscoverReport without = Discover(s.measured, options).value();
    EXPECT_FALSE(without.trace_gap.has_value());
    for (const auto& round : without.rounds) {
      for (const EffectAttribution& e : round) {
        EXPECT_FALSE(sim::FindEffect(e.id)->trace_only) << e.id;
      }
    }
    for (const std::string& id : without.effects) {
      named_without += sim::FindEffect(id)->trace_only;
    }
    TraceData traces;
    for (const TraceRun& run : s.runs) traces.runs.push_back(run.trace);
    options.traces = traces;
    const DiscoverReport with = Discover(s.measured, options).value();
    ASSERT_TRUE(with.trace_gap.has_value());
    named_with +=
        !with.effects.empty() && with.effects.back() == "load_cell_lag";
    if (VerdictName(without.verdict) == "none") {
      EXPECT_EQ(VerdictName(with.verdict), "named");
      EXPECT_EQ(with.effects, std::vector<std::string>{"load_cell_lag"});
      EXPECT_EQ(with.augmented.effect_values.size(), 1u);
    }
  }
  std::printf("discover, lag 0.05 s: named without traces %d/%d, with %d/%d\n",
              named_without, seeds, named_with, seeds);
  EXPECT_EQ(named_without, 0);
  EXPECT_EQ(named_with, seeds);
}

TEST(TraceGap, RefusesBadOptionsAndTracesWithoutContact) {
  TraceGapOptions o = BoneOptions();
  o.c_e_n_per_mm2 = -1.0;
  TraceRun run{Timeline(1.0), 2.0};
  EXPECT_EQ(TestTraceEffects({run}, o).error().message,
            "c_e_n_per_mm2 must be a positive finite number, got -1");
  o = BoneOptions();
  o.test_level = 1.5;
  EXPECT_EQ(TestTraceEffects({run}, o).error().message,
            "test_level must lie in (0, 1), got 1.5");
  EXPECT_EQ(TestTraceEffects({}, BoneOptions()).error().message,
            "the trace-gap test needs at least one trace");
  EXPECT_EQ(TestTraceEffects({run}, BoneOptions()).error().message,
            "the trace of run 1 never reaches 5 % of its force 2 N: no "
            "contact");
}

}  // namespace
}  // namespace burrlab::analysis
