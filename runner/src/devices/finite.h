// Whether a vector's three components are all finite (the checks of positions
// and forces at the device and haptic-loop boundaries).
#ifndef BURRLAB_RUNNER_DEVICES_FINITE_H_
#define BURRLAB_RUNNER_DEVICES_FINITE_H_

#include <cmath>
#include <glm/vec3.hpp>

namespace burrlab::runner {

// True unless a component is NaN or infinite.
inline bool IsFinite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_FINITE_H_
