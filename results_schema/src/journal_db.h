// SQLite access shared by the journal and the BIDS export (not public): RAII
// handles, connection settings, the schema, and reading and writing records.
// Every statement with values binds them as parameters.
#ifndef BURRLAB_RESULTS_SCHEMA_SRC_JOURNAL_DB_H_
#define BURRLAB_RESULTS_SCHEMA_SRC_JOURNAL_DB_H_

#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/results_schema/journal.h"  // SessionProgress
#include "burrlab/results_schema/records.h"

namespace burrlab::results_schema::db {

// Closes a connection (sqlite3_close_v2).
struct CloseDb {
  void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
// An open connection.
using Db = std::unique_ptr<sqlite3, CloseDb>;

// Finalizes a statement.
struct FinalizeStmt {
  void operator()(sqlite3_stmt* stmt) const { sqlite3_finalize(stmt); }
};
// A prepared statement.
using Stmt = std::unique_ptr<sqlite3_stmt, FinalizeStmt>;

// "<what> <path>: <sqlite3_errmsg>".
Error SqliteError(sqlite3* db, std::string_view what,
                  const std::filesystem::path& path);

// Opens `path` read-write (creating it only when `create`), refusing symbolic
// links, with a 10 s busy timeout.
Result<Db> OpenDb(const std::filesystem::path& path, bool create);

// Sets journal_mode=WAL (checking it took effect), synchronous=FULL and
// foreign_keys=ON on this connection.
Status Configure(sqlite3* db, const std::filesystem::path& path);

// Runs fixed SQL without parameters.
Status Exec(sqlite3* db, const char* sql, std::string_view what,
            const std::filesystem::path& path);

// Prepares one statement.
Result<Stmt> Prepare(sqlite3* db, const char* sql, std::string_view what,
                     const std::filesystem::path& path);

// The time now, ISO 8601 UTC ("2026-11-27T09:30:00Z").
std::string NowUtc();

// Rolls back if a transaction is open; keeps the first error.
void RollbackIfOpen(sqlite3* db);

// Creates the tables and writes the version and session rows (in the
// caller's transaction).
Status CreateSchema(sqlite3* db, const std::filesystem::path& path,
                    const SessionInfo& session);

// Writes (or replaces) the session row.
Status WriteSession(sqlite3* db, const std::filesystem::path& path,
                    const SessionInfo& session);

// True when `table` has `column`.
Result<bool> HasColumn(sqlite3* db, const std::filesystem::path& path,
                       std::string_view table, std::string_view column);

// Gives an older journal what later versions added (2: the session's setup,
// the trials' source; 3: the session's planned trials and completion; 4: the
// trials' practice and late marks) and
// records the current version; nothing when it has them. In the caller's
// transaction.
Status UpgradeSchema(sqlite3* db, const std::filesystem::path& path,
                     std::string_view written_by);

// Trials stored, planned trials and completion (unknown before version 3).
Result<SessionProgress> ReadProgress(sqlite3* db,
                                     const std::filesystem::path& path);

// Records the trials the session will present (NULL for 0: not known).
Status WritePlannedTrials(sqlite3* db, const std::filesystem::path& path,
                          int planned_trials);

// Records that the session ran to its end, now (the first time only).
Status WriteCompleted(sqlite3* db, const std::filesystem::path& path);

// Reads the schema version; refuses a missing table or a newer version.
Result<int> CheckSchemaVersion(sqlite3* db, const std::filesystem::path& path);

// Reads the session row.
Result<SessionInfo> ReadSession(sqlite3* db, const std::filesystem::path& path);

// Number of stored trials.
Result<int> CountTrials(sqlite3* db, const std::filesystem::path& path);

// All trials in trial_index order.
Result<std::vector<TrialRecord>> ReadTrials(sqlite3* db,
                                            const std::filesystem::path& path);

// A trace without its samples, for planning an export.
struct TraceHeader {
  TraceSamples trace;          // rows left empty
  std::int64_t row_count = 0;  // rows stored
};

// Headers of every trace in (trial_index, interval_index) order.
Result<std::vector<TraceHeader>> ReadTraceHeaders(
    sqlite3* db, const std::filesystem::path& path);

// The traces of one trial with their samples, in interval order.
Result<std::vector<TraceSamples>> ReadTraces(sqlite3* db,
                                             const std::filesystem::path& path,
                                             int trial_index);

// Inserts one trial row (in the caller's transaction).
Status InsertTrial(sqlite3* db, const std::filesystem::path& path,
                   const TrialRecord& trial);

// Inserts one trace row with compressed samples (in the caller's transaction).
Status InsertTrace(sqlite3* db, const std::filesystem::path& path,
                   const TraceSamples& trace);

}  // namespace burrlab::results_schema::db

#endif  // BURRLAB_RESULTS_SCHEMA_SRC_JOURNAL_DB_H_
