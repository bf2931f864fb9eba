// The per-session lock: flock(LOCK_EX | LOCK_NB) on journal.lock.
#include "burrlab/results_schema/session_lock.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

#include "burrlab/results_schema/dataset_layout.h"
#include "journal_db.h"
#include "text.h"

namespace burrlab::results_schema {
namespace fs = std::filesystem;
namespace {

// Longest holder line read back from a lock file.
constexpr std::size_t kMaxHolderBytes = 512;

std::string HostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof(name) - 1) != 0 || name[0] == '\0') {
    return "an unknown host";
  }
  return name;
}

// The holder line in a lock file another process holds; its bytes are
// escaped, since anyone can write the file.
std::string ReadHolder(int fd) {
  char buffer[kMaxHolderBytes];
  const ssize_t n = ::pread(fd, buffer, sizeof(buffer), 0);
  if (n <= 0) return "holder not yet written";
  std::string_view line(buffer, static_cast<std::size_t>(n));
  line = line.substr(0, line.find('\n'));
  const std::string quoted = Quoted(line);
  return quoted.substr(1, quoted.size() - 2);
}

}  // namespace

fs::path SessionLockPath(const fs::path& dir, std::string_view subject_label) {
  return SessionLockPath(dir, subject_label, "");
}

fs::path SessionLockPath(const fs::path& dir, std::string_view subject_label,
                         std::string_view session_label) {
  return SessionFolder(dir, subject_label, session_label) /
         "journal.sqlite.lock";
}

Result<SessionLock> SessionLock::Acquire(const fs::path& dir,
                                         std::string_view subject_label) {
  return Acquire(dir, subject_label, "");
}

Result<SessionLock> SessionLock::Acquire(const fs::path& dir,
                                         std::string_view subject_label,
                                         std::string_view session_label) {
  const fs::path path = SessionLockPath(dir, subject_label, session_label);
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  if (ec) {
    return Error{fmt::format("cannot create folder {}: {}",
                             path.parent_path().string(), ec.message())};
  }
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    return Error{fmt::format("cannot open the session lock {}: {}",
                             path.string(), std::strerror(errno))};
  }
  int rc = 0;
  do {
    rc = ::flock(fd, LOCK_EX | LOCK_NB);
  } while (rc != 0 && errno == EINTR);
  if (rc != 0) {
    const int err = errno;
    std::string message =
        err == EWOULDBLOCK
            ? fmt::format(
                  "{} in {} is in use by another burrlab ({}); wait for "
                  "that run to end, or stop it, before starting another on "
                  "this session",
                  SessionName(subject_label, session_label), dir.string(),
                  ReadHolder(fd))
            : fmt::format("cannot lock the session {}: {}", path.string(),
                          std::strerror(err));
    ::close(fd);
    return Error{std::move(message)};
  }
  std::string holder = fmt::format("pid {} on {} since {}", ::getpid(),
                                   HostName(), db::NowUtc());
  const std::string line = holder + "\n";
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, line.data(), line.size(), 0) !=
                                     static_cast<ssize_t>(line.size())) {
    const int err = errno;
    ::close(fd);
    return Error{fmt::format("cannot write the session lock {}: {}",
                             path.string(), std::strerror(err))};
  }
  return SessionLock(fd, std::move(holder));
}

SessionLock::SessionLock(SessionLock&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), holder_(std::move(other.holder_)) {}

SessionLock& SessionLock::operator=(SessionLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    holder_ = std::move(other.holder_);
  }
  return *this;
}

SessionLock::~SessionLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace burrlab::results_schema
