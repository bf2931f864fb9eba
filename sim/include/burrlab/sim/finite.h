// Whether a vector's three components are all finite: the input checks of the
// step and of the phantoms, and the checks of positions and forces at the
// runner's device and haptic-loop boundaries.
#ifndef BURRLAB_SIM_FINITE_H_
#define BURRLAB_SIM_FINITE_H_

#include <cmath>
#include <glm/vec3.hpp>

namespace burrlab::sim {

// True unless a component is NaN or infinite.
inline bool IsFinite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_FINITE_H_
