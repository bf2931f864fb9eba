// The simulator behind the haptic loop.
#include "devices/sim_force_source.h"

#include <cmath>
#include <limits>

namespace burrlab::runner {

double MaxRenderableCe(double radius_mm, double max_force_n,
                       double max_stiffness_n_per_mm) {
  if (!(max_force_n > 0.0) || !(max_stiffness_n_per_mm > 0.0) ||
      !(radius_mm > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  return std::pow(max_stiffness_n_per_mm / 1.5, 1.5) /
         std::sqrt(max_force_n * radius_mm);
}

SimForceSource::SimForceSource(const sim::Model& model, sim::State* state,
                               const glm::dvec3& device_to_volume_mm,
                               const glm::dvec3& spindle_rad_s,
                               RenderLimits limits)
    : model_(model), state_(state), offset_mm_(device_to_volume_mm) {
  model_.sample_estimate_hold = false;
  model_.max_force_n = std::numeric_limits<double>::infinity();
  const double max_c_e = MaxRenderableCe(model_.radius_mm, limits.max_force_n,
                                         limits.max_stiffness_n_per_mm);
  if (model_.material.c_e_n_per_mm2 > max_c_e) {
    model_.material.c_e_n_per_mm2 = max_c_e;
    stiffness_limited_ = true;
  }
  input_.spindle_rad_s = spindle_rad_s;
}

glm::dvec3 SimForceSource::Force(const glm::dvec3& position_mm) noexcept {
  const glm::dvec3 burr_mm = position_mm + offset_mm_;
  input_.velocity_mm_s =
      has_previous_ ? (burr_mm - previous_mm_) / model_.dt_s : glm::dvec3(0.0);
  input_.position_mm = burr_mm;
  previous_mm_ = burr_mm;
  has_previous_ = true;
  sim::Step(model_, *state_, input_, &output_);
  return output_.force_n;
}

}  // namespace burrlab::runner
