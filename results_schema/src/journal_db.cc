// SQLite access shared by the journal and the BIDS export.
#include "journal_db.h"

#include <fmt/chrono.h>
#include <fmt/format.h>
#include <zlib.h>

#include <bit>
#include <charconv>
#include <chrono>
#include <cstring>
#include <ctime>
#include <nlohmann/json.hpp>

#include "burrlab/results_schema/journal.h"
#include "file_writes.h"
#include "text.h"

namespace burrlab::results_schema::db {
namespace {

constexpr std::string_view kTraceEncoding = "zlib-f64le-rowmajor";

std::string ColumnText(sqlite3_stmt* stmt, int column) {
  const unsigned char* text = sqlite3_column_text(stmt, column);
  if (text == nullptr) return {};
  return std::string(
      reinterpret_cast<const char*>(text),
      static_cast<std::size_t>(sqlite3_column_bytes(stmt, column)));
}

bool IsNull(sqlite3_stmt* stmt, int column) {
  return sqlite3_column_type(stmt, column) == SQLITE_NULL;
}

std::optional<double> ColumnOptionalDouble(sqlite3_stmt* stmt, int column) {
  if (IsNull(stmt, column)) return std::nullopt;
  return sqlite3_column_double(stmt, column);
}

std::optional<int> ColumnOptionalInt(sqlite3_stmt* stmt, int column) {
  if (IsNull(stmt, column)) return std::nullopt;
  return sqlite3_column_int(stmt, column);
}

std::optional<bool> ColumnOptionalBool(sqlite3_stmt* stmt, int column) {
  if (IsNull(stmt, column)) return std::nullopt;
  return sqlite3_column_int(stmt, column) != 0;
}

int BindText(sqlite3_stmt* stmt, int index, std::string_view text) {
  return sqlite3_bind_text64(stmt, index, text.data(), text.size(),
                             SQLITE_TRANSIENT, SQLITE_UTF8);
}

int BindOptionalDouble(sqlite3_stmt* stmt, int index,
                       const std::optional<double>& value) {
  return value ? sqlite3_bind_double(stmt, index, *value)
               : sqlite3_bind_null(stmt, index);
}

int BindOptionalInt(sqlite3_stmt* stmt, int index,
                    const std::optional<int>& value) {
  return value ? sqlite3_bind_int(stmt, index, *value)
               : sqlite3_bind_null(stmt, index);
}

int BindOptionalBool(sqlite3_stmt* stmt, int index,
                     const std::optional<bool>& value) {
  return value ? sqlite3_bind_int(stmt, index, *value ? 1 : 0)
               : sqlite3_bind_null(stmt, index);
}

// Parses a JSON array of strings written by this library.
bool ParseStringArray(const std::string& text, std::vector<std::string>* out) {
  const auto json = nlohmann::json::parse(text, nullptr, false);
  if (json.is_discarded() || !json.is_array()) return false;
  out->clear();
  for (const auto& item : json) {
    if (!item.is_string()) return false;
    out->push_back(item.get<std::string>());
  }
  return true;
}

std::string StringArrayJson(const std::vector<std::string>& items) {
  return nlohmann::json(items).dump(-1, ' ', false,
                                    nlohmann::json::error_handler_t::replace);
}

// Steps a statement that returns no rows.
Status StepDone(sqlite3* db, sqlite3_stmt* stmt, std::string_view what,
                const std::filesystem::path& path) {
  if (sqlite3_step(stmt) != SQLITE_DONE) return SqliteError(db, what, path);
  return {};
}

// Row-major little-endian float64, zlib-compressed. (Each value is copied
// whole where the machine is little-endian, byte by byte elsewhere: the same
// bytes; a session's journal writes every interval's trace.)
Result<std::string> EncodeSamples(const TraceSamples& trace) {
  std::size_t values = 0;
  for (const auto& row : trace.rows) values += row.size();
  std::string raw(values * 8, '\0');
  char* out = raw.data();
  for (const auto& row : trace.rows) {
    for (double value : row) {
      auto bits = std::bit_cast<std::uint64_t>(value);
      if constexpr (std::endian::native == std::endian::little) {
        std::memcpy(out, &bits, 8);
      } else {
        for (int k = 0; k < 8; ++k) {
          out[k] = static_cast<char>(bits & 0xFFu);
          bits >>= 8;
        }
      }
      out += 8;
    }
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &size,
                reinterpret_cast<const Bytef*>(raw.data()),
                static_cast<uLong>(raw.size()), kTraceDeflateLevel) != Z_OK) {
    return Error{
        fmt::format("trial {}, interval {}: cannot compress the trace samples",
                    trace.trial_index, trace.interval_index)};
  }
  packed.resize(size);
  return packed;
}

Status DecodeSamples(const void* blob, std::size_t blob_size,
                     std::int64_t row_count, TraceSamples* trace,
                     const std::filesystem::path& path) {
  const std::uint64_t columns = trace->columns.size();
  const std::string where =
      fmt::format("{}: trial {}, interval {}", path.string(),
                  trace->trial_index, trace->interval_index);
  if (row_count < 0 || columns == 0 ||
      static_cast<std::uint64_t>(row_count) > kMaxTraceValues / columns) {
    return Error{fmt::format("{}: implausible trace size ({} rows, {} columns)",
                             where, row_count, columns)};
  }
  const std::uint64_t values = static_cast<std::uint64_t>(row_count) * columns;
  std::string raw(values * 8, '\0');
  uLongf size = static_cast<uLongf>(raw.size());
  if (values > 0 || blob_size > 0) {
    const int rc = uncompress(reinterpret_cast<Bytef*>(raw.data()), &size,
                              static_cast<const Bytef*>(blob),
                              static_cast<uLong>(blob_size));
    if (rc != Z_OK || size != raw.size()) {
      return Error{fmt::format("{}: the trace samples are damaged", where)};
    }
  }
  trace->rows.assign(static_cast<std::size_t>(row_count),
                     std::vector<double>(columns));
  const char* in = raw.data();
  for (auto& row : trace->rows) {
    for (double& value : row) {
      std::uint64_t bits = 0;
      if constexpr (std::endian::native == std::endian::little) {
        std::memcpy(&bits, in, 8);
      } else {
        for (int k = 7; k >= 0; --k) {
          bits = (bits << 8) | static_cast<unsigned char>(in[k]);
        }
      }
      value = std::bit_cast<double>(bits);
      in += 8;
    }
  }
  return {};
}

constexpr const char* kCreateSchemaSql = R"sql(
CREATE TABLE schema_version (
  version INTEGER NOT NULL,
  written_by TEXT NOT NULL
);
CREATE TABLE session (
  id INTEGER PRIMARY KEY CHECK (id = 1),
  study TEXT NOT NULL,
  protocol_path TEXT NOT NULL,
  protocol_sha256 TEXT NOT NULL,
  subject_label TEXT NOT NULL,
  master_seed TEXT NOT NULL,
  burrlab_version TEXT NOT NULL,
  started_utc TEXT NOT NULL,
  setup TEXT NOT NULL DEFAULT '{}' CHECK (json_valid(setup)),
  planned_trials INTEGER CHECK (planned_trials > 0),
  completed_utc TEXT
);
CREATE TABLE trial (
  trial_index INTEGER PRIMARY KEY CHECK (trial_index >= 0),
  block TEXT NOT NULL,
  method TEXT NOT NULL,
  task TEXT NOT NULL CHECK (task IN ('probe', 'drill')),
  trial_type TEXT NOT NULL,
  stim_level REAL,
  stim_unit TEXT NOT NULL,
  interval_materials TEXT NOT NULL CHECK (json_valid(interval_materials)),
  correct_answer TEXT NOT NULL,
  response TEXT NOT NULL,
  correct INTEGER CHECK (correct IN (0, 1)),
  response_time_s REAL,
  staircase_id INTEGER,
  reversal INTEGER CHECK (reversal IN (0, 1)),
  step_size REAL,
  estimate REAL,
  rng_state TEXT NOT NULL,
  source TEXT NOT NULL DEFAULT '',
  practice INTEGER NOT NULL DEFAULT 0 CHECK (practice IN (0, 1)),
  late INTEGER CHECK (late IN (0, 1)),
  extra TEXT NOT NULL CHECK (json_valid(extra)),
  committed_utc TEXT NOT NULL
);
CREATE TABLE trace (
  trial_index INTEGER NOT NULL REFERENCES trial (trial_index),
  interval_index INTEGER NOT NULL CHECK (interval_index >= 0),
  sampling_frequency_hz REAL NOT NULL CHECK (sampling_frequency_hz > 0),
  start_time_s REAL NOT NULL,
  columns TEXT NOT NULL CHECK (json_valid(columns)),
  row_count INTEGER NOT NULL CHECK (row_count >= 0),
  encoding TEXT NOT NULL,
  samples BLOB NOT NULL,
  PRIMARY KEY (trial_index, interval_index)
);
)sql";

}  // namespace

std::string NowUtc() {
  const std::time_t now =
      std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  return fmt::format("{:%Y-%m-%dT%H:%M:%SZ}", fmt::gmtime(now));
}

Error SqliteError(sqlite3* db, std::string_view what,
                  const std::filesystem::path& path) {
  const char* message =
      db != nullptr ? sqlite3_errmsg(db) : "out of memory opening the database";
  return Error{fmt::format("{} {}: {}", what, path.string(), message)};
}

Result<Db> OpenDb(const std::filesystem::path& path, bool create) {
  sqlite3* raw = nullptr;
  const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOFOLLOW |
                    (create ? SQLITE_OPEN_CREATE : 0);
  const int rc = sqlite3_open_v2(path.c_str(), &raw, flags, nullptr);
  Db db(raw);
  if (rc != SQLITE_OK) return SqliteError(raw, "cannot open", path);
  sqlite3_busy_timeout(raw, 10'000);
  return db;
}

Status Exec(sqlite3* db, const char* sql, std::string_view what,
            const std::filesystem::path& path) {
  if (sqlite3_exec(db, sql, nullptr, nullptr, nullptr) != SQLITE_OK) {
    return SqliteError(db, what, path);
  }
  return {};
}

Result<Stmt> Prepare(sqlite3* db, const char* sql, std::string_view what,
                     const std::filesystem::path& path) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &raw, nullptr) != SQLITE_OK) {
    sqlite3_finalize(raw);
    return SqliteError(db, what, path);
  }
  return Stmt(raw);
}

void RollbackIfOpen(sqlite3* db) {
  if (sqlite3_get_autocommit(db) == 0) {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
  }
}

Status Configure(sqlite3* db, const std::filesystem::path& path) {
  auto mode = Prepare(db, "PRAGMA journal_mode=WAL", "cannot read", path);
  if (!mode) return mode.error();
  if (sqlite3_step(mode->get()) != SQLITE_ROW) {
    return SqliteError(db, "cannot switch to WAL mode in", path);
  }
  const std::string got = ColumnText(mode->get(), 0);
  mode->reset();
  if (got != "wal") {
    return Error{fmt::format(
        "cannot use write-ahead logging in {} (journal mode stays \"{}\"); "
        "keep the output folder on a local disk",
        path.string(), got)};
  }
  if (Status s = Exec(db, "PRAGMA synchronous=FULL",
                      "cannot set synchronous=FULL on", path);
      !s) {
    return s;
  }
  return Exec(db, "PRAGMA foreign_keys=ON", "cannot enable foreign keys on",
              path);
}

// Records that this burrlab's schema version was written, by `written_by`.
Status InsertSchemaVersion(sqlite3* db, const std::filesystem::path& path,
                           std::string_view written_by) {
  auto version = Prepare(
      db, "INSERT INTO schema_version (version, written_by) VALUES (?1, ?2)",
      "cannot write the schema version of", path);
  if (!version) return version.error();
  sqlite3_bind_int(version->get(), 1, kJournalSchemaVersion);
  BindText(version->get(), 2, written_by);
  return StepDone(db, version->get(), "cannot write the schema version of",
                  path);
}

Status CreateSchema(sqlite3* db, const std::filesystem::path& path,
                    const SessionInfo& session) {
  if (Status s =
          Exec(db, kCreateSchemaSql, "cannot create the tables of", path);
      !s) {
    return s;
  }
  if (Status s = InsertSchemaVersion(db, path, session.burrlab_version); !s) {
    return s;
  }
  return WriteSession(db, path, session);
}

std::string SetupJson(const std::vector<SetupField>& setup) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const SetupField& f : setup) j[f.name] = f.value;
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

Status WriteSession(sqlite3* db, const std::filesystem::path& path,
                    const SessionInfo& session) {
  auto insert = Prepare(db,
                        "INSERT OR REPLACE INTO session (id, study, "
                        "protocol_path, protocol_sha256, subject_label, "
                        "master_seed, burrlab_version, started_utc, setup) "
                        "VALUES (1, ?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)",
                        "cannot write the session of", path);
  if (!insert) return insert.error();
  sqlite3_stmt* stmt = insert->get();
  BindText(stmt, 1, session.study);
  BindText(stmt, 2, session.protocol_path);
  BindText(stmt, 3, session.protocol_sha256);
  BindText(stmt, 4, session.subject_label);
  BindText(stmt, 5, std::to_string(session.master_seed));
  BindText(stmt, 6, session.burrlab_version);
  BindText(stmt, 7, session.started_utc);
  BindText(stmt, 8, SetupJson(session.setup));
  return StepDone(db, stmt, "cannot write the session of", path);
}

Result<bool> HasColumn(sqlite3* db, const std::filesystem::path& path,
                       std::string_view table, std::string_view column) {
  auto query = Prepare(db,
                       "SELECT COUNT(*) FROM pragma_table_info(?1) "
                       "WHERE name = ?2",
                       "cannot read the tables of", path);
  if (!query) return query.error();
  BindText(query->get(), 1, table);
  BindText(query->get(), 2, column);
  if (sqlite3_step(query->get()) != SQLITE_ROW) {
    return SqliteError(db, "cannot read the tables of", path);
  }
  return sqlite3_column_int(query->get(), 0) > 0;
}

Status UpgradeSchema(sqlite3* db, const std::filesystem::path& path,
                     std::string_view written_by) {
  struct Added {
    const char* table;
    const char* column;
    const char* sql;
  };
  static constexpr Added kAdded[] = {
      // Version 2.
      {"session", "setup",
       "ALTER TABLE session ADD COLUMN setup TEXT NOT NULL DEFAULT '{}' CHECK "
       "(json_valid(setup))"},
      {"trial", "source",
       "ALTER TABLE trial ADD COLUMN source TEXT NOT NULL DEFAULT ''"},
      // Version 3.
      {"session", "planned_trials",
       "ALTER TABLE session ADD COLUMN planned_trials INTEGER CHECK "
       "(planned_trials > 0)"},
      {"session", "completed_utc",
       "ALTER TABLE session ADD COLUMN completed_utc TEXT"},
      // Version 4: practice trials and late answers (no trial before it was
      // practice; whether an answer was late is unknown).
      {"trial", "practice",
       "ALTER TABLE trial ADD COLUMN practice INTEGER NOT NULL DEFAULT 0 "
       "CHECK (practice IN (0, 1))"},
      {"trial", "late",
       "ALTER TABLE trial ADD COLUMN late INTEGER CHECK (late IN (0, 1))"}};
  bool upgraded = false;
  for (const Added& added : kAdded) {
    Result<bool> has = HasColumn(db, path, added.table, added.column);
    if (!has) return has.error();
    if (*has) continue;
    if (Status s = Exec(db, added.sql, "cannot upgrade the journal", path);
        !s) {
      return s;
    }
    upgraded = true;
  }
  if (!upgraded) return {};
  return InsertSchemaVersion(db, path, written_by);
}

Result<SessionProgress> ReadProgress(sqlite3* db,
                                     const std::filesystem::path& path) {
  SessionProgress progress;
  Result<int> trials = CountTrials(db, path);
  if (!trials) return trials.error();
  progress.trials = *trials;
  Result<bool> has = HasColumn(db, path, "session", "completed_utc");
  if (!has) return has.error();
  if (!*has) return progress;  // schema version 1 or 2: not recorded
  auto query = Prepare(db,
                       "SELECT planned_trials, completed_utc FROM session "
                       "WHERE id = 1",
                       "cannot read the session of", path);
  if (!query) return query.error();
  if (sqlite3_step(query->get()) != SQLITE_ROW) {
    return SqliteError(db, "cannot read the session of", path);
  }
  if (!IsNull(query->get(), 0)) {
    progress.planned_trials = sqlite3_column_int(query->get(), 0);
  }
  progress.complete = !IsNull(query->get(), 1);
  return progress;
}

Status WritePlannedTrials(sqlite3* db, const std::filesystem::path& path,
                          int planned_trials) {
  auto update =
      Prepare(db, "UPDATE session SET planned_trials = ?1 WHERE id = 1",
              "cannot write the session of", path);
  if (!update) return update.error();
  if (planned_trials > 0) {
    sqlite3_bind_int(update->get(), 1, planned_trials);
  } else {
    sqlite3_bind_null(update->get(), 1);
  }
  return StepDone(db, update->get(), "cannot write the session of", path);
}

Status WriteCompleted(sqlite3* db, const std::filesystem::path& path) {
  auto update = Prepare(db,
                        "UPDATE session SET completed_utc = ?1 "
                        "WHERE id = 1 AND completed_utc IS NULL",
                        "cannot write the session of", path);
  if (!update) return update.error();
  BindText(update->get(), 1, NowUtc());
  return StepDone(db, update->get(), "cannot write the session of", path);
}

Result<int> CheckSchemaVersion(sqlite3* db, const std::filesystem::path& path) {
  auto exists = Prepare(db,
                        "SELECT COUNT(*) FROM sqlite_schema "
                        "WHERE type = 'table' AND name = ?1",
                        "cannot read", path);
  if (!exists) return exists.error();
  BindText(exists->get(), 1, "schema_version");
  if (sqlite3_step(exists->get()) != SQLITE_ROW) {
    return SqliteError(db, "cannot read", path);
  }
  if (sqlite3_column_int(exists->get(), 0) == 0) {
    return Error{fmt::format(
        "{} is not a burrlab journal (it has no schema_version table)",
        path.string())};
  }
  auto query = Prepare(db, "SELECT MAX(version) FROM schema_version",
                       "cannot read the schema version of", path);
  if (!query) return query.error();
  if (sqlite3_step(query->get()) != SQLITE_ROW || IsNull(query->get(), 0)) {
    return Error{fmt::format("{} has no schema version row", path.string())};
  }
  const std::int64_t version = sqlite3_column_int64(query->get(), 0);
  if (version > kJournalSchemaVersion) {
    return Error{fmt::format(
        "{} was written by a newer burrlab (journal schema version {}; this "
        "burrlab reads up to version {}); use a newer burrlab to resume or "
        "export it",
        path.string(), version, kJournalSchemaVersion)};
  }
  if (version < 1) {
    return Error{fmt::format("{} has an invalid schema version {}",
                             path.string(), version)};
  }
  return static_cast<int>(version);
}

Result<SessionInfo> ReadSession(sqlite3* db,
                                const std::filesystem::path& path) {
  auto query = Prepare(db,
                       "SELECT study, protocol_path, protocol_sha256, "
                       "subject_label, master_seed, burrlab_version, "
                       "started_utc FROM session WHERE id = 1",
                       "cannot read the session of", path);
  if (!query) return query.error();
  sqlite3_stmt* stmt = query->get();
  const int rc = sqlite3_step(stmt);
  if (rc == SQLITE_DONE) {
    return Error{fmt::format("{} has no session row", path.string())};
  }
  if (rc != SQLITE_ROW)
    return SqliteError(db, "cannot read the session of", path);
  SessionInfo session;
  session.study = ColumnText(stmt, 0);
  session.protocol_path = ColumnText(stmt, 1);
  session.protocol_sha256 = ColumnText(stmt, 2);
  session.subject_label = ColumnText(stmt, 3);
  const std::string seed = ColumnText(stmt, 4);
  const auto [end, ec] = std::from_chars(seed.data(), seed.data() + seed.size(),
                                         session.master_seed);
  if (ec != std::errc() || end != seed.data() + seed.size() || seed.empty()) {
    return Error{fmt::format("{}: the session's master seed {} is not a number",
                             path.string(), Quoted(seed))};
  }
  session.burrlab_version = ColumnText(stmt, 5);
  session.started_utc = ColumnText(stmt, 6);
  Result<bool> has_setup = HasColumn(db, path, "session", "setup");
  if (!has_setup) return has_setup.error();
  if (!*has_setup) return session;  // schema version 1
  auto setup_query = Prepare(db, "SELECT setup FROM session WHERE id = 1",
                             "cannot read the session of", path);
  if (!setup_query) return setup_query.error();
  if (sqlite3_step(setup_query->get()) != SQLITE_ROW) {
    return SqliteError(db, "cannot read the session of", path);
  }
  const std::string text = ColumnText(setup_query->get(), 0);
  const auto setup = nlohmann::ordered_json::parse(text, nullptr, false);
  if (setup.is_discarded() || !setup.is_object()) {
    return Error{fmt::format("{}: the session's setup {} is not a JSON object",
                             path.string(), Quoted(text))};
  }
  for (const auto& [name, value] : setup.items()) {
    if (!value.is_string()) {
      return Error{fmt::format("{}: the session's setup field {} is not text",
                               path.string(), Quoted(name))};
    }
    session.setup.push_back({name, value.get<std::string>()});
  }
  return session;
}

Result<int> CountTrials(sqlite3* db, const std::filesystem::path& path) {
  auto query = Prepare(db, "SELECT COUNT(*) FROM trial",
                       "cannot count the trials of", path);
  if (!query) return query.error();
  if (sqlite3_step(query->get()) != SQLITE_ROW) {
    return SqliteError(db, "cannot count the trials of", path);
  }
  return sqlite3_column_int(query->get(), 0);
}

Result<std::vector<TrialRecord>> ReadTrials(sqlite3* db,
                                            const std::filesystem::path& path) {
  // Columns later versions added read as their defaults in older journals
  // (an export reads a journal without upgrading it).
  Result<bool> has_source = HasColumn(db, path, "trial", "source");
  if (!has_source) return has_source.error();
  Result<bool> has_practice = HasColumn(db, path, "trial", "practice");
  if (!has_practice) return has_practice.error();
  const std::string sql = fmt::format(
      "SELECT trial_index, block, method, task, trial_type, stim_level, "
      "stim_unit, interval_materials, correct_answer, response, correct, "
      "response_time_s, staircase_id, reversal, step_size, estimate, "
      "rng_state, extra, {}, {} FROM trial ORDER BY trial_index",
      *has_source ? "source" : "''",
      *has_practice ? "practice, late" : "0, NULL");
  auto query = Prepare(db, sql.c_str(), "cannot read the trials of", path);
  if (!query) return query.error();
  sqlite3_stmt* stmt = query->get();
  std::vector<TrialRecord> trials;
  int rc = SQLITE_OK;
  while ((rc = sqlite3_step(stmt)) == SQLITE_ROW) {
    TrialRecord t;
    t.trial_index = sqlite3_column_int(stmt, 0);
    t.block = ColumnText(stmt, 1);
    t.method = ColumnText(stmt, 2);
    t.task = ColumnText(stmt, 3);
    t.trial_type = ColumnText(stmt, 4);
    t.stim_level = ColumnOptionalDouble(stmt, 5);
    t.stim_unit = ColumnText(stmt, 6);
    if (!ParseStringArray(ColumnText(stmt, 7), &t.interval_materials)) {
      return Error{
          fmt::format("{}: trial {} has a damaged interval_materials list",
                      path.string(), t.trial_index)};
    }
    t.correct_answer = ColumnText(stmt, 8);
    t.response = ColumnText(stmt, 9);
    t.correct = ColumnOptionalBool(stmt, 10);
    t.response_time_s = ColumnOptionalDouble(stmt, 11);
    t.staircase_id = ColumnOptionalInt(stmt, 12);
    t.reversal = ColumnOptionalBool(stmt, 13);
    t.step_size = ColumnOptionalDouble(stmt, 14);
    t.estimate = ColumnOptionalDouble(stmt, 15);
    t.rng_state = ColumnText(stmt, 16);
    t.extra = ColumnText(stmt, 17);
    t.source = ColumnText(stmt, 18);
    t.practice = sqlite3_column_int(stmt, 19) != 0;
    t.late = ColumnOptionalBool(stmt, 20);
    trials.push_back(std::move(t));
  }
  if (rc != SQLITE_DONE)
    return SqliteError(db, "cannot read the trials of", path);
  return trials;
}

Result<std::vector<TraceHeader>> ReadTraceHeaders(
    sqlite3* db, const std::filesystem::path& path) {
  auto query = Prepare(db,
                       "SELECT trial_index, interval_index, "
                       "sampling_frequency_hz, start_time_s, columns, "
                       "row_count FROM trace "
                       "ORDER BY trial_index, interval_index",
                       "cannot read the traces of", path);
  if (!query) return query.error();
  sqlite3_stmt* stmt = query->get();
  std::vector<TraceHeader> headers;
  int rc = SQLITE_OK;
  while ((rc = sqlite3_step(stmt)) == SQLITE_ROW) {
    TraceHeader h;
    h.trace.trial_index = sqlite3_column_int(stmt, 0);
    h.trace.interval_index = sqlite3_column_int(stmt, 1);
    h.trace.sampling_frequency_hz = sqlite3_column_double(stmt, 2);
    h.trace.start_time_s = sqlite3_column_double(stmt, 3);
    if (!ParseStringArray(ColumnText(stmt, 4), &h.trace.columns)) {
      return Error{fmt::format(
          "{}: trial {}, interval {}: damaged columns list", path.string(),
          h.trace.trial_index, h.trace.interval_index)};
    }
    h.row_count = sqlite3_column_int64(stmt, 5);
    headers.push_back(std::move(h));
  }
  if (rc != SQLITE_DONE)
    return SqliteError(db, "cannot read the traces of", path);
  return headers;
}

Result<std::vector<TraceSamples>> ReadTraces(sqlite3* db,
                                             const std::filesystem::path& path,
                                             int trial_index) {
  auto query = Prepare(db,
                       "SELECT interval_index, sampling_frequency_hz, "
                       "start_time_s, columns, row_count, encoding, samples "
                       "FROM trace WHERE trial_index = ?1 "
                       "ORDER BY interval_index",
                       "cannot read the traces of", path);
  if (!query) return query.error();
  sqlite3_stmt* stmt = query->get();
  sqlite3_bind_int(stmt, 1, trial_index);
  std::vector<TraceSamples> traces;
  int rc = SQLITE_OK;
  while ((rc = sqlite3_step(stmt)) == SQLITE_ROW) {
    TraceSamples t;
    t.trial_index = trial_index;
    t.interval_index = sqlite3_column_int(stmt, 0);
    t.sampling_frequency_hz = sqlite3_column_double(stmt, 1);
    t.start_time_s = sqlite3_column_double(stmt, 2);
    if (!ParseStringArray(ColumnText(stmt, 3), &t.columns)) {
      return Error{
          fmt::format("{}: trial {}, interval {}: damaged columns list",
                      path.string(), trial_index, t.interval_index)};
    }
    const std::int64_t row_count = sqlite3_column_int64(stmt, 4);
    if (ColumnText(stmt, 5) != kTraceEncoding) {
      return Error{fmt::format("{}: trial {}, interval {}: unknown encoding {}",
                               path.string(), trial_index, t.interval_index,
                               Quoted(ColumnText(stmt, 5)))};
    }
    const void* blob = sqlite3_column_blob(stmt, 6);
    const auto blob_size =
        static_cast<std::size_t>(sqlite3_column_bytes(stmt, 6));
    if (Status s = DecodeSamples(blob, blob_size, row_count, &t, path); !s) {
      return s.error();
    }
    traces.push_back(std::move(t));
  }
  if (rc != SQLITE_DONE)
    return SqliteError(db, "cannot read the traces of", path);
  return traces;
}

Status InsertTrial(sqlite3* db, const std::filesystem::path& path,
                   const TrialRecord& t) {
  const std::string what =
      fmt::format("cannot append trial {} to", t.trial_index);
  auto insert = Prepare(
      db,
      "INSERT INTO trial (trial_index, block, method, task, trial_type, "
      "stim_level, stim_unit, interval_materials, correct_answer, response, "
      "correct, response_time_s, staircase_id, reversal, step_size, estimate, "
      "rng_state, extra, committed_utc, source, practice, late) VALUES (?1, "
      "?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, "
      "?17, ?18, ?19, ?20, ?21, ?22)",
      what, path);
  if (!insert) return insert.error();
  sqlite3_stmt* stmt = insert->get();
  sqlite3_bind_int(stmt, 1, t.trial_index);
  BindText(stmt, 2, t.block);
  BindText(stmt, 3, t.method);
  BindText(stmt, 4, t.task);
  BindText(stmt, 5, t.trial_type);
  BindOptionalDouble(stmt, 6, t.stim_level);
  BindText(stmt, 7, t.stim_unit);
  BindText(stmt, 8, StringArrayJson(t.interval_materials));
  BindText(stmt, 9, t.correct_answer);
  BindText(stmt, 10, t.response);
  BindOptionalBool(stmt, 11, t.correct);
  BindOptionalDouble(stmt, 12, t.response_time_s);
  BindOptionalInt(stmt, 13, t.staircase_id);
  BindOptionalBool(stmt, 14, t.reversal);
  BindOptionalDouble(stmt, 15, t.step_size);
  BindOptionalDouble(stmt, 16, t.estimate);
  BindText(stmt, 17, t.rng_state);
  BindText(stmt, 18, t.extra);
  BindText(stmt, 19, NowUtc());
  BindText(stmt, 20, t.source);
  sqlite3_bind_int(stmt, 21, t.practice ? 1 : 0);
  BindOptionalBool(stmt, 22, t.late);
  return StepDone(db, stmt, what, path);
}

Status InsertTrace(sqlite3* db, const std::filesystem::path& path,
                   const TraceSamples& trace) {
  const std::string what =
      fmt::format("cannot append trial {} (interval {}) to", trace.trial_index,
                  trace.interval_index);
  Result<std::string> samples = EncodeSamples(trace);
  if (!samples) return samples.error();
  auto insert = Prepare(db,
                        "INSERT INTO trace (trial_index, interval_index, "
                        "sampling_frequency_hz, start_time_s, columns, "
                        "row_count, encoding, samples) "
                        "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)",
                        what, path);
  if (!insert) return insert.error();
  sqlite3_stmt* stmt = insert->get();
  sqlite3_bind_int(stmt, 1, trace.trial_index);
  sqlite3_bind_int(stmt, 2, trace.interval_index);
  sqlite3_bind_double(stmt, 3, trace.sampling_frequency_hz);
  sqlite3_bind_double(stmt, 4, trace.start_time_s);
  BindText(stmt, 5, StringArrayJson(trace.columns));
  sqlite3_bind_int64(stmt, 6, static_cast<sqlite3_int64>(trace.rows.size()));
  BindText(stmt, 7, kTraceEncoding);
  sqlite3_bind_blob64(stmt, 8, samples->data(), samples->size(),
                      SQLITE_TRANSIENT);
  return StepDone(db, stmt, what, path);
}

}  // namespace burrlab::results_schema::db
