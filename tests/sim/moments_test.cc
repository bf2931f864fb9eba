// Moments, depth and elastic force against the closed forms of a sphere
// immersed in a half-space (haptics notes;
// eqs. 6.17-6.22, 7.2, 7.3, 7.10-7.11).
#include "burrlab/sim/moments.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <vector>

#include "burrlab/sim/force_curve.h"
#include "burrlab/sim/octree.h"
#include "burrlab/sim/phantoms.h"

namespace burrlab::sim {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(VoxelSphere, LensVolumeIsFullVolumeInsideAndZeroOutside) {
  const double eta = EqualVolumeSphereRadius(0.3);
  EXPECT_NEAR(4.0 / 3.0 * kPi * eta * eta * eta, 0.027, 1e-12);
  EXPECT_NEAR(LensVolume(3.0 - eta, 3.0, eta), 0.027, 1e-12);
  EXPECT_NEAR(LensVolume(3.0 - eta + 1e-9, 3.0, eta), 0.027,
              1e-9);  // eq. 6.17 continuous
  EXPECT_NEAR(LensVolume(3.0 + eta - 1e-9, 3.0, eta), 0.0, 1e-9);
  EXPECT_EQ(LensVolume(3.0 + eta, 3.0, eta), 0.0);
  // Centred on the burr surface, about half the small sphere is inside.
  EXPECT_NEAR(LensVolume(3.0, 3.0, eta) / 0.027, 0.5, 0.03);
}

TEST(VoxelSphere, LensAreaIsTheDiskWhereTheSpheresMeet) {
  // Spheres of radius 1 and 1 at distance 1: circle radius sqrt(3)/2.
  EXPECT_NEAR(LensArea(1.0, 1.0, 1.0), kPi * 0.75, 1e-12);
  EXPECT_NEAR(RadicalPlaneDistance(1.0, 1.0, 1.0), 0.5, 1e-12);
  EXPECT_EQ(LensArea(2.5, 1.0, 1.0), 0.0);
}

TEST(Depth, InvertsTheCapVolumeOverTheWholeRange) {
  for (double h = 0.0; h <= 6.0; h += 0.01) {
    EXPECT_NEAR(DepthFromM0(CapVolume(h, 3.0), 3.0), h, 1e-9) << "h = " << h;
  }
  EXPECT_EQ(DepthFromM0(-1.0, 3.0), 0.0);
  EXPECT_EQ(DepthFromM0(1e9, 3.0), 6.0);
  EXPECT_NEAR(DepthFromM0(1e-12, 3.0), std::sqrt(1e-12 / (kPi * 3.0)), 1e-9);
}

// A burr of radius R = 3 mm pressed into half-spaces at several orientations
// and positions against the grid; every immersion from 0.1R to R is checked
// against the closed forms.
struct HalfSpaceCase {
  const char* name;
  glm::dvec3 normal;
  MomentMethod method;
};

class HalfSpaceClosedForm : public ::testing::TestWithParam<HalfSpaceCase> {};

TEST_P(HalfSpaceClosedForm, MomentsDepthForceAndNormalMatchWithinTolerance) {
  const HalfSpaceCase& c = GetParam();
  const double radius = 3.0, c_e = 2.145;
  for (double offset : {0.0, 0.37}) {
    ForceCurveOptions options;
    options.c_e_n_per_mm2 = c_e;
    options.radius_mm = radius;
    options.max_depth_mm = radius;
    options.points = 10;  // 0.1R .. R
    options.method = c.method;
    options.ell_over_r = 0.3;
    options.normal = c.normal;
    options.offset_voxels = offset;
    Result<std::vector<ForceCurvePoint>> curve = ComputeForceCurve(options);
    ASSERT_TRUE(curve.ok()) << curve.error().message;
    const glm::dvec3 n = c.normal / std::sqrt(glm::dot(c.normal, c.normal));
    for (const ForceCurvePoint& p : *curve) {
      const double h = p.depth_mm;
      const double m0 = kPi * h * h * (radius - h / 3.0);
      const double force = c_e * radius * radius * std::pow(h / radius, 1.5);
      EXPECT_NEAR(p.m0_mm3 / m0, 1.0, 0.05) << c.name << " depth " << h;
      EXPECT_NEAR(p.h_mm / h, 1.0, 0.05) << c.name << " depth " << h;
      EXPECT_NEAR(p.force_n / force, 1.0, 0.05) << c.name << " depth " << h;
      const double cosine = std::clamp(glm::dot(p.normal, n), -1.0, 1.0);
      EXPECT_LT(std::acos(cosine) * 180.0 / kPi, 2.0)
          << c.name << " depth " << h;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Orientations, HalfSpaceClosedForm,
    ::testing::Values(
        HalfSpaceCase{"axis_mono", {0, 0, 1}, MomentMethod::kMono},
        HalfSpaceCase{"axis_octree", {0, 0, 1}, MomentMethod::kOctree},
        HalfSpaceCase{"diagonal_mono", {0, 1, 1}, MomentMethod::kMono},
        HalfSpaceCase{"diagonal_octree", {0, 1, 1}, MomentMethod::kOctree},
        HalfSpaceCase{"oblique_mono", {1, 2, 3}, MomentMethod::kMono},
        HalfSpaceCase{"oblique_octree", {1, 2, 3}, MomentMethod::kOctree},
        HalfSpaceCase{"side_octree", {-1, 0, 0.2}, MomentMethod::kOctree}),
    [](const auto& param_info) { return std::string(param_info.param.name); });

// Dissertation fig. 7.1: multi-resolution force within a few percent of
// mono-resolution.
TEST(MultiResolution, ForceWithinTwoPercentOfMonoAtEllPoint3R) {
  for (double radius : {1.0, 5.0}) {
    for (glm::dvec3 normal : {glm::dvec3(0, 0, 1), glm::dvec3(1, 2, 3)}) {
      ForceCurveOptions options;
      options.radius_mm = radius;
      options.points = 10;  // 0.1R .. R
      options.normal = normal;
      options.offset_voxels = 0.21;
      options.method = MomentMethod::kMono;
      Result<std::vector<ForceCurvePoint>> mono = ComputeForceCurve(options);
      options.method = MomentMethod::kOctree;
      options.ell_over_r = 0.3;
      Result<std::vector<ForceCurvePoint>> multi = ComputeForceCurve(options);
      ASSERT_TRUE(mono.ok() && multi.ok());
      for (std::size_t i = 0; i < mono->size(); ++i) {
        EXPECT_NEAR((*multi)[i].force_n / (*mono)[i].force_n, 1.0, 0.02)
            << "R = " << radius << " depth " << (*mono)[i].depth_mm;
      }
    }
  }
}

TEST(MultiResolution, EqualsMonoWhenEllIsBelowTheVoxelSize) {
  PhantomGrid grid{40, 40, 40, 0.3};
  Result<Volume> volume = MakeSphere(grid, glm::dvec3(6.0, 6.1, 5.9), 4.0);
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  const MomentOctree tree = MomentOctree::Build(*volume);
  for (double x = 6.0; x < 10.5; x += 0.37) {
    const glm::dvec3 centre(x, 6.3, 7.1);
    const Moments mono = ComputeMomentsMono(*volume, centre, 2.0);
    const Moments multi = ComputeMomentsOctree(tree, *volume, centre, 2.0, 0.1);
    EXPECT_NEAR(multi.m0_mm3, mono.m0_mm3, 1e-9 * (1.0 + mono.m0_mm3));
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(multi.m1_mm4[a], mono.m1_mm4[a],
                  1e-9 * (1.0 + std::abs(mono.m1_mm4[a])));
    }
  }
}

TEST(Moments, BurrOutsideTheVolumeSeesNothing) {
  Result<Volume> volume = Volume::Create(8, 8, 8, 0.3);
  ASSERT_TRUE(volume.ok());
  for (int i = 0; i < 8; ++i) volume->Set(i, i, i, 255);
  const MomentOctree tree = MomentOctree::Build(*volume);
  const glm::dvec3 far(-50.0, 3.0, 1e6);
  EXPECT_EQ(ComputeMomentsMono(*volume, far, 3.0).m0_mm3, 0.0);
  EXPECT_EQ(ComputeMomentsOctree(tree, *volume, far, 3.0, 0.9).m0_mm3, 0.0);
}

}  // namespace
}  // namespace burrlab::sim

namespace burrlab::sim {
namespace {

// Power of the force signal at spatial period `period_mm` (one DFT bin).
double PowerAtPeriod(const std::vector<double>& force, double step_mm,
                     double period_mm) {
  double mean = 0.0;
  for (double f : force) mean += f;
  mean /= static_cast<double>(force.size());
  double re = 0.0, im = 0.0;
  for (std::size_t i = 0; i < force.size(); ++i) {
    const double phase =
        2.0 * kPi * static_cast<double>(i) * step_mm / period_mm;
    re += (force[i] - mean) * std::cos(phase);
    im += (force[i] - mean) * std::sin(phase);
  }
  return re * re + im * im;
}

// Dissertation fig. 6.5: sliding at depth R/4 over a flat surface, the
// voxel-sphere force fluctuates with the lattice period along the path: v over
// an axis-aligned plane, v sqrt(2) along the plane with normal (0, 1,
// 1)/sqrt(2).
TEST(Sliding, ForceFluctuationWavelengthsDifferBySqrtTwo) {
  const double v = 0.3, radius = 1.0;
  const PhantomGrid grid{48, 48, 48, v};
  struct Path {
    glm::dvec3 normal, direction;
  };
  const double s = 1.0 / std::sqrt(2.0);
  const Path paths[] = {{{0, 0, 1}, {1, 0, 0}}, {{0, s, s}, {0, s, -s}}};
  std::vector<double> ratios;
  for (const Path& path : paths) {
    const glm::dvec3 point(7.2, 7.2, 7.2);
    Result<Volume> volume = MakeHalfSpace(grid, point, path.normal);
    ASSERT_TRUE(volume.ok());
    const MomentOctree tree = MomentOctree::Build(*volume);
    const double step = 0.01;
    std::vector<double> force;
    for (double t = -2.4; t < 2.4; t += step) {
      const glm::dvec3 centre =
          point + 0.75 * radius * path.normal + t * path.direction;
      const Moments m = ComputeMomentsMono(*volume, centre, radius);
      force.push_back(std::pow(DepthFromM0(m.m0_mm3, radius) / radius, 1.5));
    }
    ratios.push_back(PowerAtPeriod(force, step, v) /
                     PowerAtPeriod(force, step, v * std::sqrt(2.0)));
  }
  EXPECT_GT(ratios[0], 10.0);  // axis-aligned: period v dominates
  EXPECT_LT(ratios[1], 0.1);   // oblique: period v sqrt(2) dominates
}

}  // namespace
}  // namespace burrlab::sim
