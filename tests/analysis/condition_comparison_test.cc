// Conditions fitted together and compared by likelihood ratios, against R:
// glm with psyphy's mafc.logit(2) and mafc.probit(2) links fits the same
// 2AFC models without lapses by maximum likelihood
// (fixtures/r/make_condition_comparison_fixture.R, its outputs committed).
#include "burrlab/analysis/condition_comparison.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "fixtures.h"

namespace burrlab::analysis {
namespace {

using testing::FixtureDir;
using testing::ReadCsv;

// The fixture's data sets: case -> conditions in order of appearance.
std::map<std::string, std::vector<ConditionData>> FixtureData() {
  std::map<std::string, std::vector<ConditionData>> cases;
  for (const auto& row :
       ReadCsv(FixtureDir("r") / "condition_comparison_data.csv")) {
    std::vector<ConditionData>& conditions = cases[row.at("case")];
    if (conditions.empty() || conditions.back().name != row.at("condition")) {
      conditions.push_back({row.at("condition"), {}});
    }
    conditions.back().blocks.push_back({std::stod(row.at("level")),
                                        std::stoi(row.at("n_correct")),
                                        std::stoi(row.at("n_total"))});
  }
  return cases;
}

PsychometricOptions RLikeOptions(const std::string& sigmoid) {
  PsychometricOptions o;
  o.sigmoid = *SigmoidFromName(sigmoid);
  o.n_intervals = 2;
  o.lambda_max = 0.0;  // R's glm has no lapse rate
  o.cuts = {0.5};
  o.bootstrap_samples = 0;
  return o;
}

// Relative agreement within `rel` of R's number (the issue asks for 1 %;
// maximum likelihood found twice agrees far closer).
void ExpectNear(double burrlab, const std::string& r, double rel,
                const std::string& what) {
  const double want = std::stod(r);
  EXPECT_NEAR(burrlab, want, rel * std::abs(want)) << what;
}

TEST(CompareConditions, FitsAndLikelihoodRatiosMatchRGlm) {
  const auto cases = FixtureData();
  ASSERT_EQ(cases.size(), 3u);
  std::map<std::string, ConditionComparison> results;
  for (const auto& [name, conditions] : cases) {
    for (const char* sigmoid : {"logistic", "cumnorm"}) {
      Result<ConditionComparison> c =
          CompareConditions(conditions, RLikeOptions(sigmoid));
      ASSERT_TRUE(c.ok()) << c.error().message;
      results[name + "/" + sigmoid] = *c;
    }
  }
  int fits = 0;
  for (const auto& row :
       ReadCsv(FixtureDir("r") / "condition_comparison_fits.csv")) {
    const ConditionComparison& c =
        results.at(row.at("case") + "/" + row.at("sigmoid"));
    const auto fit = std::find_if(c.fits.begin(), c.fits.end(), [&](auto& f) {
      return ConditionModelName(f.model) == row.at("model");
    });
    ASSERT_NE(fit, c.fits.end()) << row.at("model");
    const std::size_t k = static_cast<std::size_t>(
        std::find(c.names.begin(), c.names.end(), row.at("condition")) -
        c.names.begin());
    ASSERT_LT(k, c.names.size());
    const std::string what = row.at("case") + " " + row.at("sigmoid") + " " +
                             row.at("model") + " " + row.at("condition");
    EXPECT_TRUE(fit->converged) << what;
    ExpectNear(fit->params[k].alpha, row.at("alpha"), 1e-4, what + " alpha");
    ExpectNear(fit->params[k].beta, row.at("beta"), 1e-4, what + " beta");
    ExpectNear(fit->log_likelihood, row.at("log_likelihood"), 1e-8,
               what + " log L");
    ExpectNear(fit->deviance, row.at("deviance"), 1e-5, what + " deviance");
    ++fits;
  }
  EXPECT_EQ(fits, 42);
  int tests = 0;
  for (const auto& row :
       ReadCsv(FixtureDir("r") / "condition_comparison_tests.csv")) {
    const ConditionComparison& c =
        results.at(row.at("case") + "/" + row.at("sigmoid"));
    const auto t = std::find_if(c.tests.begin(), c.tests.end(), [&](auto& x) {
      return x.question == row.at("question");
    });
    ASSERT_NE(t, c.tests.end());
    const std::string what =
        row.at("case") + " " + row.at("sigmoid") + " " + row.at("question");
    ExpectNear(t->lr, row.at("lr"), 1e-5, what + " LR");
    EXPECT_EQ(t->df, std::stoi(row.at("df"))) << what;
    ExpectNear(t->p_chi_square, row.at("p"), 1e-5, what + " p");
    ++tests;
  }
  EXPECT_EQ(tests, 12);
}

// The parametric bootstrap's p-value estimates the same tail as Wilks'
// chi-square approximation, which 240 trials per condition make good: they
// agree within the bootstrap's binomial error (4 SD) plus 0.02 for the
// approximation. The same seed gives the same p.
TEST(CompareConditions, BootstrapPValuesAgreeWithTheChiSquareApproximation) {
  const auto cases = FixtureData();
  PsychometricOptions o = RLikeOptions("logistic");
  o.bootstrap_samples = 400;
  o.seed = 11;
  Result<ConditionComparison> c =
      CompareConditions(cases.at("threshold_shift"), o);
  ASSERT_TRUE(c.ok()) << c.error().message;
  for (const LikelihoodRatioTest& t : c->tests) {
    const double p = t.p_chi_square;
    EXPECT_EQ(t.bootstrap_samples, 400);
    EXPECT_EQ(t.bootstrap_failures, 0);
    EXPECT_NEAR(t.p_bootstrap, p, 4.0 * std::sqrt(p * (1.0 - p) / 400) + 0.02)
        << t.question;
  }
  Result<ConditionComparison> again =
      CompareConditions(cases.at("threshold_shift"), o);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->tests[0].p_bootstrap, c->tests[0].p_bootstrap);
  EXPECT_EQ(again->tests[1].p_bootstrap, c->tests[1].p_bootstrap);
}

TEST(CompareConditions, NamesTheConditionWithBadData) {
  auto conditions = FixtureData().at("threshold_shift");
  PsychometricOptions o = RLikeOptions("logistic");
  EXPECT_EQ(
      CompareConditions(std::span(conditions).first(1), o).error().message,
      "comparing conditions needs at least 2, got 1");
  conditions[1].blocks.resize(2);
  EXPECT_EQ(CompareConditions(conditions, o).error().message,
            "condition 'b': only 2 distinct levels: a psychometric fit needs "
            "at least 3");
}

}  // namespace
}  // namespace burrlab::analysis
