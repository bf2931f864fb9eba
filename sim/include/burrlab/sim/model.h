// The read-only simulator model: material constants, burr, method and filter
// settings. Built once per stimulus; the step function never changes it
// (MuJoCo's mjModel idea).
#ifndef BURRLAB_SIM_MODEL_H_
#define BURRLAB_SIM_MODEL_H_

#include <limits>

#include "burrlab/base/result.h"
#include "burrlab/sim/effects.h"

namespace burrlab::sim {

// Material constants of the burr-bone model (dissertation ch. 6-8). The
// dissertation gives no units for c_e and alpha; burrlab reads them as N/mm^2
// and 1/s in eqs. 7.3 and 7.12.
struct Material {
  double c_e_n_per_mm2 =
      2.145;  // elastic constant c_e, F_e = c_e R^2 (h/R)^1.5 (7.3)
  double alpha_per_s =
      0.087;  // erosion constant alpha, drho/dt = -alpha f rho (7.12)
  double c_mu_n_per_mm2 =
      0.5;          // friction constant c_mu of the cheap friction (7.13)
  double mu = 0.5;  // friction coefficient mu of the surface friction (6.23)
  double c_i_n_s_per_mm3 =
      0.0;  // impact constant c_i, F_i = -c_i R^2 (h/R) V (7.14)

  // Names the first field that is not finite or is negative (c_e must be
  // positive).
  Status Validate() const;
};

// How m0 and m1 are integrated over the burr sphere.
enum class MomentMethod {
  kMono,    // every voxel, voxel-sphere approximation (eqs. 6.17-6.22): the
            // reference
  kOctree,  // octree of block moments with accuracy scale ell (eqs. 7.9-7.11)
};

// Which friction force is added while the burr spins.
enum class FrictionModel {
  kCheap,    // F_mu = c_mu R^2 (h/R) (m1 / (m0 R)) x omega_hat (eq. 7.13)
  kSurface,  // Hertz pressure integrated over the contact surface
             // (eqs. 6.13, 6.23)
};

struct Model {
  Material material;
  double radius_mm = 3.0;  // burr sphere radius R, 1-5 mm for surgical burrs
  double dt_s = 1e-3;      // step length (1 kHz haptic loop)
  MomentMethod method = MomentMethod::kOctree;
  double ell_over_r =
      0.3;  // octree accuracy scale ell as a fraction of R (7.10)
  FrictionModel friction = FrictionModel::kCheap;
  bool sample_estimate_hold = true;  // filter the device force (§6.4.3)
  double max_force_n =
      std::numeric_limits<double>::infinity();  // clamp on |force|
  Effects effects;  // physical effects beyond the base model; null by default
  // Moment reuse between steps. 0 (the default): the moments are computed
  // afresh every step. r > 0: while the burr centre stays within r h of where
  // they were last computed (h the depth of eq. 7.2 there) and the material
  // eroded since is under r m0, a step reuses them, taken about the new centre
  // (m1 - m0 d for a move d) and less the material eroded since (each eroded
  // voxel counted whole); otherwise it computes them afresh. Neglecting the
  // material the sphere sweeps over moves h by at most about r h, so the
  // elastic force by at most about 1.5 r (eq. 7.3); drilling, where the burr
  // moves a few micrometres per step, computes its moments a few times less
  // often.
  double moment_reuse_over_h = 0.0;

  // Names the first field with a bad value and the rule it breaks.
  Status Validate() const;
};

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_MODEL_H_
