// Private: depth-first walk of the moment octree over the blocks near a sphere,
// with a fixed-size stack (no allocation; usable inside the 1 kHz tick). The
// visitor decides per block whether to accept it whole, skip it or refine it,
// and receives leaf voxels. All lengths here are in voxel units with voxel i
// spanning [i, i + 1).
#ifndef BURRLAB_SIM_SRC_OCTREE_WALK_H_
#define BURRLAB_SIM_SRC_OCTREE_WALK_H_

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>

#include "burrlab/sim/octree.h"
#include "burrlab/sim/volume.h"

namespace burrlab::sim::internal {

enum class BlockAction { kSkip, kAccept, kRefine };

// A block at level >= 1, with the squared distances from the sphere centre to
// the nearest and the farthest voxel centre it contains (voxels beyond the
// volume's edge excluded); a visitor takes the square root of the one it
// needs (DminVox, DmaxVox), so the walk pays for no other.
struct BlockView {
  int level;
  int bx, by, bz;
  const MomentOctree::Node* node;
  double dmin2_vox2;
  double dmax2_vox2;
  double DminVox() const { return std::sqrt(dmin2_vox2); }
  double DmaxVox() const { return std::sqrt(dmax2_vox2); }
};

// Visitor: BlockAction OnBlock(const BlockView&); void OnVoxel(int i, int j,
// int k, std::uint8_t occupancy, const glm::dvec3& offset_vox, double
// d2_vox2), with d2_vox2 the squared distance of the voxel centre (a visitor
// takes the square root only where it needs the distance itself).
// Blocks with zero mass or with dmin >= outer_vox are skipped before the
// visitor sees them; so are voxels.
template <typename Visitor>
void WalkSphere(const MomentOctree& tree, const Volume& volume,
                const glm::dvec3& centre_vox, double outer_vox,
                Visitor& visitor) noexcept {
  struct Item {
    int level, bx, by, bz;
  };
  constexpr int kStackSize = 256;
  std::array<Item, kStackSize> stack;
  int top = 0;
  const int levels = tree.levels();
  const std::array<int, 3> n = {volume.nx(), volume.ny(), volume.nz()};
  // Start where a block spans the sphere's box, so at most 2 blocks per axis
  // are needed.
  const double outer2_vox2 = outer_vox * outer_vox;
  int start = 1;
  while (start < levels && (1 << start) < 2.0 * outer_vox + 1.0) ++start;
  std::array<int, 3> lo_b{}, hi_b{};
  const std::array<int, 3> nb = {tree.BlocksX(start), tree.BlocksY(start),
                                 tree.BlocksZ(start)};
  for (int a = 0; a < 3; ++a) {
    const double lo = std::floor(centre_vox[a] - outer_vox);
    const double hi = std::floor(centre_vox[a] + outer_vox);
    if (hi < 0.0 || lo >= n[a]) return;
    lo_b[a] = std::max(0, static_cast<int>(lo) >> start);
    hi_b[a] = std::min(nb[a] - 1,
                       static_cast<int>(std::min(hi, n[a] - 1.0)) >> start);
  }
  for (int bz = lo_b[2]; bz <= hi_b[2]; ++bz)
    for (int by = lo_b[1]; by <= hi_b[1]; ++by)
      for (int bx = lo_b[0]; bx <= hi_b[0]; ++bx)
        stack[top++] = {start, bx, by, bz};

  while (top > 0) {
    const Item item = stack[--top];
    if (item.level == 0)
      continue;  // not used: voxels are visited directly below
    const MomentOctree::Node& node =
        tree.At(item.level, item.bx, item.by, item.bz);
    if (node.m0 == 0) continue;
    const int size = 1 << item.level;
    const std::array<int, 3> b = {item.bx, item.by, item.bz};
    double dmin2 = 0.0, dmax2 = 0.0;
    for (int a = 0; a < 3; ++a) {
      const double lo = b[a] * size + 0.5;
      const double hi = std::min((b[a] + 1) * size, n[a]) - 0.5;
      const double c = centre_vox[a];
      const double near = c < lo ? lo - c : (c > hi ? c - hi : 0.0);
      const double far = std::max(std::abs(c - lo), std::abs(c - hi));
      dmin2 += near * near;
      dmax2 += far * far;
    }
    if (dmin2 >= outer2_vox2) continue;
    const BlockView view{item.level, item.bx, item.by, item.bz,
                         &node,      dmin2,   dmax2};
    const BlockAction action = visitor.OnBlock(view);
    if (action != BlockAction::kRefine) continue;
    if (item.level == 1) {
      for (int s = 0; s < 8; ++s) {
        const int i = 2 * item.bx + (s & 1), j = 2 * item.by + ((s >> 1) & 1),
                  k = 2 * item.bz + ((s >> 2) & 1);
        if (i >= n[0] || j >= n[1] || k >= n[2]) continue;
        const std::uint8_t occupancy =
            volume.occupancy()[volume.Index(i, j, k)];
        if (occupancy == 0) continue;
        const glm::dvec3 offset(i + 0.5 - centre_vox.x, j + 0.5 - centre_vox.y,
                                k + 0.5 - centre_vox.z);
        const double d2 =
            offset.x * offset.x + offset.y * offset.y + offset.z * offset.z;
        if (d2 >= outer2_vox2) continue;
        visitor.OnVoxel(i, j, k, occupancy, offset, d2);
      }
      continue;
    }
    const int child_level = item.level - 1;
    const int cbx = tree.BlocksX(child_level), cby = tree.BlocksY(child_level),
              cbz = tree.BlocksZ(child_level);
    for (int s = 0; s < 8; ++s) {
      const int x = 2 * item.bx + (s & 1), y = 2 * item.by + ((s >> 1) & 1),
                z = 2 * item.bz + ((s >> 2) & 1);
      if (x >= cbx || y >= cby || z >= cbz) continue;
      if (top < kStackSize) stack[top++] = {child_level, x, y, z};
    }
  }
}

}  // namespace burrlab::sim::internal

#endif  // BURRLAB_SIM_SRC_OCTREE_WALK_H_
