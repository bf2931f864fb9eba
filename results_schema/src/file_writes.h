// Writing export files safely (not public): every file appears whole or not
// at all (a temporary name "<file>.tmp-<pid>-<n>", then a rename), and files
// that must never be replaced are linked into place only when absent.
#ifndef BURRLAB_RESULTS_SCHEMA_SRC_FILE_WRITES_H_
#define BURRLAB_RESULTS_SCHEMA_SRC_FILE_WRITES_H_

#include <filesystem>
#include <string_view>

#include "burrlab/base/result.h"

namespace burrlab::results_schema {

// The deflate level of trace samples, in the journal's BLOBs and the
// _physio.tsv.gz exports. Level 1 against the default 6, measured on a 20 s
// drilling trace at 100 Hz: the TSV deflates 4.3 times faster (49 vs 214 ms)
// into 11 % more bytes (ratio 2.67 vs 2.97); the journal's raw doubles 1.7
// times faster at about the same size (ratio 1.53 vs 1.55). Exports were most
// of the time of a study that shares its renderings.
inline constexpr int kTraceDeflateLevel = 1;

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
