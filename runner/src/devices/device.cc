// Device status names and workspace containment.
#include "devices/device.h"

namespace burrlab::runner {

bool Workspace::Contains(const glm::dvec3& position_mm) const noexcept {
  for (int axis = 0; axis < 3; ++axis) {
    if (!(position_mm[axis] >= min_mm[axis] &&
          position_mm[axis] <= max_mm[axis])) {
      return false;
    }
  }
  return true;
}

bool IsFault(DeviceCode code) noexcept {
  return code == DeviceCode::kNotReady || code == DeviceCode::kUnplugged ||
         code == DeviceCode::kNoResponse || code == DeviceCode::kIoError;
}

std::string_view DeviceCodeName(DeviceCode code) noexcept {
  switch (code) {
    case DeviceCode::kOk:
      return "ok";
    case DeviceCode::kStale:
      return "stale";
    case DeviceCode::kNotReady:
      return "not ready";
    case DeviceCode::kUnplugged:
      return "unplugged";
    case DeviceCode::kNoResponse:
      return "no response";
    case DeviceCode::kIoError:
      return "I/O error";
    case DeviceCode::kProtocolError:
      return "protocol error";
    case DeviceCode::kKinematicsFailed:
      return "kinematics failed";
    case DeviceCode::kInvalidArgument:
      return "invalid argument";
  }
  return "unknown";
}

}  // namespace burrlab::runner
