// Stub: being written.
#include "burrlab/sim/force_curve.h"
namespace burrlab::sim {
Status ForceCurveOptions::Validate() const { return {}; }
Result<std::vector<ForceCurvePoint>> ComputeForceCurve(const ForceCurveOptions&) { return Error{"force curve: not yet implemented"}; }
}  // namespace burrlab::sim
