// The real-time haptic loop (README.md, "Haptic devices and the 1 kHz loop";
// dissertation ch. 11): its own thread at 1 kHz, SCHED_FIFO and mlockall when
// permitted, sleep-then-spin pacing. Each tick samples the device position,
// asks a ForceSource for the force, passes it through sample-estimate-hold
// (§6.4.3) and the device's force clamp, and sends it. A watchdog sends zero
// force instead when the force is not finite or is ready later than the tick's
// budget, and counts it. A tick allocates nothing, takes no lock, does no I/O
// beyond the device and throws nothing; counters and statistics are read after
// Stop or Wait.
#ifndef BURRLAB_RUNNER_DEVICES_HAPTIC_LOOP_H_
#define BURRLAB_RUNNER_DEVICES_HAPTIC_LOOP_H_

#include <atomic>
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <thread>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/sim/seh.h"
#include "common/loop_counters.h"
#include "devices/device.h"

namespace burrlab::runner {

// What the loop renders: a force for a device position, once per tick. Must
// not allocate, lock or throw.
class ForceSource {
 public:
  virtual ~ForceSource() = default;
  virtual glm::dvec3 Force(const glm::dvec3& position_mm) noexcept = 0;
};

// Time for the loop; tests use a fake.
class LoopClock {
 public:
  virtual ~LoopClock() = default;
  virtual std::int64_t NowNs() noexcept = 0;
  // Returns at or after `time_ns` (at once when it has passed).
  virtual void SleepUntilNs(std::int64_t time_ns) noexcept = 0;
};

// CLOCK_MONOTONIC with absolute clock_nanosleep.
class MonotonicClock final : public LoopClock {
 public:
  std::int64_t NowNs() noexcept override;
  void SleepUntilNs(std::int64_t time_ns) noexcept override;
};

struct LoopOptions {
  double rate_hz = 1000.0;         // ticks per second
  std::int64_t spin_ns = 300'000;  // sleep until this long before a deadline,
                                   // then spin (build notes: p99 < 1 us)
  std::int64_t budget_ns = 0;  // the force must be ready this long after the
                               // tick's deadline; 0 = one period
  bool realtime = true;        // try SCHED_FIFO and mlockall
  bool lock_memory = true;     // mlockall for the run (false: the caller
                               // holds the lock, e.g. for a whole session)
  int fifo_priority = 80;      // SCHED_FIFO priority, 1-99
  std::size_t max_samples = 600'000;  // period errors kept (the latest)
  double max_force_n = 0.0;  // clamp on |force| below the device's own limit
                             // (the station file's); 0 = the device's limit
};

// What Start managed to set up for real time, and why not when it did not.
struct RealtimeSetup {
  bool fifo = false;           // SCHED_FIFO at LoopOptions::fifo_priority
  bool memory_locked = false;  // mlockall(MCL_CURRENT | MCL_FUTURE)
  std::string note;            // empty when both worked
};

class HapticLoop {
 public:
  // The device, source and clock must outlive the loop.
  HapticLoop(HapticDevice* device, ForceSource* source, LoopClock* clock,
             LoopOptions options = {});
  ~HapticLoop();
  HapticLoop(const HapticLoop&) = delete;
  HapticLoop& operator=(const HapticLoop&) = delete;

  // One tick due at deadline_ns (the loop body; tests call it directly).
  // Returns the device's status: on a fault (IsFault) zero force was
  // attempted and the thread stops.
  DeviceStatus Tick(std::int64_t deadline_ns) noexcept;

  // Starts the loop thread; it runs `ticks` ticks (negative: until Stop) or
  // until the device reports a fault.
  Status Start(std::int64_t ticks = -1);
  // Waits for the thread to finish by itself.
  void Wait();
  // Asks the thread to stop and waits for it.
  void Stop();
  // Whether a started thread has ended by itself (its tick count ran out or
  // the device failed); any thread may ask.
  bool ended() const { return ended_.load(std::memory_order_acquire); }

  const LoopCounters& counters() const { return counters_; }
  LoopStats Stats() const;
  const RealtimeSetup& realtime() const { return realtime_; }
  // The device failure that stopped the thread (ok when none).
  DeviceStatus fault() const { return fault_; }
  // The force sent by the last tick.
  const glm::dvec3& last_force_n() const { return last_force_n_; }
  std::int64_t period_ns() const { return period_ns_; }
  // The force limit the loop applies: the smaller of the device's and
  // LoopOptions::max_force_n.
  double max_force_n() const { return max_force_n_; }

 private:
  void Run(std::int64_t ticks) noexcept;
  void SetUpRealtime();
  void RecordPeriodError(std::int64_t error_ns) noexcept;

  HapticDevice* device_;
  ForceSource* source_;
  LoopClock* clock_;
  LoopOptions options_;
  std::int64_t period_ns_;
  std::int64_t budget_ns_;
  double max_force_n_;
  sim::SampleEstimateHold seh_;
  LoopCounters counters_;
  std::vector<std::int64_t> period_errors_ns_;  // ring of the latest errors
  std::size_t next_sample_ = 0;
  std::int64_t max_error_ns_ = 0;
  glm::dvec3 last_force_n_{0.0};
  DeviceStatus fault_;
  RealtimeSetup realtime_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> ended_{false};
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_HAPTIC_LOOP_H_
