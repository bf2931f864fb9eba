// Stub: being written.
#include "burrlab/sim/phantoms.h"
namespace burrlab::sim {
Result<Volume> MakeHalfSpace(const PhantomGrid&, const glm::dvec3&, const glm::dvec3&) { return Error{"not yet"}; }
Result<Volume> MakeSlab(const PhantomGrid&, const glm::dvec3&, const glm::dvec3&, double) { return Error{"not yet"}; }
Result<Volume> MakeSphere(const PhantomGrid&, const glm::dvec3&, double) { return Error{"not yet"}; }
Result<Volume> MakeLayeredBlock(const PhantomGrid&, const LayeredBlockSpec&) { return Error{"not yet"}; }
}  // namespace burrlab::sim
