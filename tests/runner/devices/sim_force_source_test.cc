// The simulator as the loop's force source: the device-to-volume offset, no
// filter and no clamp of its own (the loop does both), and the velocity
// estimate feeding the impact force (eq. 7.14).
#include "devices/sim_force_source.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "burrlab/sim/phantoms.h"
#include "half_space.h"

namespace burrlab::runner {
namespace {

TEST(SimForceSource, ShiftsTheDevicePositionIntoTheVolume) {
  sim::Model model;
  model.radius_mm = 3.0;
  sim::State state = sim::State::Create(model, HalfSpace(), 1).value();
  const glm::dvec3 burr_mm(9.6, 9.6, 9.6 + 3.0 - 1.0);  // 1 mm deep
  const sim::Output expected = sim::EvaluateForce(
      model, state.volume(), state.octree(), sim::Input{burr_mm, {}, {}});
  ASSERT_GT(expected.elastic_n.z, 0.0);
  // The device reports 120 mm above the volume's frame.
  SimForceSource source(model, &state, glm::dvec3(0.0, 0.0, -120.0),
                        glm::dvec3(0.0));
  const glm::dvec3 force_n =
      source.Force(burr_mm + glm::dvec3(0.0, 0.0, 120.0));
  EXPECT_NEAR(force_n.z, expected.elastic_n.z, 1e-12);
  EXPECT_NEAR(glm::length(force_n - expected.elastic_n), 0.0, 1e-12);
}

TEST(SimForceSource, LeavesFilterAndClampToTheLoop) {
  sim::Model model;
  model.radius_mm = 3.0;
  model.max_force_n = 1.0;            // would clamp
  model.sample_estimate_hold = true;  // would extrapolate
  sim::State state = sim::State::Create(model, HalfSpace(), 1).value();
  SimForceSource source(model, &state, glm::dvec3(0.0), glm::dvec3(0.0));
  const glm::dvec3 shallow(9.6, 9.6, 9.6 + 3.0 - 1.0);
  const glm::dvec3 deep(9.6, 9.6, 9.6 + 3.0 - 3.0);
  (void)source.Force(shallow);
  (void)source.Force(shallow);  // the velocity estimate is zero again
  const glm::dvec3 deep_n = source.Force(deep);
  const sim::Output expected = sim::EvaluateForce(
      model, state.volume(), state.octree(), sim::Input{deep, {}, {}});
  // No clamp at 1 N and no extrapolation from the shallow sample.
  EXPECT_GT(glm::length(deep_n), 1.0);
  EXPECT_NEAR(deep_n.z, expected.elastic_n.z, 1e-9);
}

TEST(SimForceSource, ImpactForceOpposesTheEstimatedVelocity) {
  sim::Model model;
  model.radius_mm = 3.0;
  model.material.c_i_n_s_per_mm3 = 0.001;
  sim::State state = sim::State::Create(model, HalfSpace(), 1).value();
  SimForceSource source(model, &state, glm::dvec3(0.0), glm::dvec3(0.0));
  const glm::dvec3 at(9.6, 9.6, 9.6 + 3.0 - 1.0);
  (void)source.Force(at);
  // Moving 0.01 mm in one 1 ms step: 10 mm/s along +x.
  (void)source.Force(at + glm::dvec3(0.01, 0.0, 0.0));
  EXPECT_NEAR(source.last_output().impact_n.x,
              -0.001 * 9.0 * (source.last_output().h_mm / 3.0) * 10.0, 1e-9);
  EXPECT_LT(source.last_output().impact_n.x, 0.0);
}

TEST(SimForceSource, MaxRenderableCeMeetsTheStiffnessLimitWhereTheForceIs) {
  // At c_e = MaxRenderableCe the depth where F = c_e R^0.5 h^1.5 reaches
  // F_max has local stiffness 1.5 c_e R^0.5 h^0.5 = K exactly.
  const double r_mm = 2.0, f_max_n = 8.0, k_n_per_mm = 3.0;
  const double c_e = MaxRenderableCe(r_mm, f_max_n, k_n_per_mm);
  EXPECT_NEAR(c_e, std::pow(2.0, 1.5) / 4.0, 1e-12);  // 0.707 N/mm^2
  const double h_mm = std::pow(f_max_n / (c_e * std::sqrt(r_mm)), 2.0 / 3.0);
  EXPECT_NEAR(1.5 * c_e * std::sqrt(r_mm) * std::sqrt(h_mm), k_n_per_mm, 1e-12);
  EXPECT_TRUE(std::isinf(MaxRenderableCe(r_mm, f_max_n, 0.0)));
  EXPECT_TRUE(std::isinf(MaxRenderableCe(r_mm, 0.0, k_n_per_mm)));
}

TEST(SimForceSource, SoftensATooStiffMaterialToTheStationLimits) {
  sim::Model model;
  model.radius_mm = 3.0;
  model.material.c_e_n_per_mm2 = 50.0;  // far stiffer than bone
  sim::State state = sim::State::Create(model, HalfSpace(), 1).value();
  const RenderLimits limits{8.0, 3.0};
  SimForceSource source(model, &state, glm::dvec3(0.0), glm::dvec3(0.0),
                        limits);
  const double c_e_max = MaxRenderableCe(3.0, 8.0, 3.0);
  ASSERT_TRUE(source.stiffness_limited());
  EXPECT_DOUBLE_EQ(source.rendered_c_e_n_per_mm2(), c_e_max);

  // The rendered force is the model's at the limited c_e (F_e is linear in
  // c_e), and the contact stiffness over the burr's depth stays under 3 N/mm
  // where the material as given is more than ten times stiffer.
  sim::Model limited = model;
  limited.material.c_e_n_per_mm2 = c_e_max;
  double worst_rendered_n_per_mm = 0.0, worst_given_n_per_mm = 0.0;
  double previous_rendered_n = 0.0, previous_given_n = 0.0;
  const double step_mm = 0.1;
  for (int k = 0; k <= 30; ++k) {
    const double h_mm = k * step_mm;
    const glm::dvec3 at(9.6, 9.6, 9.6 + 3.0 - h_mm);
    (void)source.Force(at);
    const glm::dvec3 rendered_n = source.Force(at);  // zero velocity
    const sim::Output expected = sim::EvaluateForce(
        limited, state.volume(), state.octree(), sim::Input{at, {}, {}});
    const sim::Output given = sim::EvaluateForce(
        model, state.volume(), state.octree(), sim::Input{at, {}, {}});
    EXPECT_NEAR(rendered_n.z, expected.elastic_n.z, 1e-9) << h_mm << " mm";
    if (k > 0) {
      worst_rendered_n_per_mm =
          std::max(worst_rendered_n_per_mm,
                   (rendered_n.z - previous_rendered_n) / step_mm);
      worst_given_n_per_mm =
          std::max(worst_given_n_per_mm,
                   (given.elastic_n.z - previous_given_n) / step_mm);
    }
    previous_rendered_n = rendered_n.z;
    previous_given_n = given.elastic_n.z;
  }
  EXPECT_LE(worst_rendered_n_per_mm, 3.0);
  EXPECT_GT(worst_given_n_per_mm, 30.0);
}

TEST(SimForceSource, LeavesARenderableMaterialAndTheForceClampToTheLoop) {
  sim::Model model;
  model.radius_mm = 3.0;
  model.material.c_e_n_per_mm2 = 0.462;  // PVC: under 0.577 at R = 3 mm
  sim::State state = sim::State::Create(model, HalfSpace(), 1).value();
  SimForceSource source(model, &state, glm::dvec3(0.0), glm::dvec3(0.0),
                        RenderLimits{8.0, 3.0});
  EXPECT_FALSE(source.stiffness_limited());
  EXPECT_DOUBLE_EQ(source.rendered_c_e_n_per_mm2(), 0.462);
  SimForceSource low(model, &state, glm::dvec3(0.0), glm::dvec3(0.0),
                     RenderLimits{2.0, 0.0});  // no stiffness limit
  const glm::dvec3 deep(9.6, 9.6, 9.6);        // h = R: c_e R^2 = 4.2 N
  (void)low.Force(deep);
  EXPECT_NEAR(glm::length(low.Force(deep)), 0.462 * 9.0, 0.462 * 9.0 * 0.05);
}

}  // namespace
}  // namespace burrlab::runner
