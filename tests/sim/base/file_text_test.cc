// The one whole-file reader: every byte back, and what went wrong named the
// way the system names it.
#include "burrlab/base/file_text.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

namespace burrlab {
namespace {

namespace fs = std::filesystem;

class FileText : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "file_text_XXXXXX");
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Write(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  fs::path dir_;
};

FileReadFailure FailureOf(const std::variant<std::string, FileReadFailure>& r) {
  EXPECT_TRUE(std::holds_alternative<FileReadFailure>(r));
  return std::holds_alternative<FileReadFailure>(r)
             ? std::get<FileReadFailure>(r)
             : FileReadFailure{};
}

TEST_F(FileText, ReadsEveryByteAsWritten) {
  // A BOM, CR LF, a NUL and a byte that is not UTF-8: nothing is translated.
  const std::string bytes("\xEF\xBB\xBFlevel\r\n1\0\xff\n", 14);
  const std::string path = Write("data.csv", bytes);
  const auto read = ReadFileBytes(path);
  ASSERT_TRUE(std::holds_alternative<std::string>(read));
  EXPECT_EQ(std::get<std::string>(read), bytes);
  // Larger than the reader's buffer, and exactly at the limit.
  const std::string big(200'000, 'x');
  const std::string big_path = Write("big.txt", big);
  const auto at_limit = ReadFileBytes(big_path, big.size());
  ASSERT_TRUE(std::holds_alternative<std::string>(at_limit));
  EXPECT_EQ(std::get<std::string>(at_limit), big);
  const Result<std::string> text = ReadTextFile(Write("empty.txt", ""));
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(*text, "");
}

TEST_F(FileText, NamesAMissingFileAndADirectoryAsTheSystemDoes) {
  const std::string missing = (dir_ / "missing.csv").string();
  const FileReadFailure gone = FailureOf(ReadFileBytes(missing));
  EXPECT_EQ(gone.problem, FileProblem::kUnreadable);
  EXPECT_EQ(gone.reason, std::strerror(ENOENT));
  EXPECT_EQ(ReadTextFile(missing).error().message,
            "cannot read " + missing + ": No such file or directory");
  const FileReadFailure folder = FailureOf(ReadFileBytes(dir_.string()));
  EXPECT_EQ(folder.problem, FileProblem::kDirectory);
  EXPECT_EQ(folder.reason, std::strerror(EISDIR));
  EXPECT_EQ(ReadTextFile(dir_.string()).error().message,
            "cannot read " + dir_.string() + ": it is a directory");
}

TEST_F(FileText, RefusesARegularFileOverTheLimitWithItsSize) {
  const std::string path = Write("eleven.txt", "0123456789\n");
  const FileReadFailure large = FailureOf(ReadFileBytes(path, 10));
  EXPECT_EQ(large.problem, FileProblem::kTooLarge);
  EXPECT_EQ(large.size, 11u);
  EXPECT_EQ(
      ReadTextFile(path, 10).error().message,
      "cannot read " + path + ": 11 bytes is more than the 10 bytes accepted");
}

TEST_F(FileText, ReadsAPipeUpToTheLimitUnlessOnlyRegularFilesAreAccepted) {
  const std::string fifo = (dir_ / "pipe").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  // A writer that sends more than the limit and stops when the reader
  // closes its end (EPIPE, with SIGPIPE ignored meanwhile).
  struct sigaction ignore = {}, before = {};
  ignore.sa_handler = SIG_IGN;
  ASSERT_EQ(sigaction(SIGPIPE, &ignore, &before), 0);
  std::thread writer([&] {
    std::ofstream out(fifo, std::ios::binary);
    const std::string chunk(4096, 'p');
    for (int i = 0; i < 64 && out; ++i) out << chunk << std::flush;
  });
  const FileReadFailure large = FailureOf(ReadFileBytes(fifo, 100'000));
  writer.join();
  sigaction(SIGPIPE, &before, nullptr);
  EXPECT_EQ(large.problem, FileProblem::kTooLarge);
  EXPECT_GT(large.size, 100'000u);
  // A pipe nobody writes to would block: kRegularOnly refuses it unopened.
  const FileReadFailure refused =
      FailureOf(ReadFileBytes(fifo, kAnySize, FileKinds::kRegularOnly));
  EXPECT_EQ(refused.problem, FileProblem::kNotRegular);
  EXPECT_EQ(refused.reason, "not a regular file");
}

TEST_F(FileText, ReadsAPipeToItsEnd) {
  const std::string fifo = (dir_ / "pipe").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer(
      [&] { std::ofstream(fifo, std::ios::binary) << "level,n\n1,2\n"; });
  const auto read = ReadFileBytes(fifo);
  writer.join();
  ASSERT_TRUE(std::holds_alternative<std::string>(read));
  EXPECT_EQ(std::get<std::string>(read), "level,n\n1,2\n");
}

}  // namespace
}  // namespace burrlab
