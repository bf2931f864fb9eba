// The height map of the block and the loop-to-window triple buffer.
#include "station/surface_snapshot.h"

#include <gtest/gtest.h>

#include "burrlab/sim/phantoms.h"

namespace burrlab::runner {
namespace {

TEST(HeightMap, ColumnsHoldTheirSolidThickness) {
  sim::Volume v = sim::Volume::Create(4, 3, 10, 0.5).value();
  for (int k = 0; k < 6; ++k) v.Set(1, 2, k, 255);
  v.Set(2, 0, 0, 51);  // a fifth of a voxel
  HeightMap map = HeightMap::For(v);
  UpdateHeightMap(v, {}, -1.0, &map);
  EXPECT_FLOAT_EQ(map.At(1, 2), 3.0f);
  EXPECT_FLOAT_EQ(map.At(2, 0), 0.1f);
  EXPECT_FLOAT_EQ(map.At(0, 0), 0.0f);
  EXPECT_DOUBLE_EQ(map.top_mm, 5.0);
}

TEST(HeightMap, UpdatesOnlyTheColumnsAroundTheBurr) {
  sim::Volume v = sim::Volume::Create(20, 20, 4, 1.0).value();
  HeightMap map = HeightMap::For(v);
  for (int j = 0; j < 20; ++j) {
    for (int i = 0; i < 20; ++i) v.Set(i, j, 0, 255);
  }
  UpdateHeightMap(v, {10.0, 10.0, 0.0}, 2.0, &map);
  EXPECT_FLOAT_EQ(map.At(10, 10), 1.0f);
  EXPECT_FLOAT_EQ(map.At(8, 8), 1.0f);
  EXPECT_FLOAT_EQ(map.At(0, 0), 0.0f);  // outside the footprint: untouched
}

TEST(SnapshotExchange, TheConsumerGetsTheNewestSnapshotOnce) {
  SurfaceSnapshot shape;
  shape.surface.nx = 2;
  shape.surface.ny = 1;
  shape.surface.height_mm = {0.0f, 0.0f};
  SnapshotExchange x(shape);
  EXPECT_EQ(x.TakeNewest(), nullptr);
  SurfaceSnapshot s = shape;
  for (int t = 1; t <= 3; ++t) {
    s.tick = t;
    s.surface.height_mm[1] = static_cast<float>(t);
    x.Publish(s);
  }
  const SurfaceSnapshot* got = x.TakeNewest();
  ASSERT_NE(got, nullptr);
  EXPECT_EQ(got->tick, 3);
  EXPECT_FLOAT_EQ(got->surface.height_mm[1], 3.0f);
  EXPECT_EQ(x.TakeNewest(), nullptr);
  s.tick = 4;
  x.Publish(s);
  ASSERT_NE(x.TakeNewest(), nullptr);
}

}  // namespace
}  // namespace burrlab::runner
