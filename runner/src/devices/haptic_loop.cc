// The haptic loop: tick, pacing, real-time set-up and statistics.
#include "devices/haptic_loop.h"

#include <fmt/format.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <glm/geometric.hpp>

#include "burrlab/sim/finite.h"

namespace burrlab::runner {
namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;

}  // namespace

std::int64_t MonotonicClock::NowNs() noexcept {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * kNsPerS + now.tv_nsec;
}

void MonotonicClock::SleepUntilNs(std::int64_t time_ns) noexcept {
  timespec until{};
  until.tv_sec = static_cast<time_t>(time_ns / kNsPerS);
  until.tv_nsec = static_cast<long>(time_ns % kNsPerS);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &until, nullptr) ==
         EINTR) {
  }
}

HapticLoop::HapticLoop(HapticDevice* device, ForceSource* source,
                       LoopClock* clock, LoopOptions options)
    : device_(device),
      source_(source),
      clock_(clock),
      options_(options),
      period_ns_(options.rate_hz > 0.0 && std::isfinite(options.rate_hz)
                     ? std::llround(1e9 / options.rate_hz)
                     : 0),
      budget_ns_(options.budget_ns > 0 ? options.budget_ns : period_ns_),
      max_force_n_(
          options.max_force_n > 0.0
              ? std::min(options.max_force_n, device->spec().max_force_n)
              : device->spec().max_force_n) {
  period_errors_ns_.reserve(options_.max_samples);
}

HapticLoop::~HapticLoop() { Stop(); }

void HapticLoop::RecordPeriodError(std::int64_t error_ns) noexcept {
  max_error_ns_ = std::max(max_error_ns_, error_ns);
  if (period_errors_ns_.capacity() == 0) return;
  if (period_errors_ns_.size() < period_errors_ns_.capacity()) {
    period_errors_ns_.push_back(error_ns);  // within the reservation
  } else {
    period_errors_ns_[next_sample_] = error_ns;
    next_sample_ = (next_sample_ + 1) % period_errors_ns_.size();
  }
}

DeviceStatus HapticLoop::Tick(std::int64_t deadline_ns) noexcept {
  RecordPeriodError(clock_->NowNs() - deadline_ns);
  ++counters_.ticks;
  glm::dvec3 position_mm(0.0);
  const DeviceStatus read = device_->ReadPosition(&position_mm);
  if (!read.usable()) {
    ++counters_.device_errors;
    seh_.Reset();
    last_force_n_ = glm::dvec3(0.0);
    (void)device_->WriteForce(last_force_n_);  // best effort; it has failed
    return read;
  }
  if (read.code == DeviceCode::kStale) ++counters_.stale_reads;

  glm::dvec3 force_n = source_->Force(position_mm);
  const std::int64_t ready_ns = clock_->NowNs();
  if (!sim::IsFinite(force_n)) {
    ++counters_.non_finite;
    force_n = glm::dvec3(0.0);
    seh_.Reset();
  } else if (ready_ns - deadline_ns > budget_ns_) {
    ++counters_.missed_deadlines;
    force_n = glm::dvec3(0.0);
    seh_.Reset();  // the history is a tick old
  } else {
    force_n = seh_.Update(force_n);
    const double max_force_n = max_force_n_;
    const double magnitude_n = glm::length(force_n);
    if (!std::isfinite(magnitude_n)) {  // overflow in the extrapolation
      ++counters_.non_finite;
      force_n = glm::dvec3(0.0);
      seh_.Reset();
    } else if (magnitude_n > max_force_n) {
      ++counters_.clamped;
      force_n *= max_force_n / magnitude_n;
    }
  }
  last_force_n_ = force_n;
  const DeviceStatus write = device_->WriteForce(force_n);
  if (!write.ok()) {
    ++counters_.device_errors;
    if (IsFault(write.code)) return write;
  }
  return read;
}

void HapticLoop::SetUpRealtime() {
  realtime_ = RealtimeSetup{};
  if (!options_.realtime) {
    realtime_.note = "real-time scheduling not requested";
    return;
  }
  std::string note;
#if defined(__SANITIZE_ADDRESS__)
  note = "mlockall skipped: AddressSanitizer maps terabytes of shadow memory";
#else
  if (!options_.lock_memory) {
    // The caller holds the lock.
  } else if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
    realtime_.memory_locked = true;
  } else {
    note = fmt::format(
        "mlockall failed ({}): page faults may delay ticks; raise the "
        "memlock limit (ulimit -l) or run with CAP_IPC_LOCK",
        std::strerror(errno));
  }
#endif
  sched_param param{};
  param.sched_priority = options_.fifo_priority;
  const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (rc == 0) {
    realtime_.fifo = true;
  } else {
    note += fmt::format(
        "{}SCHED_FIFO not permitted ({}): the loop runs at normal priority "
        "and other work can delay ticks; grant CAP_SYS_NICE or an rtprio "
        "limit in /etc/security/limits.conf",
        note.empty() ? "" : "; ", std::strerror(rc));
  }
  realtime_.note = note;
}

void HapticLoop::Run(std::int64_t ticks) noexcept {
  std::int64_t done = 0;
  std::int64_t deadline_ns = clock_->NowNs() + period_ns_;
  while (!stop_.load(std::memory_order_relaxed) &&
         (ticks < 0 || done < ticks)) {
    clock_->SleepUntilNs(deadline_ns - options_.spin_ns);
    while (clock_->NowNs() < deadline_ns) {
    }
    const DeviceStatus status = Tick(deadline_ns);
    ++done;
    if (IsFault(status.code)) {
      fault_ = status;
      break;
    }
    deadline_ns += period_ns_;
    const std::int64_t late_ns = clock_->NowNs() - deadline_ns;
    if (late_ns > period_ns_) {  // more than a whole period behind: skip
      const std::int64_t behind = late_ns / period_ns_;
      counters_.skipped_ticks += behind;
      deadline_ns += behind * period_ns_;
    }
  }
  last_force_n_ = glm::dvec3(0.0);
  (void)device_->WriteForce(last_force_n_);
}

Status HapticLoop::Start(std::int64_t ticks) {
  if (thread_.joinable()) return Error{"haptic loop: already running"};
  if (!(options_.rate_hz > 0.0) || period_ns_ <= 0) {
    return Error{fmt::format("haptic loop: rate_hz must be positive, got {}",
                             options_.rate_hz)};
  }
  stop_ = false;
  ended_ = false;
  fault_ = DeviceStatus{};
  thread_ = std::thread([this, ticks] {
    SetUpRealtime();
    Run(ticks);
    if (realtime_.memory_locked) munlockall();
    ended_.store(true, std::memory_order_release);
  });
  return {};
}

void HapticLoop::Wait() {
  if (thread_.joinable()) thread_.join();
}

void HapticLoop::Stop() {
  stop_ = true;
  Wait();
}

LoopStats HapticLoop::Stats() const {
  LoopStats stats;
  stats.samples = static_cast<std::int64_t>(period_errors_ns_.size());
  stats.max_us = static_cast<double>(max_error_ns_) * 1e-3;
  stats.overruns = counters_.missed_deadlines;
  if (period_errors_ns_.empty()) return stats;
  std::vector<std::int64_t> sorted = period_errors_ns_;
  std::sort(sorted.begin(), sorted.end());
  // Nearest rank: the smallest value with at least q of the samples at or
  // below it.
  const auto rank = [&](double q) {
    const auto n = static_cast<double>(sorted.size());
    const auto index =
        static_cast<std::size_t>(std::max(0.0, std::ceil(q * n) - 1.0));
    return static_cast<double>(sorted[std::min(index, sorted.size() - 1)]) *
           1e-3;
  };
  stats.p50_us = rank(0.50);
  stats.p99_us = rank(0.99);
  return stats;
}

}  // namespace burrlab::runner
