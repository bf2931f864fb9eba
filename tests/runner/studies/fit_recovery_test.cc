// Tests of the recovery check: published results simulated from a known
// population and fitted back (fit_recovery.h).
#include "studies/fit_recovery.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "example_protocol.h"

namespace burrlab::runner {
namespace {

// Truth: the sample's mean and SD computed by hand.
TEST(PublishedResult, RoundsAsAPaperDoes) {
  // 8, 9, 10, 11: mean 9.5, SD sqrt(5/3) = 1.291, SEM 0.6455.
  const ObservedGroup g = PublishedResult({8, 9, 10, 11}, "probe", 1);
  EXPECT_EQ(g.n, 4);
  EXPECT_EQ(g.block, "probe");
  EXPECT_EQ(g.decimals, 1);
  EXPECT_TRUE(g.scores.empty());  // only the mean and SEM are published
  EXPECT_DOUBLE_EQ(g.mean, 9.5);
  EXPECT_DOUBLE_EQ(g.sem, 0.6);
  const ObservedGroup two = PublishedResult({8, 9, 10, 11}, "probe", 2);
  EXPECT_DOUBLE_EQ(two.sem, 0.65);
  // Every subject alike: an SEM of 0 is printed as one unit of the last
  // decimal.
  const ObservedGroup alike = PublishedResult({12, 12, 12}, "drill", 1);
  EXPECT_DOUBLE_EQ(alike.mean, 12.0);
  EXPECT_DOUBLE_EQ(alike.sem, 0.1);
}

// Parameter recovery by maximum likelihood. Published results of 20
// subjects (mean +- SEM, rounded to one decimal, as papers give them) are
// simulated from a population of known Weber fraction and spread, then
// fitted; each 95 % profile interval should hold the truth in about 95 % of
// the studies. The truth is the simulation's population, drawn independently
// of the fit (its own subjects, study seeds and renderings); the check is the
// coverage a profile-likelihood interval promises (Wilks).
TEST(FitRecovery, MaximumLikelihoodIntervalsCoverTheTruth) {
  const protocols::Protocol protocol =
      ExampleProtocol("two_interval_2afc.toml");
  ObserverFit truth;
  truth.block = "probe2afc";
  truth.task = protocols::Task::kProbe;
  truth.weber = 0.35;
  truth.weber_spread = 0.5;
  ObserverFitOptions fit_options;
  fit_options.virtual_subjects = 300;
  fit_options.seed = 3;
  fit_options.base = protocols::ObserverParams{};
  RecoveryOptions options;
  options.seed = 1000;
#if defined(__SANITIZE_ADDRESS__)
  options.studies = 2;
#else
  options.studies = 20;
#endif
  CuePool pool(2, 2.0, 7);
  int progress = 0;
  Result<Recovery> r =
      CheckRecovery(protocol, {9.0, 0.4, 20, "probe2afc", 1}, truth,
                    fit_options, pool, options, [&](int done) {
                      EXPECT_EQ(done, progress + 1);
                      progress = done;
                    });
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(progress, options.studies);
  ASSERT_EQ(r->studies, options.studies);
  ASSERT_EQ(static_cast<int>(r->fits.size()), options.studies);
  for (const ObserverFit& fit : r->fits) {
    EXPECT_TRUE(fit.maximum_likelihood);
    EXPECT_EQ(fit.block, "probe2afc");
    EXPECT_LE(fit.weber_low, fit.weber);
    EXPECT_LE(fit.weber, fit.weber_high);
    EXPECT_LE(fit.spread_low, fit.weber_spread);
    EXPECT_LE(fit.weber_spread, fit.spread_high);
  }
  RecordProperty("weber_covered", r->weber_covered);
  RecordProperty("spread_covered", r->spread_covered);
  RecordProperty("both_covered", r->both_covered);
  RecordProperty("spread_at_limit", r->spread_at_limit);
#if !defined(__SANITIZE_ADDRESS__)
  // A 95 % interval holds the truth in k of 20 studies, k ~ Binomial(20,
  // 0.95): 17-20 in 95 % of checks; 15 or fewer has P 0.003.
  EXPECT_GE(r->weber_covered, 16);
  EXPECT_GE(r->spread_covered, 16);
  EXPECT_GE(r->both_covered, 15);
  // Not every interval: intervals so wide they always cover are no use.
  EXPECT_LE(r->weber_covered, 19);
#endif
}

TEST(FitRecovery, RefusesNoStudies) {
  const protocols::Protocol protocol =
      ExampleProtocol("two_interval_2afc.toml");
  ObserverFit truth;
  truth.block = "probe2afc";
  truth.weber = 0.35;
  CuePool pool(1, 2.0, 7);
  RecoveryOptions options;
  options.studies = 0;
  Result<Recovery> r =
      CheckRecovery(protocol, {9.0, 0.4, 20, "probe2afc", 1}, truth,
                    ObserverFitOptions{}, pool, options);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "recovery: studies must be at least 1, got 0");
}

}  // namespace
}  // namespace burrlab::runner
