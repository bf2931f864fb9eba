// Group statistics against R 4.2's t.test and binom.test
// (fixtures/r/make_r_fixtures.R) and the two-group comparison against R's
// t.test(x, y) and wilcox.test(x, y) (fixtures/r/make_two_group_fixtures.R),
// to 1e-6.
#include "burrlab/analysis/group_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "fixtures.h"

namespace burrlab::analysis {
namespace {

using testing::FixtureDir;
using testing::ReadCsv;

double worst_absolute = 0.0;  // over every comparison, for the report

// Within 1e-6, and within 1e-6 relative for small p-values.
void ExpectClose(double ours, const std::string& theirs_text,
                 const std::string& what) {
  const double theirs = std::stod(theirs_text);
  worst_absolute = std::max(worst_absolute, std::abs(ours - theirs));
  EXPECT_NEAR(ours, theirs, 1e-6 * std::max(1.0, std::abs(theirs))) << what;
  if (std::abs(theirs) < 1e-3) {
    EXPECT_NEAR(ours, theirs, 1e-6 * std::abs(theirs)) << what << " (relative)";
  }
}

TEST(OneSampleTTest, MatchesRTTest) {
  const auto rows = ReadCsv(FixtureDir("r") / "t_test.csv");
  ASSERT_GE(rows.size(), 3u);
  for (const auto& row : rows) {
    std::vector<double> values;
    std::stringstream in(row.at("values"));
    for (std::string v; std::getline(in, v, ';');)
      values.push_back(std::stod(v));
    const double mu = std::stod(row.at("mu"));
    Result<TTestResult> r = OneSampleTTest(values, mu);
    if (std::stod(row.at("t")) == 0.0) {
      // mean == mu: t = 0, p = 1 (R agrees).
      ASSERT_TRUE(r.ok()) << r.error().message;
    }
    ASSERT_TRUE(r.ok()) << r.error().message;
    SCOPED_TRACE(row.at("values"));
    ExpectClose(r->t, row.at("t"), "t");
    ExpectClose(r->df, row.at("df"), "df");
    ExpectClose(r->p_two_sided, row.at("p_two_sided"), "two-sided p");
    ExpectClose(r->p_greater, row.at("p_greater"), "p greater");
    ExpectClose(r->p_less, row.at("p_less"), "p less");
    ExpectClose(r->ci_low, row.at("ci_low"), "ci low");
    ExpectClose(r->ci_high, row.at("ci_high"), "ci high");
    ExpectClose(r->mean, row.at("mean"), "mean");
  }
}

TEST(ExactBinomialTest, MatchesRBinomTest) {
  const auto rows = ReadCsv(FixtureDir("r") / "binom_test.csv");
  ASSERT_GE(rows.size(), 3u);
  for (const auto& row : rows) {
    const int x = std::stoi(row.at("successes")),
              n = std::stoi(row.at("trials"));
    const double p = std::stod(row.at("p"));
    SCOPED_TRACE(std::to_string(x) + " of " + std::to_string(n) + " at " +
                 row.at("p"));
    Result<BinomialTestResult> r = ExactBinomialTest(x, n, p);
    ASSERT_TRUE(r.ok()) << r.error().message;
    ExpectClose(r->p_two_sided, row.at("p_two_sided"), "two-sided p");
    ExpectClose(r->p_greater, row.at("p_greater"), "p greater");
    ExpectClose(r->p_less, row.at("p_less"), "p less");
    ExpectClose(r->ci_low, row.at("ci_low"), "ci low");
    ExpectClose(r->ci_high, row.at("ci_high"), "ci high");
  }
  std::cout << "t.test and binom.test: worst |burrlab - R| " << worst_absolute
            << "\n";
}

std::vector<double> Values(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  for (std::string v; std::getline(in, v, ';');) values.push_back(std::stod(v));
  return values;
}

// Welch's t (t, df, p) and the Mann-Whitney test (W, p) of every fixture
// case: unequal group sizes, ties across and within groups (normal
// approximation with continuity and tie correction), small groups without
// ties (exact), 55 and 60 values (normal), 49 and 12 (exact).
TEST(TwoGroupTests, MatchRWelchTTestAndWilcoxTest) {
  const auto rows = ReadCsv(FixtureDir("r") / "two_sample_tests.csv");
  ASSERT_EQ(rows.size(), 10u);
  int exact = 0, approximate = 0, tied = 0;
  for (const auto& row : rows) {
    const std::vector<double> x = Values(row.at("x")), y = Values(row.at("y"));
    SCOPED_TRACE(row.at("x") + " vs " + row.at("y"));
    Result<WelchTTestResult> welch = WelchTTest(x, y);
    ASSERT_TRUE(welch.ok()) << welch.error().message;
    EXPECT_EQ(welch->n_x, static_cast<int>(x.size()));
    EXPECT_EQ(welch->n_y, static_cast<int>(y.size()));
    ExpectClose(welch->t, row.at("welch_t"), "Welch t");
    ExpectClose(welch->df, row.at("welch_df"), "Welch df");
    ExpectClose(welch->p_two_sided, row.at("welch_p"), "Welch p");
    Result<MannWhitneyResult> mw = MannWhitneyTest(x, y);
    ASSERT_TRUE(mw.ok()) << mw.error().message;
    ExpectClose(mw->w, row.at("w"), "W");
    ExpectClose(mw->p_two_sided, row.at("mw_p"), "Mann-Whitney p");
    EXPECT_EQ(mw->exact, row.at("mw_exact") == "1");
    EXPECT_EQ(mw->method, mw->exact ? "exact"
                          : mw->ties
                              ? "normal approximation with continuity "
                                "correction (ties: no exact p)"
                              : "normal approximation with continuity "
                                "correction (50 or more values in a group)");
    (mw->exact ? exact : approximate) += 1;
    tied += mw->ties ? 1 : 0;
  }
  EXPECT_EQ(exact, 5);
  EXPECT_EQ(approximate, 5);
  EXPECT_EQ(tied, 4);
  std::cout << "t.test(x, y) and wilcox.test(x, y): worst |burrlab - R| "
            << worst_absolute << "\n";
}

TEST(TwoGroupTests, RejectBadInputNamingIt) {
  const std::vector<double> one = {1.0}, two = {1.0, 2.0},
                            nan = {1.0, std::nan("")}, same = {3.0, 3.0};
  EXPECT_EQ(WelchTTest(one, two).error().message,
            "Welch's t-test needs at least 2 values in each group, got 1 and "
            "2");
  EXPECT_EQ(WelchTTest(two, nan).error().message,
            "y value 2 is not a finite number: nan");
  EXPECT_EQ(WelchTTest(same, same).error().message,
            "both groups are constant (3 and 3): the t statistic is "
            "undefined");
  EXPECT_EQ(MannWhitneyTest(std::vector<double>{}, two).error().message,
            "the Mann-Whitney test needs at least 1 value in each group, got "
            "0 and 2");
  EXPECT_EQ(MannWhitneyTest(nan, two).error().message,
            "x value 2 is not a finite number: nan");
  EXPECT_EQ(MannWhitneyTest(same, same).error().message,
            "all 4 values are equal (3): the rank-sum test is undefined");
  // One value against one: W is 0 or 1, each with probability 1/2, so the
  // two-sided p is 1 (R: wilcox.test(1, 2)$p.value).
  Result<MannWhitneyResult> single =
      MannWhitneyTest(one, std::vector<double>{2.0});
  ASSERT_TRUE(single.ok());
  EXPECT_EQ(single->w, 0.0);
  EXPECT_TRUE(single->exact);
  EXPECT_EQ(single->p_two_sided, 1.0);
}

TEST(MeanAndSem, IsSampleSdOverRootN) {
  const std::vector<double> scores = {7, 9, 6, 8, 10, 7, 9, 8};
  Result<MeanSem> m = MeanAndSem(scores);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->n, 8);
  EXPECT_DOUBLE_EQ(m->mean, 8.0);
  EXPECT_NEAR(m->sd, std::sqrt(12.0 / 7.0), 1e-15);
  EXPECT_NEAR(m->sem, std::sqrt(12.0 / 7.0) / std::sqrt(8.0), 1e-15);
}

TEST(GroupStats, RejectBadInputNamingIt) {
  const std::vector<double> one = {5.0};
  EXPECT_EQ(MeanAndSem(one).error().message,
            "a mean +- SEM needs at least 2 values, got 1");
  const std::vector<double> equal = {6.0, 6.0, 6.0};
  EXPECT_EQ(OneSampleTTest(equal, 6.0).error().message,
            "all 3 values are equal (6): the t statistic is undefined");
  const std::vector<double> nan = {6.0, std::nan("")};
  EXPECT_EQ(MeanAndSem(nan).error().message,
            "value 2 is not a finite number: nan");
  EXPECT_EQ(ExactBinomialTest(13, 12, 0.5).error().message,
            "successes must be in [0, trials = 12], got 13");
  EXPECT_EQ(ExactBinomialTest(0, 0, 0.5).error().message,
            "trials must be at least 1, got 0");
  EXPECT_EQ(ExactBinomialTest(3, 12, 1.5).error().message,
            "p must be in [0, 1], got 1.5");
  EXPECT_EQ(OneSampleTTest(std::vector<double>{1, 2}, 0, 1.0).error().message,
            "conf_level must be in (0, 1), got 1");
}

}  // namespace
}  // namespace burrlab::analysis
