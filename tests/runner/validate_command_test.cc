// `burrlab validate`: what it prints for protocol files an author or an
// attacker may write (the exact text), and its promise that a protocol it
// accepts runs to its end.
#include "validate_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "run_cli.h"

namespace burrlab::runner {
namespace {

namespace fs = std::filesystem;

class ValidateTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(BURRLAB_BINARY_DIR) / "test_tmp" / "validate" /
           info->test_suite_name() / info->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }

  std::string Write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  }

  fs::path dir_;
};

// The exact text: the study name is the file's, so its ESC is escaped on the
// "ok" line too.
TEST_F(ValidateTest, OkLineEscapesTheStudyName) {
  const std::string path = Write("p.toml", R"toml(format = "burrlab-protocol/1"
[study]
name = "x\u001b]0;pwned\u0007"
[materials.pvc]
builtin = "pvc_k70"
[materials.bone]
builtin = "human_temporal_bone"
[[blocks]]
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
)toml");
  const CliRun r = RunBurrlab({"validate", path});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, path + ": ok (1 block, study \"x\\x1b]0;pwned\\x07\")\n");
}

}  // namespace
}  // namespace burrlab::runner
