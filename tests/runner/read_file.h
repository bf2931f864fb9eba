// The bytes of a file, for the runner tests ("" when it cannot be read).
#ifndef BURRLAB_TESTS_RUNNER_READ_FILE_H_
#define BURRLAB_TESTS_RUNNER_READ_FILE_H_

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace burrlab::runner {

inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace burrlab::runner

#endif  // BURRLAB_TESTS_RUNNER_READ_FILE_H_
