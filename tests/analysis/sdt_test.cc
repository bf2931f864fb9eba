// d' against R psyphy 0.2.3 (fixtures/r/make_r_fixtures.R) and the test
// vectors of the Palamedes toolbox's help text (same-different, differencing
// and independent-observation models).
#include "burrlab/analysis/sdt.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <string>

#include "fixtures.h"

namespace burrlab::analysis {
namespace {

using testing::FixtureDir;
using testing::ReadCsv;

double Value(const Result<double>& r) {
  EXPECT_TRUE(r.ok()) << r.error().message;
  return r.ok() ? *r : std::nan("");
}

TEST(DPrimeSameDifferent, MatchesPalamedesVectors) {
  constexpr auto kDiff = SameDifferentModel::kDifferencing;
  constexpr auto kIo = SameDifferentModel::kIndependentObservation;
  EXPECT_NEAR(Value(DPrimeSameDifferent(0.6, 0.1, kDiff)), 2.6837, 1e-4);
  EXPECT_NEAR(Value(DPrimeSameDifferent(0.7, 0.1, kDiff)), 3.0675, 1e-4);
  EXPECT_NEAR(Value(DPrimeSameDifferent(0.8, 0.5, kDiff)), 2.0629, 1e-4);
  EXPECT_NEAR(Value(DPrimeSameDifferent(0.6, 0.1, kIo)), 2.2835, 1e-4);
  EXPECT_NEAR(Value(DPrimeSameDifferent(0.8, 0.1, kIo)), 2.8342, 1e-4);
  EXPECT_NEAR(Value(DPrimeSameDifferent(0.9, 0.6, kIo)), 1.7808, 1e-4);
}

TEST(DPrimeSameDifferent, MatchesPsyphyDprimeSdForBothModels) {
  const auto rows = ReadCsv(FixtureDir("r") / "dprime_sd.csv");
  int differencing = 0, independent = 0;
  double worst = 0.0;
  for (const auto& row : rows) {
    const double h = std::stod(row.at("hit")), f = std::stod(row.at("fa"));
    const bool diff = row.at("model") == "differencing";
    const double ours = Value(DPrimeSameDifferent(
        h, f,
        diff ? SameDifferentModel::kDifferencing
             : SameDifferentModel::kIndependentObservation));
    const double theirs = std::stod(row.at("dprime"));
    EXPECT_NEAR(ours, theirs, 1e-4)
        << row.at("model") << " H " << h << " F " << f;
    worst = std::max(worst, std::abs(ours - theirs));
    (diff ? differencing : independent) += 1;
  }
  EXPECT_GE(differencing, 10);
  EXPECT_GE(independent, 10);
  std::cout << "dprime.SD: worst |d' - psyphy| " << worst << "\n";
}

TEST(DPrimeMAfc, MatchesPsyphyDprimeMAfc) {
  const auto rows = ReadCsv(FixtureDir("r") / "dprime_mafc.csv");
  ASSERT_GE(rows.size(), 10u);
  double worst = 0.0;
  for (const auto& row : rows) {
    const double pc = std::stod(row.at("pc"));
    const int m = std::stoi(row.at("m"));
    const double ours = Value(DPrimeMAfc(pc, m));
    const double theirs = std::stod(row.at("dprime"));
    EXPECT_NEAR(ours, theirs, 1e-4) << "Pc " << pc << " m " << m;
    worst = std::max(worst, std::abs(ours - theirs));
  }
  std::cout << "dprime.mAFC: worst |d' - psyphy| " << worst << "\n";
}

TEST(DPrimeMAfc, TwoAfcIsRootTwoTimesZOfPcAndChanceIsZero) {
  // R: sqrt(2) * qnorm(0.76).
  EXPECT_NEAR(Value(DPrimeMAfc(0.76, 2)), 0.99886266350732711, 1e-12);
  EXPECT_NEAR(Value(DPrimeMAfc(0.25, 4)), 0.0, 1e-9);
  EXPECT_LT(Value(DPrimeMAfc(0.2, 4)), 0.0);
}

TEST(DPrimeYesNo, MatchesQnormDifferences) {
  const auto rows = ReadCsv(FixtureDir("r") / "dprime_yesno.csv");
  ASSERT_GE(rows.size(), 10u);
  for (const auto& row : rows) {
    const double h = std::stod(row.at("hit")), f = std::stod(row.at("fa"));
    EXPECT_NEAR(Value(DPrimeYesNo(h, f)), std::stod(row.at("dprime")), 1e-9)
        << "H " << h << " F " << f;
  }
}

TEST(DPrime, RejectsRatesOfZeroOrOneAndImpossibleCombinations) {
  EXPECT_EQ(DPrimeYesNo(1.0, 0.2).error().message,
            "the hit rate must be in (0, 1), got 1 (correct rates of 0 or 1 "
            "first, e.g. to 1/(2N) or 1 - 1/(2N))");
  EXPECT_EQ(DPrimeYesNo(0.8, 0.0).error().message.substr(0, 45),
            "the false-alarm rate must be in (0, 1), got 0");
  EXPECT_EQ(DPrimeMAfc(0.7, 1).error().message,
            "the number of alternatives m must be at least 2, got 1");
  EXPECT_EQ(DPrimeSameDifferent(0.2, 0.4, SameDifferentModel::kDifferencing)
                .error()
                .message,
            "the differencing model needs the hit rate (0.2) to be at least "
            "the false-alarm rate (0.4)");
  EXPECT_FALSE(DPrimeYesNo(std::nan(""), 0.2).ok());
  // H = F means no sensitivity; the independent-observation model is
  // antisymmetric.
  EXPECT_EQ(
      Value(DPrimeSameDifferent(0.3, 0.3, SameDifferentModel::kDifferencing)),
      0.0);
  EXPECT_NEAR(Value(DPrimeSameDifferent(
                  0.3, 0.6, SameDifferentModel::kIndependentObservation)),
              -Value(DPrimeSameDifferent(
                  0.6, 0.3, SameDifferentModel::kIndependentObservation)),
              1e-12);
}

}  // namespace
}  // namespace burrlab::analysis
