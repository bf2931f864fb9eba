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
  // One line per thing the file should change but that still reads, e.g.
  // "x.toml:12:1: note: [parameters.c_e] is the old spelling of
  // [parameters.c_e_n_per_mm2]; ...". Empty for the built-in sets.
  std::vector<std::string> notes;
};

// How both file kinds spell a material parameter: material files as
// [parameters.<key>], protocol files as a [materials.<id>] key and as an
// axis's parameter. `old_key` is the spelling material files and axes used
// before units joined the names, still read with a note (empty when the key
// never changed). `symbol` names the parameter in derived names and messages
// (the dissertation's symbol); `unit` is the unit the key's suffix spells.
struct MaterialParameterSpelling {
  std::string_view key;
  std::string_view old_key;
  std::string_view symbol;
  std::string_view unit;
  double sim::Material::*field;
};

// The five parameters in the order of sim::Material (eqs. 6.12/7.3, 7.12,
// 6.23/7.13, 6.15 and 7.14).
inline constexpr MaterialParameterSpelling kMaterialParameterSpellings[] = {
    {"c_e_n_per_mm2", "c_e", "c_e", "N/mm^2", &sim::Material::c_e_n_per_mm2},
    {"alpha_per_s", "alpha", "alpha", "1/s", &sim::Material::alpha_per_s},
    {"c_mu_n_per_mm2", "c_mu", "c_mu", "N/mm^2",
     &sim::Material::c_mu_n_per_mm2},
    {"mu", "", "mu", "1", &sim::Material::mu},
    {"c_i_n_s_per_mm3", "c_i", "c_i", "N*s/mm^3",
     &sim::Material::c_i_n_s_per_mm3},
};

// Parses a material file held in memory; `path` is used in error messages only.
// Errors read "path:line:col: error: ..." and name the key and the rule broken.
Result<MaterialSet> ParseMaterial(std::string_view path, std::string_view text);
// Reads and parses a material file from disk.
Result<MaterialSet> LoadMaterialFile(const std::string& path);

// A material file when `name_or_path` ends in ".toml" or holds a '/', else
// the built-in set of that name.
Result<MaterialSet> LoadMaterial(const std::string& name_or_path);
// A built-in material by name; an unknown name gets the list of known ones and
// a "did you mean" suggestion.
Result<MaterialSet> LoadBuiltinMaterial(std::string_view name);
// Names of the built-in materials, sorted.
std::vector<std::string> BuiltinMaterialNames();

}  // namespace burrlab::stimuli

#endif  // BURRLAB_STIMULI_MATERIALS_H_
