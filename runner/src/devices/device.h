// Haptic devices behind one interface. Every call returns a DeviceStatus with a
// reason, never a silent success (CHAI3D's base device "succeeds" when a method
// is not implemented, so an unplugged device looks like a working one). Each
// device states its limits in one DeviceSpec. ReadPosition and WriteForce run
// inside the 1 kHz tick: they allocate nothing, take no lock and throw nothing,
// and their reasons are string literals.
#ifndef BURRLAB_RUNNER_DEVICES_DEVICE_H_
#define BURRLAB_RUNNER_DEVICES_DEVICE_H_

#include <glm/vec3.hpp>
#include <string_view>

namespace burrlab::runner {

// An axis-aligned box of device positions, mm, in the device's own frame.
struct Workspace {
  glm::dvec3 min_mm{0.0};
  glm::dvec3 max_mm{0.0};

  // Whether `position_mm` lies inside the box (faces included).
  bool Contains(const glm::dvec3& position_mm) const noexcept;
};

// What a device can render; the haptic loop clamps to these.
struct DeviceSpec {
  std::string_view name;                // backend name, e.g. "falcon"
  double max_force_n = 0.0;             // largest |force| the loop may send
  double max_stiffness_n_per_mm = 0.0;  // stable stiffness at 1 kHz
  Workspace workspace;                  // reachable positions, mm
};

// Outcome of one device call. kStale is the only non-error besides kOk: the
// position returned is the previous one because no new sample arrived.
enum class DeviceCode {
  kOk,
  kStale,             // no new sample this tick; the last position is returned
  kNotReady,          // not opened, no firmware or not homed
  kUnplugged,         // the device went away (USB "no device")
  kNoResponse,        // nothing came back for too long
  kIoError,           // a transfer failed for another reason
  kProtocolError,     // bytes came back that do not follow the protocol
  kKinematicsFailed,  // encoder angles with no end-effector position
  kInvalidArgument,   // a caller passed a non-finite value
};

struct DeviceStatus {
  DeviceCode code = DeviceCode::kOk;
  const char* reason = "";  // a string literal, never owned or allocated

  bool ok() const noexcept { return code == DeviceCode::kOk; }
  // kOk and kStale: the position may be used.
  bool usable() const noexcept {
    return code == DeviceCode::kOk || code == DeviceCode::kStale;
  }
};

// Whether the device is gone or unusable (not ready, unplugged, no response,
// I/O error): the haptic loop stops on these; the others cost one tick.
bool IsFault(DeviceCode code) noexcept;
// The short name of a code, e.g. "unplugged".
std::string_view DeviceCodeName(DeviceCode code) noexcept;

class HapticDevice {
 public:
  virtual ~HapticDevice() = default;

  virtual const DeviceSpec& spec() const noexcept = 0;
  // The end-effector position, mm, in the device frame. On an error
  // `position_mm` is left unchanged.
  virtual DeviceStatus ReadPosition(glm::dvec3* position_mm) noexcept = 0;
  // Sends a force, N, in the device frame. A device refuses a non-finite force
  // (kInvalidArgument, zero force sent) and clamps |force| to its spec.
  virtual DeviceStatus WriteForce(const glm::dvec3& force_n) noexcept = 0;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_DEVICE_H_
