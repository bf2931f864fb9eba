// The scripted device.
#include "devices/simulated_device.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <glm/geometric.hpp>
#include <utility>

namespace burrlab::runner {

std::vector<glm::dvec3> SampleWaypoints(std::span<const Waypoint> waypoints,
                                        double rate_hz) {
  assert(!waypoints.empty() && rate_hz > 0.0);
  const double end_s = waypoints.back().t_s;
  const auto count =
      static_cast<std::size_t>(std::floor(end_s * rate_hz + 1e-9)) + 1;
  std::vector<glm::dvec3> positions;
  positions.reserve(count);
  std::size_t segment = 0;
  for (std::size_t n = 0; n < count; ++n) {
    const double t_s = static_cast<double>(n) / rate_hz;
    while (segment + 1 < waypoints.size() && waypoints[segment + 1].t_s < t_s) {
      ++segment;
    }
    const Waypoint& from = waypoints[segment];
    if (segment + 1 == waypoints.size() || t_s <= from.t_s) {
      positions.push_back(from.position_mm);
      continue;
    }
    const Waypoint& to = waypoints[segment + 1];
    const double span_s = to.t_s - from.t_s;
    const double u = span_s > 0.0 ? (t_s - from.t_s) / span_s : 1.0;
    positions.push_back(from.position_mm +
                        u * (to.position_mm - from.position_mm));
  }
  return positions;
}

SimulatedDevice::SimulatedDevice(SimulatedDeviceOptions options)
    : options_(std::move(options)) {
  forces_n_.reserve(options_.record_capacity);
}

DeviceStatus SimulatedDevice::ReadPosition(glm::dvec3* position_mm) noexcept {
  if (unplugged_ || (options_.unplug_after_reads >= 0 &&
                     reads_ >= options_.unplug_after_reads)) {
    unplugged_ = true;
    return {DeviceCode::kUnplugged, "simulated device unplugged"};
  }
  const std::vector<glm::dvec3>& script = options_.positions_mm;
  if (!script.empty()) {
    const auto last = static_cast<std::int64_t>(script.size()) - 1;
    *position_mm = script[static_cast<std::size_t>(std::min(reads_, last))];
  } else {
    *position_mm = glm::dvec3(0.0);
  }
  ++reads_;
  return {};
}

DeviceStatus SimulatedDevice::WriteForce(const glm::dvec3& force_n) noexcept {
  if (unplugged_) {
    return {DeviceCode::kUnplugged, "simulated device unplugged"};
  }
  ++writes_;
  glm::dvec3 sent = force_n;
  DeviceStatus status;
  if (!std::isfinite(force_n.x) || !std::isfinite(force_n.y) ||
      !std::isfinite(force_n.z)) {
    sent = glm::dvec3(0.0);
    status = {DeviceCode::kInvalidArgument,
              "non-finite force refused; zero force sent"};
  } else if (const double magnitude_n = glm::length(force_n);
             magnitude_n > options_.spec.max_force_n) {
    sent *= options_.spec.max_force_n / magnitude_n;
  }
  if (forces_n_.size() < forces_n_.capacity()) forces_n_.push_back(sent);
  return status;
}

}  // namespace burrlab::runner
