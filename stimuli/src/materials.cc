// Stub: being written.
#include "burrlab/stimuli/materials.h"
namespace burrlab::stimuli {
Result<MaterialSet> ParseMaterial(std::string_view, std::string_view) { return Error{"not yet"}; }
Result<MaterialSet> LoadMaterialFile(const std::string&) { return Error{"not yet"}; }
Result<MaterialSet> LoadBuiltinMaterial(std::string_view) { return Error{"not yet"}; }
std::vector<std::string> BuiltinMaterialNames() { return {}; }
}  // namespace burrlab::stimuli
