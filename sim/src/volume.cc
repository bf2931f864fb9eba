// Voxel volume storage.
#include "burrlab/sim/volume.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace burrlab::sim {

Result<Volume> Volume::Create(int nx, int ny, int nz, double voxel_mm) {
  if (nx <= 0 || ny <= 0 || nz <= 0) {
    return Error{fmt::format("volume extents must be positive, got {}x{}x{}",
                             nx, ny, nz)};
  }
  if (nx > kMaxVolumeExtent || ny > kMaxVolumeExtent || nz > kMaxVolumeExtent) {
    return Error{fmt::format(
        "volume extent above the limit of {} voxels per axis: {}x{}x{}",
        kMaxVolumeExtent, nx, ny, nz)};
  }
  const std::size_t count = static_cast<std::size_t>(nx) *
                            static_cast<std::size_t>(ny) *
                            static_cast<std::size_t>(nz);
  if (count > kMaxVolumeVoxels) {
    return Error{fmt::format("volume of {} voxels is above the limit of {}",
                             count, kMaxVolumeVoxels)};
  }
  if (!std::isfinite(voxel_mm) || voxel_mm <= 0.0) {
    return Error{fmt::format(
        "voxel size must be a positive finite number of mm, got {}", voxel_mm)};
  }
  Volume v;
  v.nx_ = nx;
  v.ny_ = ny;
  v.nz_ = nz;
  v.voxel_mm_ = voxel_mm;
  v.occupancy_.assign(count, 0);
  v.labels_.assign(count, 0);
  v.erosion_factor_.fill(1.0);
  return v;
}

void Volume::ShiftContentUp(int layers, std::uint8_t occupancy) {
  if (layers <= 0 || layers >= nz_) return;
  const std::size_t layer = static_cast<std::size_t>(nx_) * ny_;
  const std::size_t moved = layer * static_cast<std::size_t>(nz_ - layers);
  const std::size_t freed = layer * static_cast<std::size_t>(layers);
  std::move_backward(occupancy_.begin(), occupancy_.begin() + moved,
                     occupancy_.end());
  std::move_backward(labels_.begin(), labels_.begin() + moved, labels_.end());
  std::fill(occupancy_.begin(), occupancy_.begin() + freed, occupancy);
  std::fill(labels_.begin(), labels_.begin() + freed, std::uint8_t{0});
}

double Volume::MaterialMm3() const {
  std::uint64_t sum = 0;
  for (std::uint8_t o : occupancy_) sum += o;
  return static_cast<double>(sum) / kSolidOccupancy * voxel_mm_ * voxel_mm_ *
         voxel_mm_;
}

}  // namespace burrlab::sim
