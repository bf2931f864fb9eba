// The station's trial state machine.
#include "station/station_controller.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <set>

namespace burrlab::runner {

std::string_view StationPhaseName(StationPhase phase) noexcept {
  switch (phase) {
    case StationPhase::kReady:
      return "ready";
    case StationPhase::kInterval:
      return "interval";
    case StationPhase::kResponse:
      return "response";
    case StationPhase::kPaused:
      return "paused";
    case StationPhase::kFinished:
      return "finished";
  }
  return "?";
}

namespace {

std::string Upper(std::string_view text) {
  std::string out(text);
  for (char& c : out) {
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return out;
}

}  // namespace

std::vector<ResponseButton> ResponseButtonsFor(
    const std::vector<std::string>& options) {
  std::vector<ResponseButton> buttons;
  const bool single = std::all_of(
      options.begin(), options.end(),
      [](const std::string& o) { return o.size() == 1 && o[0] != ' '; });
  std::set<std::string> firsts;
  for (const std::string& o : options) {
    if (!o.empty()) firsts.insert(Upper(o.substr(0, 1)));
  }
  const bool distinct_firsts = firsts.size() == options.size() &&
                               !firsts.contains(" ") && !options.empty();
  for (std::size_t i = 0; i < options.size(); ++i) {
    ResponseButton b;
    b.answer = options[i];
    if (single) {
      b.key = Upper(options[i]);
    } else if (distinct_firsts) {
      b.key = Upper(options[i].substr(0, 1));
    } else {
      b.key = std::to_string(i + 1);
    }
    buttons.push_back(std::move(b));
  }
  return buttons;
}

StationController::StationController(int trials_total, std::string device_name,
                                     double max_force_n) {
  frame_.experimenter.trials_total = trials_total;
  frame_.experimenter.device_name = std::move(device_name);
  frame_.experimenter.device_state = "ok";
  frame_.subject.max_force_n = max_force_n;
}

void StationController::BeginTrial(const protocols::TrialSpec& trial,
                                   int trials_done) {
  trial_ = trial;
  trial_aborted_ = false;
  interval_ = 0;
  SubjectView& s = frame_.subject;
  s.phase = StationPhase::kReady;
  // An adaptive protocol may not know its length: then no "of N".
  s.title = frame_.experimenter.trials_total > 0
                ? fmt::format("Trial {} of {}", trials_done + 1,
                              frame_.experimenter.trials_total)
                : fmt::format("Trial {}", trials_done + 1);
  s.interval_label.clear();
  s.time_left_s = 0.0;
  s.question = trial.question;
  s.buttons = ResponseButtonsFor(trial.response_options);
  s.message = "Press SPACE to start the trial.";
  ExperimenterView& e = frame_.experimenter;
  e.trials_done = trials_done;
  e.trial_line = fmt::format(
      "trial {}, block {}, {}, {}", trial.trial_index + 1, trial.block,
      protocols::MethodName(trial.method), protocols::TaskName(trial.task));
}

void StationController::EnterInterval(std::size_t index, double now_s) {
  interval_ = index;
  interval_start_s_ = now_s;
  SubjectView& s = frame_.subject;
  s.phase = StationPhase::kInterval;
  s.interval_label =
      fmt::format("Interval {} of {}", index + 1, trial_->intervals.size());
  const double duration = trial_->intervals[index].duration_s;
  s.time_left_s = duration;
  const bool drill = trial_->task == protocols::Task::kDrill;
  if (duration > 0.0) {
    s.message = drill ? "Drill into the block." : "Probe the surface.";
  } else {
    s.message = "Feel the real sample, then press SPACE.";
  }
}

void StationController::EnterResponse(double now_s) {
  question_start_s_ = now_s;
  question_shown_ = false;
  SubjectView& s = frame_.subject;
  s.phase = StationPhase::kResponse;
  s.interval_label.clear();
  s.time_left_s = 0.0;
  s.force_n = 0.0;
  s.message = "Answer with a key or click a button.";
}

void StationController::Start(double now_s) {
  if (!trial_.has_value()) return;
  if (frame_.subject.phase == StationPhase::kReady) {
    if (trial_->intervals.empty()) {
      EnterResponse(now_s);
    } else {
      EnterInterval(0, now_s);
    }
  } else if (frame_.subject.phase == StationPhase::kInterval &&
             trial_->intervals[interval_].duration_s <= 0.0) {
    if (interval_ + 1 < trial_->intervals.size()) {
      EnterInterval(interval_ + 1, now_s);
    } else {
      EnterResponse(now_s);
    }
  }
}

void StationController::Advance(double now_s) {
  while (frame_.subject.phase == StationPhase::kInterval) {
    const double duration = trial_->intervals[interval_].duration_s;
    if (duration <= 0.0) return;  // subject-paced
    const double end_s = interval_start_s_ + duration;
    if (now_s < end_s) {
      frame_.subject.time_left_s = end_s - now_s;
      return;
    }
    if (interval_ + 1 < trial_->intervals.size()) {
      EnterInterval(interval_ + 1, end_s);
    } else {
      EnterResponse(end_s);
    }
  }
}

std::optional<protocols::Response> StationController::OnInput(
    std::string_view key_or_answer, double now_s) {
  const std::string key = Upper(key_or_answer);
  if (key == "SPACE") {
    Start(now_s);
    return std::nullopt;
  }
  if (frame_.subject.phase != StationPhase::kResponse) return std::nullopt;
  for (const ResponseButton& b : frame_.subject.buttons) {
    if (b.key == key || b.answer == key_or_answer) {
      const double rt = std::max(0.0, now_s - question_start_s_);
      frame_.experimenter.last_event =
          fmt::format("trial {}: answered {} after {:.2f} s",
                      trial_->trial_index + 1, b.answer, rt);
      frame_.subject.message = "Thank you.";
      return protocols::Response{b.answer, rt};
    }
  }
  return std::nullopt;
}

void StationController::MarkQuestionShown(double now_s) {
  if (frame_.subject.phase != StationPhase::kResponse || question_shown_) {
    return;
  }
  question_start_s_ = now_s;
  question_shown_ = true;
}

void StationController::Pause(std::string reason) {
  const StationPhase phase = frame_.subject.phase;
  if (phase == StationPhase::kFinished) return;
  if (phase == StationPhase::kInterval || phase == StationPhase::kResponse) {
    trial_aborted_ = true;
    ++aborted_trials_;
    frame_.experimenter.last_event =
        fmt::format("trial {} aborted: {}", trial_->trial_index + 1, reason);
  }
  frame_.subject.phase = StationPhase::kPaused;
  frame_.subject.interval_label.clear();
  frame_.subject.time_left_s = 0.0;
  frame_.subject.force_n = 0.0;
  frame_.subject.message = "Paused: " + reason;
  frame_.experimenter.paused = true;
}

void StationController::Resume() {
  if (frame_.subject.phase != StationPhase::kPaused) return;
  frame_.experimenter.paused = false;
  frame_.subject.phase = StationPhase::kReady;
  frame_.subject.message = "Press SPACE to start the trial.";
  trial_aborted_ = false;
}

void StationController::Abort(std::string reason) {
  if (frame_.subject.phase == StationPhase::kInterval ||
      frame_.subject.phase == StationPhase::kResponse) {
    trial_aborted_ = true;
    ++aborted_trials_;
  }
  frame_.subject.phase = StationPhase::kFinished;
  frame_.subject.interval_label.clear();
  frame_.subject.message = "The session was stopped: " + reason;
  frame_.experimenter.aborted = true;
  frame_.experimenter.last_event = "aborted: " + reason;
}

void StationController::Finish() {
  frame_.subject.phase = StationPhase::kFinished;
  frame_.subject.interval_label.clear();
  frame_.subject.force_n = 0.0;
  frame_.subject.title = "Done";
  frame_.subject.message = "The session is complete. Thank you!";
  frame_.experimenter.trials_done = frame_.experimenter.trials_total;
  frame_.experimenter.finished = true;
  frame_.experimenter.paused = false;
}

void StationController::SetLoop(std::int64_t ticks, double p50_us,
                                double p99_us, std::int64_t missed) {
  ExperimenterView& e = frame_.experimenter;
  e.loop_ticks = ticks;
  e.loop_p50_us = p50_us;
  e.loop_p99_us = p99_us;
  e.loop_missed = missed;
}

}  // namespace burrlab::runner
