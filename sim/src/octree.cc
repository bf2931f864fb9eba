// Stub: being written.
#include "burrlab/sim/octree.h"
namespace burrlab::sim {
MomentOctree MomentOctree::Build(const Volume&) { return {}; }
void MomentOctree::OnVoxelDecrement(int, int, int, int) noexcept {}
}  // namespace burrlab::sim
