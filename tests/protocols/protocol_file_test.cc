// Reading protocol files: the text and the parsed protocol, and the exact
// errors `burrlab validate` and the other commands print for a file that
// cannot be read, is too large or does not parse.
#include "burrlab/protocols/protocol_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace burrlab::protocols {
namespace {

namespace fs = std::filesystem;

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A folder of its own for the test's files, removed at the end.
class ProtocolFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("burrlab_protocol_file_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

TEST_F(ProtocolFile, LoadsTheTextAndTheProtocol) {
  const std::string path = std::string(BURRLAB_SOURCE_DIR) +
                           "/protocols/examples/two_interval_2afc.toml";
  Result<LoadedProtocol> loaded = LoadProtocol(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(loaded->path, path);
  EXPECT_EQ(loaded->text, ReadAll(path));
  EXPECT_FALSE(loaded->protocol.blocks.empty());
  // The same text parsed in memory gives the same protocol.
  Result<LoadedProtocol> parsed =
      ParseLoadedProtocol("in memory", ReadAll(path));
  ASSERT_TRUE(parsed.ok()) << parsed.error().message;
  EXPECT_EQ(parsed->path, "in memory");
  EXPECT_EQ(parsed->protocol.study_name, loaded->protocol.study_name);
  EXPECT_EQ(parsed->protocol.blocks.size(), loaded->protocol.blocks.size());
}

TEST_F(ProtocolFile, AMissingFileCannotBeRead) {
  const std::string path = (dir_ / "nope.toml").string();
  Result<LoadedProtocol> loaded = LoadProtocol(path);
  ASSERT_FALSE(loaded.ok());
  EXPECT_EQ(loaded.error().message,
            "cannot read " + path + ": No such file or directory");
}

TEST_F(ProtocolFile, ALargerFileIsRefusedUnread) {
  const fs::path path = dir_ / "big.toml";
  std::ofstream(path, std::ios::binary)
      << std::string(kMaxProtocolBytes + 1, '#');
  Result<LoadedProtocol> loaded = LoadProtocol(path.string());
  ASSERT_FALSE(loaded.ok());
  EXPECT_EQ(loaded.error().message,
            path.string() +
                ": error: the file is 1048577 bytes; protocol files are "
                "limited to 1048576 bytes");
  // At the limit the file is read (and parsed: here, all comments).
  std::ofstream(path, std::ios::binary) << std::string(kMaxProtocolBytes, '#');
  loaded = LoadProtocol(path.string());
  ASSERT_FALSE(loaded.ok());
  EXPECT_EQ(loaded.error().message.find("limited to"), std::string::npos)
      << loaded.error().message;
}

// Every diagnostic, as `burrlab validate` prints them, without the last
// newline.
TEST_F(ProtocolFile, ParseErrorsHoldEveryDiagnosticFormatted) {
  const std::string text = "format = \"burrlab-protocol/1\"\nnot_a_key = 1\n";
  const fs::path path = dir_ / "bad.toml";
  std::ofstream(path, std::ios::binary) << text;
  const ParseOutcome outcome = ParseProtocol(path.string(), text);
  ASSERT_FALSE(outcome.protocol.has_value());
  std::string expected =
      FormatDiagnostics(path.string(), text, outcome.diagnostics);
  ASSERT_EQ(expected.back(), '\n');
  expected.pop_back();
  Result<LoadedProtocol> loaded = LoadProtocol(path.string());
  ASSERT_FALSE(loaded.ok());
  EXPECT_EQ(loaded.error().message, expected);
  Result<LoadedProtocol> parsed = ParseLoadedProtocol(path.string(), text);
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().message, expected);
}

}  // namespace
}  // namespace burrlab::protocols
