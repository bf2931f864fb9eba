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
};

// "ready", "interval", "response", "paused", "finished".
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
