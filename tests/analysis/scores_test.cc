// Tests of scores per block: group statistics and same-different d' against
// R (t.test, binom.test, psyphy dprime.SD; tests/analysis/fixtures/r/
// scores_fixture.R), missed answers, blocks without a chance level, and the
// histogram's bars.
#include "burrlab/analysis/scores.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace burrlab::analysis {
namespace {

using results_schema::BehFile;
using results_schema::TrialRecord;

// A 12-trial same-different block: 6 different (AB/BA) trials of which
// `hits` are answered "different", 6 same (AA/BB) trials of which
// `false_alarms` are; `missed` different trials get no answer.
BehFile SameDifferentSubject(const std::string& subject, int hits,
                             int false_alarms, int missed = 0) {
  BehFile f;
  f.subject = subject;
  f.task = "probe";
  for (int i = 0; i < 12; ++i) {
    TrialRecord t;
    t.trial_index = i;
    t.block = "probe";
    t.method = "same_different";
    t.task = "probe";
    const bool different = i < 6;
    t.trial_type = different ? (i % 2 ? "AB" : "BA") : (i % 2 ? "AA" : "BB");
    t.correct_answer = different ? "different" : "same";
    const int k = different ? i : i - 6;
    const bool says_different = different ? k < hits : k < false_alarms;
    if (different && k >= 6 - missed) {
      t.response = "";
    } else {
      t.response = says_different ? "different" : "same";
    }
    t.correct = t.response == t.correct_answer;
    f.table.trials.push_back(t);
  }
  return f;
}

TEST(ScoresAgainstR, SameDifferentBlockOfThreeSubjects) {
  const std::vector<BehFile> files = {SameDifferentSubject("01", 5, 2),
                                      SameDifferentSubject("02", 6, 1),
                                      SameDifferentSubject("03", 4, 3)};
  Result<std::vector<BlockScores>> blocks = ScoreBlocks(files);
  ASSERT_TRUE(blocks.ok()) << blocks.error().message;
  ASSERT_EQ(blocks->size(), 1u);
  const BlockScores& b = (*blocks)[0];
  EXPECT_EQ(b.method, "same_different");
  EXPECT_EQ(b.chance, 0.5);
  EXPECT_EQ(b.trials_per_subject, 12);
  ASSERT_EQ(b.subjects.size(), 3u);
  EXPECT_EQ(b.subjects[0].correct, 9);
  EXPECT_EQ(b.subjects[1].correct, 11);
  EXPECT_EQ(b.subjects[2].correct, 7);
  // R: mean(c(9,11,7)), sd(...)/sqrt(3); t.test(c(9,11,7)/12, mu = 0.5).
  EXPECT_NEAR(b.mean_score->mean, 9.0, 1e-12);
  EXPECT_NEAR(b.mean_score->sem, 1.1547005383792517, 1e-12);
  ASSERT_TRUE(b.t_test.has_value());
  EXPECT_NEAR(b.t_test->t, 2.5980762113533165, 1e-9);
  EXPECT_EQ(b.t_test->df, 2.0);
  EXPECT_NEAR(b.t_test->p_two_sided, 0.12168993434632006, 1e-9);
  EXPECT_NEAR(b.t_test->p_greater, 0.060844967173160028, 1e-9);
  // R: binom.test(27, 36, 0.5).
  ASSERT_TRUE(b.binomial.has_value());
  EXPECT_EQ(b.binomial->successes, 27);
  EXPECT_EQ(b.binomial->trials, 36);
  EXPECT_NEAR(b.binomial->p_two_sided, 0.0039331730222329541, 1e-12);
  EXPECT_NEAR(b.binomial->p_greater, 0.001966586511116477, 1e-12);
  EXPECT_NEAR(b.binomial->ci_low, 0.57797041542185601, 1e-9);
  EXPECT_NEAR(b.binomial->ci_high, 0.87879670587616476, 1e-9);
  // psyphy dprime.SD (uniroot tolerance limits it to ~3e-5).
  const SameDifferentRates& r1 = *b.subjects[0].rates;
  EXPECT_EQ(r1.hits, 5);
  EXPECT_EQ(r1.false_alarms, 2);
  EXPECT_FALSE(r1.corrected);
  EXPECT_NEAR(*r1.dprime_differencing, 2.7255795818606514, 1e-4);
  EXPECT_NEAR(*r1.dprime_independent_observation, 2.1515828219451034, 1e-4);
  const SameDifferentRates& r2 = *b.subjects[1].rates;  // H = 1 -> 11/12
  EXPECT_TRUE(r2.corrected);
  EXPECT_EQ(r2.hit_rate, 1.0);
  EXPECT_NEAR(*r2.dprime_differencing, 3.9115449151007851, 1e-4);
  EXPECT_NEAR(*r2.dprime_independent_observation, 3.0427202015845696, 1e-4);
  const SameDifferentRates& r3 = *b.subjects[2].rates;
  EXPECT_NEAR(*r3.dprime_differencing, 1.3739693081984152, 1e-4);
  EXPECT_NEAR(*r3.dprime_independent_observation, 1.0861913287140548, 1e-4);
  const SameDifferentRates& pooled = *b.pooled_rates;  // 15/18, 6/18
  EXPECT_EQ(pooled.hits, 15);
  EXPECT_EQ(pooled.different_trials, 18);
  EXPECT_NEAR(*pooled.dprime_differencing, 2.7255795818606514, 1e-4);
  EXPECT_NEAR(*pooled.dprime_independent_observation, 2.1515828219451034, 1e-4);
}

TEST(Scores, MissedAnswersCountWrongAndLeaveTheRates) {
  const std::vector<BehFile> files = {SameDifferentSubject("01", 6, 0, 2),
                                      SameDifferentSubject("02", 6, 0)};
  Result<std::vector<BlockScores>> blocks = ScoreBlocks(files);
  ASSERT_TRUE(blocks.ok());
  const SubjectScore& s = (*blocks)[0].subjects[0];
  EXPECT_EQ(s.correct, 10);
  EXPECT_EQ(s.trials, 12);
  EXPECT_EQ(s.rates->different_trials, 4);
  EXPECT_EQ(s.rates->hits, 4);
}

TEST(Scores, DifferencingModelHasNoDPrimeBelowChance) {
  const SameDifferentRates r = RatesFromCounts(1, 6, 4, 6);
  EXPECT_FALSE(r.dprime_differencing.has_value());
  EXPECT_EQ(r.note, "H < F: the differencing model has no d'");
  ASSERT_TRUE(r.dprime_independent_observation.has_value());
  EXPECT_LT(*r.dprime_independent_observation, 0.0);
}

TEST(Scores, AdaptiveBlocksAreScoredButNotTested) {
  BehFile f;
  f.subject = "01";
  f.task = "stairs";
  for (int i = 0; i < 4; ++i) {
    TrialRecord t;
    t.trial_index = i;
    t.block = "stairs";
    t.method = "staircase";
    t.task = "probe";
    t.trial_type = "2afc";
    t.correct_answer = "1";
    t.response = i < 3 ? "1" : "2";
    t.correct = t.response == "1";
    f.table.trials.push_back(t);
  }
  BehFile g = f;
  g.subject = "02";
  Result<std::vector<BlockScores>> blocks =
      ScoreBlocks(std::vector<BehFile>{f, g});
  ASSERT_TRUE(blocks.ok());
  const BlockScores& b = (*blocks)[0];
  EXPECT_FALSE(b.chance.has_value());
  EXPECT_FALSE(b.t_test.has_value());
  EXPECT_FALSE(b.binomial.has_value());
  EXPECT_EQ(b.subjects[0].correct, 3);
  EXPECT_EQ(b.no_test_reason,
            "an adaptive track holds accuracy near its target, so its score "
            "says nothing against chance; see burrlab analyze thresholds");
}

TEST(Scores, EqualScoresGiveAWarningNotATest) {
  const std::vector<BehFile> files = {SameDifferentSubject("01", 5, 2),
                                      SameDifferentSubject("02", 5, 2)};
  Result<std::vector<BlockScores>> blocks = ScoreBlocks(files);
  ASSERT_TRUE(blocks.ok());
  EXPECT_FALSE((*blocks)[0].t_test.has_value());
  ASSERT_EQ((*blocks)[0].warnings.size(), 1u);
  EXPECT_EQ((*blocks)[0].warnings[0],
            "every subject has the same proportion correct: the t-test is "
            "undefined (zero variance)");
  EXPECT_TRUE((*blocks)[0].binomial.has_value());
}

TEST(Scores, NoScoredTrialsIsAnError) {
  BehFile f;
  f.subject = "01";
  TrialRecord t;
  t.block = "adjust";
  t.method = "adjustment";
  t.task = "drill";
  f.table.trials.push_back(t);
  Result<std::vector<BlockScores>> blocks =
      ScoreBlocks(std::vector<BehFile>{f});
  ASSERT_FALSE(blocks.ok());
  EXPECT_EQ(blocks.error().message,
            "no block has trials with a correct answer (adjustment and limits "
            "blocks have none; see burrlab analyze thresholds)");
}

// Practice trials (§13.5.1's familiarization) are recorded but never
// scored: a practice block is left out whole, and PracticeTrials says how
// many trials that was.
TEST(Scores, PracticeTrialsAreLeftOutAndCounted) {
  std::vector<BehFile> files;
  for (const std::string subject : {"01", "02"}) {
    BehFile practice = SameDifferentSubject(subject, 0, 6);  // all wrong
    for (TrialRecord& t : practice.table.trials) {
      t.block = "familiarize";
      t.practice = true;
    }
    files.push_back(practice);
    files.push_back(SameDifferentSubject(subject, 6, 0));  // all right
  }
  Result<std::vector<BlockScores>> blocks = ScoreBlocks(files);
  ASSERT_TRUE(blocks.ok()) << blocks.error().message;
  ASSERT_EQ(blocks->size(), 1u);
  EXPECT_EQ((*blocks)[0].block, "probe");
  EXPECT_EQ((*blocks)[0].subjects[0].correct, 12);
  EXPECT_EQ((*blocks)[0].subjects[0].trials, 12);
  const std::vector<PracticeLeftOut> left_out = PracticeTrials(files);
  ASSERT_EQ(left_out.size(), 1u);
  EXPECT_EQ(left_out[0].block, "familiarize");
  EXPECT_EQ(left_out[0].trials, 24);
  // Practice alone scores nothing.
  const std::vector<BehFile> only = {files[0]};
  blocks = ScoreBlocks(only);
  ASSERT_FALSE(blocks.ok());
  EXPECT_EQ(blocks.error().message,
            "no block has scored trials with a correct answer (adjustment and "
            "limits blocks have none; see burrlab analyze thresholds); the 12 "
            "practice trials are never scored");
}

// Late answers are scored like the others and counted per subject and block,
// over the answers whose block had a deadline.
TEST(Scores, LateAnswersAreCountedPerBlockAndScored) {
  std::vector<BehFile> files = {SameDifferentSubject("01", 6, 0),
                                SameDifferentSubject("02", 6, 0)};
  for (BehFile& f : files) {
    for (TrialRecord& t : f.table.trials) t.late = false;
  }
  files[0].table.trials[0].late = true;
  files[0].table.trials[5].late = true;
  files[1].table.trials[11].late = true;
  files[1].table.trials[10].late = std::nullopt;  // time unknown
  Result<std::vector<BlockScores>> blocks = ScoreBlocks(files);
  ASSERT_TRUE(blocks.ok()) << blocks.error().message;
  const BlockScores& b = (*blocks)[0];
  EXPECT_EQ(b.answers_with_deadline, 23);
  EXPECT_EQ(b.late_answers, 3);
  EXPECT_EQ(b.subjects[0].late_answers, 2);
  EXPECT_EQ(b.subjects[1].late_answers, 1);
  EXPECT_EQ(b.subjects[0].correct, 12);  // late answers still count
}

TEST(ScoreHistogram, OneBarPerScoreWithALabelledChanceLine) {
  const std::vector<BehFile> files = {SameDifferentSubject("01", 5, 2),
                                      SameDifferentSubject("02", 6, 1),
                                      SameDifferentSubject("03", 5, 2)};
  Result<std::vector<BlockScores>> blocks = ScoreBlocks(files);
  ASSERT_TRUE(blocks.ok());
  const LinePlot plot = ScoreHistogram((*blocks)[0]);
  ASSERT_EQ(plot.series.size(), 1u);
  std::vector<double> expected(13, 0.0);
  expected[9] = 2.0;
  expected[11] = 1.0;
  EXPECT_EQ(plot.series[0].y, expected);
  ASSERT_EQ(plot.reference_lines.size(), 1u);
  EXPECT_TRUE(plot.reference_lines[0].vertical);
  EXPECT_DOUBLE_EQ(plot.reference_lines[0].value, 6.0);
  EXPECT_EQ(plot.reference_lines[0].label, "chance 6 of 12");
  EXPECT_TRUE(RenderPlot(plot).ok());
}

}  // namespace
}  // namespace burrlab::analysis
