// The session journal: one SQLite database per subject and session at
// DIR/sub-<label>/journal.sqlite, or DIR/sub-<label>/ses-<session>/
// journal.sqlite for a labelled session (dataset_layout.h) (WAL,
// synchronous=FULL, foreign keys on), one transaction per completed trial. A
// crash or SIGKILL loses at most the trial being appended, never half a trial;
// `burrlab run --resume` reopens the journal, checks it belongs to the same
// protocol, seed, burrlab version and set-up, and continues from
// Trials().size() with the last trial's rng_state. An open journal holds the
// session's lock (session_lock.h): one process per session.
//
// Tables (schema version 3; every statement is parametrized):
//   schema_version(version, written_by)          one row per version written
//   session(id = 1, study, protocol_path, protocol_sha256, subject_label,
//           master_seed TEXT (decimal), burrlab_version, started_utc,
//           setup TEXT (a JSON object of text values; version 2 added it),
//           planned_trials INTEGER (NULL: not known ahead) and
//           completed_utc TEXT (NULL until the session ran to its end);
//           version 3 added these two)
//   trial(trial_index PRIMARY KEY, the TrialRecord fields, interval_materials
//         and extra as JSON text, committed_utc)
//   trace(trial_index REFERENCES trial, interval_index, sampling_frequency_hz,
//         start_time_s, columns (JSON array), row_count, encoding, samples)
// samples is zlib(row-major little-endian float64), encoding
// "zlib-f64le-rowmajor"; in Python: np.frombuffer(zlib.decompress(b),
// "<f8").reshape(row_count, len(columns)).
#ifndef BURRLAB_RESULTS_SCHEMA_JOURNAL_H_
#define BURRLAB_RESULTS_SCHEMA_JOURNAL_H_

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/results_schema/records.h"
#include "burrlab/results_schema/session_lock.h"

namespace burrlab::results_schema {

// Journal schema version this burrlab writes and the newest it reads.
inline constexpr int kJournalSchemaVersion = 4;

// DIR/sub-<label>/journal.sqlite.
std::filesystem::path JournalPath(const std::filesystem::path& dir,
                                  std::string_view subject_label);
// The journal of session `session_label` (none when empty):
// DIR/sub-<label>/ses-<session>/journal.sqlite.
std::filesystem::path JournalPath(const std::filesystem::path& dir,
                                  std::string_view subject_label,
                                  std::string_view session_label);

// The SQLite settings in force on a journal's connection (for tests and
// `burrlab run --resume` diagnostics).
struct JournalSettings {
  std::string journal_mode;   // "wal"
  int synchronous = 0;        // 2 = FULL
  bool foreign_keys = false;  // true
  int schema_version = 0;     // kJournalSchemaVersion
};

// How far a session got.
struct SessionProgress {
  int trials = 0;                     // trials stored
  std::optional<int> planned_trials;  // trials the protocol presents, when
                                      // known ahead (no adaptive block)
  std::optional<bool> complete;       // the session ran to its end; none: the
                                 // journal predates the record (version < 3)
};

// The progress recorded in DIR/sub-<label>/journal.sqlite, read without
// taking the session's lock (a running session's journal can be read).
Result<SessionProgress> ReadSessionProgress(const std::filesystem::path& dir,
                                            std::string_view subject_label);
// The same for session `session_label` of the subject (none when empty).
Result<SessionProgress> ReadSessionProgress(const std::filesystem::path& dir,
                                            std::string_view subject_label,
                                            std::string_view session_label);

// An open journal. Move-only; closing is the destructor.
class Journal {
 public:
  // Creates DIR/sub-<label>/journal.sqlite for a new session, taking the
  // session's lock first (refused with SessionLock's message when another
  // process holds it). Refuses with "sub-<label> already exists in DIR; use
  // --resume to continue it" when the journal exists (saying it holds no
  // trials and --resume starts it again when that is so), and refuses a
  // DIR/sub-<label> folder that holds files other than a journal. The file
  // appears complete or not at all (built under a temporary name and
  // hard-linked into place, which never replaces a file).
  static Result<Journal> Create(const std::filesystem::path& dir,
                                const SessionInfo& session);
  // The same for session `session_label` of the subject (none when empty),
  // in DIR/sub-<label>/ses-<session>/; messages name it "sub-<label>
  // ses-<session>". A subject's sessions are all labelled or none is: a
  // labelled session of a subject recorded without one is refused ("sub-01
  // in DIR was recorded without a session label (...)"), and so is an
  // unlabelled one of a subject with labelled sessions ("sub-01 in DIR has
  // labelled sessions (ses-1); give --session LABEL ...").
  static Result<Journal> Create(const std::filesystem::path& dir,
                                const SessionInfo& session,
                                std::string_view session_label);

  // Opens an existing journal to resume it, taking the session's lock (see
  // Create); fails with "no journal for sub-<label> in DIR ..." when there is
  // none and refuses journals written by a newer schema version.
  static Result<Journal> Open(const std::filesystem::path& dir,
                              std::string_view subject_label);
  // The same for session `session_label` of the subject (none when empty).
  static Result<Journal> Open(const std::filesystem::path& dir,
                              std::string_view subject_label,
                              std::string_view session_label);

  // Moves the open connection.
  Journal(Journal&& other) noexcept;
  // Moves the open connection, closing this one's.
  Journal& operator=(Journal&& other) noexcept;
  // Closes the connection.
  ~Journal();

  // The session recorded when the journal was created.
  const SessionInfo& session() const;

  // Path of the journal file.
  const std::filesystem::path& path() const;

  // OK when `given` (from the command line and protocol file of a resume) has
  // the journal's protocol hash, master seed, burrlab version and every setup
  // field the journal recorded; otherwise names each that differs: "cannot
  // resume sub-01 in DIR: the protocol differs from the journal's (sha256 J
  // in the journal, G now)", "the seed differs ...", "the burrlab version
  // differs ...", "radius_mm differs from the journal's ("2" in the journal,
  // "1.5" now)", joined with "; ".
  Status CheckSameSession(const SessionInfo& given) const;

  // Replaces the session row with `session` (same subject) when the journal
  // holds no trial: a run that stopped before its first trial starts again
  // with a corrected protocol or set-up. Refused once a trial is stored.
  Status Restart(const SessionInfo& session);

  // Appends one completed trial and its traces in one transaction, durable
  // when this returns OK. trial.trial_index must be the next index
  // (NextTrialIndex()); a repeated index is refused. On any error nothing of
  // the trial is stored.
  Status Append(const TrialRecord& trial,
                const std::vector<TraceSamples>& traces);

  // Records how many trials the session will present; 0: not known ahead.
  Status SetPlannedTrials(int planned_trials);

  // Records that the session ran to its end (its time, the first time).
  Status MarkComplete();

  // Trials stored, planned trials and whether the session is complete.
  Result<SessionProgress> Progress() const;

  // Index the next appended trial must have (= number of trials stored).
  Result<int> NextTrialIndex() const;

  // All stored trials in trial_index order.
  Result<std::vector<TrialRecord>> Trials() const;

  // The traces of trial `trial_index` in interval order (empty if none).
  Result<std::vector<TraceSamples>> Traces(int trial_index) const;

  // The SQLite settings in force (journal mode, synchronous, foreign keys).
  Result<JournalSettings> Settings() const;

  // OK when PRAGMA integrity_check answers "ok".
  Status CheckIntegrity() const;

  // Caps the database size (PRAGMA max_page_count) so tests can make a write
  // fail with SQLITE_FULL; not for production use.
  Status LimitSizeForTesting(std::int64_t max_bytes);

 private:
  struct Impl;
  explicit Journal(std::unique_ptr<Impl> impl);
  static Result<Journal> OpenLocked(const std::filesystem::path& dir,
                                    std::string_view subject_label,
                                    std::string_view session_label,
                                    SessionLock lock);
  std::unique_ptr<Impl> impl_;
};

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_JOURNAL_H_
