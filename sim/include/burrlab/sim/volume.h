// Voxel volume of bone occupancy: 8-bit density per voxel (255 = solid
// reference density rho0), a cubic voxel size in mm, and an 8-bit material
// label per voxel whose erosion factor scales alpha (cortical vs trabecular
// bone, dissertation §6.4.2).
//
// Coordinates: voxel (i, j, k) has its centre at ((i + 0.5) v, (j + 0.5) v, (k
// + 0.5) v) mm with v the voxel size; the volume spans [0, n v] on each axis; z
// points "up".
#ifndef BURRLAB_SIM_VOLUME_H_
#define BURRLAB_SIM_VOLUME_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::sim {

// Occupancy value of solid material at the reference density rho0.
inline constexpr int kSolidOccupancy = 255;
// Largest extent accepted on any axis, and largest voxel count (bounds
// allocation).
inline constexpr int kMaxVolumeExtent = 2048;
inline constexpr std::size_t kMaxVolumeVoxels = std::size_t{1} << 30;

class Volume {
 public:
  // An empty (all-zero) volume; fails on non-positive or oversized extents or a
  // voxel size that is not finite and positive.
  static Result<Volume> Create(int nx, int ny, int nz, double voxel_mm);

  Volume() = default;

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int nz() const { return nz_; }
  double voxel_mm() const { return voxel_mm_; }
  std::size_t size() const { return occupancy_.size(); }

  bool Contains(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < nx_ && j < ny_ && k < nz_;
  }
  std::size_t Index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(ny_) +
            static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(nx_) +
           static_cast<std::size_t>(i);
  }
  // Occupancy 0..255 of voxel (i, j, k); 0 outside the volume.
  std::uint8_t At(int i, int j, int k) const {
    return Contains(i, j, k) ? occupancy_[Index(i, j, k)] : std::uint8_t{0};
  }
  void Set(int i, int j, int k, std::uint8_t occupancy) {
    occupancy_[Index(i, j, k)] = occupancy;
  }
  std::uint8_t* occupancy() { return occupancy_.data(); }
  const std::uint8_t* occupancy() const { return occupancy_.data(); }

  // Material label of a voxel (0 by default) and the erosion factor of each
  // label (multiplies alpha in eq. 7.12; 1 by default).
  std::uint8_t Label(int i, int j, int k) const {
    return labels_[Index(i, j, k)];
  }
  void SetLabel(int i, int j, int k, std::uint8_t label) {
    labels_[Index(i, j, k)] = label;
  }
  const std::uint8_t* labels() const { return labels_.data(); }
  double ErosionFactor(std::uint8_t label) const {
    return erosion_factor_[label];
  }
  void SetErosionFactor(std::uint8_t label, double factor) {
    erosion_factor_[label] = factor;
  }

  // Moves every voxel `layers` layers up (k -> k + layers), drops the top
  // `layers` layers and fills the bottom ones with `occupancy`, label 0: a
  // sample that follows a burr down indefinitely (the descent rig). 0 <=
  // layers < nz.
  void ShiftContentUp(int layers, std::uint8_t occupancy);

  // Centre of voxel index along one axis, in mm.
  double CentreMm(int index) const { return (index + 0.5) * voxel_mm_; }
  // Total solid-equivalent material in mm^3 (sum of occupancy / 255 times voxel
  // volume).
  double MaterialMm3() const;

 private:
  int nx_ = 0, ny_ = 0, nz_ = 0;
  double voxel_mm_ = 0.3;
  std::vector<std::uint8_t> occupancy_;
  std::vector<std::uint8_t> labels_;
  std::array<double, 256> erosion_factor_{};
};

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_VOLUME_H_
