// Mouse and keyboard as a device without force feedback.
#include "devices/mouse_device.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace burrlab::runner {

MouseDevice::MouseDevice(MouseDeviceOptions options)
    : options_(options),
      spec_{"mouse", options.max_force_n, 0.0, options.workspace} {}

void MouseDevice::SetCursor(const glm::dvec2& cursor, double wheel_steps,
                            bool button_down) noexcept {
  const glm::dvec3& lo = options_.workspace.min_mm;
  const glm::dvec3& hi = options_.workspace.max_mm;
  const double u =
      std::isfinite(cursor.x) ? std::clamp(cursor.x, 0.0, 1.0) : 0.5;
  const double v =
      std::isfinite(cursor.y) ? std::clamp(cursor.y, 0.0, 1.0) : 0.5;
  const double steps = std::isfinite(wheel_steps) ? wheel_steps : 0.0;
  double depth = -steps * options_.depth_per_wheel_step_mm;
  if (button_down) depth += options_.press_depth_mm;
  x_mm_.store(lo.x + u * (hi.x - lo.x), std::memory_order_relaxed);
  // Screen y grows downwards; the workspace's y grows away from the subject.
  y_mm_.store(hi.y - v * (hi.y - lo.y), std::memory_order_relaxed);
  z_mm_.store(std::clamp(hi.z - std::max(depth, 0.0), lo.z, hi.z),
              std::memory_order_relaxed);
  version_.fetch_add(1, std::memory_order_release);
}

DeviceStatus MouseDevice::ReadPosition(glm::dvec3* position_mm) noexcept {
  const std::uint32_t version = version_.load(std::memory_order_acquire);
  if (version == 0) {
    return {DeviceCode::kNotReady,
            "the window has not reported the cursor yet"};
  }
  *position_mm = glm::dvec3(x_mm_.load(std::memory_order_relaxed),
                            y_mm_.load(std::memory_order_relaxed),
                            z_mm_.load(std::memory_order_relaxed));
  if (version == read_version_) {
    return {DeviceCode::kStale, "the cursor has not moved"};
  }
  read_version_ = version;
  return {};
}

DeviceStatus MouseDevice::WriteForce(const glm::dvec3& force_n) noexcept {
  if (!std::isfinite(force_n.x) || !std::isfinite(force_n.y) ||
      !std::isfinite(force_n.z)) {
    force_n_.store(0.0, std::memory_order_relaxed);
    return {DeviceCode::kInvalidArgument, "non-finite force"};
  }
  force_n_.store(std::min(glm::length(force_n), spec_.max_force_n),
                 std::memory_order_relaxed);
  return {};
}

}  // namespace burrlab::runner
