// The live station: controller, window, haptic loop, devices and script.
#include "station/station_session.h"

#include <fmt/format.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <glm/geometric.hpp>
#include <thread>
#include <utility>
#include <vector>

#include "burrlab/sim/phantoms.h"
#include "burrlab/sim/step.h"
#include "station/surface_snapshot.h"

namespace burrlab::runner {
namespace {

constexpr double kLoopRateHz = 1000.0;
constexpr int kSnapshotEveryTicks = 33;      // ~30 Hz for the window
constexpr double kScriptResumeAfterS = 0.3;  // a scripted pause lasts this

}  // namespace

// The simulator, force source, recording and loop of one running interval.
// The loop thread owns everything here until Stop; the window side only takes
// snapshots from the exchange.
class StationSession::Interval final : public ForceSource {
 public:
  // The recording types are nested here, not in the anonymous namespace: a
  // member of a class with external linkage must not have an internal-linkage
  // type (-Wsubobject-linkage, raised when this file is part of a unity
  // source).

  // One tick's device position and the force sent.
  struct TickSample {
    glm::dvec3 position_mm{0.0};
    glm::dvec3 force_n{0.0};
  };

  // The station's device as the loop sees it: every tick's position and the
  // force sent (after the loop's clamp) are kept while there is room.
  class RecordingDevice final : public HapticDevice {
   public:
    RecordingDevice(HapticDevice* device, std::size_t capacity)
        : device_(device) {
      samples_.resize(capacity);
    }
    const DeviceSpec& spec() const noexcept override { return device_->spec(); }
    DeviceStatus ReadPosition(glm::dvec3* position_mm) noexcept override {
      const DeviceStatus s = device_->ReadPosition(position_mm);
      if (s.usable()) position_mm_ = *position_mm;
      return s;
    }
    DeviceStatus WriteForce(const glm::dvec3& force_n) noexcept override {
      if (count_ < samples_.size()) {
        samples_[count_++] = {position_mm_, force_n};
      }
      return device_->WriteForce(force_n);
    }
    std::size_t recorded() const { return count_; }
    const TickSample& sample(std::size_t k) const { return samples_[k]; }

   private:
    HapticDevice* device_;
    glm::dvec3 position_mm_{0.0};
    std::vector<TickSample> samples_;
    std::size_t count_ = 0;
  };

  Interval(const StationSessionOptions& o, const sim::Model& model,
           sim::State state, const glm::dvec3& spindle_rad_s,
           std::size_t capacity)
      : state_(std::move(state)),
        offset_mm_(kBlockHalfWidthMm, kBlockHalfWidthMm, kBlockSurfaceMm),
        source_(model, &state_, offset_mm_, spindle_rad_s, o.limits),
        radius_mm_(model.radius_mm),
        recorder_(o.device, capacity) {
    working_.surface = HeightMap::For(state_.volume());
    UpdateHeightMap(state_.volume(), {}, -1.0, &working_.surface);
    working_.burr_radius_mm = model.radius_mm;
    working_.burr_mm = offset_mm_ + glm::dvec3(0.0, 0.0, 2.0 * radius_mm_);
    exchange_ = std::make_unique<SnapshotExchange>(working_);
    exchange_->Publish(working_);
  }

  // One tick: the simulator's force; a snapshot for the window every
  // kSnapshotEveryTicks ticks.
  glm::dvec3 Force(const glm::dvec3& position_mm) noexcept override {
    const glm::dvec3 force_n = source_.Force(position_mm);
    if (tick_ % kSnapshotEveryTicks == 0) {
      working_.burr_mm = position_mm + offset_mm_;
      UpdateHeightMap(state_.volume(), working_.burr_mm, radius_mm_ + 0.6,
                      &working_.surface);
      working_.force_n = force_n;
      working_.tick = tick_;
      exchange_->Publish(working_);
    }
    ++tick_;
    return force_n;
  }

  void StartLoop(LoopClock* clock, const LoopOptions& options) {
    loop_ = std::make_unique<HapticLoop>(&recorder_, this, clock, options);
  }
  HapticLoop& loop() { return *loop_; }
  SnapshotExchange& exchange() { return *exchange_; }
  const SimForceSource& source() const { return source_; }
  const RecordingDevice& recorder() const { return recorder_; }
  double start_s = 0.0;  // from the trial's start

 private:
  sim::State state_;
  glm::dvec3 offset_mm_;
  SimForceSource source_;
  double radius_mm_;
  RecordingDevice recorder_;
  std::int64_t tick_ = 0;
  SurfaceSnapshot working_;
  std::unique_ptr<SnapshotExchange> exchange_;
  std::unique_ptr<HapticLoop> loop_;
};

StationSession::StationSession(StationSessionOptions options)
    : options_(std::move(options)),
      controller_(options_.trials_total, options_.device_name,
                  options_.limits.max_force_n > 0.0
                      ? std::min(options_.limits.max_force_n,
                                 options_.device->spec().max_force_n)
                      : options_.device->spec().max_force_n),
      origin_ns_(MonotonicNowNs()) {
  if (!options_.screenshots_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options_.screenshots_dir, ec);
  }
  // Memory is locked once for the session: locking it for each interval's
  // loop would fault in the whole process (window and GL included) before
  // every interval.
#if !defined(__SANITIZE_ADDRESS__)
  if (options_.realtime) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
      memory_locked_ = true;
    } else {
      Log(
          fmt::format("mlockall failed ({}): page faults may delay haptic "
                      "ticks; raise the memlock limit (ulimit -l) or run "
                      "with CAP_IPC_LOCK",
                      std::strerror(errno)));
    }
  }
#endif
}

StationSession::~StationSession() {
  if (interval_ != nullptr) interval_->loop().Stop();
  if (memory_locked_) munlockall();
}

double StationSession::NowS() const {
  return static_cast<double>(MonotonicNowNs() - origin_ns_) * 1e-9;
}

void StationSession::Log(const std::string& line) {
  if (options_.log != nullptr) *options_.log << "burrlab: " << line << '\n';
}

WindowInput StationSession::DrawFrame() {
  StationWindow& w = *options_.window;
  if (interval_ != nullptr) {
    if (const SurfaceSnapshot* s = interval_->exchange().TakeNewest()) {
      w.SetSurface(*s);
      if (controller_.phase() == StationPhase::kInterval) {
        controller_.SetForce(
            std::min(glm::length(s->force_n), interval_->loop().max_force_n()));
      }
    }
  }
  return w.Draw(controller_.frame());
}

void StationSession::StopInterval(LiveTrial* out, bool keep) {
  if (interval_ == nullptr) return;
  Interval& iv = *interval_;
  iv.loop().Stop();
  const HapticLoop& loop = iv.loop();
  const LoopStats stats = loop.Stats();
  controller_.SetLoop(
      loop.counters().ticks, stats.p50_us, stats.p99_us,
      loop.counters().missed_deadlines + loop.counters().non_finite);
  if (!noted_realtime_ && !loop.realtime().note.empty()) {
    Log("haptic loop: " + loop.realtime().note);
  }
  noted_realtime_ = true;
  if (keep && running_.has_value()) {
    LiveIntervalRecord r;
    r.interval_index = static_cast<int>(*running_);
    r.rate_hz = kLoopRateHz;
    r.counters = loop.counters();
    r.stats = stats;
    r.max_force_n = loop.max_force_n();
    r.c_e_n_per_mm2 = iv.source().rendered_c_e_n_per_mm2();
    if (iv.source().stiffness_limited()) {
      r.c_e_limited_from_n_per_mm2 = material_c_e_;
    }
    out->intervals.push_back(r);
    // The trace at the protocol's rate: block means of the 1 kHz ticks.
    results_schema::TraceSamples t;
    t.interval_index = static_cast<int>(*running_);
    t.sampling_frequency_hz = options_.trace_hz;
    t.start_time_s = iv.start_s;
    t.columns = {"position_x_mm", "position_y_mm", "position_z_mm",
                 "force_x_n",     "force_y_n",     "force_z_n"};
    const std::size_t per_row = static_cast<std::size_t>(
        std::max(1, static_cast<int>(kLoopRateHz) / options_.trace_hz));
    const Interval::RecordingDevice& rec = iv.recorder();
    for (std::size_t k = 0; k < rec.recorded(); k += per_row) {
      const std::size_t end = std::min(rec.recorded(), k + per_row);
      glm::dvec3 p(0.0), f(0.0);
      for (std::size_t j = k; j < end; ++j) {
        p += rec.sample(j).position_mm;
        f += rec.sample(j).force_n;
      }
      const double n = static_cast<double>(end - k);
      p /= n;
      f /= n;
      t.rows.push_back({p.x, p.y, p.z, f.x, f.y, f.z});
    }
    out->traces.push_back(std::move(t));
  }
  interval_.reset();
  running_.reset();
}

Status StationSession::SyncInterval(LiveTrial* out) {
  // The controller's copy: an adjustment appends a comparison per step.
  const protocols::TrialSpec& trial = controller_.trial();
  std::optional<std::size_t> wanted;
  if (controller_.phase() == StationPhase::kInterval &&
      trial.intervals[controller_.interval_index()].material.has_value() &&
      trial.intervals[controller_.interval_index()].duration_s > 0.0) {
    wanted = controller_.interval_index();
  }
  if (wanted == running_) return {};
  StopInterval(out, true);
  if (!wanted.has_value()) return {};

  const protocols::PlannedInterval& planned = trial.intervals[*wanted];
  sim::Model model;
  model.material = planned.material->material;
  model.radius_mm = options_.radius_mm;
  sim::PhantomGrid grid;
  grid.nx = grid.ny = 64;
  grid.nz = 40;
  Result<sim::Volume> volume = sim::MakeHalfSpace(
      grid, {kBlockHalfWidthMm, kBlockHalfWidthMm, kBlockSurfaceMm},
      {0.0, 0.0, 1.0});
  if (!volume.ok()) return volume.error();
  // One erosion seed per interval: trial * 16 + interval + 1 (as before
  // adjustments); an adjustment's 16th and later comparisons above 2^32.
  const auto trial_number = static_cast<std::uint64_t>(trial.trial_index);
  const std::uint64_t seed = *wanted < 15
                                 ? trial_number * 16 + *wanted + 1
                                 : ((trial_number + 1) << 32) + *wanted + 1;
  Result<sim::State> state =
      sim::State::Create(model, std::move(volume.value()), seed);
  if (!state.ok()) return state.error();
  const bool drill = trial.task == protocols::Task::kDrill;
  const auto capacity =
      static_cast<std::size_t>(std::ceil(planned.duration_s * kLoopRateHz));
  material_c_e_ = model.material.c_e_n_per_mm2;
  interval_ = std::make_unique<Interval>(
      options_, model, std::move(state.value()),
      glm::dvec3(0.0, 0.0, drill ? 2094.0 : 0.0), capacity);
  interval_->start_s = NowS() - trial_start_s_;
  if (options_.simulated != nullptr) {
    options_.simulated->Rewind();
    options_.simulated->UnplugAfterReads(-1);
    if (options_.script != nullptr) {
      for (const ScriptedUnplug& u : options_.script->unplugs) {
        if (u.presentation == presentations_ &&
            u.interval == static_cast<int>(*wanted) + 1) {
          options_.simulated->UnplugAfterReads(
              std::llround(u.after_s * kLoopRateHz));
          pending_unplug_ = &u;
        }
      }
    }
  }
  LoopOptions loop_options;
  loop_options.rate_hz = kLoopRateHz;
  loop_options.realtime = options_.realtime;
  loop_options.lock_memory = false;  // locked for the session
  loop_options.max_force_n = options_.limits.max_force_n;
  loop_options.max_samples = capacity + 10'000;
  interval_->StartLoop(&clock_, loop_options);
  running_ = wanted;
  if (Status s = interval_->loop().Start(static_cast<std::int64_t>(capacity));
      !s.ok()) {
    return s;
  }
  if (interval_->source().stiffness_limited()) {
    Log(fmt::format(
        "trial {} interval {}: c_e {} N/mm^2 is stiffer than the station "
        "renders (max stiffness {} N/mm up to {} N); rendering c_e {:.4g} "
        "N/mm^2",
        trial.trial_index + 1, *wanted + 1, material_c_e_,
        options_.limits.max_stiffness_n_per_mm, options_.limits.max_force_n,
        interval_->source().rendered_c_e_n_per_mm2()));
  }
  return {};
}

void StationSession::SaveShown(const protocols::TrialSpec& trial) {
  const std::string shown = controller_.screen();
  if (options_.screenshots_dir.empty() || shown == shown_) return;
  shown_ = shown;
  const std::string path =
      (std::filesystem::path(options_.screenshots_dir) /
       fmt::format("{:03d}_trial{}_{}.png", screenshots_ + 1,
                   trial.trial_index + 1, shown))
          .string();
  if (Status s = options_.window->SaveScreenshot(path); !s.ok()) {
    Log(s.error().message);
  } else {
    ++screenshots_;
  }
}

void StationSession::WaitFrame(
    std::chrono::steady_clock::time_point frame_start) const {
  const auto frame = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::duration<double>(1.0 / options_.frame_hz));
  std::this_thread::sleep_until(frame_start + frame);
}

std::vector<StationSession::Key> StationSession::CollectKeys(
    const WindowInput& input, double now_s) {
  std::vector<Key> keys;
  for (const std::string& k : input.keys) keys.push_back({k, now_s});
  if (input.answer.has_value()) keys.push_back({*input.answer, now_s});
  if (options_.box != nullptr) {
    for (HidEvent& e : options_.box->TakeEvents()) {
      if (e.kind == HidEvent::Kind::kPress) {
        keys.push_back(
            {e.key, static_cast<double>(e.time_ns - origin_ns_) * 1e-9});
      } else if (e.kind == HidEvent::Kind::kUnplugged) {
        box_unplugged_ = true;
        box_reason_ = e.reason;
      }
    }
  }
  return keys;
}

StationSession::Ending StationSession::RunPresentation(
    const protocols::TrialSpec& trial, const AdjustedComparison& adjusted,
    LiveTrial* out) {
  StationWindow& w = *options_.window;
  const StationScript* script = options_.script;
  std::string last_screen = controller_.screen();
  phase_since_s_ = NowS();
  for (;;) {
    const auto frame_start = std::chrono::steady_clock::now();
    const double now_s = NowS();
    // A device fault ends the loop thread by itself (checked before the
    // controller can move past the interval).
    if (interval_ != nullptr && interval_->loop().ended() &&
        IsFault(interval_->loop().fault().code)) {
      const DeviceStatus fault = interval_->loop().fault();
      StopInterval(out, false);
      device_faulted_ = true;
      controller_.SetDeviceState(
          fmt::format("{}: {}", DeviceCodeName(fault.code), fault.reason));
      Pause(trial,
            fmt::format("the {} device failed ({}: {})", options_.device_name,
                        DeviceCodeName(fault.code), fault.reason));
      return Ending::kAborted;
    }
    // A timed interval lasts its ticks: the controller moves on once the
    // loop has run them all (it started a little after the interval).
    double advance_s = now_s;
    if (interval_ != nullptr && !interval_->loop().ended()) {
      advance_s = std::min(
          now_s, controller_.interval_start_s() +
                     controller_.trial().intervals[*running_].duration_s -
                     1e-6);
    }
    controller_.Advance(advance_s);
    if (controller_.screen() != last_screen) {
      last_screen = controller_.screen();
      phase_since_s_ = now_s;
      question_shown_s_ = -1.0;
    }
    if (Status s = SyncInterval(out); !s.ok()) {
      StopInterval(out, false);
      out->stop_reason = "the station failed: " + s.error().message;
      return Ending::kStopped;
    }
    if (options_.mouse != nullptr) {
      options_.mouse->SetCursor(w.CursorInBlock(), w.WheelSteps(),
                                w.LeftButtonDown());
    }
    const WindowInput input = DrawFrame();
    SaveShown(trial);
    w.Present();
    if (controller_.phase() == StationPhase::kResponse &&
        question_shown_s_ < 0.0) {
      question_shown_s_ = NowS();
      controller_.MarkQuestionShown(question_shown_s_);
    }

    if (input.close_requested || input.action == ExperimenterAction::kAbort) {
      StopInterval(out, false);
      out->stop_reason = input.close_requested
                             ? "the subject window was closed"
                             : "the experimenter aborted the session";
      controller_.Abort(out->stop_reason);
      return Ending::kStopped;
    }
    if (input.action == ExperimenterAction::kPause) {
      StopInterval(out, false);
      Pause(trial, "paused by the experimenter");
      return Ending::kAborted;
    }
    std::vector<Key> keys = CollectKeys(input, now_s);
    if (box_unplugged_) {
      StopInterval(out, false);
      Pause(trial, "the response box was unplugged (" + box_reason_ + ")");
      return Ending::kAborted;
    }
    if (script != nullptr) {
      const double in_phase_s = now_s - phase_since_s_;
      const StationPhase phase = controller_.phase();
      const bool paced_interval =
          phase == StationPhase::kInterval &&
          controller_.trial()
                  .intervals[controller_.interval_index()]
                  .duration_s <= 0.0;
      const bool goes_on =
          phase == StationPhase::kInstructions || phase == StationPhase::kBreak;
      if ((phase == StationPhase::kReady || paced_interval) &&
          in_phase_s >= script->start_delay_s) {
        keys.push_back({"SPACE", now_s});
      } else if (goes_on && in_phase_s >= script->continue_delay_s) {
        keys.push_back({"SPACE", now_s});
      } else if (phase == StationPhase::kResponse && question_shown_s_ >= 0.0 &&
                 now_s - question_shown_s_ >= script->response_delay_s) {
        if (next_answer_ >= script->answers.size()) {
          out->stop_reason =
              fmt::format("the script's answers ran out ({} given) at trial {}",
                          script->answers.size(), trial.trial_index + 1);
          return Ending::kStopped;
        }
        keys.push_back({script->answers[next_answer_++], now_s});
      }
    }
    for (const Key& k : keys) {
      std::optional<protocols::Response> r = controller_.OnInput(k.name, k.t_s);
      if (r.has_value()) {
        StopInterval(out, true);
        out->response = std::move(r);
        out->duration_s = k.t_s - trial_start_s_;
        return Ending::kAnswered;
      }
      if (const std::optional<int> step = controller_.TakeAdjustmentStep()) {
        const char c = *step > 0 ? '+' : '-';
        Result<std::optional<protocols::PlannedInterval>> next =
            adjusted ? adjusted(controller_.adjustment_path() + c)
                     : Error{"no comparison levels for an adjustment"};
        if (!next.ok()) {
          out->stop_reason = "the station failed: " + next.error().message;
          return Ending::kStopped;
        }
        if (next->has_value()) {
          controller_.PresentAdjustedComparison(std::move(**next), c, k.t_s);
          break;  // keys after the step wait for the comparison
        }
        controller_.RefuseAdjustmentStep();
      }
    }
    if (Status s = SyncInterval(out); !s.ok()) {  // start at once
      StopInterval(out, false);
      out->stop_reason = "the station failed: " + s.error().message;
      return Ending::kStopped;
    }
    WaitFrame(frame_start);
  }
}

void StationSession::Pause(const protocols::TrialSpec& trial,
                           std::string reason) {
  controller_.Pause(reason);
  Log(fmt::format("trial {} aborted: {}; the session is paused",
                  trial.trial_index + 1, reason));
  pause_reason_ = std::move(reason);
}

StationSession::Ending StationSession::WaitForResume(
    const protocols::TrialSpec& trial, std::string* stop_reason,
    bool answered) {
  StationWindow& w = *options_.window;
  const double paused_at_s = NowS();
  for (;;) {
    const auto frame_start = std::chrono::steady_clock::now();
    const WindowInput input = DrawFrame();
    SaveShown(trial);
    w.Present();
    if (input.close_requested || input.action == ExperimenterAction::kAbort) {
      *stop_reason = fmt::format("{} while paused ({})",
                                 input.close_requested
                                     ? "the subject window was closed"
                                     : "the experimenter aborted the session",
                                 pause_reason_);
      controller_.Abort(*stop_reason);
      return Ending::kStopped;
    }
    (void)CollectKeys(input, NowS());  // presses while paused count for none
    bool resume = input.action == ExperimenterAction::kResume;
    if (options_.script != nullptr) {
      const ScriptedUnplug* u = pending_unplug_;
      if (u == nullptr || !u->resume) {
        *stop_reason = "paused: " + pause_reason_;
        return Ending::kStopped;
      }
      if (NowS() - paused_at_s >= kScriptResumeAfterS) {
        if (options_.simulated != nullptr) options_.simulated->Replug();
        resume = true;
      }
    }
    if (resume) {
      if (box_unplugged_) {
        if (Status s = options_.box->Reconnect(); !s.ok()) {
          controller_.Pause("the response box is still missing: " +
                            s.error().message);
          WaitFrame(frame_start);
          continue;
        }
        box_unplugged_ = false;
      }
      if (device_faulted_ && options_.simulated == nullptr) {
        Status s = options_.reconnect ? options_.reconnect()
                                      : Status(Error{"it cannot be reopened "
                                                     "while burrlab runs"});
        if (!s.ok()) {
          controller_.Pause(fmt::format("the {} device is still missing: {}",
                                        options_.device_name,
                                        s.error().message));
          WaitFrame(frame_start);
          continue;
        }
      }
      device_faulted_ = false;
      pending_unplug_ = nullptr;
      controller_.SetDeviceState("ok");
      controller_.Resume();
      Log(answered
              ? fmt::format("resumed after trial {}", trial.trial_index + 1)
              : fmt::format("resumed: trial {} is presented again",
                            trial.trial_index + 1));
      return Ending::kAnswered;  // go on presenting
    }
    WaitFrame(frame_start);
  }
}

Result<LiveTrial> StationSession::PresentTrial(
    const protocols::TrialSpec& trial, int trials_done,
    const AdjustedComparison& adjusted) {
  LiveTrial result;
  for (;;) {
    ++presentations_;
    controller_.BeginTrial(trial, trials_done);
    trial_start_s_ = NowS();
    LiveTrial attempt;
    const Ending ending = RunPresentation(trial, adjusted, &attempt);
    if (ending == Ending::kAnswered) {
      attempt.aborted_presentations = result.aborted_presentations;
      for (results_schema::TraceSamples& t : attempt.traces) {
        t.trial_index = trial.trial_index;
      }
      return attempt;
    }
    if (ending == Ending::kStopped) {
      result.stop_reason = attempt.stop_reason;
      return result;
    }
    // A pause before SPACE cut nothing short.
    if (controller_.trial_aborted()) ++result.aborted_presentations;
    std::string stop_reason;
    if (WaitForResume(trial, &stop_reason) == Ending::kStopped) {
      result.stop_reason = stop_reason;
      return result;
    }
  }
}

std::string StationSession::AfterAnswer(const protocols::TrialSpec& trial,
                                        std::optional<bool> correct) {
  StationWindow& w = *options_.window;
  const StationScript* script = options_.script;
  const double since_s = NowS();
  controller_.BeginAfterAnswer(correct, since_s);
  while (controller_.after_answer()) {
    const auto frame_start = std::chrono::steady_clock::now();
    const double now_s = NowS();
    controller_.Advance(now_s);
    if (!controller_.after_answer()) break;
    const WindowInput input = DrawFrame();
    SaveShown(trial);
    w.Present();
    if (input.close_requested || input.action == ExperimenterAction::kAbort) {
      const std::string reason = input.close_requested
                                     ? "the subject window was closed"
                                     : "the experimenter aborted the session";
      controller_.Abort(reason);
      return reason;
    }
    if (input.action == ExperimenterAction::kPause) {
      // The answer is saved: the pause cuts only the feedback or the gap.
      pause_reason_ = "paused by the experimenter";
      controller_.Pause(pause_reason_);
      Log(fmt::format("paused after trial {} (its answer is saved)",
                      trial.trial_index + 1));
      std::string stop_reason;
      if (WaitForResume(trial, &stop_reason, true) == Ending::kStopped) {
        return stop_reason;
      }
      return {};
    }
    std::vector<Key> keys = CollectKeys(input, now_s);
    if (script != nullptr && script->end_feedback_after_s.has_value() &&
        controller_.phase() == StationPhase::kFeedback &&
        now_s - since_s >= *script->end_feedback_after_s) {
      keys.push_back({"SPACE", now_s});
    }
    for (const Key& k : keys) (void)controller_.OnInput(k.name, k.t_s);
    WaitFrame(frame_start);
  }
  return {};
}

void StationSession::Finish() {
  controller_.Finish();
  for (int k = 0; k < 2; ++k) {
    (void)DrawFrame();
    if (k == 0 && !options_.screenshots_dir.empty() && shown_ != "finished") {
      shown_ = "finished";
      const std::string path =
          (std::filesystem::path(options_.screenshots_dir) /
           fmt::format("{:03d}_finished.png", screenshots_ + 1))
              .string();
      if (options_.window->SaveScreenshot(path).ok()) ++screenshots_;
    }
    options_.window->Present();
  }
}

}  // namespace burrlab::runner
