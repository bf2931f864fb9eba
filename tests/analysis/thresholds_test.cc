// Tests of the threshold estimators on hand-made tracks: staircase reversal
// means in the step domain, QUEST's posterior, limits transitions, mean
// adjusted levels and the constant-stimuli fit on the pooled counts.
#include "burrlab/analysis/thresholds.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "golden.h"

namespace burrlab::analysis {
namespace {

using results_schema::BehFile;
using results_schema::TrialRecord;

TrialRecord Trial(int i, const std::string& method, double level,
                  const std::string& extra = "{}") {
  TrialRecord t;
  t.trial_index = i;
  t.block = method;
  t.method = method;
  t.task = "probe";
  t.trial_type = "2afc";
  t.stim_level = level;
  t.stim_unit = "ratio";
  t.extra = extra;
  return t;
}

BehFile File(std::vector<TrialRecord> trials) {
  BehFile f;
  f.subject = "01";
  f.task = trials.front().block;
  f.table.trials = std::move(trials);
  return f;
}

// Reversals at 0.4, 0.1, 0.8, 0.2, 0.4 on a log10 staircase asking for 4.
BehFile LogStaircase(const std::string& extra_k = "4") {
  const std::vector<double> levels = {1.0, 0.4, 0.2, 0.1, 0.8, 0.2, 0.4, 0.3};
  const std::vector<bool> reversal = {false, true, false, true,
                                      true,  true, true,  false};
  std::vector<TrialRecord> trials;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    TrialRecord t = Trial(
        static_cast<int>(i), "staircase", levels[i],
        R"({"step_scale":"log10","threshold_reversals":)" + extra_k + "}");
    t.staircase_id = 0;
    t.reversal = reversal[i];
    trials.push_back(t);
  }
  return File(trials);
}

TEST(Thresholds, StaircaseAveragesTheLastReversalsInLogUnits) {
  Result<std::vector<ThresholdEstimate>> e =
      EstimateThresholds(std::vector<BehFile>{LogStaircase()}, {});
  ASSERT_TRUE(e.ok()) << e.error().message;
  ASSERT_EQ(e->size(), 1u);
  const ThresholdEstimate& t = (*e)[0];
  const double logs[4] = {std::log10(0.1), std::log10(0.8), std::log10(0.2),
                          std::log10(0.4)};
  const double mean = (logs[0] + logs[1] + logs[2] + logs[3]) / 4.0;
  double ss = 0.0;
  for (double l : logs) ss += (l - mean) * (l - mean);
  EXPECT_NEAR(*t.value, std::pow(10.0, mean), 1e-12);
  EXPECT_NEAR(*t.spread, std::sqrt(ss / 3.0), 1e-12);
  EXPECT_EQ(t.spread_unit, "log10");
  EXPECT_EQ(t.n, 4);
  EXPECT_EQ(t.staircase_id, 0);
  EXPECT_EQ(t.estimator, "mean of the last 4 reversals (log10 scale)");
}

TEST(Thresholds, ReversalsFlagOverridesTheProtocol) {
  ThresholdOptions o;
  o.reversals = 2;
  Result<std::vector<ThresholdEstimate>> e =
      EstimateThresholds(std::vector<BehFile>{LogStaircase()}, o);
  ASSERT_TRUE(e.ok());
  EXPECT_NEAR(*(*e)[0].value, std::sqrt(0.2 * 0.4), 1e-12);
  o.reversals = 6;
  e = EstimateThresholds(std::vector<BehFile>{LogStaircase()}, o);
  ASSERT_TRUE(e.ok());
  EXPECT_FALSE((*e)[0].value.has_value());
  EXPECT_EQ((*e)[0].note,
            "only 5 reversals in 8 trials; 6 are needed (fewer with "
            "--reversals)");
}

TEST(Thresholds, QuestReportsThePosteriorMeanAndSd) {
  std::vector<TrialRecord> trials = {
      Trial(0, "quest", 0.3,
            R"({"posterior_mean_log10":-0.5,"posterior_sd_log10":0.4})"),
      Trial(1, "quest", 0.2,
            R"({"posterior_mean_log10":-0.6,"posterior_sd_log10":0.25})")};
  Result<std::vector<ThresholdEstimate>> e =
      EstimateThresholds(std::vector<BehFile>{File(trials)}, {});
  ASSERT_TRUE(e.ok());
  EXPECT_NEAR(*(*e)[0].value, std::pow(10.0, -0.6), 1e-12);
  EXPECT_EQ(*(*e)[0].spread, 0.25);
  EXPECT_EQ((*e)[0].n, 2);
}

TEST(Thresholds, LimitsAverageTheTransitions) {
  std::vector<TrialRecord> trials = {
      Trial(0, "limits", 0.1, R"({"ends_series":false})"),
      Trial(1, "limits", 0.15,
            R"({"ends_series":true,"transition_level":0.125})"),
      Trial(2, "limits", 0.6,
            R"({"ends_series":true,"transition_level":0.475})"),
      Trial(3, "limits", 0.8,
            R"({"ends_series":true,"transition_level":null})")};
  Result<std::vector<ThresholdEstimate>> e =
      EstimateThresholds(std::vector<BehFile>{File(trials)}, {});
  ASSERT_TRUE(e.ok());
  EXPECT_NEAR(*(*e)[0].value, 0.3, 1e-12);
  EXPECT_EQ((*e)[0].n, 2);
  // Only the first series shows its direction (two levels, stepping up).
  EXPECT_EQ((*e)[0].note,
            "1 of 3 series had no transition; ascending 0.125 (n = 1), "
            "descending n/a");
}

// The ascending and descending series apart (Gescheider 1997, ch. 3), and a
// warning for a series that began on its stopping answer. By hand: ascending
// transitions 0.175 and 0.075 (mean 0.125), descending 0.525 and 0.475
// (0.5), all four 0.3125; the third series, ascending, began on "yes".
TEST(Thresholds, LimitsSplitAscendingFromDescendingAndNameBadStarts) {
  struct Step {
    double level;
    const char* answer;
    const char* extra;
  };
  const std::vector<Step> steps = {
      {0.1, "no", R"({"ends_series":false})"},
      {0.15, "no", R"({"ends_series":false})"},
      {0.2, "yes", R"({"ends_series":true,"transition_level":0.175})"},
      {0.6, "yes", R"({"ends_series":false})"},
      {0.55, "yes", R"({"ends_series":false})"},
      {0.5, "no", R"({"ends_series":true,"transition_level":0.525})"},
      {0.05, "yes", R"({"ends_series":false})"},
      {0.1, "no", R"({"ends_series":true,"transition_level":0.075})"},
      {0.5, "yes", R"({"ends_series":false})"},
      {0.45, "no", R"({"ends_series":true,"transition_level":0.475})"}};
  std::vector<TrialRecord> trials;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    TrialRecord t =
        Trial(static_cast<int>(i), "limits", steps[i].level, steps[i].extra);
    t.response = steps[i].answer;
    trials.push_back(t);
  }
  Result<std::vector<ThresholdEstimate>> e =
      EstimateThresholds(std::vector<BehFile>{File(trials)}, {});
  ASSERT_TRUE(e.ok());
  const ThresholdEstimate& t = (*e)[0];
  EXPECT_NEAR(*t.value, 0.3125, 1e-12);
  EXPECT_NEAR(*t.ascending_mean, 0.125, 1e-12);
  EXPECT_NEAR(*t.descending_mean, 0.5, 1e-12);
  EXPECT_EQ(t.ascending_n, 2);
  EXPECT_EQ(t.descending_n, 2);
  EXPECT_EQ(t.started_on_stopping_answer, 1);
  EXPECT_EQ(t.note,
            "ascending 0.125 (n = 2), descending 0.5 (n = 2); warning: 1 of 4 "
            "series started on their stopping answer (an ascending series on "
            "\"yes\", a descending one on \"no\"): their start was already "
            "past the threshold, so start them farther out");
}

TEST(Thresholds, AdjustmentAveragesTheFinalLevels) {
  std::vector<TrialRecord> trials = {
      Trial(0, "adjustment", 1.2, R"({"final_level":1.2})"),
      Trial(1, "adjustment", 1.0, R"({"final_level":1.0})"),
      Trial(2, "adjustment", 1.1, R"({"final_level":1.1})")};
  Result<std::vector<ThresholdEstimate>> e =
      EstimateThresholds(std::vector<BehFile>{File(trials)}, {});
  ASSERT_TRUE(e.ok());
  EXPECT_NEAR(*(*e)[0].value, 1.1, 1e-12);
  EXPECT_NEAR(*(*e)[0].spread, 0.1, 1e-12);
}

TEST(Thresholds, ConstantStimuliFitsThePooledCounts) {
  // 2AFC: correct counts per level out of 20.
  const std::vector<double> levels = {1.05, 1.1, 1.2, 1.3, 1.5, 2.0};
  const std::vector<int> correct = {10, 11, 13, 16, 19, 20};
  std::vector<TrialRecord> trials;
  std::vector<DataBlock> data;
  int i = 0;
  for (std::size_t l = 0; l < levels.size(); ++l) {
    data.push_back({levels[l], correct[l], 20});
    for (int r = 0; r < 20; ++r) {
      TrialRecord t = Trial(i++, "constant_stimuli", levels[l]);
      t.correct = r < correct[l];
      trials.push_back(t);
    }
  }
  ThresholdOptions o;
  o.bootstrap_samples = 199;
  Result<std::vector<ThresholdEstimate>> e =
      EstimateThresholds(std::vector<BehFile>{File(trials)}, o);
  ASSERT_TRUE(e.ok());
  // A ratio axis is fitted in log10(level), the threshold and its interval
  // transformed back.
  std::vector<DataBlock> log_data = data;
  for (DataBlock& b : log_data) b.level = std::log10(b.level);
  PsychometricOptions p;
  p.cuts = {0.5};
  p.conf = {0.025, 0.975};
  p.bootstrap_samples = 199;
  Result<PsychometricAnalysis> direct = AnalyzePsychometric(log_data, p);
  ASSERT_TRUE(direct.ok());
  EXPECT_EQ((*e)[0].fit_scale, "log10");
  EXPECT_EQ((*e)[0].estimator,
            "logistic fit in log10(level) (2AFC), threshold F^-1(0.5)");
  EXPECT_EQ((*e)[0].ci_method, "BCa");
  EXPECT_EQ(*(*e)[0].value, std::pow(10.0, direct->thresholds[0].value));
  EXPECT_EQ(*(*e)[0].ci_low, std::pow(10.0, direct->thresholds[0].bca[0]));
  EXPECT_EQ(*(*e)[0].ci_high, std::pow(10.0, direct->thresholds[0].bca[1]));
  EXPECT_EQ((*e)[0].n, 120);

  // A linear axis is fitted in its own units.
  for (TrialRecord& t : trials) t.stim_unit = "N/mm^2";
  e = EstimateThresholds(std::vector<BehFile>{File(trials)}, o);
  ASSERT_TRUE(e.ok());
  direct = AnalyzePsychometric(data, p);
  ASSERT_TRUE(direct.ok());
  EXPECT_EQ((*e)[0].fit_scale, "linear");
  EXPECT_EQ(*(*e)[0].value, direct->thresholds[0].value);
  EXPECT_EQ(*(*e)[0].ci_low, direct->thresholds[0].bca[0]);
  EXPECT_EQ(*(*e)[0].ci_high, direct->thresholds[0].bca[1]);
}

TEST(Thresholds, SameDifferentOnlyIsAnError) {
  std::vector<TrialRecord> trials = {Trial(0, "same_different", 1.0)};
  Result<std::vector<ThresholdEstimate>> e =
      EstimateThresholds(std::vector<BehFile>{File(trials)}, {});
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().message,
            "no block has a threshold (staircase, quest, limits, adjustment "
            "or constant_stimuli); same-different and two-interval blocks are "
            "scored with burrlab analyze scores");
}

// A ratio axis' group, checked against closed forms: thresholds 1, 2 and 4
// have arithmetic mean 7/3 and SD sqrt(7/3); their logs are ln 2 x {0, 1, 2},
// so the geometric mean is 2, the SD factor 2 and the SEM factor
// 2^(1/sqrt 3). With 2 degrees of freedom Student's t has the closed-form
// CDF 1/2 + t / (2 sqrt(t^2 + 2)), so its 0.975 quantile is
// sqrt(2 * 0.95^2 / (1 - 0.95^2)). A subject without a
// value is named and left out; another session is its own group.
TEST(GroupThresholds, RatioAxisGroupsHaveArithmeticAndGeometricMeans) {
  std::vector<ThresholdEstimate> estimates;
  const auto add = [&](std::string subject, std::string session,
                       std::optional<double> value, bool unbounded = false) {
    ThresholdEstimate e;
    e.subject = std::move(subject);
    e.session = std::move(session);
    e.block = "constant";
    e.method = "constant_stimuli";
    e.estimator = "logistic fit";
    e.stim_unit = "ratio";
    e.spread_unit = "ratio";
    e.value = value;
    e.ci_high_at_search_limit = unbounded;
    if (!value) e.note = "no fit: too few levels";
    estimates.push_back(e);
  };
  add("01", "1", 1.0);
  add("02", "1", 2.0, true);
  add("03", "1", std::nullopt);
  add("04", "1", 4.0);
  add("01", "2", 1.5);
  const std::vector<GroupThreshold> groups = GroupThresholds(estimates);
  ASSERT_EQ(groups.size(), 2u);
  const GroupThreshold& g = groups[0];
  EXPECT_EQ(g.session, "1");
  EXPECT_EQ(g.n, 3);
  EXPECT_EQ(g.subjects, (std::vector<std::string>{"01", "02", "04"}));
  ASSERT_EQ(g.without_value.size(), 1u);
  EXPECT_EQ(g.without_value[0].first, "03");
  EXPECT_EQ(g.without_value[0].second, "no fit: too few levels");
  EXPECT_EQ(g.unbounded, (std::vector<std::string>{"02"}));
  EXPECT_NEAR(g.mean, 7.0 / 3.0, 1e-14);
  EXPECT_NEAR(g.sd, std::sqrt(7.0 / 3.0), 1e-14);
  EXPECT_NEAR(g.sem, std::sqrt(7.0 / 9.0), 1e-14);
  const double t = std::sqrt(2.0 * 0.95 * 0.95 / (1.0 - 0.95 * 0.95));
  EXPECT_NEAR(g.ci_low, 7.0 / 3.0 - t * std::sqrt(7.0 / 9.0), 1e-12);
  EXPECT_NEAR(g.ci_high, 7.0 / 3.0 + t * std::sqrt(7.0 / 9.0), 1e-12);
  ASSERT_TRUE(g.geometric);
  EXPECT_NEAR(g.geometric_mean, 2.0, 1e-14);
  EXPECT_NEAR(g.geometric_sd_factor, 2.0, 1e-14);
  EXPECT_NEAR(g.geometric_sem_factor, std::pow(2.0, 1.0 / std::sqrt(3.0)),
              1e-14);
  EXPECT_NEAR(g.geometric_ci_low, std::pow(2.0, 1.0 - t / std::sqrt(3.0)),
              1e-12);
  EXPECT_NEAR(g.geometric_ci_high, std::pow(2.0, 1.0 + t / std::sqrt(3.0)),
              1e-12);
  // One subject: a mean without spread.
  EXPECT_EQ(groups[1].n, 1);
  EXPECT_EQ(groups[1].mean, 1.5);
  EXPECT_TRUE(std::isnan(groups[1].sem));
  EXPECT_EQ(groups[1].geometric_mean, 1.5);
}

// A linear axis (N/mm^2) has no geometric mean; a log-stepping staircase's
// group has one.
TEST(GroupThresholds, GeometricOnlyForRatiosAndLogStaircases) {
  ThresholdEstimate e;
  e.block = "b";
  e.stim_unit = "N/mm^2";
  e.spread_unit = "N/mm^2";
  e.subject = "01";
  e.value = 2.0;
  std::vector<ThresholdEstimate> linear = {e, e};
  linear[1].subject = "02";
  linear[1].value = 3.0;
  EXPECT_FALSE(GroupThresholds(linear)[0].geometric);
  EXPECT_TRUE(std::isnan(GroupThresholds(linear)[0].geometric_mean));
  for (ThresholdEstimate& x : linear) x.spread_unit = "log10";
  EXPECT_NEAR(GroupThresholds(linear)[0].geometric_mean, std::sqrt(6.0), 1e-14);
}

// The group figure: one labelled tick per subject with a value and one for
// the group; subjects with an interval, with an interval at a search limit
// (no bar) and the group's geometric mean with its t interval in their own
// series; a log axis and the standard marked on a ratio axis. Its pixels are
// guarded by a golden image (looked at).
TEST(GroupThresholdPlot, SubjectsWithTheirIntervalsAndTheGroupMean) {
  std::vector<ThresholdEstimate> estimates;
  const std::vector<double> values = {1.3, 1.1, 1.6, 1.25, 1.4};
  for (std::size_t i = 0; i < values.size(); ++i) {
    ThresholdEstimate e;
    e.subject = fmt::format("{:02}", i + 1);
    e.block = "constant";
    e.stim_unit = e.spread_unit = "ratio";
    e.value = values[i];
    e.ci_low = values[i] / 1.2;
    e.ci_high = values[i] * 1.25;
    e.ci_high_at_search_limit = i == 2;
    estimates.push_back(e);
  }
  estimates[3].value.reset();  // left out
  const std::vector<GroupThreshold> groups = GroupThresholds(estimates);
  ASSERT_EQ(groups.size(), 1u);
  const LinePlot plot = GroupThresholdPlot(groups[0], estimates);
  EXPECT_TRUE(plot.log_y);
  EXPECT_EQ(plot.y_label, "threshold (ratio)");
  ASSERT_EQ(plot.x_tick_labels.size(), 5u);
  EXPECT_EQ(plot.x_tick_labels[2].second, "sub-03");
  EXPECT_EQ(plot.x_tick_labels[3].second, "sub-05");
  EXPECT_EQ(plot.x_tick_labels[4].second, "group");
  ASSERT_EQ(plot.series.size(), 3u);
  EXPECT_EQ(plot.series[0].x, (std::vector<double>{1, 2, 4}));
  EXPECT_EQ(plot.series[0].y_high[2], 1.4 * 1.25);
  EXPECT_EQ(plot.series[1].label, "subject, interval at a search limit");
  EXPECT_TRUE(std::isnan(plot.series[1].y_low[0]));
  EXPECT_EQ(plot.series[2].y[0], groups[0].geometric_mean);
  EXPECT_EQ(plot.series[2].y_low[0], groups[0].geometric_ci_low);
  ASSERT_EQ(plot.reference_lines.size(), 1u);
  EXPECT_EQ(plot.reference_lines[0].value, 1.0);
  EXPECT_EQ(testing::CompareWithGolden(plot, "group_thresholds"), "");
}

}  // namespace
}  // namespace burrlab::analysis
