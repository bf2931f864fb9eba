// Stub: being written.
#include "burrlab/sim/model.h"
namespace burrlab::sim {
Status Material::Validate() const { return {}; }
Status Model::Validate() const { return {}; }
}  // namespace burrlab::sim
