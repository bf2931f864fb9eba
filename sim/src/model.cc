// Validation of the simulator model: every field named with its value and the
// rule broken.
#include "burrlab/sim/model.h"

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace burrlab::sim {
namespace {

// Error unless value is finite and >= 0 (> 0 when strictly is set).
Status CheckNonNegative(const char* name, double value, bool strictly = false) {
  if (!std::isfinite(value)) {
    return Error{
        fmt::format("{} must be a finite number, got {}", name, value)};
  }
  if (strictly ? value <= 0.0 : value < 0.0) {
    return Error{fmt::format("{} must be {}, got {}", name,
                             strictly ? "positive" : "zero or positive",
                             value)};
  }
  return {};
}

}  // namespace

Status Material::Validate() const {
  for (const Status& s :
       {CheckNonNegative("c_e", c_e_n_per_mm2, /*strictly=*/true),
        CheckNonNegative("alpha", alpha_per_s),
        CheckNonNegative("c_mu", c_mu_n_per_mm2), CheckNonNegative("mu", mu),
        CheckNonNegative("c_i", c_i_n_s_per_mm3)}) {
    if (!s.ok()) return s;
  }
  return {};
}

Status Model::Validate() const {
  if (Status s = material.Validate(); !s.ok()) return s;
  if (Status s = effects.Validate(); !s.ok()) return s;
  if (Status s = CheckNonNegative("radius_mm", radius_mm, true); !s.ok())
    return s;
  if (Status s = CheckNonNegative("dt_s", dt_s, true); !s.ok()) return s;
  if (Status s = CheckNonNegative("ell_over_r", ell_over_r); !s.ok()) return s;
  if (Status s = CheckNonNegative("moment_reuse_over_h", moment_reuse_over_h);
      !s.ok()) {
    return s;
  }
  if (std::isnan(max_force_n) || max_force_n <= 0.0) {
    return Error{
        fmt::format("max_force_n must be positive, got {}", max_force_n)};
  }
  return {};
}

}  // namespace burrlab::sim
