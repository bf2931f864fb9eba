// Sample-estimate-hold output filter (dissertation §6.4.3, after Ellis, Sarkar
// & Jenkins, ASME DSC vol. 58, 1996). A zero-order hold of the sampled force
// lags the continuous force by half a period on average and so injects energy
// into stiff contact. The filter holds instead the mean of the first-order
// extrapolation of the force over the coming period,
//   H_k = F_k + (F_k - F_{k-1}) / 2,
// whose time integral matches the force-time integral of a force varying
// linearly.
#ifndef BURRLAB_SIM_SEH_H_
#define BURRLAB_SIM_SEH_H_

#include <glm/vec3.hpp>

namespace burrlab::sim {

class SampleEstimateHold {
 public:
  // Returns the value to hold over the next period, given this period's sample.
  glm::dvec3 Update(const glm::dvec3& sample) noexcept {
    const glm::dvec3 held =
        has_previous_ ? sample + 0.5 * (sample - previous_) : sample;
    previous_ = sample;
    has_previous_ = true;
    return held;
  }
  // Forgets the history (after a pause or a device fault).
  void Reset() noexcept { has_previous_ = false; }

 private:
  glm::dvec3 previous_{0.0};
  bool has_previous_ = false;
};

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_SEH_H_
