// The session journal: creation without overwriting, resume, and one
// transaction per appended trial.
#include "burrlab/results_schema/journal.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <stdio.h>  // renameat2
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <exception>
#include <optional>
#include <system_error>

#include "burrlab/results_schema/dataset_layout.h"
#include "burrlab/results_schema/session_lock.h"
#include "journal_db.h"
#include "text.h"

namespace burrlab::results_schema {
namespace fs = std::filesystem;

struct Journal::Impl {
  std::optional<SessionLock> lock;  // held while the journal is open
  db::Db db;
  fs::path dir;
  std::string session_label;  // empty: the subject has no labelled sessions
  fs::path path;
  SessionInfo session;
};

namespace {

constexpr std::string_view kJournalFile = "journal.sqlite";
constexpr std::string_view kCreatingPrefix = "journal.sqlite.creating-";
constexpr std::string_view kLockFile = "journal.sqlite.lock";

std::atomic<unsigned> g_creating_counter{0};

Error Internal(std::string_view what, const std::exception& e) {
  return Error{fmt::format("{}: internal error: {}", what, e.what())};
}

bool PathExists(const fs::path& path) {
  std::error_code ec;
  return fs::symlink_status(path, ec).type() != fs::file_type::not_found && !ec;
}

// The journal at `path` exists: resume it. When it holds no trial (the run
// stopped before its first one), --resume also starts it afresh with a
// corrected protocol or set-up.
Error AlreadyExists(const fs::path& dir, std::string_view label,
                    std::string_view session_label, const fs::path& path) {
  int trials = -1;
  if (auto opened = db::OpenDb(path, /*create=*/false)) {
    if (auto count = db::CountTrials(opened->get(), path)) trials = *count;
  }
  if (trials == 0) {
    return Error{fmt::format(
        "{} already exists in {} but holds no trials (its run stopped "
        "before the first trial); use --resume to start it again with this "
        "protocol and set-up",
        SessionName(label, session_label), dir.string())};
  }
  return Error{
      fmt::format("{} already exists in {}; use --resume to continue it",
                  SessionName(label, session_label), dir.string())};
}

// "ses-1, ses-2".
std::string SessionList(const std::vector<std::string>& labels) {
  std::string list;
  for (const std::string& label : labels) {
    list += (list.empty() ? "ses-" : ", ses-") + label;
  }
  return list;
}

Error NoJournal(const fs::path& dir, std::string_view label,
                std::string_view session_label, const fs::path& path) {
  if (session_label.empty()) {
    const std::vector<std::string> sessions = SessionLabelsOf(dir, label);
    if (!sessions.empty()) {
      return Error{fmt::format(
          "no journal for sub-{} in {}: its sessions are labelled ({}); give "
          "--session LABEL to resume one",
          label, dir.string(), SessionList(sessions))};
    }
  } else if (PathExists(JournalPath(dir, label, ""))) {
    return Error{fmt::format(
        "no journal for sub-{} ses-{} in {}: sub-{} was recorded without a "
        "session label; resume it without --session",
        label, session_label, dir.string(), label)};
  }
  return Error{fmt::format(
      "no journal for {} in {} ({} does not exist); start the session "
      "without --resume",
      SessionName(label, session_label), dir.string(), path.string())};
}

// BIDS allows one layout per subject: all of its sessions labelled
// (sub-<label>/ses-<session>/) or a single unlabelled one (sub-<label>/).
Status CheckSessionLayout(const fs::path& dir, std::string_view label,
                          std::string_view session_label) {
  const fs::path subject = SessionFolder(dir, label, "");
  if (session_label.empty()) {
    const std::vector<std::string> sessions = SessionLabelsOf(dir, label);
    if (sessions.empty()) return {};
    return Error{fmt::format(
        "sub-{} in {} has labelled sessions ({}); give --session LABEL to "
        "record another (a subject's sessions are all labelled or none is)",
        label, dir.string(), SessionList(sessions))};
  }
  for (const fs::path& unlabelled : {subject / kJournalFile, subject / "beh"}) {
    std::error_code ec;
    if (fs::symlink_status(unlabelled, ec).type() != fs::file_type::not_found) {
      return Error{fmt::format(
          "sub-{} in {} was recorded without a session label ({} exists); a "
          "subject's sessions are all labelled or none is, so record ses-{} "
          "in another output folder or run sub-{} without --session",
          label, dir.string(), unlabelled.string(), session_label, label)};
    }
  }
  return {};
}

void RemoveDbFiles(const fs::path& path) {
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm", "-journal"}) {
    fs::remove(fs::path(path.string() + suffix), ec);
  }
}

// Makes a new directory entry durable (after link/rename).
void SyncDirectory(const fs::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

// Refuses a subject folder that holds anything but the session lock and
// leftovers of an interrupted Create (which are ignored).
Status CheckSubjectFolder(const fs::path& sub) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(sub, ec);
  if (status.type() == fs::file_type::not_found) return {};
  if (ec) {
    return Error{
        fmt::format("cannot inspect {}: {}", sub.string(), ec.message())};
  }
  if (status.type() != fs::file_type::directory) {
    return Error{fmt::format(
        "{} exists and is not a folder; refusing to replace it", sub.string())};
  }
  fs::directory_iterator it(sub, ec);
  if (ec) {
    return Error{fmt::format("cannot list {}: {}", sub.string(), ec.message())};
  }
  for (; it != fs::directory_iterator(); it.increment(ec)) {
    if (ec) break;
    const std::string name = it->path().filename().string();
    if (!name.starts_with(kCreatingPrefix) && name != kLockFile) {
      return Error{fmt::format(
          "{} exists but holds no journal; refusing to write into it (move it "
          "away or choose another output folder)",
          sub.string())};
    }
  }
  if (ec) {
    return Error{fmt::format("cannot list {}: {}", sub.string(), ec.message())};
  }
  return {};
}

// Removes what a Create killed before its link left behind (only the lock's
// holder calls this, so no other process is creating one).
void RemoveCreationLeftovers(const fs::path& sub) {
  std::error_code ec;
  std::vector<fs::path> leftovers;
  for (auto it = fs::directory_iterator(sub, ec);
       !ec && it != fs::directory_iterator(); it.increment(ec)) {
    if (it->path().filename().string().starts_with(kCreatingPrefix)) {
      leftovers.push_back(it->path());
    }
  }
  for (const fs::path& p : leftovers) fs::remove(p, ec);
}

// Builds a complete journal file at `temp` (rollback-journal mode, so the
// single file is complete and synced once the transaction commits).
Status BuildJournalFile(const fs::path& temp, const SessionInfo& session) {
  auto db = db::OpenDb(temp, /*create=*/true);
  if (!db) return db.error();
  sqlite3* h = db->get();
  if (Status s = db::Exec(h, "PRAGMA synchronous=FULL",
                          "cannot set synchronous=FULL on", temp);
      !s) {
    return s;
  }
  if (Status s = db::Exec(h, "BEGIN IMMEDIATE", "cannot write", temp); !s) {
    return s;
  }
  if (Status s = db::CreateSchema(h, temp, session); !s) {
    db::RollbackIfOpen(h);
    return s;
  }
  if (Status s = db::Exec(h, "COMMIT", "cannot write", temp); !s) {
    db::RollbackIfOpen(h);
    return s;
  }
  sqlite3* raw = db->release();
  if (sqlite3_close(raw) != SQLITE_OK) {
    Error error = db::SqliteError(raw, "cannot close", temp);
    sqlite3_close_v2(raw);
    return error;
  }
  return {};
}

// Gives `temp` the name `target` unless `target` exists; never replaces.
// Returns EEXIST as `*exists`.
Status LinkNoReplace(const fs::path& temp, const fs::path& target,
                     bool* exists) {
  *exists = false;
  if (::link(temp.c_str(), target.c_str()) == 0) {
    ::unlink(temp.c_str());
    return {};
  }
  int err = errno;
  if (err == EPERM || err == ENOTSUP || err == EOPNOTSUPP || err == EXDEV ||
      err == EMLINK) {
    // File systems without hard links: an atomic rename that refuses to
    // replace.
    if (::renameat2(AT_FDCWD, temp.c_str(), AT_FDCWD, target.c_str(),
                    RENAME_NOREPLACE) == 0) {
      return {};
    }
    err = errno;
  }
  if (err == EEXIST) {
    *exists = true;
    return Error{"exists"};
  }
  return Error{
      fmt::format("cannot create {}: {}", target.string(), std::strerror(err))};
}

}  // namespace

fs::path JournalPath(const fs::path& dir, std::string_view subject_label) {
  return JournalPath(dir, subject_label, "");
}

fs::path JournalPath(const fs::path& dir, std::string_view subject_label,
                     std::string_view session_label) {
  return SessionFolder(dir, subject_label, session_label) / kJournalFile;
}

Journal::Journal(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Journal::Journal(Journal&& other) noexcept = default;
Journal& Journal::operator=(Journal&& other) noexcept = default;
Journal::~Journal() = default;

const SessionInfo& Journal::session() const { return impl_->session; }
const fs::path& Journal::path() const { return impl_->path; }

Result<Journal> Journal::Create(const fs::path& dir,
                                const SessionInfo& session) {
  return Create(dir, session, "");
}

Result<Journal> Journal::Create(const fs::path& dir, const SessionInfo& session,
                                std::string_view session_label) {
  try {
    if (Status s = ValidateSession(session); !s) return s.error();
    if (!session_label.empty()) {
      if (Status s = ValidateSessionLabel(session_label); !s) return s.error();
    }
    const std::string& label = session.subject_label;
    const fs::path path = JournalPath(dir, label, session_label);
    const fs::path sub = path.parent_path();
    if (!PathExists(path)) {
      if (Status s = CheckSessionLayout(dir, label, session_label); !s) {
        return s.error();
      }
      if (Status s = CheckSubjectFolder(sub); !s) return s.error();
    }
    // Taken before anything is written, so a running session is reported as
    // in use rather than as existing.
    Result<SessionLock> lock = SessionLock::Acquire(dir, label, session_label);
    if (!lock) return lock.error();
    if (PathExists(path)) {
      return AlreadyExists(dir, label, session_label, path);
    }
    if (Status s = CheckSessionLayout(dir, label, session_label); !s) {
      return s.error();
    }
    if (Status s = CheckSubjectFolder(sub); !s) return s.error();
    const fs::path temp =
        sub / fmt::format("{}{}-{}", kCreatingPrefix, ::getpid(),
                          g_creating_counter.fetch_add(1));
    RemoveDbFiles(temp);
    if (Status s = BuildJournalFile(temp, session); !s) {
      RemoveDbFiles(temp);
      return s.error();
    }
    bool exists = false;
    Status linked = LinkNoReplace(temp, path, &exists);
    RemoveDbFiles(temp);
    if (exists) return AlreadyExists(dir, label, session_label, path);
    if (!linked) return linked.error();
    SyncDirectory(sub);
    SyncDirectory(sub.parent_path());
    if (!session_label.empty()) SyncDirectory(dir);
    return OpenLocked(dir, label, session_label, std::move(lock).value());
  } catch (const std::exception& e) {
    return Internal("cannot create the journal", e);
  }
}

Result<Journal> Journal::Open(const fs::path& dir,
                              std::string_view subject_label) {
  return Open(dir, subject_label, "");
}

Result<Journal> Journal::Open(const fs::path& dir,
                              std::string_view subject_label,
                              std::string_view session_label) {
  try {
    if (Status s = ValidateSubjectLabel(subject_label); !s) return s.error();
    if (!session_label.empty()) {
      if (Status s = ValidateSessionLabel(session_label); !s) return s.error();
    }
    const fs::path path = JournalPath(dir, subject_label, session_label);
    if (!PathExists(path)) {
      return NoJournal(dir, subject_label, session_label, path);
    }
    Result<SessionLock> lock =
        SessionLock::Acquire(dir, subject_label, session_label);
    if (!lock) return lock.error();
    return OpenLocked(dir, subject_label, session_label,
                      std::move(lock).value());
  } catch (const std::exception& e) {
    return Internal("cannot open the journal", e);
  }
}

Result<Journal> Journal::OpenLocked(const fs::path& dir,
                                    std::string_view subject_label,
                                    std::string_view session_label,
                                    SessionLock lock) {
  const fs::path path = JournalPath(dir, subject_label, session_label);
  if (!PathExists(path)) {
    return NoJournal(dir, subject_label, session_label, path);
  }
  RemoveCreationLeftovers(path.parent_path());
  auto db = db::OpenDb(path, /*create=*/false);
  if (!db) return db.error();
  sqlite3* h = db->get();
  if (auto version = db::CheckSchemaVersion(h, path); !version) {
    return version.error();
  }
  if (Status s = db::Configure(h, path); !s) return s.error();
  // An older journal gets the newer columns before anything is appended.
  auto old = db::ReadSession(h, path);
  if (!old) return old.error();
  if (Status s = db::Exec(h, "BEGIN IMMEDIATE", "cannot upgrade", path); !s) {
    return s.error();
  }
  if (Status s = db::UpgradeSchema(h, path, "an upgrade of an older journal");
      !s) {
    db::RollbackIfOpen(h);
    return s.error();
  }
  if (Status s = db::Exec(h, "COMMIT", "cannot upgrade", path); !s) {
    db::RollbackIfOpen(h);
    return s.error();
  }
  auto session = db::ReadSession(h, path);
  if (!session) return session.error();
  if (session->subject_label != subject_label) {
    return Error{fmt::format("{} belongs to sub-{}, not sub-{}", path.string(),
                             session->subject_label, subject_label)};
  }
  auto impl = std::make_unique<Impl>();
  impl->lock = std::move(lock);
  impl->db = std::move(db).value();
  impl->dir = dir;
  impl->session_label = std::string(session_label);
  impl->path = path;
  impl->session = std::move(session).value();
  return Journal(std::move(impl));
}

Status Journal::CheckSameSession(const SessionInfo& given) const {
  try {
    const SessionInfo& kept = impl_->session;
    std::vector<std::string> differences;
    if (given.subject_label != kept.subject_label) {
      differences.push_back(fmt::format(
          "the subject differs from the journal's (sub-{} in the journal, "
          "sub-{} now)",
          kept.subject_label, given.subject_label));
    }
    if (given.protocol_sha256 != kept.protocol_sha256) {
      differences.push_back(fmt::format(
          "the protocol differs from the journal's (sha256 {} in the journal, "
          "{} now)",
          kept.protocol_sha256, given.protocol_sha256));
    }
    if (given.master_seed != kept.master_seed) {
      differences.push_back(fmt::format(
          "the seed differs from the journal's ({} in the journal, {} now)",
          kept.master_seed, given.master_seed));
    }
    if (given.burrlab_version != kept.burrlab_version) {
      differences.push_back(fmt::format(
          "the burrlab version differs from the journal's ({} in "
          "the journal, {} now)",
          Quoted(kept.burrlab_version), Quoted(given.burrlab_version)));
    }
    // Fields the journal did not record (schema version 1) are not checked.
    for (const SetupField& k : kept.setup) {
      std::string now = "not given";
      for (const SetupField& g : given.setup) {
        if (g.name == k.name) now = Quoted(g.value);
      }
      if (now != Quoted(k.value)) {
        differences.push_back(fmt::format(
            "{} differs from the journal's ({} in the journal, {} now)", k.name,
            Quoted(k.value), now));
      }
    }
    if (differences.empty()) return {};
    return Error{
        fmt::format("cannot resume {} in {}: {}",
                    SessionName(kept.subject_label, impl_->session_label),
                    impl_->dir.string(), fmt::join(differences, "; "))};
  } catch (const std::exception& e) {
    return Internal("cannot compare sessions", e);
  }
}

Status Journal::Restart(const SessionInfo& session) {
  try {
    if (Status s = ValidateSession(session); !s) return s;
    const SessionInfo& kept = impl_->session;
    if (session.subject_label != kept.subject_label) {
      return Error{fmt::format("cannot restart sub-{} as sub-{}",
                               kept.subject_label, session.subject_label)};
    }
    sqlite3* h = impl_->db.get();
    const fs::path& path = impl_->path;
    const std::string what = "cannot restart the session in";
    if (Status s = db::Exec(h, "BEGIN IMMEDIATE", what, path); !s) return s;
    auto fail = [h](Status s) {
      db::RollbackIfOpen(h);
      return s;
    };
    Result<int> trials = db::CountTrials(h, path);
    if (!trials) return fail(trials.error());
    if (*trials > 0) {
      return fail(Error{
          fmt::format("cannot restart {} in {}: it already holds {} trial{}",
                      SessionName(kept.subject_label, impl_->session_label),
                      impl_->dir.string(), *trials, *trials == 1 ? "" : "s")});
    }
    if (Status s = db::WriteSession(h, path, session); !s) return fail(s);
    if (Status s = db::Exec(h, "COMMIT", what, path); !s) return fail(s);
    impl_->session = session;
    return {};
  } catch (const std::exception& e) {
    db::RollbackIfOpen(impl_->db.get());
    return Internal("cannot restart the session", e);
  }
}

Status Journal::Append(const TrialRecord& trial,
                       const std::vector<TraceSamples>& traces) {
  try {
    if (Status s = ValidateTrial(trial); !s) return s;
    for (const TraceSamples& trace : traces) {
      if (Status s = ValidateTrace(trace, trial.trial_index); !s) return s;
    }
    sqlite3* h = impl_->db.get();
    const fs::path& path = impl_->path;
    const std::string what =
        fmt::format("cannot append trial {} to", trial.trial_index);
    if (Status s = db::Exec(h, "BEGIN IMMEDIATE", what, path); !s) return s;
    auto fail = [h](Status s) {
      db::RollbackIfOpen(h);
      return s;
    };
    Result<int> next = db::CountTrials(h, path);
    if (!next) return fail(next.error());
    if (trial.trial_index < *next) {
      return fail(
          Error{fmt::format("trial {} is already in {}; the next trial is {}",
                            trial.trial_index, path.string(), *next)});
    }
    if (trial.trial_index > *next) {
      return fail(Error{
          fmt::format("trial {} would leave a gap in {}; the next trial is {}",
                      trial.trial_index, path.string(), *next)});
    }
    if (Status s = db::InsertTrial(h, path, trial); !s) return fail(s);
    for (const TraceSamples& trace : traces) {
      if (Status s = db::InsertTrace(h, path, trace); !s) return fail(s);
    }
    if (Status s = db::Exec(h, "COMMIT", what, path); !s) return fail(s);
    return {};
  } catch (const std::exception& e) {
    db::RollbackIfOpen(impl_->db.get());
    return Internal("cannot append a trial", e);
  }
}

Status Journal::SetPlannedTrials(int planned_trials) {
  try {
    return db::WritePlannedTrials(impl_->db.get(), impl_->path, planned_trials);
  } catch (const std::exception& e) {
    return Internal("cannot write the planned trials", e);
  }
}

Status Journal::MarkComplete() {
  try {
    return db::WriteCompleted(impl_->db.get(), impl_->path);
  } catch (const std::exception& e) {
    return Internal("cannot mark the session complete", e);
  }
}

Result<SessionProgress> Journal::Progress() const {
  try {
    return db::ReadProgress(impl_->db.get(), impl_->path);
  } catch (const std::exception& e) {
    return Internal("cannot read the progress", e);
  }
}

Result<SessionProgress> ReadSessionProgress(const fs::path& dir,
                                            std::string_view subject_label) {
  return ReadSessionProgress(dir, subject_label, "");
}

Result<SessionProgress> ReadSessionProgress(const fs::path& dir,
                                            std::string_view subject_label,
                                            std::string_view session_label) {
  const fs::path path = JournalPath(dir, subject_label, session_label);
  try {
    auto db = db::OpenDb(path, /*create=*/false);
    if (!db) return db.error();
    if (auto version = db::CheckSchemaVersion(db->get(), path); !version) {
      return version.error();
    }
    return db::ReadProgress(db->get(), path);
  } catch (const std::exception& e) {
    return Internal("cannot read the progress", e);
  }
}

Result<int> Journal::NextTrialIndex() const {
  try {
    return db::CountTrials(impl_->db.get(), impl_->path);
  } catch (const std::exception& e) {
    return Internal("cannot count the trials", e);
  }
}

Result<std::vector<TrialRecord>> Journal::Trials() const {
  try {
    return db::ReadTrials(impl_->db.get(), impl_->path);
  } catch (const std::exception& e) {
    return Internal("cannot read the trials", e);
  }
}

Result<std::vector<TraceSamples>> Journal::Traces(int trial_index) const {
  try {
    return db::ReadTraces(impl_->db.get(), impl_->path, trial_index);
  } catch (const std::exception& e) {
    return Internal("cannot read the traces", e);
  }
}

Result<JournalSettings> Journal::Settings() const {
  try {
    sqlite3* h = impl_->db.get();
    const fs::path& path = impl_->path;
    JournalSettings settings;
    auto mode = db::Prepare(h, "PRAGMA journal_mode", "cannot read", path);
    if (!mode) return mode.error();
    if (sqlite3_step(mode->get()) != SQLITE_ROW) {
      return db::SqliteError(h, "cannot read", path);
    }
    const unsigned char* text = sqlite3_column_text(mode->get(), 0);
    settings.journal_mode = text ? reinterpret_cast<const char*>(text) : "";
    auto sync = db::Prepare(h, "PRAGMA synchronous", "cannot read", path);
    if (!sync) return sync.error();
    if (sqlite3_step(sync->get()) != SQLITE_ROW) {
      return db::SqliteError(h, "cannot read", path);
    }
    settings.synchronous = sqlite3_column_int(sync->get(), 0);
    auto keys = db::Prepare(h, "PRAGMA foreign_keys", "cannot read", path);
    if (!keys) return keys.error();
    if (sqlite3_step(keys->get()) != SQLITE_ROW) {
      return db::SqliteError(h, "cannot read", path);
    }
    settings.foreign_keys = sqlite3_column_int(keys->get(), 0) != 0;
    auto version = db::CheckSchemaVersion(h, path);
    if (!version) return version.error();
    settings.schema_version = *version;
    return settings;
  } catch (const std::exception& e) {
    return Internal("cannot read the settings", e);
  }
}

Status Journal::CheckIntegrity() const {
  try {
    sqlite3* h = impl_->db.get();
    const fs::path& path = impl_->path;
    auto check = db::Prepare(h, "PRAGMA integrity_check",
                             "cannot check the integrity of", path);
    if (!check) return check.error();
    std::vector<std::string> problems;
    int rc = SQLITE_OK;
    while ((rc = sqlite3_step(check->get())) == SQLITE_ROW) {
      const unsigned char* text = sqlite3_column_text(check->get(), 0);
      problems.emplace_back(text ? reinterpret_cast<const char*>(text) : "");
    }
    if (rc != SQLITE_DONE) {
      return db::SqliteError(h, "cannot check the integrity of", path);
    }
    if (problems.size() == 1 && problems[0] == "ok") return {};
    return Error{fmt::format("{} fails the integrity check: {}", path.string(),
                             fmt::join(problems, "; "))};
  } catch (const std::exception& e) {
    return Internal("cannot check the integrity", e);
  }
}

Status Journal::LimitSizeForTesting(std::int64_t max_bytes) {
  try {
    sqlite3* h = impl_->db.get();
    const fs::path& path = impl_->path;
    auto size = db::Prepare(h, "PRAGMA page_size", "cannot read", path);
    if (!size) return size.error();
    if (sqlite3_step(size->get()) != SQLITE_ROW) {
      return db::SqliteError(h, "cannot read", path);
    }
    const std::int64_t page_size = sqlite3_column_int64(size->get(), 0);
    // PRAGMA arguments cannot be bound; this one is a number formatted here.
    const std::string sql =
        fmt::format("PRAGMA max_page_count = {}", max_bytes / page_size);
    return db::Exec(h, sql.c_str(), "cannot limit the size of", path);
  } catch (const std::exception& e) {
    return Internal("cannot limit the size", e);
  }
}

}  // namespace burrlab::results_schema
