// What the subject window draws, as plain data: the subject's view (trial
// phase, interval and time left, question, response buttons with their keys,
// force) and the experimenter's panel (progress, trial, loop timing, device
// state, pause). The views are functions of this struct, so tests check the
// state without a window and screenshots are reproducible.
#ifndef BURRLAB_RUNNER_STATION_STATION_FRAME_H_
#define BURRLAB_RUNNER_STATION_STATION_FRAME_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace burrlab::runner {

enum class StationPhase {
  kReady,     // before the trial: "press space to start"
  kInterval,  // an interval runs: the subject probes or drills
  kResponse,  // the question is asked
  kPaused,    // the experimenter or a device fault paused the session
  kFinished,  // the protocol ran to its end or was aborted
  // The pacing of a session (§13.5.1: familiarization before the scored
  // trials; protocols/README.md, "Pacing, practice and breaks"):
  kInstructions,  // the study's or a block's instructions, until SPACE
  kIsi,           // the blank gap between two intervals (isi_s)
  kFeedback,      // "Correct" or "Wrong", about 1 s or until a key
  kBreak,         // a rest break, until a key
  kIti,           // the gap after the answer, before the next trial (iti_s)
};

// "ready", "interval", "response", "paused", "finished", "instructions",
// "isi", "feedback", "break", "iti".
std::string_view StationPhaseName(StationPhase phase) noexcept;

// One answer the subject can give.
struct ResponseButton {
  std::string answer;  // the response option, e.g. "1" or "same"
  std::string key;     // the key that gives it, e.g. "1" or "S"
};

struct SubjectView {
  StationPhase phase = StationPhase::kReady;
  std::string title;           // e.g. "Trial 3 of 12"
  std::string interval_label;  // e.g. "Interval 1 of 2"; empty outside one
  double time_left_s = 0.0;    // of the running interval
  std::string question;        // shown in kResponse
  std::vector<ResponseButton> buttons;
  std::string message;       // instruction or pause reason for the subject
  double force_n = 0.0;      // |force| sent (or rendered, for the mouse)
  double max_force_n = 8.0;  // the device's limit, for the indicator scale
  // Drawn over the block view in kInstructions, kIsi, kFeedback, kBreak and
  // kIti: a large heading ("Instructions", "Correct", "Rest break", ...) and
  // text under it (the protocol's instructions; may be empty).
  std::string panel_heading;
  std::string panel_text;
  bool panel_good = true;  // kFeedback: "Correct" (green) or "Wrong"
};

struct ExperimenterView {
  int trials_done = 0;
  int trials_total = 0;
  std::string trial_line;    // e.g. "trial 3, block probe2afc, 2afc, probe"
  std::string device_name;   // e.g. "mouse"
  std::string device_state;  // e.g. "ok" or "unplugged: ..."
  std::int64_t loop_ticks = 0;
  double loop_p50_us = 0.0;
  double loop_p99_us = 0.0;
  std::int64_t loop_missed = 0;  // missed deadlines + non-finite forces
  bool paused = false;
  bool aborted = false;
  bool finished = false;   // the protocol ran to its end
  std::string last_event;  // e.g. "trial 2: answered 1 after 0.84 s"
};

struct StationFrame {
  SubjectView subject;
  ExperimenterView experimenter;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_FRAME_H_
