// Falcon kinematics pose for pose: forward(inverse(p)) = p over the
// workspace, inverse kinematics against Stamper's tan-half-angle quadratic
// evaluated independently, symmetric configurations, the Jacobian against
// finite differences and torques against virtual work.
#include "devices/falcon_kinematics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <vector>

#include "devices/falcon_device.h"

namespace burrlab::runner::falcon {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Every 5 mm of the Falcon's nominal workspace box.
std::vector<glm::dvec3> WorkspaceGrid(double step_mm) {
  const Workspace& box = FalconSpec().workspace;
  std::vector<glm::dvec3> grid;
  for (double x = box.min_mm.x; x <= box.max_mm.x + 1e-9; x += step_mm)
    for (double y = box.min_mm.y; y <= box.max_mm.y + 1e-9; y += step_mm)
      for (double z = box.min_mm.z; z <= box.max_mm.z + 1e-9; z += step_mm)
        grid.emplace_back(x, y, z);
  return grid;
}

// theta1 of leg i by Stamper's route: with t = tan(theta1 / 2) the loop
// closure is l2 t^2 + l1 t + l0 = 0; the Falcon takes the root with the minus
// sign.
double StamperTheta1(const glm::dvec3& p, int i) {
  const double a = kArmMm, b = kShinMm, c = kEffectorUMm, d = kShinJointMm,
               e = kKneeJointMm, f = kEffectorVMm;
  const double phi = kLegAngleRad[static_cast<std::size_t>(i)];
  const double u = std::cos(phi) * p.x + std::sin(phi) * p.y - kBaseUMm;
  const double v = -std::sin(phi) * p.x + std::cos(phi) * p.y - kBaseVMm;
  const double w = p.z;
  const double s3 = std::sin(std::acos((v + f) / b));
  const double k = w * w + u * u + 2 * c * u + a * a + c * c - d * d - e * e -
                   b * b * s3 * s3 - 2 * b * e * s3 - 2 * b * d * s3 -
                   2 * d * e;
  const double l0 = k - 2 * a * u - 2 * a * c;
  const double l1 = -4 * a * w;
  const double l2 = k + 2 * a * u + 2 * a * c;
  const double t = (-l1 - std::sqrt(l1 * l1 - 4 * l0 * l2)) / (2 * l2);
  return 2 * std::atan(t);
}

TEST(FalconKinematics, EncoderCountsToAngles) {
  EXPECT_DOUBLE_EQ(EncoderToAngleRad(0), 35.0 * kDeg);
  // 14.25 mm shaft, 4 x 320 counts per turn, 110 mm pulley:
  // 360 * 14.25 / (1280 * 110) = 0.0364346590909... degrees per count.
  EXPECT_NEAR(EncoderToAngleRad(1000), (35.0 + 36.4346590909091) * kDeg, 1e-12);
  EXPECT_NEAR(EncoderToAngleRad(-1447), (35.0 - 52.7209517045455) * kDeg,
              1e-12);
  for (int count : {-32768, -1447, 0, 1, 32767}) {
    EXPECT_NEAR(
        AngleRadToEncoder(EncoderToAngleRad(static_cast<std::int16_t>(count))),
        count, 1e-9);
  }
}

TEST(FalconKinematics, ForwardOfInverseIsIdentityOverTheWorkspace) {
  const std::vector<glm::dvec3> grid = WorkspaceGrid(5.0);
  ASSERT_EQ(grid.size(), 15u * 15u * 17u);
  for (const glm::dvec3& p : grid) {
    glm::dvec3 angles;
    ASSERT_TRUE(InverseKinematics(p, &angles))
        << p.x << " " << p.y << " " << p.z;
    glm::dvec3 back;
    ASSERT_TRUE(ForwardKinematics(angles, kWorkspaceCentreMm, &back))
        << p.x << " " << p.y << " " << p.z;
    EXPECT_NEAR(back.x, p.x, 1e-9);
    EXPECT_NEAR(back.y, p.y, 1e-9);
    EXPECT_NEAR(back.z, p.z, 1e-9);
  }
}

TEST(FalconKinematics, InverseMatchesStampersQuadraticOverTheWorkspace) {
  for (const glm::dvec3& p : WorkspaceGrid(5.0)) {
    glm::dvec3 angles;
    ASSERT_TRUE(InverseKinematics(p, &angles));
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(angles[i], StamperTheta1(p, i), 1e-10);
    }
  }
}

TEST(FalconKinematics, PointsOnTheAxisHaveEqualAnglesAndBack) {
  // The legs are 120 degrees apart: on the z axis all three angles agree;
  // at z = 110 mm they are 14.5665851912 degrees (Stamper's quadratic).
  glm::dvec3 angles;
  ASSERT_TRUE(InverseKinematics({0.0, 0.0, 110.0}, &angles));
  EXPECT_NEAR(angles.x / kDeg, 14.5665851912, 1e-9);
  EXPECT_NEAR(angles.y, angles.x, 1e-12);
  EXPECT_NEAR(angles.z, angles.x, 1e-12);
  // And all angles equal put the effector on the axis.
  for (double degrees : {0.0, 14.5665851912, 30.0, 45.0, 60.0}) {
    glm::dvec3 p;
    ASSERT_TRUE(
        ForwardKinematics(glm::dvec3(degrees * kDeg), kWorkspaceCentreMm, &p))
        << degrees;
    EXPECT_NEAR(p.x, 0.0, 1e-9) << degrees;
    EXPECT_NEAR(p.y, 0.0, 1e-9) << degrees;
  }
  glm::dvec3 p;
  ASSERT_TRUE(ForwardKinematics(glm::dvec3(14.5665851912 * kDeg),
                                kWorkspaceCentreMm, &p));
  EXPECT_NEAR(p.z, 110.0, 1e-8);
}

TEST(FalconKinematics, OutOfReachIsRefused) {
  glm::dvec3 angles(1.0);
  EXPECT_FALSE(InverseKinematics({0.0, 0.0, 400.0}, &angles));
  EXPECT_EQ(angles, glm::dvec3(1.0));  // unchanged
  glm::dvec3 p(7.0);
  EXPECT_FALSE(
      ForwardKinematics(glm::dvec3(170.0 * kDeg), kWorkspaceCentreMm, &p));
  EXPECT_EQ(p, glm::dvec3(7.0));
  EXPECT_FALSE(
      ForwardKinematics(glm::dvec3(std::nan("")), kWorkspaceCentreMm, &p));
}

TEST(FalconKinematics, JacobianMatchesCentralDifferences) {
  constexpr double kH = 1e-4;  // mm
  for (const glm::dvec3& p : WorkspaceGrid(10.0)) {
    std::array<glm::dvec3, 3> rows;
    ASSERT_TRUE(AngleJacobian(p, &rows));
    for (int j = 0; j < 3; ++j) {
      glm::dvec3 plus = p, minus = p;
      plus[j] += kH;
      minus[j] -= kH;
      glm::dvec3 a_plus, a_minus;
      ASSERT_TRUE(InverseKinematics(plus, &a_plus));
      ASSERT_TRUE(InverseKinematics(minus, &a_minus));
      const glm::dvec3 numeric = (a_plus - a_minus) / (2.0 * kH);
      for (int i = 0; i < 3; ++i) {
        const double analytic = rows[static_cast<std::size_t>(i)][j];
        EXPECT_NEAR(analytic, numeric[i], 1e-7 * std::abs(numeric[i]) + 1e-10)
            << "d theta" << i << " / d x" << j << " at " << p.x << " " << p.y
            << " " << p.z;
      }
    }
  }
}

TEST(FalconKinematics, TorquesDoTheSameVirtualWorkAsTheForce) {
  // tau . d theta = F . dp for every small displacement: J^T tau = F.
  for (const glm::dvec3& p : WorkspaceGrid(10.0)) {
    for (const glm::dvec3& force_n :
         {glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(0.0, -2.0, 0.0),
          glm::dvec3(0.0, 0.0, 8.0), glm::dvec3(3.0, -1.0, 2.5)}) {
      glm::dvec3 torques_n_m;
      ASSERT_TRUE(ForceToTorques(p, force_n, &torques_n_m));
      std::array<glm::dvec3, 3> rows;
      ASSERT_TRUE(AngleJacobian(p, &rows));
      const glm::dvec3 back_n =
          1e3 * (torques_n_m.x * rows[0] + torques_n_m.y * rows[1] +
                 torques_n_m.z * rows[2]);
      EXPECT_NEAR(back_n.x, force_n.x, 1e-9);
      EXPECT_NEAR(back_n.y, force_n.y, 1e-9);
      EXPECT_NEAR(back_n.z, force_n.z, 1e-9);
    }
  }
  // By symmetry, a force along the axis at a point on the axis loads the
  // three motors equally.
  glm::dvec3 torques_n_m;
  ASSERT_TRUE(ForceToTorques({0.0, 0.0, 110.0}, {0.0, 0.0, 4.0}, &torques_n_m));
  EXPECT_NEAR(torques_n_m.y, torques_n_m.x, 1e-12);
  EXPECT_NEAR(torques_n_m.z, torques_n_m.x, 1e-12);
  EXPECT_GT(std::abs(torques_n_m.x), 0.0);
}

TEST(FalconKinematics, MotorCommandsScaleSaturateAndKeepDirection) {
  using Commands = std::array<std::int16_t, 3>;
  EXPECT_EQ(TorquesToMotorCommands({0.1, -0.2, 0.05}),
            (Commands{-1000, 2000, -500}));
  // -100000, 50000, 0 exceed the int16 range: all scaled by 32767/100000.
  EXPECT_EQ(TorquesToMotorCommands({10.0, -5.0, 0.0}),
            (Commands{-32767, 16384, 0}));
  EXPECT_EQ(TorquesToMotorCommands({std::nan(""), 1.0, 1.0}),
            (Commands{0, 0, 0}));
}

}  // namespace
}  // namespace burrlab::runner::falcon
