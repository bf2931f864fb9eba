// The trial state machine of a subject station, free of windows and devices:
// ready -> intervals (timed, or subject-paced) -> response -> next trial, with
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

class StationController {
 public:
  StationController(int trials_total, std::string device_name,
                    double max_force_n);

  // Shows `trial` (trials_done completed before it) in the ready phase.
  void BeginTrial(const protocols::TrialSpec& trial, int trials_done);
  // The subject starts the trial (space) or ends a subject-paced interval.
  void Start(double now_s);
  // Moves through the timed intervals up to the question.
  void Advance(double now_s);
  // A key (as named in ResponseButton::key, or "SPACE") or a clicked answer.
  // Returns the response when it answers the question; the response time is
  // from the moment the question appeared.
  std::optional<protocols::Response> OnInput(std::string_view key_or_answer,
                                             double now_s);
  // A live window: the question first reached the screen at now_s (the
  // first call in a response phase counts); the response time then counts
  // from there, not from when the last interval was due to end.
  void MarkQuestionShown(double now_s);
  // Pauses with a reason for both views; a trial under way is aborted (it
  // will be presented again from the start after Resume).
  void Pause(std::string reason);
  // Back to the ready phase of the current trial.
  void Resume();
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
  StationPhase phase() const { return frame_.subject.phase; }
  // The interval shown (0-based; meaningful in kInterval).
  std::size_t interval_index() const { return interval_; }
  // When the interval shown started, s on the session clock.
  double interval_start_s() const { return interval_start_s_; }
  // Whether the trial shown was cut short by a pause (reset by BeginTrial).
  bool trial_aborted() const { return trial_aborted_; }
  int aborted_trials() const { return aborted_trials_; }

 private:
  void EnterInterval(std::size_t index, double now_s);
  void EnterResponse(double now_s);

  StationFrame frame_;
  std::optional<protocols::TrialSpec> trial_;
  std::size_t interval_ = 0;
  double interval_start_s_ = 0.0;
  double question_start_s_ = 0.0;
  bool question_shown_ = false;  // MarkQuestionShown came in this phase
  bool trial_aborted_ = false;
  int aborted_trials_ = 0;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_CONTROLLER_H_
