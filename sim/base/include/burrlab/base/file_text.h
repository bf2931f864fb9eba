// Reading a whole file into memory: one reader for every file burrlab takes
// (protocols, materials, station files and scripts, CSV data, exports read
// back). ReadFileBytes says what went wrong, so each caller can word its
// message; ReadTextFile words it the common way ("cannot read PATH: reason").
#ifndef BURRLAB_BASE_FILE_TEXT_H_
#define BURRLAB_BASE_FILE_TEXT_H_

#include <cstdint>
#include <limits>
#include <string>
#include <variant>

#include "burrlab/base/result.h"

namespace burrlab {

// What a read found wrong.
enum class FileProblem {
  kUnreadable,  // missing, not permitted, or an I/O error
  kDirectory,   // the path names a directory
  kNotRegular,  // a pipe, device or socket, where only a regular file is read
  kTooLarge,    // more bytes than the caller accepts
};

struct FileReadFailure {
  FileProblem problem = FileProblem::kUnreadable;
  // The system's words ("No such file or directory", "Is a directory");
  // empty when it gave none.
  std::string reason;
  // kTooLarge: the file's size, or the bytes read before the limit was passed
  // when the file is not a regular one (at least max_bytes + 1).
  std::uintmax_t size = 0;
};

// Which kinds of file a read accepts.
enum class FileKinds {
  kAny,          // regular files, pipes (e.g. a shell's <(...)), devices
  kRegularOnly,  // regular files only: nothing that can block or never end
};

inline constexpr std::uintmax_t kAnySize =
    std::numeric_limits<std::uintmax_t>::max();

// Every byte of the file at `path`, at most `max_bytes` of them. A regular
// file larger than that is refused before it is read; any other file is read
// up to one byte beyond the limit.
std::variant<std::string, FileReadFailure> ReadFileBytes(
    const std::string& path, std::uintmax_t max_bytes = kAnySize,
    FileKinds kinds = FileKinds::kAny);

// The same with one message: "cannot read PATH: REASON" ("it is a directory";
// "N bytes is more than the L bytes accepted"; the system's words, or none).
Result<std::string> ReadTextFile(const std::string& path,
                                 std::uintmax_t max_bytes = kAnySize);

}  // namespace burrlab

#endif  // BURRLAB_BASE_FILE_TEXT_H_
