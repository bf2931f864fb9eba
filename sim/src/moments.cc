// Moments of bone mass in the burr sphere: voxel-sphere geometry
// (eqs. 6.17-6.20), the mono-resolution sums (6.21-6.22), the multi-resolution
// octree descent (7.9-7.11) and the effective depth of eq. 7.2.
#include "burrlab/sim/moments.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "cube_cut.h"
#include "octree_walk.h"

namespace burrlab::sim {
namespace {

constexpr double kPi = std::numbers::pi;
// (3 / (4 pi))^(1/3): radius of the sphere with the volume of a unit cube.
constexpr double kEqualVolumeRadiusPerSide = 0.62035049089940001667;

// Centroid distance, from the burr centre, of the lens where the burr sphere
// (radius R) and a sphere of radius eta at distance d overlap: the lens is a
// cap of each sphere cut by the radical plane, and a cap of height h on a
// sphere of radius r has its centroid 3 (2r - h)^2 / (4 (3r - h)) from that
// sphere's centre.
double LensCentroidDistance(double d, double radius, double eta) {
  const double x = RadicalPlaneDistance(d, radius, eta);
  const double h1 =
      std::clamp(radius - x, 0.0, 2.0 * radius);  // cap of the burr sphere
  const double h2 =
      std::clamp(eta - (d - x), 0.0, 2.0 * eta);  // cap of the eta-sphere
  const double v1 = kPi * h1 * h1 * (3.0 * radius - h1) / 3.0;
  const double v2 = kPi * h2 * h2 * (3.0 * eta - h2) / 3.0;
  if (v1 + v2 <= 0.0) return x;
  const double z1 = 3.0 * (2.0 * radius - h1) * (2.0 * radius - h1) /
                    (4.0 * (3.0 * radius - h1));
  const double z2 =
      d - 3.0 * (2.0 * eta - h2) * (2.0 * eta - h2) / (4.0 * (3.0 * eta - h2));
  return (v1 * z1 + v2 * z2) / (v1 + v2);
}

// cbrt(occupancy / 255) for every occupancy, the radius of a partial voxel's
// own-volume sphere over the voxel sphere's (AddVoxel), looked up rather than
// computed for every partial voxel of every step. The table is filled at run
// time (once, at start-up, so the tick never meets a first-use guard) by the
// same libm cbrt the step called before, through a volatile pointer: a loop
// calling std::cbrt itself was compiled to give the correctly rounded values
// (cbrt(225/255) = ...251) rather than glibc's (...262), and that last bit
// changed every result downstream.
const std::array<double, 256> kCbrtOfOccupancy = [] {
  std::array<double, 256> table{};
  double (*volatile libm_cbrt)(double) = &::cbrt;
  for (std::size_t o = 0; o < table.size(); ++o) {
    table[o] = libm_cbrt(static_cast<double>(o) /
                         static_cast<double>(kSolidOccupancy));
  }
  return table;
}();

// One voxel's contribution by the voxel-sphere approximation (eqs. 6.21-6.22).
// The voxel sphere wholly inside the burr contributes its full volume at its
// centre; a partial one contributes the lens volume Delta V (6.17) at distance
// r(d) (6.20) along its direction. (Eq. 6.22 as printed applies r_i/d_i to
// every voxel; for a voxel wholly inside, r(d) is not a point of the voxel, so
// its own centre is used there.)
//
// Partial-volume voxels (0 < occupancy < 255) on a surface hold their material
// on the solid side, not spread over the voxel: treated as uniform spheres they
// move the surface by up to half a voxel towards the burr, which at an
// immersion of one voxel overstates m0 by 20 % and h by 10 %. burrlab therefore
// represents such a voxel by a sphere of its own material volume (radius eta
// f^(1/3)), moved (1 - f) v / 2 along the local occupancy gradient (central
// differences): the exact centroid of a partial voxel cut by an axis-aligned
// surface.
// occupancy / 255 for every occupancy: the same values, without a division
// per voxel.
const std::array<double, 256> kDensityOfOccupancy = [] {
  std::array<double, 256> table{};
  for (std::size_t o = 0; o < table.size(); ++o) {
    table[o] = static_cast<double>(o) / static_cast<double>(kSolidOccupancy);
  }
  return table;
}();

// What AddVoxel needs of the burr and the voxel size, computed once per moment
// evaluation rather than for every voxel. Distances are compared squared, so a
// voxel wholly inside or outside the burr costs no square root, and the lens
// of a voxel sphere cut by the burr surface costs one square root and one
// division (eqs. 6.17, 6.20 with 1/d shared).
struct VoxelSphere {
  VoxelSphere(double radius_mm, double eta_mm, double voxel_mm)
      : radius(radius_mm),
        eta(eta_mm),
        voxel(voxel_mm),
        voxel_volume(voxel_mm * voxel_mm * voxel_mm),
        // Wholly inside: d <= R - eta (none when the burr is the smaller).
        inside2(radius_mm > eta_mm ? (radius_mm - eta_mm) * (radius_mm - eta_mm)
                                   : -1.0),
        outside2((radius_mm + eta_mm) * (radius_mm + eta_mm)),
        // Where a moved partial-volume sphere may cut the burr surface.
        moved_inside2(radius_mm > 2.0 * eta_mm ? (radius_mm - 2.0 * eta_mm) *
                                                     (radius_mm - 2.0 * eta_mm)
                                               : -1.0),
        moved_outside2((radius_mm + 2.0 * eta_mm) * (radius_mm + 2.0 * eta_mm)),
        // Eq. 6.18: Delta V = pi/12 (d^3 - linear d + constant - inverse / d).
        lens_linear(6.0 * (radius_mm * radius_mm + eta_mm * eta_mm)),
        lens_constant(8.0 * (radius_mm * radius_mm * radius_mm +
                             eta_mm * eta_mm * eta_mm)),
        lens_inverse(3.0 * (eta_mm * eta_mm - radius_mm * radius_mm) *
                     (eta_mm * eta_mm - radius_mm * radius_mm)),
        // Eq. 6.20 over d: r(d) / d = 1/2 + half_power_difference / d^2.
        half_power_difference(0.5 * (radius_mm * radius_mm - eta_mm * eta_mm)) {
  }
  double radius, eta, voxel, voxel_volume;
  double inside2, outside2, moved_inside2, moved_outside2;
  double lens_linear, lens_constant, lens_inverse, half_power_difference;
};

// A sphere of radius `sphere_eta` and volume `volume_mm3` (density 1) at
// `offset_mm` from the burr centre, distance d_mm: the general form of
// AddVoxel's terms, for the moved partial-volume spheres.
void AddSphere(const glm::dvec3& offset_mm, double d_mm, double radius,
               double sphere_eta, double volume_mm3, Moments& m) {
  if (d_mm >= radius + sphere_eta) return;
  if (d_mm <= radius - sphere_eta) {
    m.m0_mm3 += volume_mm3;
    m.m1_mm4 += volume_mm3 * offset_mm;
    return;
  }
  const double w = LensVolume(d_mm, radius, sphere_eta);
  m.m0_mm3 += w;
  m.m1_mm4 +=
      (w * RadicalPlaneDistance(d_mm, radius, sphere_eta) / d_mm) * offset_mm;
}

// One voxel's contribution by the voxel-sphere approximation (eqs. 6.21-6.22),
// the voxel centre at `offset_mm` from the burr centre, d2_mm2 its squared
// distance. The voxel sphere wholly inside the burr contributes its full
// volume at its centre; a partial one contributes the lens volume Delta V
// (6.17) at distance r(d) (6.20) along its direction. (Eq. 6.22 as printed
// applies r_i/d_i to every voxel; for a voxel wholly inside, r(d) is not a
// point of the voxel, so its own centre is used there.)
//
// Partial-volume voxels (0 < occupancy < 255) on a surface hold their material
// on the solid side, not spread over the voxel: treated as uniform spheres they
// move the surface by up to half a voxel towards the burr, which at an
// immersion of one voxel overstates m0 by 20 % and h by 10 %. burrlab therefore
// represents such a voxel by a sphere of its own material volume (radius eta
// f^(1/3)), moved (1 - f) v / 2 along the local occupancy gradient (central
// differences): the exact centroid of a partial voxel cut by an axis-aligned
// surface.
inline void AddVoxel(const Volume& volume, const VoxelSphere& s, int i, int j,
                     int k, std::uint8_t occupancy, const glm::dvec3& offset_mm,
                     double d2_mm2, Moments& m) {
  const double density = kDensityOfOccupancy[occupancy];
  if (occupancy < kSolidOccupancy && d2_mm2 > s.moved_inside2 &&
      d2_mm2 < s.moved_outside2) {
    const glm::dvec3 gradient(volume.At(i + 1, j, k) - volume.At(i - 1, j, k),
                              volume.At(i, j + 1, k) - volume.At(i, j - 1, k),
                              volume.At(i, j, k + 1) - volume.At(i, j, k - 1));
    const double g =
        std::sqrt(gradient.x * gradient.x + gradient.y * gradient.y +
                  gradient.z * gradient.z);
    if (g > 0.0) {
      const double shift = 0.5 * (1.0 - density) * s.voxel;
      const glm::dvec3 moved = offset_mm + (shift / g) * gradient;
      AddSphere(
          moved,
          std::sqrt(moved.x * moved.x + moved.y * moved.y + moved.z * moved.z),
          s.radius, s.eta * kCbrtOfOccupancy[occupancy],
          density * s.voxel_volume, m);
      return;
    }
  }
  if (d2_mm2 >= s.outside2) return;
  if (d2_mm2 <= s.inside2) {
    const double w = density * s.voxel_volume;
    m.m0_mm3 += w;
    m.m1_mm4 += w * offset_mm;
    return;
  }
  const double d = std::sqrt(d2_mm2);
  if (!(s.inside2 > 0.0)) {  // a burr smaller than a voxel sphere
    Moments one;
    AddSphere(offset_mm, d, s.radius, s.eta, s.voxel_volume, one);
    m.m0_mm3 += density * one.m0_mm3;
    m.m1_mm4 += density * one.m1_mm4;
    return;
  }
  const double inv_d = 1.0 / d;
  const double w = density * (kPi / 12.0) *
                   (d2_mm2 * d - s.lens_linear * d + s.lens_constant -
                    s.lens_inverse * inv_d);
  m.m0_mm3 += w;
  m.m1_mm4 += (w * (0.5 + s.half_power_difference * inv_d * inv_d)) * offset_mm;
}

// Octree visitor for the multi-resolution moments.
struct MomentVisitor {
  // Largest relative density change across a partial block accepted whole.
  static constexpr double kMaxGradient = 0.25;
  const Volume* volume;
  glm::dvec3 centre_vox;
  double radius_vox, eta_vox, ell_vox;
  double voxel_mm, radius_mm, eta_mm, voxel_volume;
  VoxelSphere sphere;
  // (R - 2 eta)^2 in voxels^2: a block whose farthest voxel centre is nearer
  // lies wholly inside the burr; -1 when no block can.
  double whole2_vox2;
  Moments moments;
  // What OnBlock needs of the voxel size and of each level whose blocks it may
  // take as partial blocks (2^level <= ell_vox), computed once per evaluation
  // by the expressions OnBlock used per block (SetUp): the same values.
  struct PartialLevel {
    double side_mm, eta_block, sag, gradient_scale;
  };
  static constexpr int kMaxPartialLevel = 30;
  double unit = 0.0;     // mm^3 per occupancy unit
  double m1_unit = 0.0;  // mm^4 per occupancy unit x half-voxel
  std::array<PartialLevel, kMaxPartialLevel + 1> partial_levels{};

  void SetUp() {
    unit = voxel_volume / kSolidOccupancy;
    m1_unit = 0.5 * voxel_mm * unit;
    for (int level = 1; level <= kMaxPartialLevel &&
                        static_cast<double>(1 << level) <= ell_vox;
         ++level) {
      const double side_mm = static_cast<double>(1 << level) * voxel_mm;
      partial_levels[static_cast<std::size_t>(level)] = {
          side_mm, EqualVolumeSphereRadius(side_mm),
          side_mm * side_mm / (12.0 * radius_mm), 12.0 / (side_mm * side_mm)};
    }
  }

  internal::BlockAction OnBlock(const internal::BlockView& b) {
    const double size_vox = static_cast<double>(1 << b.level);
    const bool whole = b.dmax2_vox2 <= whole2_vox2;
    if (!whole && size_vox > ell_vox) {
      // Where no level is taken as partial blocks (ell under 2 voxels), a
      // wholly solid block whose nearest voxel centre lies beyond R + eta
      // adds nothing: it would be refined down to voxels, each of which
      // Ignores drops (every voxel's squared distance is at least the
      // block's, rounding included, the sums being of the same non-negative
      // terms or larger ones). Skipped rather than refined. (Levels above 18
      // are left to the refinement: their full mass would overflow m0.)
      if (ell_vox < 2.0 && b.level <= 18 &&
          b.node->m0 == std::int64_t{kSolidOccupancy} << (3 * b.level) &&
          b.dmin2_vox2 * (voxel_mm * voxel_mm) >= sphere.outside2) {
        return internal::BlockAction::kSkip;
      }
      return internal::BlockAction::kRefine;
    }
    const double m0 = static_cast<double>(b.node->m0) * unit;
    const glm::dvec3 m1_about_block(static_cast<double>(b.node->m1[0]),
                                    static_cast<double>(b.node->m1[1]),
                                    static_cast<double>(b.node->m1[2]));
    const glm::dvec3 block_centre_vox((b.bx + 0.5) * size_vox,
                                      (b.by + 0.5) * size_vox,
                                      (b.bz + 0.5) * size_vox);
    const glm::dvec3 rel_mm = (block_centre_vox - centre_vox) * voxel_mm;
    if (whole) {
      // Every voxel sphere of the block lies inside the burr, even a moved
      // partial-volume voxel sphere (see AddVoxel): the exact block moments.
      moments.m0_mm3 += m0;
      moments.m1_mm4 += m0 * rel_mm + m1_about_block * m1_unit;
      return internal::BlockAction::kAccept;
    }
    // A block holding a sharp surface (of the bone or of an eroded cavity) is
    // poorly served by the linear-density estimate below where that surface
    // meets the burr surface: up to +20 % in m0 at an immersion of 0.1R. Such a
    // block has a large density gradient across it relative to its mean
    // density, g L / rho = 12 |m1| / (L m0); above kMaxGradient it is refined.
    // Only blocks along the contact rim qualify, so the cost stays O(rim /
    // ell).
    const double m1_norm = std::sqrt(m1_about_block.x * m1_about_block.x +
                                     m1_about_block.y * m1_about_block.y +
                                     m1_about_block.z * m1_about_block.z);
    // m1 is in half-voxels: 12 |m1| (v/2) / (2^l v m0) = 6 |m1| / (2^l m0).
    if (6.0 * m1_norm >
        kMaxGradient * size_vox * static_cast<double>(b.node->m0)) {
      return internal::BlockAction::kRefine;
    }
    // Partial block no larger than ell (eqs. 7.10-7.11). The dissertation
    // replaces the block by a sphere of equal volume to get the overlap Delta V
    // and its centroid R_c. For the volume burrlab cuts the cube itself by the
    // burr surface, taken as the plane tangent at the block's direction, moved
    // inwards by the sphere's mean sag over the block (L^2 / 12R): a block
    // sphere misjudges a thin immersion by up to 20 % (h = 0.1R at R = 3 mm),
    // the cut cube by under 2 %. R_c stays the lens centroid of the
    // equal-volume sphere. The density inside the block is modelled as linear
    // with the gradient implied by the block's first moment (for a cube of side
    // L, m1 = g V L^2 / 12); eq. 7.11 writes this correction as m1 . (R_c -
    // R_I), and the factor 12 / L^2 makes it dimensionally consistent.
    // (A block of a level with 2^level > ell_vox is refined above.)
    const PartialLevel& pl = partial_levels[static_cast<std::size_t>(b.level)];
    const double side_mm = pl.side_mm;
    const double d = std::sqrt(rel_mm.x * rel_mm.x + rel_mm.y * rel_mm.y +
                               rel_mm.z * rel_mm.z);
    if (d <= 0.0) return internal::BlockAction::kRefine;
    // The cut plane lies beyond the cube's far corner whatever the direction
    // (its distance from the centre is at most sqrt(3)/2 of an edge), so that
    // CubeFractionBelow would return 0: skipped before the direction's
    // divisions, with a margin far beyond rounding.
    const double below = radius_mm - d - pl.sag;
    if (below < -0.8661 * side_mm) return internal::BlockAction::kSkip;
    const double fraction =
        internal::CubeFractionBelow(rel_mm / d, below / side_mm);
    if (fraction <= 0.0) return internal::BlockAction::kSkip;
    const glm::dvec3 centroid =
        rel_mm * (LensCentroidDistance(d, radius_mm, pl.eta_block) / d);
    const glm::dvec3 m1_mm = m1_about_block * m1_unit;
    const glm::dvec3 from_block = centroid - rel_mm;
    const double gradient_term =
        pl.gradient_scale * (m1_mm.x * from_block.x + m1_mm.y * from_block.y +
                             m1_mm.z * from_block.z);
    const double dm0 = std::clamp(fraction * (m0 + gradient_term), 0.0, m0);
    moments.m0_mm3 += dm0;
    moments.m1_mm4 += dm0 * centroid;
    return internal::BlockAction::kAccept;
  }

  // A solid voxel whose voxel sphere lies outside the burr adds nothing
  // (AddVoxel, with d2_mm2 computed as OnVoxel computes it); near the contact
  // disk most of the voxels the walk meets are such.
  bool Ignores(std::uint8_t occupancy, double d2_vox2) const {
    return (occupancy == kSolidOccupancy) &
           (d2_vox2 * (voxel_mm * voxel_mm) >= sphere.outside2);
  }

  void OnVoxel(int i, int j, int k, std::uint8_t occupancy,
               const glm::dvec3& offset_vox, double d2_vox2) {
    AddVoxel(*volume, sphere, i, j, k, occupancy, offset_vox * voxel_mm,
             d2_vox2 * (voxel_mm * voxel_mm), moments);
  }
};

}  // namespace

double EqualVolumeSphereRadius(double side_mm) {
  return side_mm * kEqualVolumeRadiusPerSide;
}

double LensVolume(double d, double radius, double eta) {
  if (d >= radius + eta) return 0.0;
  if (d <= std::abs(radius - eta)) {
    const double r = std::min(radius, eta);
    return 4.0 / 3.0 * kPi * r * r * r;
  }
  // Eqs. 6.17-6.18.
  const double diff = eta * eta - radius * radius;
  return kPi / 12.0 *
         (d * d * d - 6.0 * (radius * radius + eta * eta) * d +
          8.0 * (radius * radius * radius + eta * eta * eta) -
          3.0 * diff * diff / d);
}

double LensArea(double d, double radius, double eta) {
  if (d >= radius + eta || d <= std::abs(radius - eta)) return 0.0;
  // Eq. 6.19: pi a^2, a the radius of the circle where the spheres meet.
  const double diff = eta * eta - radius * radius;
  return kPi / 4.0 *
         (2.0 * (eta * eta + radius * radius) - d * d - diff * diff / (d * d));
}

double RadicalPlaneDistance(double d, double radius, double eta) {
  return 0.5 * d + 0.5 * (radius * radius - eta * eta) / d;  // eq. 6.20
}

double CapVolume(double h, double radius) {
  return kPi * h * h * (radius - h / 3.0);
}

double DepthFromM0(double m0, double radius) {
  // m0 = pi h^2 (R - h/3) is the cubic h^3 - 3R h^2 + 3 m0 / pi = 0; with h = R
  // + y it is y^3 - 3R^2 y + (3 m0/pi - 2R^3) = 0, whose root in [-R, R] is y =
  // 2R cos((phi - 2 pi) / 3), phi = acos(1 - 3 m0 / (2 pi R^3)).
  const double full = 4.0 / 3.0 * kPi * radius * radius * radius;
  if (!(m0 > 0.0)) return 0.0;
  if (m0 >= full) return 2.0 * radius;
  const double c = std::clamp(
      1.0 - 3.0 * m0 / (2.0 * kPi * radius * radius * radius), -1.0, 1.0);
  double h = radius + 2.0 * radius * std::cos((std::acos(c) - 2.0 * kPi) / 3.0);
  // One Newton step recovers the precision acos loses for shallow immersion.
  const double slope = kPi * h * (2.0 * radius - h);
  if (slope > 0.0) h -= (CapVolume(h, radius) - m0) / slope;
  return std::clamp(h, 0.0, 2.0 * radius);
}

Moments ComputeMomentsMono(const Volume& volume, const glm::dvec3& centre_mm,
                           double radius_mm) noexcept {
  Moments m;
  const double v = volume.voxel_mm();
  const double eta = EqualVolumeSphereRadius(v);
  const double reach =
      radius_mm + 2.0 * eta;  // moved partial-volume spheres reach further
  const VoxelSphere sphere(radius_mm, eta, v);
  const auto range = [&](double c, int n, int* lo, int* hi) {
    *lo = std::max(0, static_cast<int>(std::floor((c - reach) / v - 0.5)));
    *hi = std::min(n - 1, static_cast<int>(std::ceil((c + reach) / v - 0.5)));
  };
  int i0, i1, j0, j1, k0, k1;
  range(centre_mm.x, volume.nx(), &i0, &i1);
  range(centre_mm.y, volume.ny(), &j0, &j1);
  range(centre_mm.z, volume.nz(), &k0, &k1);
  const std::uint8_t* data = volume.occupancy();
  const double reach2 = reach * reach;
  for (int k = k0; k <= k1; ++k) {
    const double dz = (k + 0.5) * v - centre_mm.z;
    for (int j = j0; j <= j1; ++j) {
      // Only the row's chord through the reach sphere: a voxel centre at or
      // beyond `reach` adds nothing (AddVoxel), so visiting the chord, widened
      // by a voxel each side against rounding, sums the same terms in the same
      // order as the whole row.
      const double dy = (j + 0.5) * v - centre_mm.y;
      const double rest2 = reach2 - dy * dy - dz * dz;
      if (rest2 <= 0.0) continue;
      const double half_chord = std::sqrt(rest2);
      const int lo = std::max(
          i0, static_cast<int>(std::floor((centre_mm.x - half_chord) / v)) - 1);
      const int hi = std::min(
          i1, static_cast<int>(std::ceil((centre_mm.x + half_chord) / v)) + 1);
      const std::uint8_t* row = data + volume.Index(0, j, k);
      for (int i = lo; i <= hi; ++i) {
        if (row[i] == 0) continue;
        const glm::dvec3 offset((i + 0.5) * v - centre_mm.x,
                                (j + 0.5) * v - centre_mm.y,
                                (k + 0.5) * v - centre_mm.z);
        AddVoxel(
            volume, sphere, i, j, k, row[i], offset,
            offset.x * offset.x + offset.y * offset.y + offset.z * offset.z, m);
      }
    }
  }
  return m;
}

Moments ComputeMomentsOctree(const MomentOctree& octree, const Volume& volume,
                             const glm::dvec3& centre_mm, double radius_mm,
                             double ell_mm) noexcept {
  const double v = volume.voxel_mm();
  const double eta = EqualVolumeSphereRadius(v);
  MomentVisitor visitor{
      &volume,
      centre_mm / v,
      radius_mm / v,
      eta / v,
      ell_mm / v,
      v,
      radius_mm,
      eta,
      v * v * v,
      VoxelSphere(radius_mm, eta, v),
      radius_mm > 2.0 * eta
          ? (radius_mm - 2.0 * eta) * (radius_mm - 2.0 * eta) / (v * v)
          : -1.0,
      Moments{}};
  visitor.SetUp();
  internal::WalkSphere(octree, volume, centre_mm / v,
                       (radius_mm + 2.0 * eta) / v, visitor);
  return visitor.moments;
}

}  // namespace burrlab::sim
