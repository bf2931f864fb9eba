// Tests of the observer_* columns of participants.tsv: a simulated subject's
// true parameters written so they read back exactly, each column described
// (with its unit where it has one), and no column an experimenter's value
// could take by accident without being refused.
#include "studies/participant_rows.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "burrlab/results_schema/participants.h"

namespace burrlab::runner {
namespace {

TEST(ParticipantRows, ObserverValuesReadBackExactly) {
  protocols::ObserverParams o;
  o.weber_stiffness = 0.1 + 0.2;  // 0.30000000000000004
  o.weber_removal = 0.25;
  o.lapse = 0.0;
  o.criterion = 1.5;
  o.rule = protocols::SameDifferentRule::kLikelihood;
  o.bias = -0.5;
  o.exploration.force_factor = 1.1;
  o.exploration.speed_factor = 0.9;
  o.exploration.force_spread = 0.15;
  o.exploration.speed_spread = 0.12;
  o.exploration.subject_force_spread = 0.05;  // the population's: no column
  o.rt_median_s = 0.8;
  o.rt_log_sd = 0.35;
  o.match_tolerance = 0.5;
  o.answers = protocols::AnswerRule::kAlwaysWrong;
  const std::vector<results_schema::ParticipantValue> values =
      ObserverParticipantValues(o);
  const std::vector<results_schema::ParticipantValue> expected = {
      {"observer_weber_stiffness", "0.30000000000000004"},
      {"observer_weber_removal", "0.25"},
      {"observer_lapse", "0"},
      {"observer_criterion", "1.5"},
      {"observer_rule", "likelihood"},
      {"observer_bias", "-0.5"},
      {"observer_force_factor", "1.1"},
      {"observer_speed_factor", "0.9"},
      {"observer_force_spread", "0.15"},
      {"observer_speed_spread", "0.12"},
      {"observer_rt_median", "0.8"},
      {"observer_rt_log_sd", "0.35"},
      {"observer_match_tolerance", "0.5"},
      {"observer_answers", "always_wrong"}};
  EXPECT_EQ(values, expected);
  EXPECT_EQ(std::stod(values[0].value), o.weber_stiffness);
}

TEST(ParticipantRows, EveryObserverColumnIsDescribedAndValid) {
  const std::vector<results_schema::ParticipantValue> values =
      ObserverParticipantValues(protocols::ObserverParams{});
  const auto& columns = ObserverParticipantColumns();
  ASSERT_EQ(columns.size(), values.size());
  for (std::size_t i = 0; i < columns.size(); ++i) {
    EXPECT_EQ(columns[i].name, values[i].column);
    EXPECT_TRUE(IsObserverColumn(columns[i].name)) << columns[i].name;
    EXPECT_TRUE(results_schema::CheckParticipantColumn(columns[i].name).ok())
        << columns[i].name;
    EXPECT_FALSE(columns[i].description.empty()) << columns[i].name;
  }
  EXPECT_EQ(columns[10].name, "observer_rt_median");
  EXPECT_EQ(columns[10].units, "s");
  std::set<std::string> levels;
  ASSERT_EQ(columns[13].name, "observer_answers");
  for (const auto& [value, meaning] : columns[13].levels) levels.insert(value);
  EXPECT_EQ(levels, (std::set<std::string>{"percepts", "always_correct",
                                           "always_wrong"}));
  // Every rule a value can name is a level.
  levels.clear();
  ASSERT_EQ(columns[4].name, "observer_rule");
  for (const auto& [value, meaning] : columns[4].levels) levels.insert(value);
  EXPECT_EQ(levels,
            (std::set<std::string>{"fixed", "differencing", "likelihood"}));
  EXPECT_FALSE(IsObserverColumn("age"));
}

}  // namespace
}  // namespace burrlab::runner
