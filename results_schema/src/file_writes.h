// Writing export files safely (not public): every file appears whole or not
// at all (a temporary name "<file>.tmp-<pid>-<n>", then a rename), and files
// that must never be replaced are linked into place only when absent.
#ifndef BURRLAB_RESULTS_SCHEMA_SRC_FILE_WRITES_H_
#define BURRLAB_RESULTS_SCHEMA_SRC_FILE_WRITES_H_

#include <filesystem>
#include <string_view>

#include "burrlab/base/result.h"

namespace burrlab::results_schema {

// A fresh temporary name beside `path`: "<path>.tmp-<pid>-<n>".
std::filesystem::path TempPathFor(const std::filesystem::path& path);

// Removes the temporary files an export killed before its rename left in
// `folder`: those of processes that no longer exist (a live process's are
// its export in progress).
void RemoveStaleTempFiles(const std::filesystem::path& folder);

// "cannot write PATH: <strerror(err)>".
Error WriteError(const std::filesystem::path& path, int err);

// Writes `bytes` to `path`, replacing an older export atomically.
Status ReplaceFile(const std::filesystem::path& path, std::string_view bytes);

// Writes `bytes` to `path` unless something is there already (kept as is).
Status WriteIfAbsent(const std::filesystem::path& path, std::string_view bytes);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_SRC_FILE_WRITES_H_
