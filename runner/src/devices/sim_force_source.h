// The burr simulator as the haptic loop's force source: the device position,
// shifted into the volume's frame, becomes the burr centre; the burr velocity
// is the backward difference of positions over one step (eq. 7.14 needs it).
// The loop applies sample-estimate-hold and the device clamp itself, so the
// model's own filter is turned off and its clamp opened. The station's
// stiffness limit applies here: a material stiffer than the device renders
// stably up to the loop's force limit is softened to the stiffest it can
// (MaxRenderableCe).
#ifndef BURRLAB_RUNNER_DEVICES_SIM_FORCE_SOURCE_H_
#define BURRLAB_RUNNER_DEVICES_SIM_FORCE_SOURCE_H_

#include <glm/vec3.hpp>

#include "burrlab/sim/model.h"
#include "burrlab/sim/step.h"
#include "devices/haptic_loop.h"

namespace burrlab::runner {

// What the station lets the simulator render; 0 = no limit.
struct RenderLimits {
  double max_force_n = 0.0;  // |force| the loop lets through, N (the loop
                             // clamps; here it bounds the stiffness range)
  double max_stiffness_n_per_mm = 0.0;  // contact stiffness limit, N/mm
};

// The stiffest elastic constant c_e (N/mm^2) a device renders within
// `max_stiffness_n_per_mm` for forces up to `max_force_n` with a burr of
// `radius_mm`. The contact force F = c_e R^0.5 h^1.5 (eq. 7.3) has the local
// stiffness dF/dh = 1.5 c_e R^0.5 h^0.5, largest where F reaches F_max;
// requiring it <= K gives c_e <= (K / 1.5)^1.5 / (F_max R)^0.5. Infinity when
// either limit is 0 (none).
double MaxRenderableCe(double radius_mm, double max_force_n,
                       double max_stiffness_n_per_mm);

class SimForceSource final : public ForceSource {
 public:
  // `state` must outlive the source and belong to `model`.
  SimForceSource(const sim::Model& model, sim::State* state,
                 const glm::dvec3& device_to_volume_mm,
                 const glm::dvec3& spindle_rad_s, RenderLimits limits = {});

  glm::dvec3 Force(const glm::dvec3& position_mm) noexcept override;

  const sim::Output& last_output() const { return output_; }
  // The c_e rendered: the material's, or MaxRenderableCe when that is lower.
  double rendered_c_e_n_per_mm2() const {
    return model_.material.c_e_n_per_mm2;
  }
  // Whether the material's c_e was lowered to the stiffness limit.
  bool stiffness_limited() const { return stiffness_limited_; }

 private:
  sim::Model model_;
  sim::State* state_;
  glm::dvec3 offset_mm_;
  sim::Input input_;
  sim::Output output_;
  glm::dvec3 previous_mm_{0.0};
  bool has_previous_ = false;
  bool stiffness_limited_ = false;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_SIM_FORCE_SOURCE_H_
