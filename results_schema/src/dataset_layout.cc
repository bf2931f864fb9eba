// Session folders of a results folder (see dataset_layout.h).
#include "burrlab/results_schema/dataset_layout.h"

#include <fmt/format.h>

#include <algorithm>
#include <system_error>

#include "burrlab/results_schema/records.h"

namespace burrlab::results_schema {
namespace fs = std::filesystem;

fs::path SessionFolder(const fs::path& dir, std::string_view subject,
                       std::string_view session) {
  const fs::path folder = dir / fmt::format("sub-{}", subject);
  return session.empty() ? folder : folder / fmt::format("ses-{}", session);
}

std::string SessionFilePrefix(std::string_view subject,
                              std::string_view session) {
  return session.empty() ? fmt::format("sub-{}", subject)
                         : fmt::format("sub-{}_ses-{}", subject, session);
}

std::string SessionName(std::string_view subject, std::string_view session) {
  return session.empty() ? fmt::format("sub-{}", subject)
                         : fmt::format("sub-{} ses-{}", subject, session);
}

std::vector<std::string> SessionLabelsOf(const fs::path& dir,
                                         std::string_view subject) {
  std::vector<std::string> labels;
  std::error_code ec;
  for (fs::directory_iterator it(SessionFolder(dir, subject, ""), ec);
       !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code type_ec;
    if (name.starts_with("ses-") && ValidateSessionLabel(name.substr(4)) &&
        it->is_directory(type_ec)) {
      labels.push_back(name.substr(4));
    }
  }
  std::sort(labels.begin(), labels.end());
  return labels;
}

std::vector<SessionFolderEntry> ListSessionFolders(const fs::path& dir) {
  std::vector<std::string> subjects;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec);
       !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code type_ec;
    if (name.starts_with("sub-") && ValidateSubjectLabel(name.substr(4)) &&
        it->is_directory(type_ec)) {
      subjects.push_back(name.substr(4));
    }
  }
  std::sort(subjects.begin(), subjects.end());
  std::vector<SessionFolderEntry> entries;
  for (const std::string& subject : subjects) {
    entries.push_back({subject, "", SessionFolder(dir, subject, "")});
    for (const std::string& session : SessionLabelsOf(dir, subject)) {
      entries.push_back(
          {subject, session, SessionFolder(dir, subject, session)});
    }
  }
  return entries;
}

}  // namespace burrlab::results_schema
