// Shared by the model-gap tests: how many seeds to run (fewer under the
// sanitizers, more with BURRLAB_SLOW_TESTS=1), the bone design their
// scenarios start from, and the files they read from the source tree.
#ifndef BURRLAB_TESTS_ANALYSIS_MODEL_GAP_DISCOVER_FIXTURES_H_
#define BURRLAB_TESTS_ANALYSIS_MODEL_GAP_DISCOVER_FIXTURES_H_

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "burrlab/analysis/model_gap/discover_scenarios.h"

namespace burrlab::analysis::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

inline bool Slow() { return std::getenv("BURRLAB_SLOW_TESTS") != nullptr; }

inline ScenarioDesign BoneDesign() {
  ScenarioDesign d;
  d.material.c_e_n_per_mm2 = 2.145;  // human temporal bone (§8.7)
  d.material.alpha_per_s = 0.087;
  d.full_rig = false;
  return d;
}

// The bytes of `relative` under the source tree (BURRLAB_SOURCE_DIR, set for
// every test target); empty when it cannot be read.
inline std::string ReadSourceFile(const std::string& relative) {
  std::ifstream in(std::filesystem::path(BURRLAB_SOURCE_DIR) / relative,
                   std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace burrlab::analysis::testing

#endif  // BURRLAB_TESTS_ANALYSIS_MODEL_GAP_DISCOVER_FIXTURES_H_
