// Octree of bone mass moments (eq. 7.9). Level 0 is the voxel grid itself; a
// block at level l covers 2^l voxels per axis and stores the exact integer sums
//   m0 = sum of occupancy, m1 = sum of occupancy * (voxel centre - block
//   centre),
// with offsets in half-voxel units, so block moments equal brute-force sums
// exactly. Erosion keeps them current leaf to root (OnVoxelDecrement,
// O(levels), no allocation).
#ifndef BURRLAB_SIM_OCTREE_H_
#define BURRLAB_SIM_OCTREE_H_

#include <array>
#include <cstdint>
#include <vector>

#include "burrlab/sim/volume.h"

namespace burrlab::sim {

class MomentOctree {
 public:
  // Block moments in integer units: m0 in occupancy units, m1 in occupancy x
  // half-voxels.
  struct Node {
    std::int64_t m0 = 0;
    std::array<std::int64_t, 3> m1{};
  };

  MomentOctree() = default;
  // Builds every level from the volume, bottom up with the centre-of-mass rule
  // (7.9).
  static MomentOctree Build(const Volume& volume);

  // Number of levels above the voxels; the top level has a single block.
  int levels() const { return static_cast<int>(nodes_.size()); }
  // Blocks per axis at level l >= 1.
  int BlocksX(int level) const { return dims_[level - 1][0]; }
  int BlocksY(int level) const { return dims_[level - 1][1]; }
  int BlocksZ(int level) const { return dims_[level - 1][2]; }
  // Block (bx, by, bz) of level l >= 1; the indices must be inside the level.
  const Node& At(int level, int bx, int by, int bz) const {
    const auto& d = dims_[level - 1];
    return nodes_[level - 1]
                 [(static_cast<std::size_t>(bz) * d[1] + by) * d[0] + bx];
  }
  // The blocks of level l >= 1, x fastest then y then z (At's order).
  const Node* LevelNodes(int level) const { return nodes_[level - 1].data(); }
  // Updates every ancestor of voxel (i, j, k) after its occupancy dropped by
  // `amount`.
  void OnVoxelDecrement(int i, int j, int k, int amount) noexcept;

 private:
  std::vector<std::array<int, 3>> dims_;
  std::vector<std::vector<Node>> nodes_;
};

}  // namespace burrlab::sim

#endif  // BURRLAB_SIM_OCTREE_H_
