// Where a results folder (a BIDS dataset) keeps each session. A subject
// recorded without session labels has one session, in DIR/sub-<label>/; a
// subject whose sessions are labelled (`burrlab run --session 2`) has one
// folder per session, DIR/sub-<label>/ses-<session>/, and nothing of a
// session directly in DIR/sub-<label>/ (BIDS allows one layout per
// subject). A session folder holds the session's journal and lock, beh/ and
// <prefix>_scans.tsv, where every file name starts with the prefix
// sub-<label> or sub-<label>_ses-<session>.
#ifndef BURRLAB_RESULTS_SCHEMA_DATASET_LAYOUT_H_
#define BURRLAB_RESULTS_SCHEMA_DATASET_LAYOUT_H_

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace burrlab::results_schema {

// DIR/sub-<subject>, or DIR/sub-<subject>/ses-<session> when `session` is
// not empty.
std::filesystem::path SessionFolder(const std::filesystem::path& dir,
                                    std::string_view subject,
                                    std::string_view session);

// "sub-01", or "sub-01_ses-2": how the session's file names start.
std::string SessionFilePrefix(std::string_view subject,
                              std::string_view session);

// "sub-01", or "sub-01 ses-2": the session in messages.
std::string SessionName(std::string_view subject, std::string_view session);

// One folder that may hold a session.
struct SessionFolderEntry {
  std::string subject;  // label without "sub-"
  std::string session;  // label without "ses-"; empty: DIR/sub-<subject>
  std::filesystem::path folder;
};

// Every DIR/sub-<label>/ (with an empty session) and every
// DIR/sub-<label>/ses-<label>/ folder whose labels are BIDS labels, sorted by
// subject, then session (the subject's own folder first). Callers look for
// the files they need in each.
std::vector<SessionFolderEntry> ListSessionFolders(
    const std::filesystem::path& dir);

// The session labels of DIR/sub-<subject>/ses-*/ folders, sorted.
std::vector<std::string> SessionLabelsOf(const std::filesystem::path& dir,
                                         std::string_view subject);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_DATASET_LAYOUT_H_
