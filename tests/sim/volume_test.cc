// Volume storage: creation limits (checked before allocating), x-fastest
// indexing, reads outside the grid, material totals, labels and erosion
// factors.
#include "burrlab/sim/volume.h"

#include <gtest/gtest.h>

#include <cmath>

namespace burrlab::sim {
namespace {

TEST(Volume, CreateGivesAnEmptyVolumeWithUnitErosionFactors) {
  Result<Volume> volume = Volume::Create(5, 4, 3, 0.25);
  ASSERT_TRUE(volume.ok()) << volume.error().message;
  EXPECT_EQ(volume->nx(), 5);
  EXPECT_EQ(volume->ny(), 4);
  EXPECT_EQ(volume->nz(), 3);
  EXPECT_EQ(volume->voxel_mm(), 0.25);
  EXPECT_EQ(volume->size(), 60u);
  for (std::size_t v = 0; v < volume->size(); ++v) {
    EXPECT_EQ(volume->occupancy()[v], 0);
    EXPECT_EQ(volume->labels()[v], 0);
  }
  for (int label = 0; label < 256; ++label) {
    EXPECT_EQ(volume->ErosionFactor(static_cast<std::uint8_t>(label)), 1.0);
  }
  EXPECT_EQ(volume->MaterialMm3(), 0.0);
}

TEST(Volume, CreateRefusesNonPositiveExtents) {
  EXPECT_EQ(Volume::Create(0, 4, 4, 0.3).error().message,
            "volume extents must be positive, got 0x4x4");
  EXPECT_EQ(Volume::Create(4, 4, -2, 0.3).error().message,
            "volume extents must be positive, got 4x4x-2");
}

TEST(Volume, CreateRefusesOversizedVolumesBeforeAllocating) {
  EXPECT_EQ(Volume::Create(4096, 4, 4, 0.3).error().message,
            "volume extent above the limit of 2048 voxels per axis: 4096x4x4");
  // Each extent within limits, but 2^31 voxels in all.
  EXPECT_EQ(Volume::Create(2048, 2048, 512, 0.3).error().message,
            "volume of 2147483648 voxels is above the limit of 1073741824");
}

TEST(Volume, CreateRefusesVoxelSizesThatAreNotPositiveAndFinite) {
  EXPECT_EQ(Volume::Create(4, 4, 4, 0.0).error().message,
            "voxel size must be a positive finite number of mm, got 0");
  EXPECT_FALSE(Volume::Create(4, 4, 4, -0.3).ok());
  EXPECT_FALSE(Volume::Create(4, 4, 4, std::nan("")).ok());
  EXPECT_FALSE(Volume::Create(4, 4, 4, HUGE_VAL).ok());
}

TEST(Volume, IndexRunsXFastestThenYThenZ) {
  Result<Volume> volume = Volume::Create(5, 4, 3, 0.3);
  ASSERT_TRUE(volume.ok());
  EXPECT_EQ(volume->Index(0, 0, 0), 0u);
  EXPECT_EQ(volume->Index(1, 0, 0), 1u);
  EXPECT_EQ(volume->Index(0, 1, 0), 5u);
  EXPECT_EQ(volume->Index(0, 0, 1), 20u);
  EXPECT_EQ(volume->Index(4, 3, 2), 59u);
  volume->Set(2, 3, 1, 77);
  EXPECT_EQ(volume->occupancy()[volume->Index(2, 3, 1)], 77);
  EXPECT_EQ(volume->At(2, 3, 1), 77);
}

TEST(Volume, ReadsOutsideTheGridAreEmpty) {
  Result<Volume> volume = Volume::Create(2, 2, 2, 0.3);
  ASSERT_TRUE(volume.ok());
  for (std::size_t v = 0; v < volume->size(); ++v) {
    volume->occupancy()[v] = 255;
  }
  EXPECT_TRUE(volume->Contains(1, 1, 1));
  EXPECT_FALSE(volume->Contains(-1, 0, 0));
  EXPECT_FALSE(volume->Contains(0, 2, 0));
  EXPECT_FALSE(volume->Contains(0, 0, 2));
  EXPECT_EQ(volume->At(-1, 0, 0), 0);
  EXPECT_EQ(volume->At(2, 0, 0), 0);
  EXPECT_EQ(volume->At(0, 0, 1000000), 0);
}

TEST(Volume, VoxelCentresAreAtHalfIntegerMultiplesOfTheVoxelSize) {
  Result<Volume> volume = Volume::Create(4, 4, 4, 0.3);
  ASSERT_TRUE(volume.ok());
  EXPECT_DOUBLE_EQ(volume->CentreMm(0), 0.15);
  EXPECT_DOUBLE_EQ(volume->CentreMm(3), 1.05);
}

TEST(Volume, MaterialIsOccupancyOverRho0TimesVoxelVolume) {
  Result<Volume> volume = Volume::Create(3, 3, 3, 0.5);
  ASSERT_TRUE(volume.ok());
  volume->Set(0, 0, 0, 255);  // one solid voxel: 0.125 mm^3
  volume->Set(2, 2, 2, 51);   // a fifth of one
  volume->Set(1, 2, 0, 204);  // four fifths of one
  EXPECT_DOUBLE_EQ(volume->MaterialMm3(), 2 * 0.125);
}

TEST(Volume, LabelsAndErosionFactorsAreKeptPerVoxelAndPerLabel) {
  Result<Volume> volume = Volume::Create(3, 3, 3, 0.3);
  ASSERT_TRUE(volume.ok());
  volume->SetLabel(1, 2, 0, 7);
  EXPECT_EQ(volume->Label(1, 2, 0), 7);
  EXPECT_EQ(volume->labels()[volume->Index(1, 2, 0)], 7);
  EXPECT_EQ(volume->Label(2, 1, 0), 0);
  volume->SetErosionFactor(7, 2.5);
  EXPECT_EQ(volume->ErosionFactor(7), 2.5);
  EXPECT_EQ(volume->ErosionFactor(6), 1.0);
}

// The descent rig's sample follows the burr down: every voxel moves up by the
// shift, the top layers are dropped, the bottom ones are fresh and unlabelled.
TEST(Volume, ShiftContentUpMovesEveryVoxelAndFillsTheBottom) {
  Volume v = Volume::Create(3, 2, 5, 0.5).value();
  for (int k = 0; k < 5; ++k) {
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 3; ++i) {
        v.Set(i, j, k, static_cast<std::uint8_t>(100 + 10 * k + 3 * j + i));
        v.SetLabel(i, j, k, static_cast<std::uint8_t>(k + 1));
      }
    }
  }
  v.ShiftContentUp(2, 255);
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 2; ++k) {
        EXPECT_EQ(v.At(i, j, k), 255);
        EXPECT_EQ(v.Label(i, j, k), 0);
      }
      for (int k = 2; k < 5; ++k) {
        EXPECT_EQ(v.At(i, j, k), 100 + 10 * (k - 2) + 3 * j + i);
        EXPECT_EQ(v.Label(i, j, k), k - 1);
      }
    }
  }
  // Out of range: nothing moves.
  const std::uint8_t before = v.At(1, 1, 4);
  v.ShiftContentUp(5, 0);
  v.ShiftContentUp(0, 0);
  EXPECT_EQ(v.At(1, 1, 4), before);
}

}  // namespace
}  // namespace burrlab::sim
