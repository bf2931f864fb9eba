// One whole-file reader with the reason when it cannot read.
#include "burrlab/base/file_text.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

namespace burrlab {
namespace {

FileReadFailure Unreadable(int error) {
  return {FileProblem::kUnreadable,
          error != 0 ? std::generic_category().message(error) : std::string(),
          0};
}

}  // namespace

std::variant<std::string, FileReadFailure> ReadFileBytes(
    const std::string& path, std::uintmax_t max_bytes, FileKinds kinds) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (ec) return FileReadFailure{FileProblem::kUnreadable, ec.message(), 0};
  if (std::filesystem::is_directory(status)) {
    return FileReadFailure{
        FileProblem::kDirectory,
        std::make_error_code(std::errc::is_a_directory).message(), 0};
  }
  const bool regular = std::filesystem::is_regular_file(status);
  if (!regular && kinds == FileKinds::kRegularOnly) {
    return FileReadFailure{FileProblem::kNotRegular, "not a regular file", 0};
  }
  if (regular) {
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) return FileReadFailure{FileProblem::kUnreadable, ec.message(), 0};
    if (size > max_bytes) {
      return FileReadFailure{FileProblem::kTooLarge, std::string(), size};
    }
  }
  errno = 0;
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(
      std::fopen(path.c_str(), "rb"), &std::fclose);
  if (file == nullptr) return Unreadable(errno);
  // Read until the end, or one byte beyond the limit (the size is checked
  // on what was read: a file may grow between the stat and the read).
  std::string text;
  char buffer[1 << 16];
  while (true) {
    const std::size_t n = std::fread(buffer, 1, sizeof buffer, file.get());
    if (n > max_bytes - std::min<std::uintmax_t>(text.size(), max_bytes)) {
      return FileReadFailure{FileProblem::kTooLarge, std::string(),
                             text.size() + n};
    }
    text.append(buffer, n);
    if (n < sizeof buffer) break;
  }
  if (std::ferror(file.get()) != 0) return Unreadable(errno != 0 ? errno : EIO);
  return text;
}

Result<std::string> ReadTextFile(const std::string& path,
                                 std::uintmax_t max_bytes) {
  std::variant<std::string, FileReadFailure> read =
      ReadFileBytes(path, max_bytes);
  if (std::string* text = std::get_if<std::string>(&read)) {
    return std::move(*text);
  }
  const FileReadFailure& failure = std::get<FileReadFailure>(read);
  switch (failure.problem) {
    case FileProblem::kDirectory:
      return Error{fmt::format("cannot read {}: it is a directory", path)};
    case FileProblem::kTooLarge:
      return Error{fmt::format(
          "cannot read {}: {} bytes is more than the {} bytes accepted", path,
          failure.size, max_bytes)};
    case FileProblem::kUnreadable:
    case FileProblem::kNotRegular:
      break;
  }
  return Error{failure.reason.empty()
                   ? fmt::format("cannot read {}", path)
                   : fmt::format("cannot read {}: {}", path, failure.reason)};
}

}  // namespace burrlab
