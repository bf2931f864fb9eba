// Stub: being written.
#include "burrlab/sim/nrrd.h"
namespace burrlab::sim {
Result<Volume> ParseNrrd(std::string_view, std::string_view, const IntensityMapping&) { return Error{"not yet"}; }
Result<Volume> LoadNrrd(const std::string&, const IntensityMapping&) { return Error{"not yet"}; }
}  // namespace burrlab::sim
