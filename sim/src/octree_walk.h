// Private: depth-first walk of the moment octree over the blocks near a sphere,
// with a fixed-size stack (no allocation; usable inside the 1 kHz tick). The
// visitor decides per block whether to accept it whole, skip it or refine it,
// and receives leaf voxels. All lengths here are in voxel units with voxel i
// spanning [i, i + 1).
#ifndef BURRLAB_SIM_SRC_OCTREE_WALK_H_
#define BURRLAB_SIM_SRC_OCTREE_WALK_H_

#include <algorithm>
#include <array>
#include <bit>
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
// visitor sees them; so are voxels, and, for a visitor that has the optional
// bool Ignores(std::uint8_t occupancy, double d2_vox2) const, the voxels for
// which it returns true (voxels whose OnVoxel would do nothing, dropped without
// a call or a branch of their own).
template <typename Visitor>
void WalkSphere(const MomentOctree& tree, const Volume& volume,
                const glm::dvec3& centre_vox, double outer_vox,
                Visitor& visitor) noexcept {
  // A block on the stack has mass and reaches into the sphere: both are
  // checked before it is pushed, so a block the walk would drop costs no push
  // and no pop (erosion changes only the blocks below the one being visited,
  // never a block waiting on the stack, so the checks hold until its turn).
  struct Item {
    int level, bx, by, bz;
    const MomentOctree::Node* node;
    double dmin2_vox2, dmax2_vox2;
  };
  constexpr int kStackSize = 256;
  constexpr int kMaxLevels = 32;
  std::array<Item, kStackSize> stack;
  int top = 0;
  const int levels = std::min(tree.levels(), kMaxLevels);
  const std::array<int, 3> n = {volume.nx(), volume.ny(), volume.nz()};
  // Start where a block spans the sphere's box, so at most 2 blocks per axis
  // are needed.
  int start = 1;
  while (start < levels && (1 << start) < 2.0 * outer_vox + 1.0) ++start;
  // The blocks and extents of the levels the walk visits (start and below),
  // looked up once per walk; the entries above start are never read.
  std::array<const MomentOctree::Node*, kMaxLevels + 1> level_nodes;
  std::array<std::array<int, 3>, kMaxLevels + 1> level_blocks;
  for (int l = 1; l <= start; ++l) {
    level_nodes[static_cast<std::size_t>(l)] = tree.LevelNodes(l);
    level_blocks[static_cast<std::size_t>(l)] = {
        tree.BlocksX(l), tree.BlocksY(l), tree.BlocksZ(l)};
  }
  const double outer2_vox2 = outer_vox * outer_vox;
  // Squared distances from the centre to the nearest and the farthest voxel
  // centre of block b (level l) along axis a.
  struct AxisSpan {
    double near2, far2;
  };
  const auto span = [&](int a, int b, int size) {
    const double lo = b * size + 0.5;
    const double hi = std::min((b + 1) * size, n[a]) - 0.5;
    const double c = centre_vox[a];
    const double near = c < lo ? lo - c : (c > hi ? c - hi : 0.0);
    const double far = std::max(std::abs(c - lo), std::abs(c - hi));
    return AxisSpan{near * near, far * far};
  };
  // Pushes block (level, x, y, z) with its axis spans if it has mass and
  // reaches into the sphere.
  const auto push = [&](int level, int x, int y, int z, const AxisSpan& sx,
                        const AxisSpan& sy, const AxisSpan& sz) {
    const double dmin2 = sx.near2 + sy.near2 + sz.near2;
    if (dmin2 >= outer2_vox2) return;
    const auto& d = level_blocks[level];
    const MomentOctree::Node* node =
        level_nodes[level] +
        ((static_cast<std::size_t>(z) * static_cast<std::size_t>(d[1]) +
          static_cast<std::size_t>(y)) *
             static_cast<std::size_t>(d[0]) +
         static_cast<std::size_t>(x));
    if (node->m0 == 0) return;
    if (top < kStackSize) {
      stack[top++] = {level, x, y, z, node, dmin2, sx.far2 + sy.far2 + sz.far2};
    }
  };
  std::array<int, 3> lo_b{}, hi_b{};
  const std::array<int, 3>& nb = level_blocks[start];
  for (int a = 0; a < 3; ++a) {
    const double lo = std::floor(centre_vox[a] - outer_vox);
    const double hi = std::floor(centre_vox[a] + outer_vox);
    if (hi < 0.0 || lo >= n[a]) return;
    lo_b[a] = std::max(0, static_cast<int>(lo) >> start);
    hi_b[a] = std::min(nb[a] - 1,
                       static_cast<int>(std::min(hi, n[a] - 1.0)) >> start);
  }
  const int start_size = 1 << start;
  for (int bz = lo_b[2]; bz <= hi_b[2]; ++bz) {
    const AxisSpan sz = span(2, bz, start_size);
    for (int by = lo_b[1]; by <= hi_b[1]; ++by) {
      const AxisSpan sy = span(1, by, start_size);
      for (int bx = lo_b[0]; bx <= hi_b[0]; ++bx)
        push(start, bx, by, bz, span(0, bx, start_size), sy, sz);
    }
  }

  const std::uint8_t* occupancy = volume.occupancy();
  const std::size_t stride_y = static_cast<std::size_t>(n[0]);
  const std::size_t stride_z = stride_y * static_cast<std::size_t>(n[1]);
  // The voxels of a level-1 block the visitor refines, first voxel (x0, y0,
  // z0).
  const auto visit_voxels = [&](int x0, int y0, int z0) {
    // The block's 8 voxels, x fastest.
    const std::array<double, 2> ox = {x0 + 0.5 - centre_vox.x,
                                      (x0 + 1) + 0.5 - centre_vox.x};
    const std::array<double, 2> oy = {y0 + 0.5 - centre_vox.y,
                                      (y0 + 1) + 0.5 - centre_vox.y};
    const std::array<double, 2> oz = {z0 + 0.5 - centre_vox.z,
                                      (z0 + 1) + 0.5 - centre_vox.z};
    const std::array<double, 2> ox2 = {ox[0] * ox[0], ox[1] * ox[1]};
    const std::array<double, 2> oy2 = {oy[0] * oy[0], oy[1] * oy[1]};
    const std::array<double, 2> oz2 = {oz[0] * oz[0], oz[1] * oz[1]};
    const std::uint8_t* base = occupancy + volume.Index(x0, y0, z0);
    const std::array<bool, 2> in_x = {true, x0 + 1 < n[0]};
    const std::array<bool, 2> in_y = {true, y0 + 1 < n[1]};
    const std::array<bool, 2> in_z = {true, z0 + 1 < n[2]};
    // Which voxels hold mass with their centre inside the sphere, found
    // without a branch per voxel (their pattern is as good as random to the
    // branch predictor), then visited in order.
    std::array<std::uint8_t, 8> o{};
    std::array<double, 8> d2{};
    unsigned visit = 0;
    for (std::size_t s = 0; s < 8; ++s) {
      const std::size_t dx = s & 1, dy = (s >> 1) & 1, dz = (s >> 2) & 1;
      const bool inside = in_x[dx] & in_y[dy] & in_z[dz];
      o[s] =
          inside ? base[dx + dy * stride_y + dz * stride_z] : std::uint8_t{0};
      d2[s] = ox2[dx] + oy2[dy] + oz2[dz];
      bool wanted = (o[s] != 0) & (d2[s] < outer2_vox2);
      if constexpr (requires { visitor.Ignores(o[s], d2[s]); }) {
        wanted &= !visitor.Ignores(o[s], d2[s]);
      }
      visit |= static_cast<unsigned>(wanted) << s;
    }
    while (visit != 0) {
      const auto s = static_cast<std::size_t>(std::countr_zero(visit));
      visit &= visit - 1;
      const std::size_t dx = s & 1, dy = (s >> 1) & 1, dz = (s >> 2) & 1;
      visitor.OnVoxel(x0 + static_cast<int>(dx), y0 + static_cast<int>(dy),
                      z0 + static_cast<int>(dz), o[s],
                      glm::dvec3(ox[dx], oy[dy], oz[dz]), d2[s]);
    }
  };
  // The children of the block whose first child is (x0, y0, z0) at
  // child_level: which exist (x0 always does, x0 + 1 only inside the level;
  // likewise y, z), their axis spans and the first child's node.
  struct Children {
    int cx, cy, cz;
    std::array<AxisSpan, 2> sx, sy, sz;
    std::size_t node_y, node_z;
    const MomentOctree::Node* first;
    double Dmin2(int dx, int dy, int dz) const {
      return sx[dx].near2 + sy[dy].near2 + sz[dz].near2;
    }
    double Dmax2(int dx, int dy, int dz) const {
      return sx[dx].far2 + sy[dy].far2 + sz[dz].far2;
    }
    const MomentOctree::Node* Node(int dx, int dy, int dz) const {
      return first + (static_cast<std::size_t>(dx) +
                      static_cast<std::size_t>(dy) * node_y +
                      static_cast<std::size_t>(dz) * node_z);
    }
  };
  const auto children = [&](int child_level, int x0, int y0, int z0) {
    const int child_size = 1 << child_level;
    const std::array<int, 3>& cb = level_blocks[child_level];
    Children c;
    c.cx = x0 + 1 < cb[0] ? 2 : 1;
    c.cy = y0 + 1 < cb[1] ? 2 : 1;
    c.cz = z0 + 1 < cb[2] ? 2 : 1;
    for (int i = 0; i < c.cx; ++i) c.sx[i] = span(0, x0 + i, child_size);
    for (int i = 0; i < c.cy; ++i) c.sy[i] = span(1, y0 + i, child_size);
    for (int i = 0; i < c.cz; ++i) c.sz[i] = span(2, z0 + i, child_size);
    c.node_y = static_cast<std::size_t>(cb[0]);
    c.node_z = c.node_y * static_cast<std::size_t>(cb[1]);
    c.first = level_nodes[child_level] +
              ((static_cast<std::size_t>(z0) * static_cast<std::size_t>(cb[1]) +
                static_cast<std::size_t>(y0)) *
                   c.node_y +
               static_cast<std::size_t>(x0));
    return c;
  };
  // Children at levels 1 and 2 are visited as soon as their parent is
  // refined, from the last octant to the first, just as they would be popped
  // had they been pushed in octant order: nothing is pushed while they are
  // visited, and erosion changes only the block being visited and its
  // ancestors, never a sibling's mass, so each child meets the same tests
  // with the same values. (The stack, at most 7 blocks per level below the
  // start and 8 at the start, never fills, so none would have been
  // dropped.)
  const auto visit_inline = [&](int child_level, int x0, int y0, int z0,
                                const auto& refine) {
    const Children c = children(child_level, x0, y0, z0);
    for (int dz = c.cz - 1; dz >= 0; --dz) {
      for (int dy = c.cy - 1; dy >= 0; --dy) {
        for (int dx = c.cx - 1; dx >= 0; --dx) {
          const double dmin2 = c.Dmin2(dx, dy, dz);
          if (dmin2 >= outer2_vox2) continue;
          const MomentOctree::Node* node = c.Node(dx, dy, dz);
          if (node->m0 == 0) continue;
          const BlockView child{
              child_level,        x0 + dx, y0 + dy, z0 + dz, node, dmin2,
              c.Dmax2(dx, dy, dz)};
          if (visitor.OnBlock(child) == BlockAction::kRefine) {
            refine(2 * (x0 + dx), 2 * (y0 + dy), 2 * (z0 + dz));
          }
        }
      }
    }
  };
  // The level-1 children of a level-2 block, first child (x0, y0, z0).
  const auto visit_level1 = [&](int x0, int y0, int z0) {
    visit_inline(1, x0, y0, z0, visit_voxels);
  };
  while (top > 0) {
    const Item item = stack[--top];
    const BlockView view{item.level, item.bx,         item.by,        item.bz,
                         item.node,  item.dmin2_vox2, item.dmax2_vox2};
    const BlockAction action = visitor.OnBlock(view);
    if (action != BlockAction::kRefine) continue;
    const int x0 = 2 * item.bx, y0 = 2 * item.by, z0 = 2 * item.bz;
    if (item.level == 1) {
      visit_voxels(x0, y0, z0);
      continue;
    }
    const int child_level = item.level - 1;
    if (child_level == 1) {
      visit_level1(x0, y0, z0);
      continue;
    }
    if (child_level == 2) {
      visit_inline(2, x0, y0, z0, visit_level1);
      continue;
    }
    // Higher children are pushed in octant order (x fastest, then y, then z)
    // so that they are visited from the last octant to the first.
    const Children c = children(child_level, x0, y0, z0);
    for (int dz = 0; dz < c.cz; ++dz) {
      for (int dy = 0; dy < c.cy; ++dy) {
        for (int dx = 0; dx < c.cx; ++dx) {
          const double dmin2 = c.Dmin2(dx, dy, dz);
          if (dmin2 >= outer2_vox2) continue;
          const MomentOctree::Node* node = c.Node(dx, dy, dz);
          if (node->m0 == 0) continue;
          if (top < kStackSize) {
            stack[top++] = {
                child_level,        x0 + dx, y0 + dy, z0 + dz, node, dmin2,
                c.Dmax2(dx, dy, dz)};
          }
        }
      }
    }
  }
}

}  // namespace burrlab::sim::internal

#endif  // BURRLAB_SIM_SRC_OCTREE_WALK_H_
