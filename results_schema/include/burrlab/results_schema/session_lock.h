// One process per session: an exclusive advisory lock (flock) on
// journal.sqlite.lock in the session's folder (DIR/sub-<label>/, or
// DIR/sub-<label>/ses-<session>/: dataset_layout.h), held while a process
// writes the session's journal. The file names its holder ("pid P on HOST since
// UTC"), so a second process is refused with a message saying who has the
// session. The kernel drops the lock when its holder exits or is killed, so a
// lock left by a crashed or SIGKILLed run is free: the next run takes it over
// and rewrites the holder line. The file itself stays (it is not part of the
// exports). flock works on local file systems and on NFS v4 (Linux emulates it
// with byte-range locks there).
#ifndef BURRLAB_RESULTS_SCHEMA_SESSION_LOCK_H_
#define BURRLAB_RESULTS_SCHEMA_SESSION_LOCK_H_

#include <filesystem>
#include <string>
#include <string_view>

#include "burrlab/base/result.h"

namespace burrlab::results_schema {

// DIR/sub-<label>/journal.sqlite.lock.
std::filesystem::path SessionLockPath(const std::filesystem::path& dir,
                                      std::string_view subject_label);
// The same in the folder of session `session_label` (none when empty).
std::filesystem::path SessionLockPath(const std::filesystem::path& dir,
                                      std::string_view subject_label,
                                      std::string_view session_label);

// The lock of one session. Move-only; the destructor releases it.
class SessionLock {
 public:
  // Takes the lock of sub-<label> in DIR, creating DIR/sub-<label> and the
  // lock file when needed, and writes this process's holder line. When
  // another process holds it: "sub-<label> in DIR is in use by another
  // burrlab (pid P on HOST since UTC); wait for that run to end, or stop it,
  // before starting another on this session".
  static Result<SessionLock> Acquire(const std::filesystem::path& dir,
                                     std::string_view subject_label);
  // The same for session `session_label` of the subject (none when empty);
  // the message names it "sub-<label> ses-<session>".
  static Result<SessionLock> Acquire(const std::filesystem::path& dir,
                                     std::string_view subject_label,
                                     std::string_view session_label);

  // Moves the lock.
  SessionLock(SessionLock&& other) noexcept;
  // Moves the lock, releasing this one's.
  SessionLock& operator=(SessionLock&& other) noexcept;
  // Releases the lock.
  ~SessionLock();

  // The holder line written ("pid P on HOST since UTC").
  const std::string& holder() const { return holder_; }

 private:
  SessionLock(int fd, std::string holder)
      : fd_(fd), holder_(std::move(holder)) {}
  int fd_ = -1;
  std::string holder_;
};

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_SESSION_LOCK_H_
