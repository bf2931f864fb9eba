// The files at a dataset's root that say what it is and how it was made
// (BIDS): README, written once, and code/, a copy of every protocol file its
// sessions ran (BIDS validators do not look into code/). bids_export.h writes
// dataset_description.json, participants.h participants.tsv.
#ifndef BURRLAB_RESULTS_SCHEMA_DATASET_FILES_H_
#define BURRLAB_RESULTS_SCHEMA_DATASET_FILES_H_

#include <filesystem>
#include <string>
#include <string_view>

#include "burrlab/base/result.h"

namespace burrlab::results_schema {

// Where a dataset's sessions came from.
struct DatasetSource {
  std::string study;            // the protocol's study name
  std::string burrlab_version;  // the burrlab that ran them
  std::string protocol_path;    // the protocol file as given; its name
                                // names the copy
  std::string protocol_text;    // the protocol file's bytes
  std::string protocol_sha256;  // their SHA-256, lowercase hex
};

// The copy's path relative to DIR: code/<file name of protocol_path>, or
// code/<stem>_sha256-<first 12 hex digits><extension> when DIR/code/<file
// name> holds another protocol ("protocol.toml" stands for a name that
// cannot be a file name in code/).
std::string ProtocolCopyName(const std::filesystem::path& dir,
                             const DatasetSource& source);

// Copies the protocol to DIR/ProtocolCopyName() (an existing copy with the
// same bytes is kept) and writes DIR/README when the folder has no README
// (nor README.md, README.rst, README.txt): what the dataset is, how burrlab
// made it and what each file holds. Nothing is replaced; no wall-clock time
// is written.
Status WriteDatasetSource(const std::filesystem::path& dir,
                          const DatasetSource& source);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_DATASET_FILES_H_
