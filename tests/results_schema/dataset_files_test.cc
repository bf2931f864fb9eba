// Tests of a dataset's README and code/: the README says what the dataset is
// and is written once, never over the experimenter's; the protocol is copied
// into code/ without replacing another protocol of the same name.
#include "burrlab/results_schema/dataset_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "temp_dir.h"

namespace burrlab::results_schema {
namespace {

namespace fs = std::filesystem;

std::string DatasetFileText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

DatasetSource PvcSource(const std::string& text) {
  DatasetSource s;
  s.study = "PVC vs bone";
  s.burrlab_version = "0.1.0";
  s.protocol_path = "protocols/examples/pvc.toml";
  s.protocol_text = text;
  s.protocol_sha256 = "0123456789abcdef" + std::string(48, '0');
  return s;
}

TEST(DatasetFiles, TheReadmeSaysWhatTheDatasetIsAndIsWrittenOnce) {
  TempDir dir;
  ASSERT_TRUE(WriteDatasetSource(dir.path(), PvcSource("format = 1\n")).ok());
  const std::string readme = DatasetFileText(dir.path() / "README");
  EXPECT_TRUE(readme.starts_with(
      "# PVC vs bone\n\nA BIDS dataset (BIDS 1.9.0) recorded with burrlab "
      "0.1.0, a runner of haptic\n"))
      << readme;
  EXPECT_NE(readme.find("the protocol file code/pvc.toml\n"), std::string::npos)
      << readme;
  EXPECT_NE(readme.find("participants.tsv"), std::string::npos);
  EXPECT_GT(readme.size(), 150u);  // BIDS validators warn of a smaller one
  EXPECT_EQ(DatasetFileText(dir.path() / "code" / "pvc.toml"), "format = 1\n");
  // The experimenter's words stay; so does a README.md of theirs.
  std::ofstream(dir.path() / "README") << "ours\n";
  ASSERT_TRUE(WriteDatasetSource(dir.path(), PvcSource("format = 1\n")).ok());
  EXPECT_EQ(DatasetFileText(dir.path() / "README"), "ours\n");
  TempDir md;
  std::ofstream(md.path() / "README.md") << "ours\n";
  ASSERT_TRUE(WriteDatasetSource(md.path(), PvcSource("format = 1\n")).ok());
  EXPECT_FALSE(fs::exists(md.path() / "README"));
}

TEST(DatasetFiles, AnotherProtocolOfTheSameNameGetsItsHashInTheName) {
  TempDir dir;
  ASSERT_TRUE(WriteDatasetSource(dir.path(), PvcSource("first\n")).ok());
  EXPECT_EQ(ProtocolCopyName(dir.path(), PvcSource("first\n")),
            "code/pvc.toml");
  EXPECT_EQ(ProtocolCopyName(dir.path(), PvcSource("second\n")),
            "code/pvc_sha256-0123456789ab.toml");
  ASSERT_TRUE(WriteDatasetSource(dir.path(), PvcSource("second\n")).ok());
  EXPECT_EQ(DatasetFileText(dir.path() / "code" / "pvc.toml"), "first\n");
  EXPECT_EQ(
      DatasetFileText(dir.path() / "code" / "pvc_sha256-0123456789ab.toml"),
      "second\n");
  DatasetSource hidden = PvcSource("x\n");
  hidden.protocol_path = ".hidden";
  EXPECT_EQ(ProtocolCopyName(dir.path(), hidden), "code/protocol.toml");
}

TEST(DatasetFiles, ACodeFileInTheWayIsAnError) {
  TempDir dir;
  std::ofstream(dir.path() / "code") << "x";
  Status s = WriteDatasetSource(dir.path(), PvcSource("x\n"));
  ASSERT_FALSE(s.ok());
  EXPECT_TRUE(s.error().message.starts_with(
      "cannot create folder " + (dir.path() / "code").string() + ": "))
      << s.error().message;
}

}  // namespace
}  // namespace burrlab::results_schema
