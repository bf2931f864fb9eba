// Material sets: named simulator parameter sets (sim::Material) read from TOML
// files, with the source of every number. Built-in sets live in
// stimuli/materials/*.toml and are embedded into the library at build time, so
// the binary needs no data folder.
#ifndef BURRLAB_STIMULI_MATERIALS_H_
#define BURRLAB_STIMULI_MATERIALS_H_

#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/sim/model.h"

namespace burrlab::stimuli {

struct MaterialSet {
  std::string name;          // identifier, e.g. "human_temporal_bone"
  std::string display_name;  // for people, e.g. "Human temporal bone"
  std::string description;   // optional longer text, empty when absent
  std::string source;        // where the numbers come from
  sim::Material material;    // the parameters swapped into the simulator
};

// Parses a material file held in memory; `path` is used in error messages only.
// Errors read "path:line:col: error: ..." and name the key and the rule broken.
Result<MaterialSet> ParseMaterial(std::string_view path, std::string_view text);
// Reads and parses a material file from disk.
Result<MaterialSet> LoadMaterialFile(const std::string& path);
// A built-in material by name; an unknown name gets the list of known ones and
// a "did you mean" suggestion.
Result<MaterialSet> LoadBuiltinMaterial(std::string_view name);
// Names of the built-in materials, sorted.
std::vector<std::string> BuiltinMaterialNames();

}  // namespace burrlab::stimuli

#endif  // BURRLAB_STIMULI_MATERIALS_H_
