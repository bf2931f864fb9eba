// The `simulated` device: plays a scripted position per read and records every
// force it is sent, for tests, dry runs and the loop benchmark. Memory is
// reserved at construction; reads and writes allocate nothing.
#ifndef BURRLAB_RUNNER_DEVICES_SIMULATED_DEVICE_H_
#define BURRLAB_RUNNER_DEVICES_SIMULATED_DEVICE_H_

#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "devices/device.h"

namespace burrlab::runner {

// A position to pass through at time t_s (for SampleWaypoints).
struct Waypoint {
  double t_s = 0.0;
  glm::dvec3 position_mm{0.0};
};

// Positions at rate_hz from t = 0 to the last waypoint's time, linearly
// interpolated between waypoints (sorted by time; at least one).
std::vector<glm::dvec3> SampleWaypoints(std::span<const Waypoint> waypoints,
                                        double rate_hz);

struct SimulatedDeviceOptions {
  DeviceSpec spec{"simulated",
                  8.0,
                  3.0,
                  {glm::dvec3(-50.0), glm::dvec3(50.0)}};  // Falcon-like
  std::vector<glm::dvec3> positions_mm;  // one per read; the last one is held
  std::size_t record_capacity = 0;       // forces kept (beyond: counted only)
  std::int64_t unplug_after_reads = -1;  // reads that succeed, then kUnplugged
};

class SimulatedDevice final : public HapticDevice {
 public:
  explicit SimulatedDevice(SimulatedDeviceOptions options);

  const DeviceSpec& spec() const noexcept override { return options_.spec; }
  // The next scripted position (the origin when the script is empty).
  DeviceStatus ReadPosition(glm::dvec3* position_mm) noexcept override;
  // Records the force as sent: clamped to |force| <= max_force_n; a
  // non-finite force is recorded as zero and refused.
  DeviceStatus WriteForce(const glm::dvec3& force_n) noexcept override;

  // Unplugs (true) or re-plugs (false) the device now. Like the calls
  // below, only while no loop thread uses the device.
  void SetUnplugged(bool unplugged) noexcept { unplugged_ = unplugged; }
  // Plays the script from its first position again.
  void Rewind() noexcept { reads_ = 0; }
  // Unplugs after `reads` more successful reads (negative: never).
  void UnplugAfterReads(std::int64_t reads) noexcept {
    options_.unplug_after_reads = reads < 0 ? -1 : reads_ + reads;
  }
  // Re-plugs the device and cancels a pending unplug.
  void Replug() noexcept {
    unplugged_ = false;
    options_.unplug_after_reads = -1;
  }
  // The forces sent so far, oldest first, up to record_capacity.
  std::span<const glm::dvec3> forces_n() const { return forces_n_; }
  std::int64_t reads() const { return reads_; }
  std::int64_t writes() const { return writes_; }

 private:
  SimulatedDeviceOptions options_;
  std::vector<glm::dvec3> forces_n_;
  std::int64_t reads_ = 0;
  std::int64_t writes_ = 0;
  bool unplugged_ = false;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_SIMULATED_DEVICE_H_
