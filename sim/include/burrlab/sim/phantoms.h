// Synthetic bone phantoms with partial-volume (anti-aliased) surfaces: each
// voxel's occupancy is 255 times the fraction of the voxel inside the shape, so
// moments of the voxelised shape converge to the continuous ones (tests compare
// against closed forms).
#ifndef BURRLAB_SIM_PHANTOMS_H_
#define BURRLAB_SIM_PHANTOMS_H_

#include <cstdint>
#include <glm/vec3.hpp>

#include "burrlab/base/result.h"
#include "burrlab/sim/volume.h"

namespace burrlab::sim {

// Grid of a phantom: extents in voxels and the cubic voxel size.
struct PhantomGrid {
  int nx = 64;
  int ny = 64;
  int nz = 64;
  double voxel_mm = 0.3;
};

// Solid material on the side of the plane through point_mm opposite to
// outward_normal (the normal need not be unit length; it must be non-zero and
// finite).
Result<Volume> MakeHalfSpace(const PhantomGrid& grid,
                             const glm::dvec3& point_mm,
                             const glm::dvec3& outward_normal);

// Solid slab of thickness_mm centred on the plane through centre_mm with the
// given normal.
Result<Volume> MakeSlab(const PhantomGrid& grid, const glm::dvec3& centre_mm,
                        const glm::dvec3& normal, double thickness_mm);

// Solid ball.
Result<Volume> MakeSphere(const PhantomGrid& grid, const glm::dvec3& centre_mm,
                          double radius_mm);

// A block of temporal bone: a cortical layer (label kCorticalLabel, erosion
// factor 1) of cortical_thickness_mm below the top surface at surface_z_mm,
// over trabecular bone (label kTrabecularLabel) of lower density and higher
// erosion factor. Air above.
struct LayeredBlockSpec {
  double surface_z_mm = 15.0;          // top surface height
  double cortical_thickness_mm = 2.0;  // cortex thickness below the surface
  double trabecular_density =
      0.6;  // trabecular occupancy as a fraction of rho0 (0, 1]
  double trabecular_erosion_factor =
      2.5;  // alpha multiplier of trabecular voxels (> 0)
};
inline constexpr std::uint8_t kCorticalLabel = 1;
inline constexpr std::uint8_t kTrabecularLabel = 2;
Result<Volume> MakeLayeredBlock(const PhantomGrid& grid,
                                const LayeredBlockSpec& spec);

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_PHANTOMS_H_
