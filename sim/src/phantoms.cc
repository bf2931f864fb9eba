// Synthetic phantoms with partial-volume surfaces. Voxels whose centre is
// farther from the surface than half the voxel diagonal are set to 0 or 255
// directly; a voxel the surface passes through gets round(255 x the fraction of
// its volume inside the shape):
//   - planes (half-space, slab): the exact volume of a cube cut by a plane,
//   - spheres: adaptive subdivision of the voxel down to cells of h <= v/4 and
//     R/8, with the exact cut of a sag-corrected tangent plane in the smallest
//     cells (ball volumes within ~1e-4 of 4/3 pi R^3 for R >= 1 mm at 0.3 mm).
#include "burrlab/sim/phantoms.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <string_view>

#include "burrlab/sim/finite.h"
#include "cube_cut.h"

namespace burrlab::sim {
namespace {

using internal::CubeFractionBelow;

constexpr double kHalfDiagonal = 0.8660254037844386;  // sqrt(3) / 2

std::string FormatVec(const glm::dvec3& v) {
  return fmt::format("({}, {}, {})", v.x, v.y, v.z);
}

// round(255 * fraction), with the fraction clamped to [0, 1] (NaN -> 0).
std::uint8_t Occupancy(double fraction) {
  if (!(fraction > 0.0)) return 0;
  if (fraction >= 1.0) return kSolidOccupancy;
  return static_cast<std::uint8_t>(std::lround(kSolidOccupancy * fraction));
}

// Unit vector along `normal`, or false when it is zero or not finite. Scales
// by the largest component first so tiny or huge normals do not underflow or
// overflow.
bool UnitNormal(const glm::dvec3& normal, glm::dvec3* unit) {
  if (!IsFinite(normal)) return false;
  const double largest =
      std::max({std::abs(normal.x), std::abs(normal.y), std::abs(normal.z)});
  if (largest == 0.0) return false;
  const glm::dvec3 scaled = normal / largest;
  *unit = scaled / std::sqrt(scaled.x * scaled.x + scaled.y * scaled.y +
                             scaled.z * scaled.z);
  return true;
}

glm::dvec3 VoxelCentre(const Volume& volume, int i, int j, int k) {
  return {volume.CentreMm(i), volume.CentreMm(j), volume.CentreMm(k)};
}

// Fills every voxel with Occupancy(fraction(centre)).
template <typename Fraction>
void Fill(Volume& volume, const Fraction& fraction) {
  for (int k = 0; k < volume.nz(); ++k) {
    for (int j = 0; j < volume.ny(); ++j) {
      for (int i = 0; i < volume.nx(); ++i) {
        volume.Set(i, j, k, Occupancy(fraction(VoxelCentre(volume, i, j, k))));
      }
    }
  }
}

Result<Volume> CreateGrid(std::string_view what, const PhantomGrid& grid) {
  Result<Volume> volume =
      Volume::Create(grid.nx, grid.ny, grid.nz, grid.voxel_mm);
  if (!volume.ok()) {
    return Error{fmt::format("{}: grid: {}", what, volume.error().message)};
  }
  return volume;
}

// Fraction of the cube (centre, edge) inside the ball, by subdividing cells
// the sphere surface passes through down to `depth_left` levels.
double BallFraction(const glm::dvec3& ball_centre, double radius,
                    const glm::dvec3& cell_centre, double edge,
                    int depth_left) {
  const glm::dvec3 offset = cell_centre - ball_centre;
  const double distance = std::sqrt(offset.x * offset.x + offset.y * offset.y +
                                    offset.z * offset.z);
  const double reach = kHalfDiagonal * edge;
  if (distance - radius >= reach) return 0.0;
  if (radius - distance >= reach) return 1.0;
  if (depth_left == 0) {
    // The plane normal to the radius through the cell centre, lowered by the
    // mean sag of the sphere below its tangent plane across the cell: at
    // lateral distance rho the sphere lies rho^2 / 2R inside the tangent plane,
    // and over a cube of edge h the mean rho^2 is h^2 / 6. This removes the
    // leading O(h^2 / R^2) bias of the plain tangent plane.
    const glm::dvec3 unit =
        distance > 0.0 ? offset / distance : glm::dvec3(0.0, 0.0, 1.0);
    const double sag = edge * edge / (12.0 * radius);
    return CubeFractionBelow(unit, (radius - distance - sag) / edge);
  }
  const double quarter = 0.25 * edge;
  double sum = 0.0;
  for (int child = 0; child < 8; ++child) {
    const glm::dvec3 shift((child & 1) ? quarter : -quarter,
                           (child & 2) ? quarter : -quarter,
                           (child & 4) ? quarter : -quarter);
    sum += BallFraction(ball_centre, radius, cell_centre + shift, 0.5 * edge,
                        depth_left - 1);
  }
  return sum / 8.0;
}

}  // namespace

Result<Volume> MakeHalfSpace(const PhantomGrid& grid,
                             const glm::dvec3& point_mm,
                             const glm::dvec3& outward_normal) {
  if (!IsFinite(point_mm)) {
    return Error{fmt::format("half-space: point_mm must be finite, got {}",
                             FormatVec(point_mm))};
  }
  glm::dvec3 unit;
  if (!UnitNormal(outward_normal, &unit)) {
    return Error{fmt::format(
        "half-space: outward_normal must be finite and non-zero, got {}",
        FormatVec(outward_normal))};
  }
  Result<Volume> volume = CreateGrid("half-space", grid);
  if (!volume.ok()) return volume;
  const double v = grid.voxel_mm;
  const double reach = kHalfDiagonal * v;
  Fill(*volume, [&](const glm::dvec3& centre) {
    const glm::dvec3 offset = centre - point_mm;
    const double d = unit.x * offset.x + unit.y * offset.y + unit.z * offset.z;
    if (d >= reach) return 0.0;
    if (d <= -reach) return 1.0;
    return CubeFractionBelow(unit, -d / v);
  });
  return volume;
}

Result<Volume> MakeSlab(const PhantomGrid& grid, const glm::dvec3& centre_mm,
                        const glm::dvec3& normal, double thickness_mm) {
  if (!IsFinite(centre_mm)) {
    return Error{fmt::format("slab: centre_mm must be finite, got {}",
                             FormatVec(centre_mm))};
  }
  glm::dvec3 unit;
  if (!UnitNormal(normal, &unit)) {
    return Error{fmt::format("slab: normal must be finite and non-zero, got {}",
                             FormatVec(normal))};
  }
  if (!std::isfinite(thickness_mm) || thickness_mm <= 0.0) {
    return Error{
        fmt::format("slab: thickness_mm must be positive and finite, got {}",
                    thickness_mm)};
  }
  Result<Volume> volume = CreateGrid("slab", grid);
  if (!volume.ok()) return volume;
  const double v = grid.voxel_mm;
  const double reach = kHalfDiagonal * v;
  const double half = 0.5 * thickness_mm;
  Fill(*volume, [&](const glm::dvec3& centre) {
    const glm::dvec3 offset = centre - centre_mm;
    const double d = unit.x * offset.x + unit.y * offset.y + unit.z * offset.z;
    const double from_middle = std::abs(d);
    if (from_middle >= half + reach) return 0.0;
    if (from_middle <= half - reach) return 1.0;
    // Material where -half <= unit . (x - centre_mm) <= half.
    return CubeFractionBelow(unit, (half - d) / v) -
           CubeFractionBelow(unit, (-half - d) / v);
  });
  return volume;
}

Result<Volume> MakeSphere(const PhantomGrid& grid, const glm::dvec3& centre_mm,
                          double radius_mm) {
  if (!IsFinite(centre_mm)) {
    return Error{fmt::format("sphere: centre_mm must be finite, got {}",
                             FormatVec(centre_mm))};
  }
  if (!std::isfinite(radius_mm) || radius_mm <= 0.0) {
    return Error{fmt::format(
        "sphere: radius_mm must be positive and finite, got {}", radius_mm)};
  }
  Result<Volume> volume = CreateGrid("sphere", grid);
  if (!volume.ok()) return volume;
  const double v = grid.voxel_mm;
  // Subdivide straddling voxels until cells are at most v / 4 and R / 8.
  int depth = 2;
  while (depth < 12 && std::ldexp(v, -depth) > radius_mm / 8.0) ++depth;
  Fill(*volume, [&](const glm::dvec3& centre) {
    return BallFraction(centre_mm, radius_mm, centre, v, depth);
  });
  return volume;
}

Result<Volume> MakeLayeredBlock(const PhantomGrid& grid,
                                const LayeredBlockSpec& spec) {
  if (!std::isfinite(spec.surface_z_mm)) {
    return Error{
        fmt::format("layered block: surface_z_mm must be finite, got {}",
                    spec.surface_z_mm)};
  }
  if (!std::isfinite(spec.cortical_thickness_mm) ||
      spec.cortical_thickness_mm < 0.0) {
    return Error{fmt::format(
        "layered block: cortical_thickness_mm must be finite and >= 0, got {}",
        spec.cortical_thickness_mm)};
  }
  if (!(spec.trabecular_density > 0.0 && spec.trabecular_density <= 1.0)) {
    return Error{fmt::format(
        "layered block: trabecular_density must be in (0, 1], got {}",
        spec.trabecular_density)};
  }
  if (!std::isfinite(spec.trabecular_erosion_factor) ||
      spec.trabecular_erosion_factor <= 0.0) {
    return Error{fmt::format(
        "layered block: trabecular_erosion_factor must be positive and "
        "finite, got {}",
        spec.trabecular_erosion_factor)};
  }
  Result<Volume> volume = CreateGrid("layered block", grid);
  if (!volume.ok()) return volume;
  volume->SetErosionFactor(kCorticalLabel, 1.0);
  volume->SetErosionFactor(kTrabecularLabel, spec.trabecular_erosion_factor);
  const double v = grid.voxel_mm;
  const double top = spec.surface_z_mm;
  const double boundary = top - spec.cortical_thickness_mm;
  // Length of [lo, hi] inside [z0, z1], as a fraction of the voxel.
  const auto overlap = [v](double z0, double z1, double lo, double hi) {
    return std::max(0.0, std::min(z1, hi) - std::max(z0, lo)) / v;
  };
  for (int k = 0; k < volume->nz(); ++k) {
    const double z0 = k * v;
    const double z1 = z0 + v;
    const double cortical = overlap(z0, z1, boundary, top);
    const double trabecular = std::max(0.0, std::min(z1, boundary) - z0) / v;
    const std::uint8_t occupancy =
        Occupancy(cortical + trabecular * spec.trabecular_density);
    // The label of the larger share of the voxel's material volume (ties go
    // to the cortex); air voxels keep label 0.
    const std::uint8_t label = cortical + trabecular <= 0.0 ? 0
                               : cortical >= trabecular     ? kCorticalLabel
                                                            : kTrabecularLabel;
    for (int j = 0; j < volume->ny(); ++j) {
      for (int i = 0; i < volume->nx(); ++i) {
        volume->Set(i, j, k, occupancy);
        volume->SetLabel(i, j, k, label);
      }
    }
  }
  return volume;
}

}  // namespace burrlab::sim
