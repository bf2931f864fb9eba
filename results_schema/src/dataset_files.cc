// The README and code/ folder of a dataset (see dataset_files.h).
#include "burrlab/results_schema/dataset_files.h"

#include <fmt/format.h>

#include <exception>
#include <system_error>
#include <variant>

#include "burrlab/base/file_text.h"
#include "burrlab/results_schema/bids_export.h"
#include "file_writes.h"
#include "text.h"

namespace burrlab::results_schema {
namespace fs = std::filesystem;
namespace {

// The protocol's own file name when it can name a file in code/.
std::string CopyFileName(const DatasetSource& source) {
  const std::string name = fs::path(source.protocol_path).filename().string();
  bool plain = !name.empty() && name[0] != '.' && IsValidUtf8(name);
  for (char c : name) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f || c == '\\') plain = false;
  }
  return plain ? name : std::string("protocol.toml");
}

// True when `path` holds exactly `bytes` (false when it cannot be read).
bool HoldsBytes(const fs::path& path, std::string_view bytes) {
  std::variant<std::string, FileReadFailure> read =
      ReadFileBytes(path.string(), bytes.size(), FileKinds::kRegularOnly);
  const std::string* text = std::get_if<std::string>(&read);
  return text != nullptr && *text == bytes;
}

bool Exists(const fs::path& path) {
  std::error_code ec;
  return fs::symlink_status(path, ec).type() != fs::file_type::not_found;
}

// The README: what the dataset is, how it was made, what each file holds.
std::string Readme(const DatasetSource& source, std::string_view copy) {
  return fmt::format(
      R"(# {0}

A BIDS dataset (BIDS {1}) recorded with burrlab {2}, a runner of haptic
psychophysics experiments for bone-burring research. In each trial the subject
probed or drilled virtual materials, every interval rendered by burrlab's burr
simulator (felt through a haptic device, or by a simulated hand for simulated
subjects), and answered the trial's question.

How it was made: the protocol file {3}
defines the blocks, methods, materials and trials. `burrlab run` ran each subject's session from it (or
`burrlab study` a population of simulated subjects), committed every trial to
the session's journal (journal.sqlite in the session's folder, listed in
.bidsignore) and exported the files below from the journal.

Files:
- sub-<label>/[ses-<session>/]beh/*_beh.tsv: one row per trial; the
  *_beh.json beside it describes every column.
- *_physio.tsv.gz with *_physio.json: the force and burr position traces of
  the intervals (time in s on the session clock).
- *_scans.tsv: each session's data files and whether the session ran to its
  end.
- participants.tsv with participants.json: one row per subject; a simulated
  subject's row holds the true parameters of its simulated observer.
- code/: the protocol files the sessions ran.

burrlab writes this file once, when the dataset is first exported, and never
replaces it: add what a reader should know (who ran the study, where, and
under which consent).
)",
      source.study, kBidsVersion, source.burrlab_version, copy);
}

Status Write(const fs::path& dir, const DatasetSource& source) {
  const fs::path code = dir / "code";
  std::error_code ec;
  fs::create_directories(code, ec);
  if (ec || !fs::is_directory(code, ec)) {
    return Error{fmt::format("cannot create folder {}: {}", code.string(),
                             ec ? ec.message() : "a file has its name")};
  }
  RemoveStaleTempFiles(code);
  const std::string copy = ProtocolCopyName(dir, source);
  if (!Exists(dir / copy)) {
    if (Status s = WriteIfAbsent(dir / copy, source.protocol_text); !s) {
      return s;
    }
  }
  for (const char* name : {"README", "README.md", "README.rst", "README.txt"}) {
    if (Exists(dir / name)) return {};
  }
  return WriteIfAbsent(dir / "README", Readme(source, copy));
}

}  // namespace

std::string ProtocolCopyName(const fs::path& dir, const DatasetSource& source) {
  const fs::path name = CopyFileName(source);
  const fs::path plain = fs::path("code") / name;
  if (!Exists(dir / plain) || HoldsBytes(dir / plain, source.protocol_text)) {
    return plain.string();
  }
  return (fs::path("code") / fmt::format("{}_sha256-{}{}", name.stem().string(),
                                         source.protocol_sha256.substr(0, 12),
                                         name.extension().string()))
      .string();
}

Status WriteDatasetSource(const fs::path& dir, const DatasetSource& source) {
  try {
    return Write(dir, source);
  } catch (const std::exception& e) {
    return Error{
        fmt::format("cannot write the README and code/ of {}: "
                    "internal error: {}",
                    dir.string(), e.what())};
  }
}

}  // namespace burrlab::results_schema
