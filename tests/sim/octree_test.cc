// Octree block moments against brute-force sums, before and after erosion
// (eq. 7.9).
#include "burrlab/sim/octree.h"

#include <gtest/gtest.h>

#include <random>

namespace burrlab::sim {
namespace {

MomentOctree::Node BruteForce(const Volume& volume, int level, int bx, int by,
                              int bz) {
  MomentOctree::Node node;
  const int size = 1 << level;
  for (int k = bz * size; k < (bz + 1) * size; ++k)
    for (int j = by * size; j < (by + 1) * size; ++j)
      for (int i = bx * size; i < (bx + 1) * size; ++i) {
        const std::int64_t o = volume.At(i, j, k);
        node.m0 += o;
        // Voxel centre minus block centre in half-voxels.
        node.m1[0] += o * ((2 * i + 1) - (2 * bx + 1) * size);
        node.m1[1] += o * ((2 * j + 1) - (2 * by + 1) * size);
        node.m1[2] += o * ((2 * k + 1) - (2 * bz + 1) * size);
      }
  return node;
}

void ExpectAllBlocksEqualBruteForce(const MomentOctree& tree,
                                    const Volume& volume) {
  for (int level = 1; level <= tree.levels(); ++level)
    for (int bz = 0; bz < tree.BlocksZ(level); ++bz)
      for (int by = 0; by < tree.BlocksY(level); ++by)
        for (int bx = 0; bx < tree.BlocksX(level); ++bx) {
          const MomentOctree::Node expected =
              BruteForce(volume, level, bx, by, bz);
          const MomentOctree::Node& got = tree.At(level, bx, by, bz);
          ASSERT_EQ(got.m0, expected.m0) << "level " << level;
          ASSERT_EQ(got.m1, expected.m1) << "level " << level;
        }
}

Volume RandomVolume(int nx, int ny, int nz, std::uint32_t seed) {
  Volume volume = Volume::Create(nx, ny, nz, 0.3).value();
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> occupancy(0, 255);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        volume.Set(i, j, k, static_cast<std::uint8_t>(occupancy(rng)));
  return volume;
}

TEST(MomentOctree, BlockMomentsEqualBruteForceSumsOnNonPowerOfTwoGrid) {
  const Volume volume = RandomVolume(37, 20, 9, 7);
  const MomentOctree tree = MomentOctree::Build(volume);
  EXPECT_EQ(tree.levels(), 6);  // 37 -> 19 -> 10 -> 5 -> 3 -> 2 -> 1
  EXPECT_EQ(tree.BlocksX(tree.levels()), 1);
  ExpectAllBlocksEqualBruteForce(tree, volume);
}

TEST(MomentOctree, StaysEqualToBruteForceSumsUnderErosion) {
  Volume volume = RandomVolume(24, 17, 16, 11);
  MomentOctree tree = MomentOctree::Build(volume);
  std::mt19937 rng(3);
  for (int n = 0; n < 2000; ++n) {
    const int i = static_cast<int>(rng() % 24),
              j = static_cast<int>(rng() % 17),
              k = static_cast<int>(rng() % 16);
    const int occupancy = volume.At(i, j, k);
    const int amount =
        occupancy == 0 ? 0 : 1 + static_cast<int>(rng() % occupancy);
    volume.Set(i, j, k, static_cast<std::uint8_t>(occupancy - amount));
    tree.OnVoxelDecrement(i, j, k, amount);
  }
  ExpectAllBlocksEqualBruteForce(tree, volume);
}

TEST(MomentOctree, TopBlockHoldsTheWholeVolume) {
  const Volume volume = RandomVolume(256, 256, 128, 5);
  const MomentOctree tree = MomentOctree::Build(volume);
  std::int64_t sum = 0;
  for (std::size_t n = 0; n < volume.size(); ++n) sum += volume.occupancy()[n];
  EXPECT_EQ(tree.levels(), 8);
  EXPECT_EQ(tree.At(tree.levels(), 0, 0, 0).m0, sum);
}

}  // namespace
}  // namespace burrlab::sim
