// Moments of bone mass inside the burr sphere (eqs. 6.10-6.11 / 7.1) and the
// quantities derived from them: the voxel-sphere approximations of
// eqs. 6.17-6.22, the effective depth h of eq. 7.2, and the mono- and
// multi-resolution integrators.
//
// Units: density is occupancy / 255 (rho0 = 1), so m0 is a solid-equivalent
// volume in mm^3 and m1 is in mm^4, both about the burr centre.
#ifndef BURRLAB_SIM_MOMENTS_H_
#define BURRLAB_SIM_MOMENTS_H_

#include <glm/vec3.hpp>

#include "burrlab/sim/octree.h"
#include "burrlab/sim/volume.h"

namespace burrlab::sim {

struct Moments {
  double m0_mm3 = 0.0;     // zeroth moment (solid-equivalent volume)
  glm::dvec3 m1_mm4{0.0};  // first moment about the burr centre
};

// Radius eta of the sphere with the volume of a cube of side `side_mm`: 4/3 pi
// eta^3 = l^3.
double EqualVolumeSphereRadius(double side_mm);
// Volume of the intersection of the burr sphere (radius R) and a sphere of
// radius eta whose centre is at distance d (eqs. 6.17-6.18, extended to full
// containment and no overlap).
double LensVolume(double d_mm, double radius_mm, double eta_mm);
// Area of the burr-sphere surface inside the eta-sphere (eq. 6.19; 0 without
// crossing).
double LensArea(double d_mm, double radius_mm, double eta_mm);
// Distance from the burr centre to the plane where the two spheres meet
// (eq. 6.20).
double RadicalPlaneDistance(double d_mm, double radius_mm, double eta_mm);

// Volume of a spherical cap of height h on a sphere of radius R: pi h^2 (R -
// h/3).
double CapVolume(double h_mm, double radius_mm);
// Effective depth h: smallest positive root of m0 = pi rho0 h^2 (R - h/3)
// (eq. 7.2), clamped to [0, 2R]; closed-form trigonometric solution of the
// cubic.
double DepthFromM0(double m0_mm3, double radius_mm);

// Mono-resolution moments: every voxel whose equal-volume sphere meets the burr
// sphere contributes Delta V chi at distance r(d) along its centre direction
// (eqs. 6.21-6.22).
Moments ComputeMomentsMono(const Volume& volume, const glm::dvec3& centre_mm,
                           double radius_mm) noexcept;

// Multi-resolution moments: octree descent adding whole blocks inside the
// sphere and partial blocks no larger than ell by eqs. 7.10-7.11; leaves as in
// the mono method. With ell below the voxel size the result equals
// ComputeMomentsMono.
Moments ComputeMomentsOctree(const MomentOctree& octree, const Volume& volume,
                             const glm::dvec3& centre_mm, double radius_mm,
                             double ell_mm) noexcept;

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_MOMENTS_H_
