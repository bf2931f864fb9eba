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
    case StationPhase::kInstructions:
      return "instructions";
    case StationPhase::kIsi:
      return "isi";
    case StationPhase::kFeedback:
      return "feedback";
    case StationPhase::kBreak:
      return "break";
    case StationPhase::kIti:
      return "iti";
  }
  return "?";
}

namespace {

// Protocol text as the window wraps it: the author's line breaks within a
// paragraph (a TOML multi-line string keeps them) become spaces; a blank
// line separates paragraphs.
std::string Reflow(std::string_view text) {
  std::string out;
  bool blank = false;  // a blank line since the last text
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) {
      line.remove_suffix(1);
    }
    while (!line.empty() && line.front() == ' ') line.remove_prefix(1);
    if (line.empty()) {
      blank = !out.empty();
      continue;
    }
    if (!out.empty()) out += blank ? "\n\n" : " ";
    out += line;
    blank = false;
  }
  return out;
}

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

std::vector<ResponseButton> AdjustmentButtons() {
  return {{"+", "UP"}, {"-", "DOWN"}, {"=", "ENTER"}};
}

StationController::StationController(int trials_total, std::string device_name,
                                     double max_force_n) {
  frame_.experimenter.trials_total = trials_total;
  frame_.experimenter.device_name = std::move(device_name);
  frame_.experimenter.device_state = "ok";
  frame_.subject.max_force_n = max_force_n;
}

std::string StationController::TrialTitle() const {
  // An adaptive protocol may not know its length: then no "of N".
  const std::string title =
      frame_.experimenter.trials_total > 0
          ? fmt::format("Trial {} of {}", trials_done_ + 1,
                        frame_.experimenter.trials_total)
          : fmt::format("Trial {}", trials_done_ + 1);
  return trial_->practice ? "Practice - " + title : title;
}

void StationController::BeginTrial(const protocols::TrialSpec& trial,
                                   int trials_done) {
  trial_ = trial;
  trials_done_ = trials_done;
  trial_aborted_ = false;
  after_answer_ = false;
  interval_ = 0;
  SubjectView& s = frame_.subject;
  s.title = TrialTitle();
  s.question = trial.question;
  const bool adjustment = trial.method == protocols::Method::kAdjustment;
  s.buttons = adjustment ? AdjustmentButtons()
                         : ResponseButtonsFor(trial.response_options);
  adjustment_path_.clear();
  pending_step_.reset();
  ExperimenterView& e = frame_.experimenter;
  e.trials_done = trials_done;
  e.trial_line = fmt::format(
      "trial {}, block {}, {}, {}{}", trial.trial_index + 1, trial.block,
      protocols::MethodName(trial.method), protocols::TaskName(trial.task),
      trial.practice ? ", practice" : "");
  intro_.clear();
  if (intro_done_for_ != trial.trial_index) {
    if (!trial.study_instructions.empty()) {
      intro_.push_back(
          {StationPhase::kInstructions, trial.study_instructions, true});
    }
    if (trial.break_before) intro_.push_back({StationPhase::kBreak, "", false});
    if (!trial.block_instructions.empty()) {
      intro_.push_back(
          {StationPhase::kInstructions, trial.block_instructions, false});
    }
  }
  if (intro_.empty()) {
    intro_done_for_ = trial.trial_index;
    EnterReady();
  } else {
    EnterIntroStep(0);
  }
}

void StationController::EnterIntroStep(std::size_t index) {
  intro_index_ = index;
  const IntroStep& step = intro_[index];
  SubjectView& s = frame_.subject;
  s.phase = step.phase;
  s.interval_label.clear();
  s.time_left_s = 0.0;
  s.force_n = 0.0;
  if (step.phase == StationPhase::kBreak) {
    s.title = "Rest break";
    s.panel_heading = "Rest break";
    s.panel_text = "Take a rest. The next trials follow when you are ready.";
    s.message = "Press any key to continue.";
  } else {
    s.title = step.study         ? "Welcome"
              : trial_->practice ? "Practice"
                                 : "Next block";
    s.panel_heading = "Instructions";
    s.panel_text = Reflow(step.text);
    s.message = "Press SPACE to continue.";
  }
}

void StationController::EnterReady() {
  SubjectView& s = frame_.subject;
  s.phase = StationPhase::kReady;
  s.title = TrialTitle();
  s.interval_label.clear();
  s.time_left_s = 0.0;
  s.panel_heading.clear();
  s.panel_text.clear();
  s.message = "Press SPACE to start the trial.";
}

std::string StationController::screen() const {
  const StationPhase phase = frame_.subject.phase;
  const std::string name(StationPhaseName(phase));
  switch (phase) {
    case StationPhase::kInterval:
    case StationPhase::kIsi:
      return fmt::format("{}{}", name, interval_ + 1);
    case StationPhase::kInstructions:
      return intro_index_ < intro_.size() && intro_[intro_index_].study
                 ? name + "_study"
                 : name + "_block";
    default:
      return name;
  }
}

void StationController::EnterInterval(std::size_t index, double now_s) {
  interval_ = index;
  interval_start_s_ = now_s;
  SubjectView& s = frame_.subject;
  s.phase = StationPhase::kInterval;
  s.panel_heading.clear();
  s.panel_text.clear();
  if (trial_->method == protocols::Method::kAdjustment) {
    // The standard, the comparison at its start, then the comparison after
    // each step.
    s.interval_label = index == 0 ? std::string("Standard")
                       : index == 1
                           ? std::string("Comparison")
                           : fmt::format("Comparison after step {}", index - 1);
  } else {
    s.interval_label =
        fmt::format("Interval {} of {}", index + 1, trial_->intervals.size());
  }
  const double duration = trial_->intervals[index].duration_s;
  s.time_left_s = duration;
  const bool drill = trial_->task == protocols::Task::kDrill;
  if (duration > 0.0) {
    s.message = drill ? "Drill into the block." : "Probe the surface.";
  } else {
    s.message = "Feel the real sample, then press SPACE.";
  }
}

void StationController::EndInterval(double end_s) {
  if (interval_ + 1 >= trial_->intervals.size()) {
    EnterResponse(end_s);
    return;
  }
  if (trial_->isi_s <= 0.0) {
    EnterInterval(interval_ + 1, end_s);
    return;
  }
  // The blank gap: nothing to feel, nothing to see (interval_ stays the one
  // it follows).
  gap_start_s_ = end_s;
  SubjectView& s = frame_.subject;
  s.phase = StationPhase::kIsi;
  s.interval_label = fmt::format("Interval {} of {} next", interval_ + 2,
                                 trial_->intervals.size());
  s.time_left_s = trial_->isi_s;
  s.force_n = 0.0;
  s.panel_heading.clear();
  s.panel_text = fmt::format("Interval {} of {} comes next.", interval_ + 2,
                             trial_->intervals.size());
  s.message = "Wait for the next interval.";
}

void StationController::EnterResponse(double now_s) {
  question_start_s_ = now_s;
  question_shown_ = false;
  SubjectView& s = frame_.subject;
  s.phase = StationPhase::kResponse;
  s.interval_label.clear();
  s.time_left_s = 0.0;
  s.force_n = 0.0;
  if (trial_->method == protocols::Method::kAdjustment) {
    if (adjustment_path_.empty()) adjustment_start_s_ = now_s;
    s.message = fmt::format(
        "UP raises the comparison one step, DOWN lowers it; you then feel it "
        "again. ENTER when it matches. Steps taken: {}.",
        adjustment_path_.size());
  } else {
    s.message = "Answer with a key or click a button.";
  }
}

std::optional<int> StationController::TakeAdjustmentStep() {
  const std::optional<int> step = pending_step_;
  pending_step_.reset();
  return step;
}

void StationController::PresentAdjustedComparison(
    protocols::PlannedInterval comparison, char step, double now_s) {
  if (!trial_.has_value() || phase() != StationPhase::kResponse) return;
  adjustment_path_ += step;
  trial_->intervals.push_back(std::move(comparison));
  EnterInterval(trial_->intervals.size() - 1, now_s);
}

void StationController::RefuseAdjustmentStep() {
  frame_.subject.message = fmt::format(
      "No more steps: this adjustment allows {}. Press ENTER to finish.",
      adjustment_path_.size());
}

void StationController::Start(double now_s) {
  if (!trial_.has_value()) return;
  if (frame_.subject.phase == StationPhase::kInstructions) {
    if (intro_index_ + 1 < intro_.size()) {
      EnterIntroStep(intro_index_ + 1);
    } else {
      intro_done_for_ = trial_->trial_index;
      EnterReady();
    }
    return;
  }
  if (frame_.subject.phase == StationPhase::kReady) {
    if (trial_->intervals.empty()) {
      EnterResponse(now_s);
    } else {
      EnterInterval(0, now_s);
    }
  } else if (frame_.subject.phase == StationPhase::kInterval &&
             trial_->intervals[interval_].duration_s <= 0.0) {
    EndInterval(now_s);
  }
}

void StationController::Advance(double now_s) {
  for (;;) {
    SubjectView& s = frame_.subject;
    if (s.phase == StationPhase::kInterval) {
      const double duration = trial_->intervals[interval_].duration_s;
      if (duration <= 0.0) return;  // subject-paced
      const double end_s = interval_start_s_ + duration;
      if (now_s < end_s) {
        s.time_left_s = end_s - now_s;
        return;
      }
      EndInterval(end_s);
    } else if (s.phase == StationPhase::kIsi) {
      const double end_s = gap_start_s_ + trial_->isi_s;
      if (now_s < end_s) {
        s.time_left_s = end_s - now_s;
        return;
      }
      EnterInterval(interval_ + 1, end_s);
    } else if (s.phase == StationPhase::kFeedback) {
      if (now_s < gap_start_s_ + kFeedbackS) return;
      EnterIti(gap_start_s_ + kFeedbackS);
    } else if (s.phase == StationPhase::kIti && after_answer_) {
      if (now_s < gap_start_s_ + trial_->iti_s) return;
      EndAfterAnswer();
    } else {
      const double asked_s = trial_->method == protocols::Method::kAdjustment
                                 ? adjustment_start_s_
                                 : question_start_s_;
      if (s.phase == StationPhase::kResponse &&
          trial_->response_deadline_s.has_value() &&
          now_s - asked_s > *trial_->response_deadline_s) {
        s.message = "Time is up: please answer now.";
      }
      return;
    }
  }
}

void StationController::BeginAfterAnswer(std::optional<bool> correct,
                                         double now_s) {
  if (!trial_.has_value()) return;
  after_answer_ = true;
  SubjectView& s = frame_.subject;
  if (trial_->feedback && correct.has_value()) {
    gap_start_s_ = now_s;
    s.phase = StationPhase::kFeedback;
    s.interval_label.clear();
    s.time_left_s = 0.0;
    s.force_n = 0.0;
    s.panel_heading = *correct ? "Correct" : "Wrong";
    s.panel_text.clear();
    s.panel_good = *correct;
    s.message =
        *correct ? "Your answer was correct." : "Your answer was wrong.";
    return;
  }
  EnterIti(now_s);
}

void StationController::EnterIti(double now_s) {
  if (trial_->iti_s <= 0.0) {
    EndAfterAnswer();
    return;
  }
  gap_start_s_ = now_s;
  SubjectView& s = frame_.subject;
  s.phase = StationPhase::kIti;
  s.interval_label.clear();
  s.time_left_s = 0.0;
  s.force_n = 0.0;
  s.panel_heading.clear();
  s.panel_text = "The next trial follows shortly.";
  s.message = "Please wait.";
}

void StationController::EndAfterAnswer() {
  after_answer_ = false;
  SubjectView& s = frame_.subject;
  s.panel_heading.clear();
  s.panel_text.clear();
}

std::optional<protocols::Response> StationController::OnInput(
    std::string_view key_or_answer, double now_s) {
  const std::string key = Upper(key_or_answer);
  const StationPhase phase = frame_.subject.phase;
  if (phase == StationPhase::kBreak) {  // any key ends a rest break
    if (intro_index_ + 1 < intro_.size()) {
      EnterIntroStep(intro_index_ + 1);
    } else {
      intro_done_for_ = trial_->trial_index;
      EnterReady();
    }
    return std::nullopt;
  }
  if (phase == StationPhase::kFeedback) {  // any key ends feedback
    EnterIti(now_s);
    return std::nullopt;
  }
  if (key == "SPACE") {
    Start(now_s);
    return std::nullopt;
  }
  if (phase != StationPhase::kResponse) return std::nullopt;
  if (trial_->method == protocols::Method::kAdjustment) {
    for (const ResponseButton& b : frame_.subject.buttons) {
      if (b.key != key && b.answer != key_or_answer) continue;
      if (b.answer != "=") {
        pending_step_ = b.answer == "+" ? 1 : -1;
        return std::nullopt;
      }
      // The adjustment's time runs from its first question to ENTER, the
      // comparisons felt after each step included.
      const double rt = std::max(0.0, now_s - adjustment_start_s_);
      const bool late = trial_->response_deadline_s.has_value() &&
                        rt > *trial_->response_deadline_s;
      frame_.experimenter.last_event = fmt::format(
          "trial {}: adjusted {}= in {:.2f} s{}", trial_->trial_index + 1,
          adjustment_path_, rt, late ? " (late)" : "");
      frame_.subject.message = "Thank you.";
      return protocols::Response{adjustment_path_ + "=", rt};
    }
    return std::nullopt;
  }
  for (const ResponseButton& b : frame_.subject.buttons) {
    if (b.key == key || b.answer == key_or_answer) {
      const double rt = std::max(0.0, now_s - question_start_s_);
      // Late answers are kept (the engine marks them); the experimenter sees
      // it at once.
      const bool late = trial_->response_deadline_s.has_value() &&
                        rt > *trial_->response_deadline_s;
      frame_.experimenter.last_event = fmt::format(
          "trial {}: answered {} after {:.2f} s{}", trial_->trial_index + 1,
          b.answer, rt, late ? " (late)" : "");
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
  if (trial_->method == protocols::Method::kAdjustment &&
      adjustment_path_.empty()) {
    adjustment_start_s_ = now_s;
  }
}

void StationController::Pause(std::string reason) {
  const StationPhase phase = frame_.subject.phase;
  if (phase == StationPhase::kFinished) return;
  if (phase == StationPhase::kInterval || phase == StationPhase::kIsi ||
      phase == StationPhase::kResponse) {
    trial_aborted_ = true;
    ++aborted_trials_;
    frame_.experimenter.last_event =
        fmt::format("trial {} aborted: {}", trial_->trial_index + 1, reason);
  }
  after_answer_ = false;  // the answer is saved: nothing is lost
  frame_.subject.panel_heading.clear();
  frame_.subject.panel_text.clear();
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
      frame_.subject.phase == StationPhase::kIsi ||
      frame_.subject.phase == StationPhase::kResponse) {
    trial_aborted_ = true;
    ++aborted_trials_;
  }
  after_answer_ = false;
  frame_.subject.panel_heading.clear();
  frame_.subject.panel_text.clear();
  frame_.subject.phase = StationPhase::kFinished;
  frame_.subject.interval_label.clear();
  frame_.subject.message = "The session was stopped: " + reason;
  frame_.experimenter.aborted = true;
  frame_.experimenter.last_event = "aborted: " + reason;
}

void StationController::Finish() {
  after_answer_ = false;
  frame_.subject.panel_heading.clear();
  frame_.subject.panel_text.clear();
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
