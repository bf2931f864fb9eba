// The README's tours work exactly as written: every ```sh block of README.md
// runs, in order, with bash (-e -u -o pipefail) in one scratch folder that
// holds a link to the source tree's protocols/ and has this build's
// `burrlab` first on PATH. Blocks fenced otherwise (make, output) are not
// run. Not in the sanitizer build: the commands are the optimised build's
// (their code runs under the sanitizers in the other tests).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../results_schema/temp_dir.h"
#include "read_file.h"

#ifndef __SANITIZE_ADDRESS__
namespace {

namespace fs = std::filesystem;

std::vector<std::string> ShellBlocks(const std::string& readme) {
  std::istringstream in(readme);
  std::vector<std::string> blocks;
  std::string line, block;
  bool inside = false, shell = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      if (!inside) {
        inside = true;
        shell = line == "```sh";
        block.clear();
      } else {
        inside = false;
        if (shell) blocks.push_back(block);
      }
      continue;
    }
    if (inside && shell) block += line + "\n";
  }
  return blocks;
}

using burrlab::runner::ReadFile;

TEST(ReadmeCommands, EveryShellBlockRunsAsWritten) {
  const std::string readme =
      ReadFile(fs::path(BURRLAB_SOURCE_DIR) / "README.md");
  const std::vector<std::string> blocks = ShellBlocks(readme);
  ASSERT_GE(blocks.size(), 4u) << "the README's tours have gone";
  burrlab::results_schema::TempDir dir;
  fs::create_directory_symlink(fs::path(BURRLAB_SOURCE_DIR) / "protocols",
                               dir.path() / "protocols");
  const fs::path bin = fs::path(BURRLAB_BINARY_DIR) / "runner";
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const fs::path script = dir.path() / ("block" + std::to_string(i) + ".sh");
    std::ofstream(script) << blocks[i];
    const fs::path log = dir.path() / ("block" + std::to_string(i) + ".log");
    const std::string command =
        "cd '" + dir.path().string() + "' && PATH='" + bin.string() +
        "':\"$PATH\" bash -euo pipefail '" + script.string() + "' > '" +
        log.string() + "' 2>&1";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << "README block " << i + 1 << " failed:\n"
        << blocks[i] << "--- its output:\n"
        << ReadFile(log);
  }
}

}  // namespace
#endif  // __SANITIZE_ADDRESS__
