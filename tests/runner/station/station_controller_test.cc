// The station's trial state machine: phases, keys, response times, pause and
// abort, without a window.
#include "station/station_controller.h"

#include <gtest/gtest.h>

namespace burrlab::runner {
namespace {

protocols::TrialSpec TwoIntervals(double duration_s) {
  protocols::TrialSpec t;
  t.trial_index = 4;
  t.block = "probe2afc";
  t.method = protocols::Method::kTwoInterval;
  t.task = protocols::Task::kProbe;
  t.question = "Which interval held the plastic bone?";
  t.response_options = {"1", "2"};
  t.intervals.resize(2);
  for (auto& i : t.intervals) i.duration_s = duration_s;
  return t;
}

TEST(ResponseButtonsFor, SingleCharacterOptionsAreTheirOwnKeys) {
  const auto b = ResponseButtonsFor({"1", "2"});
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b[0].key, "1");
  EXPECT_EQ(b[1].key, "2");
}

TEST(ResponseButtonsFor, WordsUseTheirFirstLetterWhenTheyDiffer) {
  const auto b = ResponseButtonsFor({"same", "different"});
  EXPECT_EQ(b[0].key, "S");
  EXPECT_EQ(b[1].key, "D");
}

TEST(ResponseButtonsFor, ClashingFirstLettersFallBackToNumbers) {
  const auto b = ResponseButtonsFor({"softer", "stiffer", "equal"});
  EXPECT_EQ(b[0].key, "1");
  EXPECT_EQ(b[1].key, "2");
  EXPECT_EQ(b[2].key, "3");
}

TEST(StationController, RunsTimedIntervalsThenAsks) {
  StationController c(12, "mouse", 8.0);
  c.BeginTrial(TwoIntervals(5.0), 3);
  EXPECT_EQ(c.phase(), StationPhase::kReady);
  EXPECT_EQ(c.frame().subject.title, "Trial 4 of 12");
  EXPECT_EQ(c.frame().experimenter.trial_line,
            "trial 5, block probe2afc, two_interval, probe");
  EXPECT_FALSE(c.OnInput("1", 0.0).has_value());  // not asked yet
  (void)c.OnInput("space", 10.0);
  EXPECT_EQ(c.frame().subject.interval_label, "Interval 1 of 2");
  c.Advance(13.5);
  EXPECT_NEAR(c.frame().subject.time_left_s, 1.5, 1e-12);
  c.Advance(16.0);
  EXPECT_EQ(c.frame().subject.interval_label, "Interval 2 of 2");
  EXPECT_NEAR(c.frame().subject.time_left_s, 4.0, 1e-12);
  c.Advance(30.0);  // both over: the question came at 20 s
  ASSERT_EQ(c.phase(), StationPhase::kResponse);
  EXPECT_FALSE(c.OnInput("3", 30.0).has_value());
  const auto r = c.OnInput("2", 30.25);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->answer, "2");
  EXPECT_NEAR(*r->response_time_s, 10.25, 1e-12);
  EXPECT_EQ(c.frame().experimenter.last_event,
            "trial 5: answered 2 after 10.25 s");
}

TEST(StationController, ResponseTimeCountsFromWhenTheQuestionWasShown) {
  StationController c(1, "simulated", 8.0);
  c.BeginTrial(TwoIntervals(5.0), 0);
  (void)c.OnInput("SPACE", 10.0);
  c.MarkQuestionShown(12.0);  // not asked yet: ignored
  c.Advance(20.5);            // the question was due at 20 s
  ASSERT_EQ(c.phase(), StationPhase::kResponse);
  c.MarkQuestionShown(20.6);  // the frame that showed it
  c.MarkQuestionShown(21.0);  // later frames change nothing
  const auto r = c.OnInput("1", 21.1);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(*r->response_time_s, 0.5, 1e-12);
}

TEST(StationController, SubjectPacedIntervalsEndWithSpace) {
  StationController c(1, "hid", 0.0);
  c.BeginTrial(TwoIntervals(0.0), 0);
  (void)c.OnInput("SPACE", 1.0);
  c.Advance(100.0);
  EXPECT_EQ(c.frame().subject.interval_label, "Interval 1 of 2");
  EXPECT_EQ(c.frame().subject.message,
            "Feel the real sample, then press SPACE.");
  (void)c.OnInput("SPACE", 101.0);
  (void)c.OnInput("SPACE", 102.0);
  EXPECT_EQ(c.phase(), StationPhase::kResponse);
}

TEST(StationController, PauseMidTrialAbortsItAndResumeStartsItAgain) {
  StationController c(12, "hid", 8.0);
  c.BeginTrial(TwoIntervals(5.0), 0);
  (void)c.OnInput("SPACE", 0.0);
  c.Pause("the response box was unplugged");
  EXPECT_EQ(c.phase(), StationPhase::kPaused);
  EXPECT_TRUE(c.trial_aborted());
  EXPECT_EQ(c.aborted_trials(), 1);
  EXPECT_EQ(c.frame().subject.message,
            "Paused: the response box was unplugged");
  EXPECT_EQ(c.frame().experimenter.last_event,
            "trial 5 aborted: the response box was unplugged");
  EXPECT_FALSE(c.OnInput("1", 1.0).has_value());
  c.Resume();
  EXPECT_EQ(c.phase(), StationPhase::kReady);
  EXPECT_FALSE(c.frame().experimenter.paused);
}

TEST(StationController, PauseBetweenTrialsAbortsNothing) {
  StationController c(12, "mouse", 8.0);
  c.BeginTrial(TwoIntervals(5.0), 0);
  c.Pause("experimenter");
  EXPECT_FALSE(c.trial_aborted());
  EXPECT_EQ(c.aborted_trials(), 0);
}

TEST(StationController, AbortEndsTheSession) {
  StationController c(12, "mouse", 8.0);
  c.BeginTrial(TwoIntervals(5.0), 0);
  (void)c.OnInput("SPACE", 0.0);
  c.Abort("experimenter pressed Abort");
  EXPECT_EQ(c.phase(), StationPhase::kFinished);
  EXPECT_TRUE(c.frame().experimenter.aborted);
  EXPECT_EQ(c.frame().subject.message,
            "The session was stopped: experimenter pressed Abort");
  (void)c.OnInput("SPACE", 1.0);
  EXPECT_EQ(c.phase(), StationPhase::kFinished);
}

}  // namespace
}  // namespace burrlab::runner
