// What Discover answers on noise-only data from the full rig: the initial
// velocity of `burrlab sim measure` (the voxel simulator, not the surrogate
// Discover fits) at nine loads per material over the realistic ranges (bone
// and Pettigrew 0.5-5 N, PVC 0.2-3 N, R = 2 mm), three replicates per load
// drawn with log-normal noise, nothing hidden. Truth kind: the full rig,
// another discretisation of the physics the surrogate integrates.
//
// The rig's velocities are committed fixtures (a run costs up to minutes at
// the lightest loads), rig_initial_MATERIAL.csv in ../fixtures, written by
//   burrlab sim measure --material MATERIAL --forces LOADS --replicates 1
//     --noise-cv 0 --radius-mm 2 --velocity-definition initial --seed 1
// with LOADS 0.5,0.75,1,1.5,2,2.5,3,4,5 (bone, Pettigrew) and
// 0.2,0.4,0.6,0.8,1,1.5,2,2.5,3 (PVC), on the rig's default voxels and ell
// (sim::RigVoxelsPerRadius, sim::RigEllOverR). The regular tier checks them
// against the surrogate. The table (IndependentTruth.NoiseOnlyOnTheRigTable)
// runs only with BURRLAB_SLOW_TESTS set: 40 seeds x 3 materials x 2 noise
// levels x 2 truths, 400 s wall on 2 cores. Knobs: BURRLAB_TRUTH_SEEDS
// (default 40), BURRLAB_TRUTH_JOBS (threads sharing the seeds),
// BURRLAB_TRUTH_FILTER (only the materials whose name contains it),
// BURRLAB_TRUTH_MISSES (print each seed that is not `none`).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "burrlab/analysis/model_gap/calibration.h"
#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/analysis/model_gap/measured_data.h"
#include "discover_fixtures.h"
#include "independent_truth/measured_csv.h"

namespace burrlab::analysis::independent_truth {
namespace {

struct RigMaterial {
  const char* name;
  double c_e_n_per_mm2;  // the built-in material (dissertation §8.7)
  double alpha_per_s;
  const char* fixture;
};

constexpr RigMaterial kRigMaterials[] = {
    {"human_temporal_bone", 2.145, 0.087,
     "tests/analysis/model_gap/fixtures/rig_initial_human_temporal_bone.csv"},
    {"pettigrew_temporal_bone", 1.504, 0.116,
     "tests/analysis/model_gap/fixtures/"
     "rig_initial_pettigrew_temporal_bone.csv"},
    {"pvc_k70", 0.462, 0.296,
     "tests/analysis/model_gap/fixtures/rig_initial_pvc_k70.csv"},
};
constexpr double kRigRadiusMm = 2.0;

// The rig's noise-free velocity at each force of the fixture, in file order.
MeasuredData RigData(const RigMaterial& m) {
  const std::string text = testing::ReadSourceFile(m.fixture);
  EXPECT_FALSE(text.empty()) << m.fixture;
  Result<MeasuredData> data = ParseMeasuredData(m.fixture, text);
  EXPECT_TRUE(data.ok()) << data.error().message;
  return data.ok() ? std::move(*data) : MeasuredData{};
}

// The design that redraws the fixture's loads with noise.
Design RigDesign(const RigMaterial& m, const MeasuredData& rig,
                 double noise_cv) {
  Design d;
  d.material_name = m.name;
  d.c_e_n_per_mm2 = m.c_e_n_per_mm2;
  d.alpha_per_s = m.alpha_per_s;
  d.radius_mm = kRigRadiusMm;
  d.loads.clear();
  for (const MeasuredRun& r : rig.runs) {
    d.loads.push_back(r.force_n /
                      (m.c_e_n_per_mm2 * kRigRadiusMm * kRigRadiusMm));
  }
  d.replicates = 3;
  d.noise_cv = noise_cv;
  d.velocity_definition = "initial";
  return d;
}

double SurrogateOverRig(const RigMaterial& m, const MeasuredRun& r) {
  DescentSurrogateInput in;
  in.force_n = r.force_n;
  in.c_e_n_per_mm2 = m.c_e_n_per_mm2;
  in.alpha_per_s = m.alpha_per_s;
  in.radius_mm = kRigRadiusMm;
  return SurrogateVelocityMmS(in, sim::VelocityDefinition::kInitial,
                              InitialTransientFactor(in)) /
         r.velocity_mm_s;
}

// The fixtures are what the null table stands on: nine loads of the rig's
// initial velocity per material, each within 3.5 % of the surrogate (the
// largest parts at the lightest loads, where the rig's voxels and ell are
// coarse against the skin the burr cuts; analysis/README.md's table).
TEST(IndependentTruthRig, FixturesFollowTheInitialSurrogate) {
  for (const RigMaterial& m : kRigMaterials) {
    const MeasuredData rig = RigData(m);
    ASSERT_EQ(rig.runs.size(), 9u) << m.fixture;
    ASSERT_TRUE(rig.velocity_definition.has_value());
    EXPECT_EQ(*rig.velocity_definition, sim::VelocityDefinition::kInitial);
    for (const MeasuredRun& r : rig.runs) {
      EXPECT_EQ(r.material, m.name);
      EXPECT_NEAR(SurrogateOverRig(m, r), 1.0, 0.035)
          << m.name << " " << r.force_n << " N";
    }
  }
}

// Near full immersion the base fit reaches the least-squares minimum. PVC
// 0.2-3 N, three replicates, 10 % noise around the surrogate itself (noise
// seed 52): the search with each point's own transient factors, started
// where the held-factor refits cycled, stopped on a nearly flat valley at
// c_e 0.908, alpha 1.07 with an RSS of 0.494 against 0.302 at the
// parameters that made the data, and Discover then named an effect set.
// Truth kind: the fitted model itself, checked by a property no least-
// squares fit can break (its RSS is at most the RSS at the data's own
// parameters) and the parameters near the truth.
TEST(IndependentTruthRig, BaseFitNearFullImmersionReachesTheMinimum) {
  if (analysis::testing::kSanitized) {
    // About 15 CPU-s here and several times that under the sanitizers,
    // where Calibrate.RecoversTheInitialVelocityNearFullImmersion runs the
    // same search (the shared FitWithOwnFactors).
    GTEST_SKIP() << "the optimised build checks it";
  }
  const RigMaterial& m = kRigMaterials[2];
  ASSERT_EQ(std::string(m.name), "pvc_k70");
  const MeasuredData rig = RigData(m);
  std::vector<double> surrogate_mm_s;
  for (const MeasuredRun& r : rig.runs) {
    surrogate_mm_s.push_back(r.velocity_mm_s * SurrogateOverRig(m, r));
  }
  const Design d = RigDesign(m, rig, 0.10);
  const Result<MeasuredData> data =
      ParseMeasuredData("seed-52.csv", MeasuredCsv(d, surrogate_mm_s, 52));
  ASSERT_TRUE(data.ok()) << data.error().message;
  double rss_at_truth = 0.0;
  for (std::size_t i = 0; i < data->runs.size(); ++i) {
    rss_at_truth += std::pow(
        std::log(data->runs[i].velocity_mm_s / surrogate_mm_s[i / 3]), 2);
  }
  EXPECT_NEAR(rss_at_truth, 0.302, 0.001);

  CalibrationOptions calibration;
  calibration.radius_mm = kRigRadiusMm;
  calibration.definition = sim::VelocityDefinition::kInitial;
  calibration.bootstrap_replicates = 0;
  const Result<CalibrationSummary> fit = Calibrate(*data, calibration);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  EXPECT_LE(fit->rss_log_v, rss_at_truth);
  EXPECT_NEAR(fit->c_e_n_per_mm2, m.c_e_n_per_mm2, 0.1 * m.c_e_n_per_mm2);
  EXPECT_NEAR(fit->alpha_per_s, m.alpha_per_s, 0.15 * m.alpha_per_s);

  DiscoverOptions options;
  options.radius_mm = kRigRadiusMm;
  options.definition = sim::VelocityDefinition::kInitial;
  const Result<DiscoverReport> report = Discover(*data, options);
  ASSERT_TRUE(report.ok()) << report.error().message;
  EXPECT_LE(report->baseline.rss_log_v, rss_at_truth);
  EXPECT_NEAR(report->baseline.c_e_n_per_mm2, m.c_e_n_per_mm2,
              0.1 * m.c_e_n_per_mm2);
  EXPECT_EQ(VerdictName(report->verdict), "none") << report->summary;
}

// The verdicts of `seeds` noise draws around `truth` (noise-free velocities at
// the fixture's forces), by verdict.
std::map<std::string, int> CountVerdicts(const RigMaterial& m, const Design& d,
                                         const std::vector<double>& truth,
                                         const char* truth_name, int seeds,
                                         int jobs, bool misses) {
  std::vector<std::string> verdicts(static_cast<std::size_t>(seeds));
  std::vector<std::string> summaries(verdicts.size());
  std::atomic<int> next{0};
  const auto work = [&] {
    for (int k = next++; k < seeds; k = next++) {
      const std::uint64_t seed = static_cast<std::uint64_t>(k) + 1;
      const Result<MeasuredData> data = ParseMeasuredData(
          fmt::format("seed-{}.csv", seed), MeasuredCsv(d, truth, seed));
      DiscoverOptions options;
      options.radius_mm = kRigRadiusMm;
      options.definition = sim::VelocityDefinition::kInitial;
      sim::Material reference;
      reference.c_e_n_per_mm2 = m.c_e_n_per_mm2;
      reference.alpha_per_s = m.alpha_per_s;
      options.reference = reference;
      const Result<DiscoverReport> report =
          data.ok() ? Discover(*data, options)
                    : Result<DiscoverReport>(data.error());
      const std::size_t slot = static_cast<std::size_t>(k);
      verdicts[slot] =
          report.ok() ? std::string(VerdictName(report->verdict)) : "error";
      summaries[slot] = report.ok() ? report->summary : report.error().message;
    }
  };
  std::vector<std::thread> workers;
  for (int j = 1; j < std::min(jobs, seeds); ++j) workers.emplace_back(work);
  work();
  for (std::thread& t : workers) t.join();
  std::map<std::string, int> count;
  for (int k = 0; k < seeds; ++k) {
    const std::size_t slot = static_cast<std::size_t>(k);
    EXPECT_NE(verdicts[slot], "error")
        << m.name << " seed " << k + 1 << ": " << summaries[slot];
    ++count[verdicts[slot]];
    if (misses && verdicts[slot] != "none") {
      std::fprintf(stderr, "  %s, %s, CV %g, seed %d (%s): %s\n", m.name,
                   truth_name, d.noise_cv, k + 1, verdicts[slot].c_str(),
                   summaries[slot].c_str());
    }
  }
  return count;
}

// Each cell twice: around the rig's velocities, and, as the control, around
// the surrogate's at the same forces (the model Discover fits, so every
// report that is not `none` there is the test's own false-positive rate on
// this design, not the rig's distance from the surrogate). The same noise
// seeds for both truths and every material.
TEST(IndependentTruth, NoiseOnlyOnTheRigTable) {
  if (!analysis::testing::Slow()) {
    GTEST_SKIP() << "set BURRLAB_SLOW_TESTS=1 (about 4 CPU-minutes a cell)";
  }
  const char* seeds_text = std::getenv("BURRLAB_TRUTH_SEEDS");
  const char* jobs_text = std::getenv("BURRLAB_TRUTH_JOBS");
  const int seeds = seeds_text ? std::max(1, std::atoi(seeds_text)) : 40;
  const int jobs = jobs_text ? std::max(1, std::atoi(jobs_text)) : 1;
  const bool misses = std::getenv("BURRLAB_TRUTH_MISSES") != nullptr;
  const char* filter = std::getenv("BURRLAB_TRUTH_FILTER");
  std::string table = fmt::format(
      "R = 2 mm, 9 loads, 3 replicates, noise seeds 1-{} per cell, Discover "
      "with the material as reference; `none` / named or ambiguous / "
      "unexplained / absorbed\n\n"
      "| material | CV | the full rig (fixtures) | the surrogate (control) "
      "|\n|---|---|---|---|\n",
      seeds);
  const auto cell = [seeds](std::map<std::string, int> c) {
    return fmt::format("{}/{} · {} · {} · {}", c["none"], seeds,
                       c["named"] + c["ambiguous"], c["unexplained"],
                       c["absorbed"]);
  };
  for (const RigMaterial& m : kRigMaterials) {
    if (filter != nullptr &&
        std::string(m.name).find(filter) == std::string::npos) {
      continue;
    }
    const MeasuredData rig = RigData(m);
    std::vector<double> rig_mm_s, surrogate_mm_s;
    for (const MeasuredRun& r : rig.runs) {
      rig_mm_s.push_back(r.velocity_mm_s);
      surrogate_mm_s.push_back(r.velocity_mm_s * SurrogateOverRig(m, r));
    }
    for (double cv : {0.05, 0.10}) {
      const Design d = RigDesign(m, rig, cv);
      const std::string row = fmt::format(
          "| {} | {:g} % | {} | {} |\n", m.name, 100 * cv,
          cell(CountVerdicts(m, d, rig_mm_s, "rig", seeds, jobs, misses)),
          cell(CountVerdicts(m, d, surrogate_mm_s, "surrogate", seeds, jobs,
                             misses)));
      std::fprintf(stderr, "%s", row.c_str());
      table += row;
    }
  }
  std::printf("\n%s\n", table.c_str());
}

}  // namespace
}  // namespace burrlab::analysis::independent_truth
