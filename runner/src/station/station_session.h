// The live station behind `burrlab run --device ...`: each trial goes through
// StationController in the subject window (with the instructions, rest
// breaks, gaps and feedback the protocol paces it with); every simulated
// interval runs the
// haptic loop on its own thread with the chosen device, the interval's
// material rendered by the simulator (SimForceSource, within the station's
// force and stiffness limits) and the block shown from loop snapshots; the
// answer comes from the window (keys, buttons), the HID response box, or a
// station script. A device fault aborts the trial and pauses the session with
// its reason; the experimenter resumes (the trial is shown again from its
// start) or aborts (the session stops; nothing committed is lost).
#ifndef BURRLAB_RUNNER_STATION_STATION_SESSION_H_
#define BURRLAB_RUNNER_STATION_STATION_SESSION_H_

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <ostream>
#include <string>

#include "burrlab/stimuli/interval.h"
#include "devices/device.h"
#include "devices/haptic_loop.h"
#include "devices/hid_response_box.h"
#include "devices/mouse_device.h"
#include "devices/sim_force_source.h"
#include "devices/simulated_device.h"
#include "station/station_controller.h"
#include "station/station_script.h"
#include "station/window.h"
#include "studies/session.h"

namespace burrlab::runner {

// The simulated block of every interval: 64 x 64 x 40 voxels of 0.3 mm, solid
// below z = 8 mm; the device origin sits at the centre of its surface.
inline constexpr double kBlockSurfaceMm = 8.0;
inline constexpr double kBlockHalfWidthMm = 9.6;

struct StationSessionOptions {
  std::string device_name;               // shown to the experimenter
  HapticDevice* device = nullptr;        // renders the intervals (required)
  MouseDevice* mouse = nullptr;          // fed from the window's cursor, if any
  SimulatedDevice* simulated = nullptr;  // played from the script, if any
  HidResponseBox* box = nullptr;         // answers from the box, if any
  const StationScript* script = nullptr;  // a scripted subject, if any
  StationWindow* window = nullptr;        // required
  int trials_total = 0;  // for "Trial k of N"; 0 = not known ahead
  double radius_mm = stimuli::kDefaultBurrRadiusMm;  // burr radius
  int trace_hz = 1000;                               // trace rate; divides 1000
  RenderLimits limits;          // the station's force and stiffness limits
  bool realtime = true;         // SCHED_FIFO and mlockall for the loop
  double frame_hz = 60.0;       // window frames per second
  std::string screenshots_dir;  // one PNG per phase shown, when not empty
  // Brings the haptic device back after a fault when the experimenter
  // resumes; empty: the device cannot come back (the session stays paused).
  std::function<Status()> reconnect;
  std::ostream* log = nullptr;  // notes for the experimenter, if any
};

class StationSession final : public LiveStation {
 public:
  explicit StationSession(StationSessionOptions options);
  ~StationSession() override;
  StationSession(const StationSession&) = delete;
  StationSession& operator=(const StationSession&) = delete;

  Result<LiveTrial> PresentTrial(const protocols::TrialSpec& trial,
                                 int trials_done,
                                 const AdjustedComparison& adjusted) override;
  std::string AfterAnswer(const protocols::TrialSpec& trial,
                          std::optional<bool> correct) override;
  void Finish() override;

  int screenshots_saved() const { return screenshots_; }

 private:
  class Interval;
  // How a presentation (or a pause) ended: answered (or resumed), aborted
  // by a pause, or the session stops.
  enum class Ending { kAnswered, kAborted, kStopped };
  struct Key {
    std::string name;  // a key, "SPACE", or a clicked answer
    double t_s = 0.0;  // when, on the session clock
  };

  double NowS() const;
  Ending RunPresentation(const protocols::TrialSpec& trial,
                         const AdjustedComparison& adjusted, LiveTrial* out);
  // `answered`: the pause came after the trial's answer was saved (the next
  // trial follows), not during it (the trial is presented again).
  Ending WaitForResume(const protocols::TrialSpec& trial,
                       std::string* stop_reason, bool answered = false);
  void Pause(const protocols::TrialSpec& trial, std::string reason);
  // Starts or stops the interval's loop to match the controller (its trial:
  // an adjustment's comparisons are appended there).
  Status SyncInterval(LiveTrial* out);
  // Stops the running interval's loop; `keep` adds its record and trace.
  void StopInterval(LiveTrial* out, bool keep);
  WindowInput DrawFrame();
  void SaveShown(const protocols::TrialSpec& trial);
  void WaitFrame(std::chrono::steady_clock::time_point frame_start) const;
  std::vector<Key> CollectKeys(const WindowInput& input, double now_s);
  void Log(const std::string& line);

  StationSessionOptions options_;
  StationController controller_;
  MonotonicClock clock_;
  std::int64_t origin_ns_;
  std::unique_ptr<Interval> interval_;
  std::optional<std::size_t> running_;  // interval index with a loop
  double trial_start_s_ = 0.0;
  double phase_since_s_ = 0.0;
  double question_shown_s_ = -1.0;  // when the question reached the screen
  std::string shown_;      // phase (and interval) of the last screenshot
  int presentations_ = 0;  // trials presented in this run, repeats included
  std::size_t next_answer_ = 0;
  const ScriptedUnplug* pending_unplug_ = nullptr;  // the one that fired
  std::string pause_reason_;                        // why the session is paused
  double material_c_e_ = 0.0;  // of the running interval, as given
  bool device_faulted_ = false;
  bool box_unplugged_ = false;
  std::string box_reason_;
  bool noted_realtime_ = false;
  bool memory_locked_ = false;  // mlockall for the session
  int screenshots_ = 0;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_SESSION_H_
