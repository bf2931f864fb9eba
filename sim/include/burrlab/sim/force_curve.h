// Force-depth curves: a burr pressed into a solid half-space of any
// orientation, from first contact to a given immersion (dissertation
// fig. 6.4(a) and 7.1(a)). Probing only: no friction, no erosion, no filter.
#ifndef BURRLAB_SIM_FORCE_CURVE_H_
#define BURRLAB_SIM_FORCE_CURVE_H_

#include <glm/vec3.hpp>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/sim/model.h"

namespace burrlab::sim {

struct ForceCurveOptions {
  double c_e_n_per_mm2 = 2.145;  // elastic constant of the half-space material
  double radius_mm = 3.0;        // burr radius R
  double voxel_mm = 0.3;         // voxel size
  double max_depth_mm = 0.0;     // deepest immersion; 0 means R
  int points = 21;               // samples from max_depth/points to max_depth
  MomentMethod method = MomentMethod::kOctree;
  double ell_over_r = 0.3;           // octree accuracy scale
  glm::dvec3 normal{0.0, 0.0, 1.0};  // outward normal of the half-space surface
  double offset_voxels = 0.0;  // lateral offset of the contact point, in voxels
                               // (moves the burr against the voxel grid)

  // Names the first bad field.
  Status Validate() const;
};

struct ForceCurvePoint {
  double depth_mm = 0.0;   // true geometric immersion of the sphere
  double h_mm = 0.0;       // the model's depth estimate (eq. 7.2)
  double m0_mm3 = 0.0;     // zeroth moment
  double force_n = 0.0;    // |F_e| (eq. 7.3)
  glm::dvec3 normal{0.0};  // estimated normal -m1/|m1|
};

Result<std::vector<ForceCurvePoint>> ComputeForceCurve(
    const ForceCurveOptions& options);

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_FORCE_CURVE_H_
