// Model and material validation messages.
#include "burrlab/sim/model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace burrlab::sim {
namespace {

TEST(Model, DefaultsAreValid) { EXPECT_TRUE(Model{}.Validate().ok()); }

TEST(Model, ValidateNamesTheFieldAndTheRule) {
  Model model;
  model.material.c_e_n_per_mm2 = 0.0;
  EXPECT_EQ(model.Validate().error().message, "c_e must be positive, got 0");
  model = Model{};
  model.material.alpha_per_s = std::nan("");
  EXPECT_EQ(model.Validate().error().message,
            "alpha must be a finite number, got nan");
  model = Model{};
  model.material.c_i_n_s_per_mm3 = -0.1;
  EXPECT_EQ(model.Validate().error().message,
            "c_i must be zero or positive, got -0.1");
  model = Model{};
  model.dt_s = std::numeric_limits<double>::infinity();
  EXPECT_EQ(model.Validate().error().message,
            "dt_s must be a finite number, got inf");
  model = Model{};
  model.max_force_n = 0.0;
  EXPECT_EQ(model.Validate().error().message,
            "max_force_n must be positive, got 0");
}

}  // namespace
}  // namespace burrlab::sim
