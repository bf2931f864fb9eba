// The virtual calibration rig (dissertation ch. 8).
#include "burrlab/sim/descent.h"

#include <gtest/gtest.h>

namespace burrlab::sim {
namespace {

Material Mat(double c_e, double alpha) {
  Material m;
  m.c_e_n_per_mm2 = c_e;
  m.alpha_per_s = alpha;
  return m;
}

double SteadyVelocity(const Material& material, double force_n) {
  DescentOptions options;
  options.material = material;
  options.force_n = force_n;
  Result<DescentResult> result = RunDescent(options);
  EXPECT_TRUE(result.ok()) << result.error().message;
  if (!result.ok()) return 0.0;
  EXPECT_TRUE(result->steady_reached);
  EXPECT_GT(result->removed_mm3, 0.0);
  EXPECT_FALSE(result->trace.empty());
  return result->steady_velocity_mm_s;
}

// Built-in materials of §8.7.
const Material kBone = Mat(2.145, 0.087), kPettigrew = Mat(1.504, 0.116),
               kPvc = Mat(0.462, 0.296);

TEST(Descent, SteadyVelocityOrdersPvcAbovePettigrewAboveBone) {
  const double bone = SteadyVelocity(kBone, 4.0),
               pettigrew = SteadyVelocity(kPettigrew, 4.0),
               pvc = SteadyVelocity(kPvc, 4.0);
  EXPECT_GT(bone, 0.0);
  EXPECT_GT(pettigrew, bone);
  EXPECT_GT(pvc, pettigrew);
}

TEST(Descent, SteadyVelocityRisesWithForce) {
  double previous = 0.0;
  for (double force : {3.0, 4.0, 6.0}) {
    const double velocity = SteadyVelocity(kPettigrew, force);
    EXPECT_GT(velocity, previous) << force;
    previous = velocity;
  }
}

TEST(Descent, ControllerHoldsTheForceOnceInside) {
  DescentOptions options;
  options.material = kPettigrew;
  options.force_n = 4.0;
  Result<DescentResult> result = RunDescent(options);
  ASSERT_TRUE(result.ok());
  double sum = 0.0;
  int n = 0;
  for (const DescentSample& s : result->trace) {
    if (s.depth_mm > options.radius_mm / 3.0) {
      sum += s.force_n;
      ++n;
    }
  }
  ASSERT_GT(n, 100);
  EXPECT_NEAR(sum / n, 4.0, 0.1);
}

TEST(Descent, SameSeedReproducesTheTrace) {
  DescentOptions options;
  options.material = kPvc;
  options.force_n = 2.0;
  options.duration_s = 3.0;
  const DescentResult a = RunDescent(options).value(),
                      b = RunDescent(options).value();
  EXPECT_EQ(a.final_depth_mm, b.final_depth_mm);
  EXPECT_EQ(a.removed_mm3, b.removed_mm3);
}

TEST(Descent, RejectsBadOptionsNamingTheField) {
  DescentOptions options;
  options.force_n = -2.0;
  Result<DescentResult> result = RunDescent(options);
  ASSERT_FALSE(result.ok());
  EXPECT_EQ(result.error().message,
            "force_n must be a positive finite number, got -2");
}

}  // namespace
}  // namespace burrlab::sim
