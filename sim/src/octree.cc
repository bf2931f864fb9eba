// Octree of bone mass moments, built bottom up with the centre-of-mass rule
// (eq. 7.9) and kept current under erosion leaf to root.
#include "burrlab/sim/octree.h"

namespace burrlab::sim {
namespace {

int HalfUp(int n) { return (n + 1) / 2; }

}  // namespace

MomentOctree MomentOctree::Build(const Volume& volume) {
  MomentOctree tree;
  std::array<int, 3> dims = {volume.nx(), volume.ny(), volume.nz()};
  // Level 1 from the voxels: offsets of voxel centres from the 2x2x2 block
  // centre are
  // +-1 half-voxel.
  int level = 1;
  do {
    const std::array<int, 3> child = dims;
    dims = {HalfUp(child[0]), HalfUp(child[1]), HalfUp(child[2])};
    std::vector<Node> nodes(static_cast<std::size_t>(dims[0]) * dims[1] *
                            dims[2]);
    // Offset of a child centre from its parent centre, in half-voxels:
    // +-2^(level-1).
    const std::int64_t half = std::int64_t{1} << (level - 1);
    for (int bz = 0; bz < dims[2]; ++bz) {
      for (int by = 0; by < dims[1]; ++by) {
        for (int bx = 0; bx < dims[0]; ++bx) {
          Node& node =
              nodes[(static_cast<std::size_t>(bz) * dims[1] + by) * dims[0] +
                    bx];
          for (int s = 0; s < 8; ++s) {
            const int cx = 2 * bx + (s & 1), cy = 2 * by + ((s >> 1) & 1),
                      cz = 2 * bz + ((s >> 2) & 1);
            if (cx >= child[0] || cy >= child[1] || cz >= child[2]) continue;
            std::int64_t m0 = 0;
            std::array<std::int64_t, 3> m1{};
            if (level == 1) {
              m0 = volume.At(cx, cy, cz);
            } else {
              const Node& c = tree.At(level - 1, cx, cy, cz);
              m0 = c.m0;
              m1 = c.m1;
            }
            const std::array<std::int64_t, 3> offset = {
                ((s & 1) ? half : -half), (((s >> 1) & 1) ? half : -half),
                (((s >> 2) & 1) ? half : -half)};
            node.m0 += m0;
            for (int a = 0; a < 3; ++a)
              node.m1[a] += m1[a] + offset[a] * m0;  // eq. 7.9
          }
        }
      }
    }
    tree.dims_.push_back(dims);
    tree.nodes_.push_back(std::move(nodes));
    ++level;
  } while (dims[0] > 1 || dims[1] > 1 || dims[2] > 1);
  return tree;
}

void MomentOctree::OnVoxelDecrement(int i, int j, int k, int amount) noexcept {
  const std::array<int, 3> v = {i, j, k};
  for (int level = 1; level <= levels(); ++level) {
    const auto& d = dims_[level - 1];
    const int bx = i >> level, by = j >> level, bz = k >> level;
    Node& node = nodes_[level - 1]
                       [(static_cast<std::size_t>(bz) * d[1] + by) * d[0] + bx];
    node.m0 -= amount;
    for (int a = 0; a < 3; ++a) {
      // Voxel centre minus block centre, in half-voxels.
      const std::int64_t offset =
          (2 * std::int64_t{v[a]} + 1) -
          ((2 * std::int64_t{v[a] >> level} + 1) << level);
      node.m1[a] -= offset * amount;
    }
  }
}

}  // namespace burrlab::sim
