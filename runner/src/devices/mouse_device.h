// The `mouse` device: mouse and keyboard for pilots and demos, no force
// feedback. The cursor over the block view moves the burr in x and y, the
// wheel (or the held left button) lowers it; the force the loop would send is
// kept for the window's force indicator. The window's thread feeds the cursor
// through atomics; the loop's reads and writes take no lock and allocate
// nothing.
#ifndef BURRLAB_RUNNER_DEVICES_MOUSE_DEVICE_H_
#define BURRLAB_RUNNER_DEVICES_MOUSE_DEVICE_H_

#include <atomic>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "devices/device.h"

namespace burrlab::runner {

struct MouseDeviceOptions {
  Workspace workspace{glm::dvec3(-20.0, -20.0, -20.0),
                      glm::dvec3(20.0, 20.0, 20.0)};  // mm
  double depth_per_wheel_step_mm = 0.5;  // one wheel notch lowers this much
  double press_depth_mm = 3.0;           // the left button lowers this much
  double max_force_n = 8.0;              // scale of the force indicator
};

class MouseDevice final : public HapticDevice {
 public:
  explicit MouseDevice(MouseDeviceOptions options = {});

  const DeviceSpec& spec() const noexcept override { return spec_; }
  // The burr position from the last cursor update: x and y across the
  // workspace, z from the top of the workspace down by wheel and button.
  // kNotReady until the window has reported a cursor; kStale when it has not
  // moved since the last read.
  DeviceStatus ReadPosition(glm::dvec3* position_mm) noexcept override;
  // Keeps the force for the indicator (nothing is rendered): clamped to the
  // spec; a non-finite force is refused and kept as zero.
  DeviceStatus WriteForce(const glm::dvec3& force_n) noexcept override;

  // From the window's thread: cursor over the block view, (0, 0) top left to
  // (1, 1) bottom right (clamped), wheel steps (up positive) and the button.
  void SetCursor(const glm::dvec2& cursor, double wheel_steps,
                 bool button_down) noexcept;
  // The last force kept, N (any thread).
  double force_magnitude_n() const noexcept {
    return force_n_.load(std::memory_order_relaxed);
  }

 private:
  MouseDeviceOptions options_;
  DeviceSpec spec_;
  std::atomic<double> x_mm_{0.0}, y_mm_{0.0}, z_mm_{0.0};
  std::atomic<std::uint32_t> version_{0};
  std::uint32_t read_version_ = 0;
  std::atomic<double> force_n_{0.0};
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_MOUSE_DEVICE_H_
