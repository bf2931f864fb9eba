// Stub: being written.
#include "burrlab/sim/descent.h"
namespace burrlab::sim {
Status DescentOptions::Validate() const { return {}; }
Result<DescentResult> RunDescent(const DescentOptions&) { return Error{"descent: not yet implemented"}; }
}  // namespace burrlab::sim
