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

// A trial with what a paced protocol puts before it and around it.
protocols::TrialSpec Paced() {
  protocols::TrialSpec t = TwoIntervals(5.0);
  t.study_instructions = "Feel both intervals.";
  t.break_before = true;
  t.block_instructions = "Practice: you will be told if you are right.";
  t.practice = true;
  t.feedback = true;
  t.isi_s = 0.5;
  t.iti_s = 2.0;
  return t;
}

TEST(StationController, InstructionsAndABreakComeBeforeTheTrialOnce) {
  StationController c(12, "mouse", 8.0);
  c.BeginTrial(Paced(), 0);
  ASSERT_EQ(c.phase(), StationPhase::kInstructions);
  EXPECT_EQ(c.screen(), "instructions_study");
  EXPECT_EQ(c.frame().subject.panel_heading, "Instructions");
  EXPECT_EQ(c.frame().subject.panel_text, "Feel both intervals.");
  EXPECT_EQ(c.frame().subject.message, "Press SPACE to continue.");
  (void)c.OnInput("1", 1.0);  // only SPACE goes on from instructions
  EXPECT_EQ(c.screen(), "instructions_study");
  (void)c.OnInput("SPACE", 2.0);
  ASSERT_EQ(c.phase(), StationPhase::kBreak);
  EXPECT_EQ(c.frame().subject.panel_heading, "Rest break");
  EXPECT_EQ(c.frame().subject.message, "Press any key to continue.");
  (void)c.OnInput("Q", 3.0);  // any key ends a rest break
  ASSERT_EQ(c.phase(), StationPhase::kInstructions);
  EXPECT_EQ(c.screen(), "instructions_block");
  EXPECT_EQ(c.frame().subject.title, "Practice");
  EXPECT_EQ(c.frame().subject.panel_text,
            "Practice: you will be told if you are right.");
  (void)c.OnInput("SPACE", 4.0);
  ASSERT_EQ(c.phase(), StationPhase::kReady);
  EXPECT_EQ(c.frame().subject.title, "Practice - Trial 1 of 12");
  EXPECT_EQ(c.frame().subject.panel_heading, "");
  EXPECT_EQ(c.frame().experimenter.trial_line,
            "trial 5, block probe2afc, two_interval, probe, practice");
  // Paused mid-trial and presented again: straight to the ready phase.
  (void)c.OnInput("SPACE", 5.0);
  c.Pause("experimenter");
  c.Resume();
  c.BeginTrial(Paced(), 0);
  EXPECT_EQ(c.phase(), StationPhase::kReady);
}

// The window wraps the instructions: a TOML multi-line string's line breaks
// within a paragraph are spaces there; a blank line starts a paragraph.
TEST(StationController, InstructionsAreReflowedIntoParagraphs) {
  StationController c(1, "mouse", 8.0);
  protocols::TrialSpec t = TwoIntervals(5.0);
  t.study_instructions =
      "Each trial has two intervals.\nFeel both,  \r\n  then answer.\n\n\n"
      "Take your time.\n";
  c.BeginTrial(t, 0);
  EXPECT_EQ(c.frame().subject.title, "Welcome");
  EXPECT_EQ(c.frame().subject.panel_text,
            "Each trial has two intervals. Feel both, then answer.\n\nTake "
            "your time.");
}

TEST(StationController, APauseDuringTheInstructionsShowsThemAgain) {
  StationController c(12, "mouse", 8.0);
  c.BeginTrial(Paced(), 0);
  (void)c.OnInput("SPACE", 1.0);  // to the break
  c.Pause("experimenter");
  EXPECT_FALSE(c.trial_aborted());  // nothing of the trial was shown
  c.Resume();
  c.BeginTrial(Paced(), 0);
  EXPECT_EQ(c.screen(), "instructions_study");
}

TEST(StationController, ABlankGapSeparatesTheIntervals) {
  StationController c(12, "mouse", 8.0);
  protocols::TrialSpec t = TwoIntervals(5.0);
  t.isi_s = 0.5;
  c.BeginTrial(t, 0);
  (void)c.OnInput("SPACE", 0.0);
  c.Advance(5.2);
  ASSERT_EQ(c.phase(), StationPhase::kIsi);
  EXPECT_EQ(c.screen(), "isi1");
  EXPECT_NEAR(c.frame().subject.time_left_s, 0.3, 1e-12);
  EXPECT_EQ(c.frame().subject.panel_text, "Interval 2 of 2 comes next.");
  (void)c.OnInput("SPACE", 5.3);  // the gap is not the subject's to end
  EXPECT_EQ(c.phase(), StationPhase::kIsi);
  c.Advance(5.6);
  ASSERT_EQ(c.phase(), StationPhase::kInterval);
  EXPECT_EQ(c.screen(), "interval2");
  EXPECT_NEAR(c.interval_start_s(), 5.5, 1e-12);  // when the gap ended
  c.Advance(20.0);
  ASSERT_EQ(c.phase(), StationPhase::kResponse);
  const auto r = c.OnInput("1", 11.0);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(*r->response_time_s, 0.5, 1e-12);  // asked at 10.5 s
  // A pause in the gap cuts the trial short, as in an interval.
  c.BeginTrial(t, 1);
  (void)c.OnInput("SPACE", 30.0);
  c.Advance(35.1);
  ASSERT_EQ(c.phase(), StationPhase::kIsi);
  c.Pause("experimenter");
  EXPECT_TRUE(c.trial_aborted());
}

TEST(StationController, FeedbackForASecondOrUntilAKeyThenTheGap) {
  StationController c(12, "mouse", 8.0);
  c.BeginTrial(Paced(), 0);
  c.BeginAfterAnswer(true, 100.0);
  ASSERT_TRUE(c.after_answer());
  ASSERT_EQ(c.phase(), StationPhase::kFeedback);
  EXPECT_EQ(c.frame().subject.panel_heading, "Correct");
  EXPECT_TRUE(c.frame().subject.panel_good);
  c.Advance(100.9);
  EXPECT_EQ(c.phase(), StationPhase::kFeedback);
  c.Advance(101.0);  // kFeedbackS later: the gap after the answer
  ASSERT_EQ(c.phase(), StationPhase::kIti);
  EXPECT_EQ(c.frame().subject.panel_heading, "");
  c.Advance(102.9);
  EXPECT_TRUE(c.after_answer());
  c.Advance(103.0);  // iti_s = 2 s after the feedback
  EXPECT_FALSE(c.after_answer());

  c.BeginAfterAnswer(false, 200.0);
  EXPECT_EQ(c.frame().subject.panel_heading, "Wrong");
  EXPECT_FALSE(c.frame().subject.panel_good);
  (void)c.OnInput("W", 200.25);  // a key ends the feedback
  ASSERT_EQ(c.phase(), StationPhase::kIti);
  c.Advance(202.25);
  EXPECT_FALSE(c.after_answer());

  // No feedback where the trial has no verdict; no gap where iti_s is 0.
  c.BeginAfterAnswer(std::nullopt, 300.0);
  EXPECT_EQ(c.phase(), StationPhase::kIti);
  protocols::TrialSpec plain = TwoIntervals(5.0);
  c.BeginTrial(plain, 1);
  c.BeginAfterAnswer(true, 400.0);
  EXPECT_FALSE(c.after_answer());
  EXPECT_EQ(c.phase(), StationPhase::kReady);
}

TEST(StationController, ALateAnswerIsTakenAndShownAsLate) {
  StationController c(12, "mouse", 8.0);
  protocols::TrialSpec t = TwoIntervals(5.0);
  t.response_deadline_s = 2.0;
  c.BeginTrial(t, 0);
  (void)c.OnInput("SPACE", 10.0);
  c.Advance(21.0);  // asked at 20 s
  ASSERT_EQ(c.phase(), StationPhase::kResponse);
  EXPECT_EQ(c.frame().subject.message, "Answer with a key or click a button.");
  c.Advance(22.5);
  EXPECT_EQ(c.frame().subject.message, "Time is up: please answer now.");
  const auto r = c.OnInput("2", 23.0);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(*r->response_time_s, 3.0, 1e-12);
  EXPECT_EQ(c.frame().experimenter.last_event,
            "trial 5: answered 2 after 3.00 s (late)");
}

// An adjustment: UP and DOWN (or the + and - buttons) ask for a step; the
// station presents the comparison at the level it reaches as one more
// interval and asks again; a step past max_steps is refused with a message;
// ENTER answers with the path, timed from the first question.
TEST(StationController, AdjustmentStepsPresentTheComparisonAgainUntilEnter) {
  StationController c(0, "mouse", 8.0);
  protocols::TrialSpec t = TwoIntervals(2.0);
  t.method = protocols::Method::kAdjustment;
  t.response_options.clear();
  t.intervals[0].role = "standard";
  t.intervals[1].role = "comparison";
  c.BeginTrial(t, 0);
  ASSERT_EQ(c.frame().subject.buttons.size(), 3u);
  EXPECT_EQ(c.frame().subject.buttons[0].answer, "+");
  EXPECT_EQ(c.frame().subject.buttons[0].key, "UP");
  EXPECT_EQ(c.frame().subject.buttons[2].key, "ENTER");
  (void)c.OnInput("SPACE", 10.0);
  EXPECT_EQ(c.frame().subject.interval_label, "Standard");
  c.Advance(12.5);
  EXPECT_EQ(c.frame().subject.interval_label, "Comparison");
  c.Advance(14.0);  // asked at 14 s
  ASSERT_EQ(c.phase(), StationPhase::kResponse);
  EXPECT_FALSE(c.TakeAdjustmentStep().has_value());
  EXPECT_FALSE(c.OnInput("up", 15.0).has_value());
  EXPECT_EQ(c.TakeAdjustmentStep(), std::optional<int>(1));
  EXPECT_FALSE(c.TakeAdjustmentStep().has_value());  // taken once
  protocols::PlannedInterval after = t.intervals[1];
  after.level = 1.1;
  c.PresentAdjustedComparison(after, '+', 15.0);
  EXPECT_EQ(c.phase(), StationPhase::kInterval);
  EXPECT_EQ(c.interval_index(), 2u);
  EXPECT_EQ(c.screen(), "interval3");
  EXPECT_EQ(c.frame().subject.interval_label, "Comparison after step 1");
  ASSERT_EQ(c.trial().intervals.size(), 3u);
  EXPECT_EQ(c.trial().intervals[2].level, std::optional<double>(1.1));
  c.Advance(17.0);
  ASSERT_EQ(c.phase(), StationPhase::kResponse);
  EXPECT_EQ(c.frame().subject.message,
            "UP raises the comparison one step, DOWN lowers it; you then feel "
            "it again. ENTER when it matches. Steps taken: 1.");
  (void)c.OnInput("-", 18.0);  // a clicked button
  EXPECT_EQ(c.TakeAdjustmentStep(), std::optional<int>(-1));
  c.RefuseAdjustmentStep();
  EXPECT_EQ(c.phase(), StationPhase::kResponse);
  EXPECT_EQ(c.frame().subject.message,
            "No more steps: this adjustment allows 1. Press ENTER to finish.");
  EXPECT_EQ(c.adjustment_path(), "+");
  const auto r = c.OnInput("ENTER", 19.5);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->answer, "+=");
  EXPECT_NEAR(*r->response_time_s, 5.5, 1e-12);
  EXPECT_EQ(c.frame().experimenter.last_event,
            "trial 5: adjusted += in 5.50 s");
  // Presented again (after a pause), the adjustment starts afresh.
  c.BeginTrial(t, 0);
  EXPECT_EQ(c.adjustment_path(), "");
  EXPECT_EQ(c.trial().intervals.size(), 2u);
}

}  // namespace
}  // namespace burrlab::runner
