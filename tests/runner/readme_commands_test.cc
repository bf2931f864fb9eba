// The README's tours work exactly as written: every ```sh block of README.md
// runs, in order, with bash (-e -u -o pipefail) in one scratch folder that
// holds a link to the source tree's protocols/ (TMPDIR points there too) and
// has this build's `burrlab` first on PATH. Blocks fenced otherwise (make,
// output) are not run. Not in the sanitizer build: the commands are the
// optimised build's (their code runs under the sanitizers in the other tests).
//
// Two slow runs of the tours are checked here rather than run again by their
// own tests: `sim materials` (the order check and its figures) and the bone
// data of the modeller's tour, which `calibrate` must recover (the bone case
// of CalibrateCommand.RecoversTheBuiltInMaterialsFromSimMeasureData).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../results_schema/temp_dir.h"
#include "read_file.h"
#include "run_cli.h"

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
using burrlab::runner::RunBurrlab;
using ::testing::HasSubstr;

TEST(ReadmeCommands, EveryShellBlockRunsAsWritten) {
  const std::string readme =
      ReadFile(fs::path(BURRLAB_SOURCE_DIR) / "README.md");
  const std::vector<std::string> blocks = ShellBlocks(readme);
  ASSERT_GE(blocks.size(), 4u) << "the README's tours have gone";
  burrlab::results_schema::TempDir dir;
  fs::create_directory_symlink(fs::path(BURRLAB_SOURCE_DIR) / "protocols",
                               dir.path() / "protocols");
  const fs::path bin = fs::path(BURRLAB_BINARY_DIR) / "runner";
  std::string logs;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const fs::path script = dir.path() / ("block" + std::to_string(i) + ".sh");
    std::ofstream(script) << blocks[i];
    const fs::path log = dir.path() / ("block" + std::to_string(i) + ".log");
    const std::string command =
        "cd '" + dir.path().string() + "' && TMPDIR='" + dir.path().string() +
        "' PATH='" + bin.string() + "':\"$PATH\" bash -euo pipefail '" +
        script.string() + "' > '" + log.string() + "' 2>&1";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << "README block " << i + 1 << " failed:\n"
        << blocks[i] << "--- its output:\n"
        << ReadFile(log);
    logs += ReadFile(log);
  }

  // The first block sets up the tours' scratch folder (under TMPDIR, here the
  // test's own folder) with its link to the examples.
  EXPECT_TRUE(fs::is_symlink(dir.path() / "burrlab-tours" / "protocols"))
      << "the README's tours no longer start in a scratch folder";
  EXPECT_THAT(blocks[0], HasSubstr("build/release/runner"));

  // `burrlab sim materials --plots materials`: the order of §8.7 and three
  // figures.
  ASSERT_TRUE(fs::is_directory(dir.path() / "materials"))
      << "the README no longer runs `burrlab sim materials --plots materials`";
  EXPECT_THAT(logs, HasSubstr("at 4 N:  PVC > Pettigrew > bone holds"));
  for (const char* name :
       {"force_depth.png", "descent_depth.png", "descent_velocity.png"}) {
    EXPECT_GT(fs::file_size(dir.path() / "materials" / name), 1000u) << name;
  }

  // bone.csv: the full rig's initial velocities (the default definition) of
  // the built-in bone (c_e 2.145 N/mm^2, alpha 0.087 1/s) at loads
  // F / (c_e R^2) of 0.7-1.45, 4 replicates, 5 % noise; calibrate's intervals
  // hold the truth.
  const fs::path bone = dir.path() / "bone.csv";
  ASSERT_TRUE(fs::exists(bone)) << "the README no longer writes bone.csv";
  const auto fit =
      RunBurrlab({"calibrate", "--measured", bone.string(), "--json"});
  ASSERT_EQ(fit.code, 0) << fit.err;
  const nlohmann::json j = nlohmann::json::parse(fit.out);
  EXPECT_EQ(j["velocity_definition"], "initial");
  ASSERT_TRUE(j["identifiable"]["both"].get<bool>()) << fit.out;
  EXPECT_LE(j["ci"]["c_e"][0].get<double>(), 2.145) << fit.out;
  EXPECT_GE(j["ci"]["c_e"][1].get<double>(), 2.145) << fit.out;
  EXPECT_LE(j["ci"]["alpha"][0].get<double>(), 0.087) << fit.out;
  EXPECT_GE(j["ci"]["alpha"][1].get<double>(), 0.087) << fit.out;
  EXPECT_LT(j["rmse_log_v"].get<double>(), 0.2);
}

}  // namespace
#endif  // __SANITIZE_ADDRESS__
