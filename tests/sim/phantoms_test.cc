// Phantoms against closed forms: volumes of half-spaces, slabs and balls, the
// moments of a half-space inside a burr-sized sphere (the quantities the force
// model reads), the layers of the temporal-bone block, and the exact error
// texts of invalid inputs.
#include "burrlab/sim/phantoms.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <string>

namespace burrlab::sim {
namespace {

// Material of a volume in mm^3 (sum of occupancy / 255 times voxel volume),
// summed here rather than through Volume::MaterialMm3.
double SumMaterialMm3(const Volume& volume) {
  double sum = 0.0;
  for (int k = 0; k < volume.nz(); ++k) {
    for (int j = 0; j < volume.ny(); ++j) {
      for (int i = 0; i < volume.nx(); ++i) sum += volume.At(i, j, k);
    }
  }
  const double v = volume.voxel_mm();
  return sum / 255.0 * v * v * v;
}

glm::dvec3 Centre(const Volume& volume, int i, int j, int k) {
  return {volume.CentreMm(i), volume.CentreMm(j), volume.CentreMm(k)};
}

// Fraction of the voxel (i, j, k) where inside(x) holds, by the midpoint rule
// on n^3 points.
template <typename Inside>
double SampledFraction(const Volume& volume, int i, int j, int k, int n,
                       const Inside& inside) {
  const double v = volume.voxel_mm();
  int count = 0;
  for (int c = 0; c < n; ++c) {
    for (int b = 0; b < n; ++b) {
      for (int a = 0; a < n; ++a) {
        const glm::dvec3 x((i + (a + 0.5) / n) * v, (j + (b + 0.5) / n) * v,
                           (k + (c + 0.5) / n) * v);
        count += inside(x) ? 1 : 0;
      }
    }
  }
  return static_cast<double>(count) / (n * n * n);
}

// Mass moments m0 (mm^3) and m1 (mm^4, about `centre`) of the voxelised
// material inside a sphere, by brute force: each voxel's material is spread
// evenly over 4^3 sub-points.
struct BruteMoments {
  double m0 = 0.0;
  glm::dvec3 m1{0.0};
};
BruteMoments MomentsInSphere(const Volume& volume, const glm::dvec3& centre,
                             double radius) {
  constexpr int kSub = 4;
  const double v = volume.voxel_mm();
  const double cell = v / kSub;
  const double cell_volume = cell * cell * cell;
  BruteMoments moments;
  for (int k = 0; k < volume.nz(); ++k) {
    for (int j = 0; j < volume.ny(); ++j) {
      for (int i = 0; i < volume.nx(); ++i) {
        const double density = volume.At(i, j, k) / 255.0;
        if (density == 0.0) continue;
        if (glm::length(Centre(volume, i, j, k) - centre) > radius + v) {
          continue;
        }
        for (int c = 0; c < kSub; ++c) {
          for (int b = 0; b < kSub; ++b) {
            for (int a = 0; a < kSub; ++a) {
              const glm::dvec3 x(i * v + (a + 0.5) * cell,
                                 j * v + (b + 0.5) * cell,
                                 k * v + (c + 0.5) * cell);
              const glm::dvec3 r = x - centre;
              if (glm::dot(r, r) > radius * radius) continue;
              moments.m0 += density * cell_volume;
              moments.m1 += density * cell_volume * r;
            }
          }
        }
      }
    }
  }
  return moments;
}

const PhantomGrid kGrid{64, 64, 64, 0.3};  // a 19.2 mm cube
constexpr double kSide = 64 * 0.3;

TEST(Phantom, HalfSpaceMaterialMatchesClosedFormVolumeForAxisAlignedNormals) {
  // Material below z = 5.05 mm: the top layer is 5/6 of a voxel.
  Result<Volume> below =
      MakeHalfSpace(kGrid, glm::dvec3(1.0, 2.0, 5.05), glm::dvec3(0, 0, 1));
  ASSERT_TRUE(below.ok()) << below.error().message;
  EXPECT_NEAR(SumMaterialMm3(*below) / (kSide * kSide * 5.05), 1.0, 1e-3);
  // The normal need not be unit length; material above x = 7.37 mm.
  Result<Volume> above =
      MakeHalfSpace(kGrid, glm::dvec3(7.37, 0.0, 0.0), glm::dvec3(-4, 0, 0));
  ASSERT_TRUE(above.ok()) << above.error().message;
  EXPECT_NEAR(SumMaterialMm3(*above) / (kSide * kSide * (kSide - 7.37)), 1.0,
              1e-3);
}

TEST(Phantom, HalfSpaceMaterialMatchesClosedFormVolumeForObliqueNormals) {
  // y + z <= 12 mm: a triangular prism of legs 12 mm along x.
  Result<Volume> prism = MakeHalfSpace(kGrid, glm::dvec3(0.0, 6.0, 6.0),
                                       glm::dvec3(0, 1, 1) / std::sqrt(2.0));
  ASSERT_TRUE(prism.ok()) << prism.error().message;
  EXPECT_NEAR(SumMaterialMm3(*prism) / (kSide * 12.0 * 12.0 / 2.0), 1.0, 1e-3);
  // x + 2y + 3z <= 18 mm: the corner tetrahedron of intercepts 18, 9, 6 mm.
  Result<Volume> tetra =
      MakeHalfSpace(kGrid, glm::dvec3(3.0, 3.0, 3.0), glm::dvec3(1, 2, 3));
  ASSERT_TRUE(tetra.ok()) << tetra.error().message;
  EXPECT_NEAR(SumMaterialMm3(*tetra) / (18.0 * 18.0 * 18.0 / 36.0), 1.0, 1e-3);
  // Any plane through the centre of the box halves it.
  Result<Volume> half =
      MakeHalfSpace(kGrid, glm::dvec3(kSide / 2), glm::dvec3(-1, 2, 3));
  ASSERT_TRUE(half.ok()) << half.error().message;
  EXPECT_NEAR(SumMaterialMm3(*half) / (kSide * kSide * kSide / 2.0), 1.0, 1e-3);
}

TEST(Phantom, HalfSpaceCornerVoxelHoldsTheExactCutCubeVolume) {
  // Below the plane x + y + z = t (in voxels), voxel (0, 0, 0) holds the
  // corner tetrahedron t^3 / 6, less the three tips of legs t - 1 that stick
  // out of it once t > 1 (inclusion-exclusion over the corners).
  const PhantomGrid grid{4, 4, 4, 1.0};
  Result<Volume> small =
      MakeHalfSpace(grid, glm::dvec3(0.3, 0.3, 0.3), glm::dvec3(1, 1, 1));
  ASSERT_TRUE(small.ok()) << small.error().message;
  EXPECT_EQ(small->At(0, 0, 0), std::lround(255 * 0.9 * 0.9 * 0.9 / 6));
  Result<Volume> large =
      MakeHalfSpace(grid, glm::dvec3(0.6, 0.6, 0.6), glm::dvec3(2, 2, 2));
  ASSERT_TRUE(large.ok()) << large.error().message;
  const double t = 1.8;
  const double tip = t - 1.0;
  EXPECT_EQ(large->At(0, 0, 0),
            std::lround(255 * (t * t * t - 3 * tip * tip * tip) / 6));
  // Voxel (1, 0, 0) holds a tetrahedron of legs 0.8: 0.8^3 / 6 of a voxel.
  EXPECT_EQ(large->At(1, 0, 0), std::lround(255 * tip * tip * tip / 6));
  EXPECT_EQ(large->At(1, 1, 0), 0);  // the plane only touches its corner
}

TEST(Phantom, HalfSpaceVoxelsAreExactFarFromThePlaneAndSampledNearIt) {
  const PhantomGrid grid{12, 12, 12, 0.5};
  const glm::dvec3 point(2.9, 3.1, 3.05);
  const glm::dvec3 n = glm::normalize(glm::dvec3(1, 2, 3));
  Result<Volume> volume = MakeHalfSpace(grid, point, glm::dvec3(1, 2, 3));
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  const double reach = std::sqrt(3.0) / 2.0 * grid.voxel_mm;
  int straddling = 0;
  for (int k = 0; k < grid.nz; ++k) {
    for (int j = 0; j < grid.ny; ++j) {
      for (int i = 0; i < grid.nx; ++i) {
        const double d = glm::dot(Centre(*volume, i, j, k) - point, n);
        if (d > reach) {
          ASSERT_EQ(volume->At(i, j, k), 0) << i << " " << j << " " << k;
        } else if (d < -reach) {
          ASSERT_EQ(volume->At(i, j, k), 255) << i << " " << j << " " << k;
        } else if (straddling++ % 7 == 0) {  // a sample of the cut voxels
          const double fraction =
              SampledFraction(*volume, i, j, k, 64, [&](const glm::dvec3& x) {
                return glm::dot(x - point, n) <= 0.0;
              });
          EXPECT_NEAR(volume->At(i, j, k), 255 * fraction, 1.0)
              << i << " " << j << " " << k;
        }
      }
    }
  }
  EXPECT_GT(straddling, 100);
}

TEST(Phantom, HalfSpaceMomentsInABurrSphereMatchTheCapFormulas) {
  // A burr of radius R = 3 mm centred delta = 0.75 mm above the surface holds
  // a cap of height h = R - delta: m0 = pi h^2 (R - h/3) (eq. 7.2), and m1
  // points into the material with |m1| = pi/4 (R^2 - delta^2)^2.
  const double radius = 3.0;
  const double delta = 0.75;
  const double h = radius - delta;
  const double cap_m0 = std::numbers::pi * h * h * (radius - h / 3.0);
  const double cap_m1 = std::numbers::pi / 4.0 *
                        (radius * radius - delta * delta) *
                        (radius * radius - delta * delta);
  for (const glm::dvec3 normal :
       {glm::dvec3(0, 0, 1), glm::dvec3(0, 1, 1), glm::dvec3(1, 2, 3)}) {
    const glm::dvec3 n = glm::normalize(normal);
    const glm::dvec3 surface(9.61, 9.53, 9.47);
    Result<Volume> volume = MakeHalfSpace(kGrid, surface, normal);
    ASSERT_TRUE(volume.ok()) << volume.error().message;
    const BruteMoments m =
        MomentsInSphere(*volume, surface + delta * n, radius);
    EXPECT_NEAR(m.m0 / cap_m0, 1.0, 0.02)
        << "normal " << normal.x << " " << normal.y << " " << normal.z;
    EXPECT_NEAR(glm::dot(m.m1, -n) / cap_m1, 1.0, 0.02);
    EXPECT_LT(glm::length(m.m1 - glm::dot(m.m1, n) * n), 0.01 * cap_m1);
  }
}

TEST(Phantom, SphereMaterialMatchesFourThirdsPiRCubed) {
  for (const double radius : {1.0, 3.0, 4.5, 8.0}) {
    Result<Volume> volume =
        MakeSphere(kGrid, glm::dvec3(9.6, 9.57, 9.71), radius);
    ASSERT_TRUE(volume.ok()) << volume.error().message;
    EXPECT_NEAR(SumMaterialMm3(*volume) /
                    (4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3)),
                1.0, 0.001)
        << "radius " << radius;
  }
}

TEST(Phantom, SphereVoxelsAreExactFarFromTheSurfaceAndSampledNearIt) {
  const PhantomGrid grid{16, 16, 16, 0.3};
  const glm::dvec3 centre(2.41, 2.37, 2.45);
  const double radius = 1.7;
  Result<Volume> volume = MakeSphere(grid, centre, radius);
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  const double reach = std::sqrt(3.0) / 2.0 * grid.voxel_mm;
  int straddling = 0;
  for (int k = 0; k < grid.nz; ++k) {
    for (int j = 0; j < grid.ny; ++j) {
      for (int i = 0; i < grid.nx; ++i) {
        const double d =
            glm::length(Centre(*volume, i, j, k) - centre) - radius;
        if (d > reach) {
          ASSERT_EQ(volume->At(i, j, k), 0) << i << " " << j << " " << k;
        } else if (d < -reach) {
          ASSERT_EQ(volume->At(i, j, k), 255) << i << " " << j << " " << k;
        } else if (straddling++ % 5 == 0) {
          const double fraction =
              SampledFraction(*volume, i, j, k, 48, [&](const glm::dvec3& x) {
                return glm::length(x - centre) <= radius;
              });
          EXPECT_NEAR(volume->At(i, j, k), 255 * fraction, 1.0)
              << i << " " << j << " " << k;
        }
      }
    }
  }
  EXPECT_GT(straddling, 100);
}

TEST(Phantom, SlabMaterialMatchesClosedFormVolume) {
  // Horizontal slab 2.05 mm thick around z = 7.3 mm.
  Result<Volume> flat =
      MakeSlab(kGrid, glm::dvec3(1.0, 1.0, 7.3), glm::dvec3(0, 0, -2), 2.05);
  ASSERT_TRUE(flat.ok()) << flat.error().message;
  EXPECT_NEAR(SumMaterialMm3(*flat) / (kSide * kSide * 2.05), 1.0, 1e-3);
  // Diagonal slab 3 mm thick through the centre: in the x-y square it covers
  // all but two corner triangles of legs L - w, w = 3 / sqrt(2).
  Result<Volume> diagonal =
      MakeSlab(kGrid, glm::dvec3(kSide / 2), glm::dvec3(1, 1, 0), 3.0);
  ASSERT_TRUE(diagonal.ok()) << diagonal.error().message;
  const double w = 3.0 / std::sqrt(2.0);
  EXPECT_NEAR(SumMaterialMm3(*diagonal) /
                  (kSide * (kSide * kSide - (kSide - w) * (kSide - w))),
              1.0, 1e-3);
  // Oblique slab thinner than a voxel: still the right amount of material.
  const glm::dvec3 n = glm::normalize(glm::dvec3(1, 2, 3));
  Result<Volume> thin =
      MakeSlab(kGrid, glm::dvec3(1.0, 1.0, 1.0) + 2.0 * n, n, 0.1);
  ASSERT_TRUE(thin.ok()) << thin.error().message;
  // The plane x + 2y + 3z = c cuts the box in a triangle of legs c, c/2, c/3
  // (c = 6 + 2 sqrt(14) < 19.2 mm) whose area is c^2 sqrt(14) / 12.
  const double c = 6.0 + 2.0 * std::sqrt(14.0);
  EXPECT_NEAR(SumMaterialMm3(*thin) / (0.1 * c * c * std::sqrt(14.0) / 12.0),
              1.0, 0.01);
}

TEST(Phantom, LayeredBlockHasCortexOverTrabecularBoneUnderAir) {
  const PhantomGrid grid{4, 3, 40, 0.5};
  LayeredBlockSpec spec;
  spec.surface_z_mm = 15.2;          // 0.4 of voxel k = 30 is below the surface
  spec.cortical_thickness_mm = 2.0;  // cortex down to 13.2 mm, inside k = 26
  spec.trabecular_density = 0.6;
  spec.trabecular_erosion_factor = 2.5;
  Result<Volume> block = MakeLayeredBlock(grid, spec);
  ASSERT_TRUE(block.ok()) << block.error().message;
  for (int j = 0; j < grid.ny; ++j) {
    for (int i = 0; i < grid.nx; ++i) {
      for (int k = 31; k < grid.nz; ++k) {
        EXPECT_EQ(block->At(i, j, k), 0);
        EXPECT_EQ(block->Label(i, j, k), 0);
      }
      EXPECT_EQ(block->At(i, j, 30), 102);  // round(255 * 0.4)
      EXPECT_EQ(block->Label(i, j, 30), kCorticalLabel);
      for (int k = 27; k < 30; ++k) {
        EXPECT_EQ(block->At(i, j, k), 255);
        EXPECT_EQ(block->Label(i, j, k), kCorticalLabel);
      }
      // 0.6 cortex + 0.4 trabecular bone: round(255 * (0.6 + 0.4 * 0.6)).
      EXPECT_EQ(block->At(i, j, 26), 214);
      EXPECT_EQ(block->Label(i, j, 26), kCorticalLabel);
      for (int k = 0; k < 26; ++k) {
        EXPECT_EQ(block->At(i, j, k), 153);  // round(255 * 0.6)
        EXPECT_EQ(block->Label(i, j, k), kTrabecularLabel);
      }
    }
  }
  EXPECT_EQ(block->ErosionFactor(kCorticalLabel), 1.0);
  EXPECT_EQ(block->ErosionFactor(kTrabecularLabel), 2.5);
}

TEST(Phantom, LayeredBlockBoundaryVoxelTakesTheMajorityLabel) {
  const PhantomGrid grid{2, 2, 40, 0.5};
  LayeredBlockSpec spec;
  spec.surface_z_mm = 15.4;
  spec.cortical_thickness_mm =
      2.0;  // boundary at 13.4 mm: 0.2 cortex in k = 26
  spec.trabecular_density = 0.6;
  Result<Volume> block = MakeLayeredBlock(grid, spec);
  ASSERT_TRUE(block.ok()) << block.error().message;
  EXPECT_EQ(block->Label(1, 1, 26), kTrabecularLabel);
  EXPECT_EQ(block->At(1, 1, 26), 173);  // round(255 * (0.2 + 0.8 * 0.6))
  EXPECT_EQ(block->Label(1, 1, 27), kCorticalLabel);
  EXPECT_EQ(block->At(1, 1, 30), 204);  // round(255 * 0.8)
}

TEST(Phantom, LayeredBlockWithoutCortexIsTrabecularUpToTheSurface) {
  const PhantomGrid grid{2, 2, 10, 1.0};
  LayeredBlockSpec spec;
  spec.surface_z_mm = 5.5;
  spec.cortical_thickness_mm = 0.0;
  spec.trabecular_density = 1.0;
  Result<Volume> block = MakeLayeredBlock(grid, spec);
  ASSERT_TRUE(block.ok()) << block.error().message;
  EXPECT_EQ(block->At(0, 0, 4), 255);
  EXPECT_EQ(block->Label(0, 0, 4), kTrabecularLabel);
  EXPECT_EQ(block->At(0, 0, 5), 128);  // round(127.5)
  EXPECT_EQ(block->Label(0, 0, 5), kTrabecularLabel);
  EXPECT_EQ(block->At(0, 0, 6), 0);
  EXPECT_NEAR(block->MaterialMm3(), 2 * 2 * 5.5, 0.01);
}

TEST(Phantom, RejectsInvalidInputsWithMessagesNamingTheFieldAndValue) {
  const glm::dvec3 origin(0.0);
  const glm::dvec3 up(0, 0, 1);
  const double nan = std::nan("");
  EXPECT_EQ(MakeHalfSpace(kGrid, origin, glm::dvec3(0.0)).error().message,
            "half-space: outward_normal must be finite and non-zero, got (0, "
            "0, 0)");
  EXPECT_EQ(MakeHalfSpace(kGrid, glm::dvec3(nan, 0, 0), up).error().message,
            "half-space: point_mm must be finite, got (nan, 0, 0)");
  EXPECT_EQ(
      MakeHalfSpace(kGrid, origin, glm::dvec3(1, HUGE_VAL, 0)).error().message,
      "half-space: outward_normal must be finite and non-zero, got (1, inf, "
      "0)");
  EXPECT_EQ(MakeSlab(kGrid, origin, up, -1.0).error().message,
            "slab: thickness_mm must be positive and finite, got -1");
  EXPECT_EQ(MakeSlab(kGrid, origin, glm::dvec3(0.0), 1.0).error().message,
            "slab: normal must be finite and non-zero, got (0, 0, 0)");
  EXPECT_EQ(MakeSphere(kGrid, origin, 0.0).error().message,
            "sphere: radius_mm must be positive and finite, got 0");
  EXPECT_EQ(MakeSphere(kGrid, glm::dvec3(0, HUGE_VAL, 0), 1.0).error().message,
            "sphere: centre_mm must be finite, got (0, inf, 0)");
  EXPECT_EQ(
      MakeSphere(PhantomGrid{0, 64, 64, 0.3}, origin, 1.0).error().message,
      "sphere: grid: volume extents must be positive, got 0x64x64");

  LayeredBlockSpec spec;
  spec.trabecular_density = 1.5;
  EXPECT_EQ(MakeLayeredBlock(kGrid, spec).error().message,
            "layered block: trabecular_density must be in (0, 1], got 1.5");
  spec.trabecular_density = 0.0;
  EXPECT_EQ(MakeLayeredBlock(kGrid, spec).error().message,
            "layered block: trabecular_density must be in (0, 1], got 0");
  spec = LayeredBlockSpec{};
  spec.trabecular_erosion_factor = nan;
  EXPECT_EQ(MakeLayeredBlock(kGrid, spec).error().message,
            "layered block: trabecular_erosion_factor must be positive and "
            "finite, got nan");
  spec = LayeredBlockSpec{};
  spec.cortical_thickness_mm = -0.5;
  EXPECT_EQ(MakeLayeredBlock(kGrid, spec).error().message,
            "layered block: cortical_thickness_mm must be finite and >= 0, got "
            "-0.5");
  spec = LayeredBlockSpec{};
  spec.surface_z_mm = -HUGE_VAL;
  EXPECT_EQ(MakeLayeredBlock(kGrid, spec).error().message,
            "layered block: surface_z_mm must be finite, got -inf");
}

TEST(Phantom, TinyAndHugeNormalsGiveTheSameHalfSpace) {
  const PhantomGrid grid{8, 8, 8, 0.3};
  const glm::dvec3 point(1.21, 1.19, 1.23);
  Result<Volume> unit = MakeHalfSpace(grid, point, glm::dvec3(1, 2, 3));
  Result<Volume> tiny =
      MakeHalfSpace(grid, point, glm::dvec3(1e-300, 2e-300, 3e-300));
  Result<Volume> huge =
      MakeHalfSpace(grid, point, glm::dvec3(1e300, 2e300, 3e300));
  ASSERT_TRUE(unit.ok() && tiny.ok() && huge.ok());
  for (std::size_t v = 0; v < unit->size(); ++v) {
    ASSERT_EQ(tiny->occupancy()[v], unit->occupancy()[v]);
    ASSERT_EQ(huge->occupancy()[v], unit->occupancy()[v]);
  }
}

TEST(Phantom, NearlyAxisAlignedNormalsAgreeWithTheAxisAlignedCut) {
  // Components far below a voxel's resolution must not disturb the cut.
  const PhantomGrid grid{6, 6, 6, 0.3};
  const glm::dvec3 point(0.9, 0.9, 0.95);
  Result<Volume> exact = MakeHalfSpace(grid, point, glm::dvec3(0, 0, 1));
  ASSERT_TRUE(exact.ok());
  for (const double eps : {1e-12, 1e-8, 1e-5, 1e-4, 3e-4}) {
    Result<Volume> tilted =
        MakeHalfSpace(grid, point, glm::dvec3(eps, -eps, 1.0));
    ASSERT_TRUE(tilted.ok());
    for (std::size_t v = 0; v < exact->size(); ++v) {
      ASSERT_NEAR(tilted->occupancy()[v], exact->occupancy()[v], 1)
          << "eps " << eps << " voxel " << v;
    }
  }
}

}  // namespace
}  // namespace burrlab::sim
