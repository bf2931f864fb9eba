// Stub: being written.
#include "burrlab/sim/moments.h"
namespace burrlab::sim {
double EqualVolumeSphereRadius(double) { return 0; }
double LensVolume(double, double, double) { return 0; }
double LensArea(double, double, double) { return 0; }
double RadicalPlaneDistance(double, double, double) { return 0; }
double CapVolume(double, double) { return 0; }
double DepthFromM0(double, double) { return 0; }
Moments ComputeMomentsMono(const Volume&, const glm::dvec3&, double) noexcept { return {}; }
Moments ComputeMomentsOctree(const MomentOctree&, const Volume&, const glm::dvec3&, double, double) noexcept { return {}; }
}  // namespace burrlab::sim
