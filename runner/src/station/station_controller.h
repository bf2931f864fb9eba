// The trial state machine of a subject station, free of windows and devices:
// [instructions, rest break] -> ready -> intervals (timed, or subject-paced;
// a blank gap between them) -> response -> [feedback, gap] -> next trial, with
// pause, resume and abort. Inputs carry their own times (s on the session
// clock), so a script drives it exactly as a person would, and the frame it
// produces is what the window draws.
#ifndef BURRLAB_RUNNER_STATION_STATION_CONTROLLER_H_
#define BURRLAB_RUNNER_STATION_STATION_CONTROLLER_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/protocols/engine.h"
#include "station/station_frame.h"

namespace burrlab::runner {

// The key of each response option: the option itself, upper-cased, when every
// option is one character; else each option's upper-cased first letter when
// those differ; else "1", "2", ... in order.
std::vector<ResponseButton> ResponseButtonsFor(
    const std::vector<std::string>& options);

// The buttons of an adjustment's question: "+" (UP) steps the comparison
// level up, "-" (DOWN) down, "=" (ENTER) ends the adjustment.
std::vector<ResponseButton> AdjustmentButtons();

// How long "Correct" or "Wrong" stays up unless a key ends it, s.
inline constexpr double kFeedbackS = 1.0;

class StationController {
 public:
  StationController(int trials_total, std::string device_name,
                    double max_force_n);

  // Shows `trial` (trials_done completed before it): first what comes before
  // it (the study's instructions, a rest break, the block's instructions:
  // TrialSpec), once per trial (a trial presented again after a pause goes
  // straight to ready), then the ready phase.
  void BeginTrial(const protocols::TrialSpec& trial, int trials_done);
  // The subject starts the trial (space), ends a subject-paced interval, or
  // goes on from instructions.
  void Start(double now_s);
  // Moves through the timed intervals and the gaps between them up to the
  // question, through feedback and the gap after the answer, and marks the
  // question late once its deadline has passed.
  void Advance(double now_s);
  // A key (as named in ResponseButton::key, or "SPACE") or a clicked answer.
  // Returns the response when it answers the question; the response time is
  // from the moment the question appeared. Any key ends a rest break and
  // feedback; SPACE goes on from instructions. In an adjustment, "+" and "-"
  // ask for a step (TakeAdjustmentStep) and "=" answers with the path taken
  // ("++-="), timed from the adjustment's first question.
  std::optional<protocols::Response> OnInput(std::string_view key_or_answer,
                                             double now_s);
  // Adjustment trials: the step asked for by the last key (+1 up, -1 down),
  // once; none when no step is waiting.
  std::optional<int> TakeAdjustmentStep();
  // The steps taken so far ('+' and '-').
  const std::string& adjustment_path() const { return adjustment_path_; }
  // Takes the step (`step` is '+' or '-') and presents the comparison at the
  // level it reaches as the trial's next interval, from now_s.
  void PresentAdjustedComparison(protocols::PlannedInterval comparison,
                                 char step, double now_s);
  // The step cannot be taken (the block's max_steps): says so and keeps
  // asking.
  void RefuseAdjustmentStep();
  // After the trial's answer was saved: "Correct" or "Wrong" for kFeedbackS
  // (or until a key) when the trial gives feedback and `correct` is known,
  // then the trial's gap after the answer (iti_s), from now_s.
  void BeginAfterAnswer(std::optional<bool> correct, double now_s);
  // Whether feedback or the gap after the answer is still shown.
  bool after_answer() const { return after_answer_; }
  // The screen shown, for screenshot names: the phase's name, with the
  // interval's number ("interval2"), the number of the interval a gap follows
  // ("isi1") or whose instructions ("instructions_study",
  // "instructions_block").
  std::string screen() const;
  // A live window: the question first reached the screen at now_s (the
  // first call in a response phase counts); the response time then counts
  // from there, not from when the last interval was due to end.
  void MarkQuestionShown(double now_s);
  // Pauses with a reason for both views; a trial under way is aborted (it
  // will be presented again from the start after Resume).
  void Pause(std::string reason);
  // Back to the ready phase of the current trial.
  void Resume();  // (what came before the trial, if cut short, is shown
                  // again by the next BeginTrial)
  // Ends the session: nothing more is presented.
  void Abort(std::string reason);
  // Marks the session as finished after the last trial.
  void Finish();

  void SetForce(double force_n) { frame_.subject.force_n = force_n; }
  void SetDeviceState(std::string state) {
    frame_.experimenter.device_state = std::move(state);
  }
  void SetLoop(std::int64_t ticks, double p50_us, double p99_us,
               std::int64_t missed);

  const StationFrame& frame() const { return frame_; }
  // The trial shown, with an adjustment's comparisons after each step
  // appended to its intervals (only after BeginTrial).
  const protocols::TrialSpec& trial() const { return *trial_; }
  StationPhase phase() const { return frame_.subject.phase; }
  // The interval shown (0-based; meaningful in kInterval).
  std::size_t interval_index() const { return interval_; }
  // When the interval shown started, s on the session clock.
  double interval_start_s() const { return interval_start_s_; }
  // Whether the trial shown was cut short by a pause (reset by BeginTrial).
  bool trial_aborted() const { return trial_aborted_; }
  int aborted_trials() const { return aborted_trials_; }

 private:
  // One screen before the trial.
  struct IntroStep {
    StationPhase phase = StationPhase::kInstructions;
    std::string text;    // kInstructions: the protocol's text
    bool study = false;  // kInstructions: the study's, not the block's
  };

  void EnterIntroStep(std::size_t index);
  void EnterReady();
  void EnterInterval(std::size_t index, double now_s);
  // The next interval after `interval_`, or the blank gap before it.
  void EndInterval(double end_s);
  void EnterResponse(double now_s);
  void EnterIti(double now_s);
  void EndAfterAnswer();
  std::string TrialTitle() const;

  StationFrame frame_;
  std::optional<protocols::TrialSpec> trial_;
  int trials_done_ = 0;
  std::vector<IntroStep> intro_;
  std::size_t intro_index_ = 0;
  std::optional<int> intro_done_for_;  // trial index whose intro was shown
  std::size_t interval_ = 0;
  double interval_start_s_ = 0.0;
  double gap_start_s_ = 0.0;  // kIsi, kFeedback, kIti: when it began
  double question_start_s_ = 0.0;
  bool question_shown_ = false;      // MarkQuestionShown came in this phase
  std::string adjustment_path_;      // steps taken in this adjustment
  std::optional<int> pending_step_;  // asked for, not yet taken
  double adjustment_start_s_ = 0.0;  // its first question appeared
  bool after_answer_ = false;
  bool trial_aborted_ = false;
  int aborted_trials_ = 0;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_CONTROLLER_H_
