// Height map of the material block and the loop-to-window triple buffer.
#include "station/surface_snapshot.h"

#include <algorithm>
#include <cmath>

namespace burrlab::runner {

HeightMap HeightMap::For(const sim::Volume& volume) {
  HeightMap map;
  map.nx = volume.nx();
  map.ny = volume.ny();
  map.cell_mm = volume.voxel_mm();
  map.top_mm = volume.nz() * volume.voxel_mm();
  map.height_mm.assign(static_cast<std::size_t>(map.nx) * map.ny, 0.0f);
  return map;
}

void UpdateHeightMap(const sim::Volume& volume, const glm::dvec3& centre_mm,
                     double radius_mm, HeightMap* map) noexcept {
  const double v = volume.voxel_mm();
  int i0 = 0, i1 = volume.nx() - 1, j0 = 0, j1 = volume.ny() - 1;
  if (radius_mm >= 0.0) {
    i0 = std::max(i0,
                  static_cast<int>(std::floor((centre_mm.x - radius_mm) / v)));
    i1 = std::min(i1,
                  static_cast<int>(std::floor((centre_mm.x + radius_mm) / v)));
    j0 = std::max(j0,
                  static_cast<int>(std::floor((centre_mm.y - radius_mm) / v)));
    j1 = std::min(j1,
                  static_cast<int>(std::floor((centre_mm.y + radius_mm) / v)));
  }
  const std::uint8_t* occupancy = volume.occupancy();
  const std::size_t layer = static_cast<std::size_t>(volume.nx()) * volume.ny();
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const std::size_t column = volume.Index(i, j, 0);
      std::uint32_t sum = 0;
      for (int k = 0; k < volume.nz(); ++k) {
        sum += occupancy[column + static_cast<std::size_t>(k) * layer];
      }
      map->height_mm[static_cast<std::size_t>(j) * map->nx + i] =
          static_cast<float>(sum / 255.0 * v);
    }
  }
}

SnapshotExchange::SnapshotExchange(const SurfaceSnapshot& shape) {
  for (SurfaceSnapshot& slot : slots_) slot = shape;
}

void SnapshotExchange::Publish() noexcept {
  const std::uint8_t old = middle_.exchange(
      static_cast<std::uint8_t>(write_ | kFresh), std::memory_order_acq_rel);
  write_ = old & 3;
}

void SnapshotExchange::Publish(const SurfaceSnapshot& snapshot) noexcept {
  SurfaceSnapshot& slot = slots_[write_];
  std::copy(snapshot.surface.height_mm.begin(),
            snapshot.surface.height_mm.end(), slot.surface.height_mm.begin());
  slot.burr_mm = snapshot.burr_mm;
  slot.burr_radius_mm = snapshot.burr_radius_mm;
  slot.force_n = snapshot.force_n;
  slot.tick = snapshot.tick;
  Publish();
}

const SurfaceSnapshot* SnapshotExchange::TakeNewest() noexcept {
  if ((middle_.load(std::memory_order_acquire) & kFresh) == 0) return nullptr;
  const std::uint8_t old = middle_.exchange(static_cast<std::uint8_t>(read_),
                                            std::memory_order_acq_rel);
  read_ = old & 3;
  return &slots_[read_];
}

}  // namespace burrlab::runner
