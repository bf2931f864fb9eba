// The independent truth's data (measured_csv.h): the CSV reads back as a
// user's file would, the noise is log-normal with the design's CV and
// deterministic per seed, and truths on one seed share their noise.
#include "independent_truth/measured_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "burrlab/analysis/model_gap/measured_data.h"

namespace burrlab::analysis::independent_truth {
namespace {

TEST(IndependentTruthCsv, ReadsBackAsMeasuredData) {
  const Design d = BoneDesign();
  const std::vector<double> truth =
      NoiseFreeVelocitiesMmS(d, TruthFor(d, Mechanism::kNone, 0.0));
  const std::string csv = MeasuredCsv(d, truth, 7);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "run,material,burr_radius_mm,force_n,velocity_mm_s,velocity_"
            "definition");
  const Result<MeasuredData> data = ParseMeasuredData("truth.csv", csv);
  ASSERT_TRUE(data.ok()) << data.error().message;
  EXPECT_EQ(data->runs.size(), 24u);
  EXPECT_EQ(data->force_levels, 6);
  EXPECT_EQ(data->burr_radius_mm, 1.0);
  ASSERT_TRUE(data->velocity_definition.has_value());
  EXPECT_EQ(*data->velocity_definition, sim::VelocityDefinition::kSettled);
  const std::vector<double> forces = d.ForcesN();
  for (std::size_t i = 0; i < data->runs.size(); ++i) {
    const MeasuredRun& run = data->runs[i];
    EXPECT_EQ(run.force_n, forces[i / 4]);  // written to read back exactly
    EXPECT_EQ(run.material, "human_temporal_bone");
    EXPECT_EQ(run.run, std::to_string(i + 1));
    // CV 10 %: within 5 sigma of the truth.
    EXPECT_LT(std::abs(std::log(run.velocity_mm_s / truth[i / 4])),
              5.0 * d.SigmaLogV());
  }
}

TEST(IndependentTruthCsv, NoiseIsDeterministicPerSeedAndSharedByTruths) {
  const Design d = PvcDesign();
  const std::vector<double> base =
      NoiseFreeVelocitiesMmS(d, TruthFor(d, Mechanism::kNone, 0.0));
  std::vector<double> other = base;
  for (std::size_t k = 0; k < other.size(); ++k)
    other[k] *= 1.0 + 0.1 * static_cast<double>(k);
  EXPECT_EQ(MeasuredCsv(d, base, 3), MeasuredCsv(d, base, 3));
  EXPECT_NE(MeasuredCsv(d, base, 3), MeasuredCsv(d, base, 4));
  const std::vector<MeasuredRunValue> a = DrawRuns(d, base, 3);
  const std::vector<MeasuredRunValue> b = DrawRuns(d, other, 3);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(b[i].velocity_mm_s / a[i].velocity_mm_s,
                other[i / 4] / base[i / 4], 1e-12);
  }
  // No noise: the truth itself.
  Design quiet = d;
  quiet.noise_cv = 0.0;
  for (const MeasuredRunValue& r : DrawRuns(quiet, base, 3)) {
    EXPECT_EQ(r.velocity_mm_s, base[static_cast<std::size_t>(r.run - 1) / 4]);
  }
}

// A level where the burr does not cut is left out; the other levels keep the
// noise they have on the same seed.
TEST(IndependentTruthCsv, LeavesOutLevelsThatDoNotCut) {
  const Design d = BoneDesign();
  std::vector<double> truth(6, 0.01);
  const std::vector<MeasuredRunValue> all = DrawRuns(d, truth, 11);
  truth[1] = 0.0;
  const std::vector<MeasuredRunValue> some = DrawRuns(d, truth, 11);
  ASSERT_EQ(some.size(), 20u);
  EXPECT_EQ(some[4].run, 5);
  EXPECT_EQ(some[4].force_n, all[8].force_n);
  EXPECT_EQ(some[4].velocity_mm_s, all[8].velocity_mm_s);
}

// v = truth exp(sigma z): ln v has mean ln truth and SD sigma =
// sqrt(ln(1 + cv^2)), v itself has CV cv.
TEST(IndependentTruthCsv, NoiseIsLogNormalWithTheDesignsCv) {
  for (double cv : {0.05, 0.1}) {
    Design d = BoneDesign();
    d.noise_cv = cv;
    d.loads = {1.0};
    d.replicates = 20000;
    const std::vector<MeasuredRunValue> runs = DrawRuns(d, {2.0}, 5);
    double sum = 0.0, sum2 = 0.0, sum_v = 0.0, sum_v2 = 0.0;
    for (const MeasuredRunValue& r : runs) {
      const double e = std::log(r.velocity_mm_s / 2.0);
      sum += e;
      sum2 += e * e;
      sum_v += r.velocity_mm_s;
      sum_v2 += r.velocity_mm_s * r.velocity_mm_s;
    }
    const double n = static_cast<double>(runs.size());
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    const double sigma = std::sqrt(std::log1p(cv * cv));
    EXPECT_NEAR(mean, 0.0, 4.0 * sigma / std::sqrt(n)) << cv;
    EXPECT_NEAR(sd / sigma, 1.0, 0.03) << cv;
    const double mean_v = sum_v / n;
    const double cv_v = std::sqrt(sum_v2 / n - mean_v * mean_v) / mean_v;
    EXPECT_NEAR(cv_v / cv, 1.0, 0.03) << cv;
  }
}

}  // namespace
}  // namespace burrlab::analysis::independent_truth
