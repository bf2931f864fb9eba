// The burr simulator as the haptic loop's force source: the device position,
// shifted into the volume's frame, becomes the burr centre; the burr velocity
// is the backward difference of positions over one step (eq. 7.14 needs it).
// The loop applies sample-estimate-hold and the device clamp itself, so the
// model's own filter is turned off and its clamp opened.
#ifndef BURRLAB_RUNNER_SIM_FORCE_SOURCE_H_
#define BURRLAB_RUNNER_SIM_FORCE_SOURCE_H_

#include <glm/vec3.hpp>

#include "burrlab/sim/model.h"
#include "burrlab/sim/step.h"
#include "haptic_loop.h"

namespace burrlab::runner {

class SimForceSource final : public ForceSource {
 public:
  // `state` must outlive the source and belong to `model`.
  SimForceSource(const sim::Model& model, sim::State* state,
                 const glm::dvec3& device_to_volume_mm,
                 const glm::dvec3& spindle_rad_s);

  glm::dvec3 Force(const glm::dvec3& position_mm) noexcept override;

  const sim::Output& last_output() const { return output_; }

 private:
  sim::Model model_;
  sim::State* state_;
  glm::dvec3 offset_mm_;
  sim::Input input_;
  sim::Output output_;
  glm::dvec3 previous_mm_{0.0};
  bool has_previous_ = false;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_SIM_FORCE_SOURCE_H_
