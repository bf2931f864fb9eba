// The simulator as the loop's force source: the device-to-volume offset, no
// filter and no clamp of its own (the loop does both), and the velocity
// estimate feeding the impact force (eq. 7.14).
#include "sim_force_source.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "burrlab/sim/phantoms.h"

namespace burrlab::runner {
namespace {

// Solid below z = 9.6 mm in a 19.2 mm cube of 0.3 mm voxels.
sim::Volume HalfSpace() {
  sim::PhantomGrid grid;
  grid.nx = grid.ny = grid.nz = 64;
  return sim::MakeHalfSpace(grid, {9.6, 9.6, 9.6}, {0.0, 0.0, 1.0}).value();
}

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

}  // namespace
}  // namespace burrlab::runner
