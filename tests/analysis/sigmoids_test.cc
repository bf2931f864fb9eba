// The four sigmoids as psignifit 2.5.6 parameterises them: values against
// the closed forms, thresholds and slopes against psignifit's own output for
// its example data set, and the derivatives the BCa method uses against
// finite differences.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "burrlab/analysis/psychometric.h"

namespace burrlab::analysis {
namespace {

constexpr Sigmoid kAll[] = {Sigmoid::kLogistic, Sigmoid::kCumulativeNormal,
                            Sigmoid::kWeibull, Sigmoid::kGumbel};

TEST(Sigmoid, ValuesFollowTheClosedForms) {
  EXPECT_NEAR(SigmoidValue(Sigmoid::kLogistic, 3.0, 2.0, 0.5),
              1.0 / (1.0 + std::exp(-2.0)), 1e-15);
  EXPECT_NEAR(SigmoidValue(Sigmoid::kCumulativeNormal, 3.0, 2.0, 0.5),
              0.5 * std::erfc(-2.0 / std::numbers::sqrt2), 1e-15);
  EXPECT_NEAR(SigmoidValue(Sigmoid::kWeibull, 3.0, 2.0, 1.5),
              1.0 - std::exp(-std::pow(1.5, 1.5)), 1e-15);
  EXPECT_NEAR(SigmoidValue(Sigmoid::kGumbel, 3.0, 2.0, 0.5),
              1.0 - std::exp(-std::exp(2.0)), 1e-15);
  EXPECT_EQ(SigmoidValue(Sigmoid::kWeibull, 0.0, 2.0, 1.5), 0.0);
  EXPECT_EQ(SigmoidValue(Sigmoid::kWeibull, -1.0, 2.0, 1.5), 0.0);
  const PsychometricParams p{2.0, 0.5, 0.5, 0.02};
  EXPECT_NEAR(Psi(Sigmoid::kLogistic, p, 2.0), 0.5 + 0.48 * 0.5, 1e-15);
}

// psignifit 2.5.6 on /usr/share/doc/psignifit/examples/dat (2AFC, runs 0,
// cuts 0.2 0.5 0.8): its fitted alpha and beta for each shape, and the
// thresholds (#TH_EST) and slopes (#SL_EST) it printed from them.
struct PsignifitExample {
  Sigmoid sigmoid;
  double alpha, beta;
  double thresholds[3];
  double slopes[3];
};
constexpr PsignifitExample kExamples[] = {
    {Sigmoid::kLogistic,
     2.78305,
     0.482604,
     {2.11401, 2.78305, 3.45208},
     {0.331535, 0.518023, 0.331535}},
    {Sigmoid::kCumulativeNormal,
     2.77722,
     0.813318,
     {2.09271, 2.77722, 3.46172},
     {0.344222, 0.490512, 0.344222}},
    {Sigmoid::kWeibull,
     3.06836,
     4.00961,
     {2.11078, 2.80032, 3.45502},
     {0.339105, 0.496238, 0.373556}},
    {Sigmoid::kGumbel,
     3.12652,
     0.719916,
     {2.04669, 2.86266, 3.46911},
     {0.247966, 0.481408, 0.447118}},
};

TEST(Sigmoid, ThresholdsAndSlopesMatchPsignifitsParameterisation) {
  const double cuts[3] = {0.2, 0.5, 0.8};
  for (const PsignifitExample& e : kExamples) {
    SCOPED_TRACE(std::string(SigmoidName(e.sigmoid)));
    for (int k = 0; k < 3; ++k) {
      const double t = SigmoidInverse(e.sigmoid, cuts[k], e.alpha, e.beta);
      EXPECT_NEAR(t, e.thresholds[k], 1e-5 * e.thresholds[k]);
      EXPECT_NEAR(SigmoidSlope(e.sigmoid, t, e.alpha, e.beta), e.slopes[k],
                  2e-5 * e.slopes[k]);
    }
  }
}

TEST(Sigmoid, InverseAndSlopeAgreeWithValue) {
  for (Sigmoid s : kAll) {
    SCOPED_TRACE(std::string(SigmoidName(s)));
    const double alpha = 3.0, beta = s == Sigmoid::kWeibull ? 2.5 : 0.7;
    for (double cut : {0.01, 0.2, 0.5, 0.8, 0.99}) {
      const double x = SigmoidInverse(s, cut, alpha, beta);
      EXPECT_NEAR(SigmoidValue(s, x, alpha, beta), cut, 1e-12);
      const double h = 1e-6;
      const double numeric = (SigmoidValue(s, x + h, alpha, beta) -
                              SigmoidValue(s, x - h, alpha, beta)) /
                             (2 * h);
      EXPECT_NEAR(SigmoidSlope(s, x, alpha, beta), numeric, 1e-7);
    }
  }
}

TEST(Sigmoid, GradientsOfThresholdAndSlopeMatchFiniteDifferences) {
  for (Sigmoid s : kAll) {
    SCOPED_TRACE(std::string(SigmoidName(s)));
    const double alpha = 3.0, beta = s == Sigmoid::kWeibull ? 2.5 : 0.7;
    for (double cut : {0.2, 0.5, 0.8}) {
      const auto threshold = [&](double a, double b) {
        return SigmoidInverse(s, cut, a, b);
      };
      const auto slope = [&](double a, double b) {
        return SigmoidSlope(s, SigmoidInverse(s, cut, a, b), a, b);
      };
      const double h = 1e-6;
      const std::array<double, 2> t = ThresholdGradient(s, cut, alpha, beta);
      EXPECT_NEAR(
          t[0],
          (threshold(alpha + h, beta) - threshold(alpha - h, beta)) / (2 * h),
          1e-7);
      EXPECT_NEAR(
          t[1],
          (threshold(alpha, beta + h) - threshold(alpha, beta - h)) / (2 * h),
          1e-7);
      const std::array<double, 2> g = SlopeGradient(s, cut, alpha, beta);
      EXPECT_NEAR(g[0],
                  (slope(alpha + h, beta) - slope(alpha - h, beta)) / (2 * h),
                  1e-7);
      EXPECT_NEAR(g[1],
                  (slope(alpha, beta + h) - slope(alpha, beta - h)) / (2 * h),
                  1e-7);
    }
  }
}

TEST(Sigmoid, NamesRoundTrip) {
  for (Sigmoid s : kAll) EXPECT_EQ(SigmoidFromName(SigmoidName(s)), s);
  EXPECT_FALSE(SigmoidFromName("probit").has_value());
}

}  // namespace
}  // namespace burrlab::analysis
