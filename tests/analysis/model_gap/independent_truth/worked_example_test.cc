// The data of the README's worked example (README.md, "Worked example — PVC
// whose motor droops") are this folder's output: PVC K70 at R = 1 mm, seven
// loads from 0.3 to 2.5 of c_e R^2 (up to near full immersion), 6 replicates,
// CV 10 %, a motor whose removal rate droops smoothly towards
// Q_max = 0.18 mm^3/s as Q = Q_u / (1 + (Q_u/Q_max)^2)^{1/2} (a shape the
// effect library does not have: its droop has the power 1.5), noise seed 1.
// The committed file is regenerated here and compared value by value. With
// BURRLAB_WRITE_WORKED_EXAMPLE=FILE the file is written instead:
//   BURRLAB_WRITE_WORKED_EXAMPLE=tests/analysis/model_gap/independent_truth/pvc_power_droop.csv
//   build/release/tests/analysis/model_gap/independent_truth/independent_truth_tests
//   --gtest_filter=IndependentTruthWorkedExample.*
// (one command line).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "burrlab/analysis/model_gap/measured_data.h"
#include "discover_fixtures.h"
#include "independent_truth/measured_csv.h"

namespace burrlab::analysis::independent_truth {
namespace {

constexpr double kMaxRemovalMm3PerS = 0.18;
constexpr std::uint64_t kSeed = 1;

std::string WorkedExampleCsv() {
  Design d = PvcDesign();
  d.loads = {0.3, 0.5, 0.9, 1.3, 1.7, 2.1, 2.5};
  d.replicates = 6;
  d.noise_cv = 0.1;
  const Truth truth =
      TruthFor(d, Mechanism::kPowerDroop, 1.0 / kMaxRemovalMm3PerS);
  return MeasuredCsv(d, NoiseFreeVelocitiesMmS(d, truth), kSeed);
}

TEST(IndependentTruthWorkedExample, TheCommittedDataAreTheGeneratorsOutput) {
  const std::string fresh = WorkedExampleCsv();
  if (const char* path = std::getenv("BURRLAB_WRITE_WORKED_EXAMPLE")) {
    std::ofstream(path, std::ios::binary) << fresh;
    GTEST_SKIP() << "wrote " << path;
  }
  const std::string committed = testing::ReadSourceFile(
      "tests/analysis/model_gap/independent_truth/pvc_power_droop.csv");
  ASSERT_FALSE(committed.empty());
  const Result<MeasuredData> a = ParseMeasuredData("committed", committed);
  const Result<MeasuredData> b = ParseMeasuredData("fresh", fresh);
  ASSERT_TRUE(a.ok()) << a.error().message;
  ASSERT_TRUE(b.ok()) << b.error().message;
  ASSERT_EQ(a->runs.size(), 42u);
  ASSERT_EQ(a->runs.size(), b->runs.size());
  for (std::size_t i = 0; i < a->runs.size(); ++i) {
    EXPECT_EQ(a->runs[i].run, b->runs[i].run);
    EXPECT_EQ(a->runs[i].material, "pvc_k70");
    EXPECT_EQ(a->runs[i].force_n, b->runs[i].force_n) << i;
    // Written to 10 significant digits; the last may differ with the libm.
    EXPECT_NEAR(a->runs[i].velocity_mm_s / b->runs[i].velocity_mm_s, 1.0, 1e-8)
        << i;
  }
  EXPECT_EQ(a->velocity_definition, sim::VelocityDefinition::kSettled);
}

}  // namespace
}  // namespace burrlab::analysis::independent_truth
