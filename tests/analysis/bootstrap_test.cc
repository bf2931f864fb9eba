// Percentile and BCa limits on small hand-checkable samples (psignifit's
// own replicates are in psychometric_test.cc).
#include "burrlab/analysis/bootstrap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace burrlab::analysis {
namespace {

TEST(BootstrapQuantile, InterpolatesAtLevelTimesRPlusOne) {
  const std::vector<double> sorted = {1, 2, 3, 4, 5, 6, 7, 8, 9};  // R = 9
  EXPECT_DOUBLE_EQ(BootstrapQuantile(sorted, 0.1), 1.0);           // position 1
  EXPECT_DOUBLE_EQ(BootstrapQuantile(sorted, 0.5), 5.0);           // position 5
  EXPECT_DOUBLE_EQ(BootstrapQuantile(sorted, 0.25), 2.5);    // position 2.5
  EXPECT_DOUBLE_EQ(BootstrapQuantile(sorted, 0.9), 9.0);     // position 9
  EXPECT_TRUE(std::isnan(BootstrapQuantile(sorted, 0.05)));  // position 0.5
  EXPECT_TRUE(std::isnan(BootstrapQuantile(sorted, 0.95)));  // position 9.5
}

TEST(CumulativeProbabilityEstimate, CountsStrictlySmallerOverRPlusOne) {
  const std::vector<double> samples = {3, 1, 2, 2, 5};
  EXPECT_DOUBLE_EQ(CumulativeProbabilityEstimate(samples, 2.0), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(CumulativeProbabilityEstimate(samples, 2.5), 3.0 / 6.0);
}

TEST(BcaAcceleration, IsMeanCubeOverSixSdCubed) {
  const std::vector<double> s = {1.0, -2.0, 0.5, 3.0};
  const double mean = 2.5 / 4.0;
  double squares = 0.0;
  for (double v : s) squares += (v - mean) * (v - mean);
  const double variance = squares / 3.0;
  const double cubes = (1.0 - 8.0 + 0.125 + 27.0) / 4.0;
  EXPECT_NEAR(BcaAcceleration(s), cubes / (6.0 * std::pow(variance, 1.5)),
              1e-15);
  EXPECT_EQ(BcaAcceleration(std::vector<double>{2.0, 2.0, 2.0}), 0.0);
}

TEST(BcaLimits, ReduceToPercentileLimitsWithoutBiasOrAcceleration) {
  std::vector<double> sorted;
  for (int i = 1; i <= 1999; ++i) sorted.push_back(i * 0.01);
  const std::vector<double> conf = {0.025, 0.159, 0.841, 0.975};
  const std::vector<double> bca = BcaLimits(sorted, 0.0, 0.0, conf);
  const std::vector<double> percentile = PercentileLimits(sorted, conf);
  for (std::size_t k = 0; k < conf.size(); ++k) {
    EXPECT_NEAR(bca[k], percentile[k], 1e-12);
  }
  EXPECT_DOUBLE_EQ(percentile[0], 0.5);  // position 50
  // Positive bias moves both limits up; a level beyond the sample is NaN.
  EXPECT_GT(BcaLimits(sorted, 0.3, 0.0, conf)[0], percentile[0]);
  EXPECT_TRUE(std::isnan(BcaLimits(sorted, 3.0, 0.0, conf)[3]));
  EXPECT_TRUE(std::isnan(BcaLevel(0.0, 1.0, 0.975)));  // 1 - a z <= 0
}

TEST(ComputeBootstrapLimits, PutsNonFiniteReplicatesAtTheTop) {
  std::vector<double> replicates;
  for (int i = 1; i <= 999; ++i) replicates.push_back(i);
  replicates[10] = std::nan("");
  const std::vector<double> conf = {0.5, 0.999};
  const BootstrapLimits limits =
      ComputeBootstrapLimits(replicates, {}, 500.0, conf);
  EXPECT_DOUBLE_EQ(limits.percentile[0], 501.0);
  EXPECT_TRUE(std::isinf(limits.percentile[1]));
  EXPECT_TRUE(std::isnan(limits.bca[0]));  // no scores, no BCa
}

}  // namespace
}  // namespace burrlab::analysis
