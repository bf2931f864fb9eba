// Tests of the session journal: round trip, SQLite settings, one transaction
// per trial, refusal to overwrite, resume checks, and crash safety under
// SIGKILL at random points.
#include "burrlab/results_schema/journal.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "burrlab/results_schema/bids_export.h"
#include "burrlab/results_schema/bids_read.h"
#include "burrlab/results_schema/records.h"
#include "burrlab/results_schema/session_lock.h"
#include "temp_dir.h"

namespace burrlab::results_schema {
namespace {

namespace fs = std::filesystem;

SessionInfo MakeSession(const std::string& label) {
  SessionInfo s;
  s.study = "stiffness discrimination";
  s.protocol_path = "protocols/examples/same_different.toml";
  s.protocol_sha256 = std::string(64, 'a');
  s.subject_label = label;
  s.master_seed = 18'446'744'073'709'551'557u;  // above 2^63: survives as text
  s.burrlab_version = "0.1.0";
  s.started_utc = "2024-05-01T09:30:00Z";
  return s;
}

TrialRecord MakeTrial(int i) {
  TrialRecord t;
  t.trial_index = i;
  t.block = i < 6 ? "practice" : "main block";
  t.method = "staircase";
  t.task = i % 2 == 0 ? "probe" : "drill";
  t.trial_type = "2AFC";
  t.stim_level = 1.0 + 0.1 * i;
  t.stim_unit = "ratio";
  t.interval_materials = {"pvc_k70", "human_temporal_bone"};
  t.correct_answer = "1";
  if (i % 3 != 0) {
    t.response = i % 3 == 1 ? "1" : "2";
    t.correct = i % 3 == 1;
    t.response_time_s = 0.25 + 0.001 * i;
  }
  t.staircase_id = i % 2;
  t.reversal = i % 4 == 0;
  t.step_size = 0.05;
  if (i > 2) t.estimate = 1.0 / (i + 1);
  t.rng_state = "mt19937_64 " + std::to_string(i) + "\n5489 1 2 3";
  t.extra = R"({"quest_sd": 0.125, "path": [1, 2]})";
  return t;
}

std::vector<TraceSamples> MakeTraces(int i, int rows = 40) {
  std::vector<TraceSamples> traces;
  for (int interval = 0; interval < 2; ++interval) {
    TraceSamples t;
    t.trial_index = i;
    t.interval_index = interval;
    t.sampling_frequency_hz = 1000.0;
    t.start_time_s = 10.0 * i + 4.0 * interval;
    t.columns = {"force_n", "position_mm", "velocity_mm_per_s"};
    for (int r = 0; r < rows + i % 7; ++r) {
      t.rows.push_back({0.01 * r + i, -0.5 * r + interval, std::sin(0.1 * r)});
    }
    traces.push_back(std::move(t));
  }
  return traces;
}

// Runs `sql` on the journal file with a separate raw connection.
void RawSql(const fs::path& path, const char* sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* message = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, &message), SQLITE_OK)
      << (message ? message : "");
  sqlite3_free(message);
  sqlite3_close(db);
}

TEST(Journal, RoundTripsSessionTrialsAndTraces) {
  TempDir dir;
  {
    auto journal = Journal::Create(dir.path(), MakeSession("01"));
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    EXPECT_EQ(journal->path(), dir.path() / "sub-01" / "journal.sqlite");
    for (int i = 0; i < 10; ++i) {
      Status s = journal->Append(MakeTrial(i), MakeTraces(i));
      ASSERT_TRUE(s.ok()) << s.error().message;
    }
  }
  auto journal = Journal::Open(dir.path(), "01");
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  EXPECT_EQ(journal->session(), MakeSession("01"));
  auto trials = journal->Trials();
  ASSERT_TRUE(trials.ok()) << trials.error().message;
  ASSERT_EQ(trials->size(), 10u);
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ((*trials)[static_cast<std::size_t>(i)], MakeTrial(i)) << i;
    auto traces = journal->Traces(i);
    ASSERT_TRUE(traces.ok()) << traces.error().message;
    EXPECT_EQ(*traces, MakeTraces(i)) << i;
  }
  EXPECT_EQ(*journal->NextTrialIndex(), 10);
  EXPECT_TRUE(journal->Traces(99)->empty());
}

TEST(Journal, KeepsNonFiniteAndEmptyTraces) {
  TempDir dir;
  auto journal = Journal::Create(dir.path(), MakeSession("01"));
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  TraceSamples empty;
  empty.columns = {"force_n"};
  TraceSamples odd;
  odd.interval_index = 1;
  odd.columns = {"force_n"};
  odd.rows = {{INFINITY}, {-0.0}, {5e-324}};
  ASSERT_TRUE(journal->Append(MakeTrial(0), {empty, odd}).ok());
  auto traces = journal->Traces(0);
  ASSERT_TRUE(traces.ok()) << traces.error().message;
  ASSERT_EQ(traces->size(), 2u);
  EXPECT_EQ((*traces)[0], empty);
  EXPECT_EQ((*traces)[1], odd);
  EXPECT_TRUE(std::signbit((*traces)[1].rows[1][0]));
}

TEST(Journal, UsesWalSynchronousFullAndForeignKeys) {
  TempDir dir;
  for (bool reopen : {false, true}) {
    auto journal = reopen ? Journal::Open(dir.path(), "01")
                          : Journal::Create(dir.path(), MakeSession("01"));
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    auto settings = journal->Settings();
    ASSERT_TRUE(settings.ok()) << settings.error().message;
    EXPECT_EQ(settings->journal_mode, "wal");
    EXPECT_EQ(settings->synchronous, 2);  // FULL
    EXPECT_TRUE(settings->foreign_keys);
    EXPECT_EQ(settings->schema_version, kJournalSchemaVersion);
  }
  // WAL is recorded in the file itself, so other readers see it too.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(JournalPath(dir.path(), "01").c_str(), &db),
            SQLITE_OK);
  sqlite3_stmt* stmt = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &stmt, nullptr),
            SQLITE_OK);
  ASSERT_EQ(sqlite3_step(stmt), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(stmt, 0)),
               "wal");
  sqlite3_finalize(stmt);
  sqlite3_close(db);
}

TEST(Journal, FailureInsideAppendLeavesNoPartialTrial) {
  TempDir dir;
  auto journal = Journal::Create(dir.path(), MakeSession("01"));
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  ASSERT_TRUE(journal->Append(MakeTrial(0), MakeTraces(0)).ok());
  // The second trace repeats interval 0: the trial row and the first trace
  // are already inserted when the database refuses it.
  std::vector<TraceSamples> traces = MakeTraces(1);
  traces[1].interval_index = 0;
  Status s = journal->Append(MakeTrial(1), traces);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            "cannot append trial 1 (interval 0) to " +
                journal->path().string() +
                ": UNIQUE constraint failed: trace.trial_index, "
                "trace.interval_index");
  EXPECT_EQ(*journal->NextTrialIndex(), 1);
  EXPECT_TRUE(journal->Traces(1)->empty());
  EXPECT_TRUE(journal->CheckIntegrity().ok());
  // Also after reopening, and the same trial can then be appended whole.
  journal = Error{"closed"};
  auto reopened = Journal::Open(dir.path(), "01");
  ASSERT_TRUE(reopened.ok()) << reopened.error().message;
  EXPECT_EQ(reopened->Trials()->size(), 1u);
  ASSERT_TRUE(reopened->Append(MakeTrial(1), MakeTraces(1)).ok());
  EXPECT_EQ(*reopened->Traces(1), MakeTraces(1));
}

TEST(Journal, FullDiskFailsTheAppendAndKeepsTheJournalConsistent) {
  TempDir dir;
  auto journal = Journal::Create(dir.path(), MakeSession("01"));
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  ASSERT_TRUE(journal->Append(MakeTrial(0), MakeTraces(0)).ok());
  ASSERT_TRUE(journal->LimitSizeForTesting(64 * 1024).ok());
  // Incompressible samples, about 300 kB per trial.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  std::vector<TraceSamples> big = MakeTraces(1);
  big[1].rows.assign(12'500, {0.0, 0.0, 0.0});
  for (auto& row : big[1].rows) {
    for (double& v : row) v = noise(rng);
  }
  Status s = journal->Append(MakeTrial(1), big);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, "cannot append trial 1 (interval 1) to " +
                                   journal->path().string() +
                                   ": database or disk is full");
  EXPECT_EQ(*journal->NextTrialIndex(), 1);
  EXPECT_TRUE(journal->Traces(1)->empty());
  EXPECT_TRUE(journal->CheckIntegrity().ok());
  ASSERT_TRUE(journal->LimitSizeForTesting(1 << 30).ok());
  Status again = journal->Append(MakeTrial(1), big);
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(*journal->Traces(1), big);
}

TEST(Journal, RefusesRepeatedAndSkippedTrialIndices) {
  TempDir dir;
  auto journal = Journal::Create(dir.path(), MakeSession("01"));
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  ASSERT_TRUE(journal->Append(MakeTrial(0), {}).ok());
  ASSERT_TRUE(journal->Append(MakeTrial(1), {}).ok());
  Status repeated = journal->Append(MakeTrial(1), {});
  ASSERT_FALSE(repeated.ok());
  EXPECT_EQ(repeated.error().message, "trial 1 is already in " +
                                          journal->path().string() +
                                          "; the next trial is 2");
  Status skipped = journal->Append(MakeTrial(5), {});
  ASSERT_FALSE(skipped.ok());
  EXPECT_EQ(skipped.error().message, "trial 5 would leave a gap in " +
                                         journal->path().string() +
                                         "; the next trial is 2");
  EXPECT_EQ(journal->Trials()->size(), 2u);
}

TEST(Journal, RefusesInvalidRecordsBeforeWriting) {
  TempDir dir;
  auto journal = Journal::Create(dir.path(), MakeSession("01"));
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  std::vector<TraceSamples> traces = MakeTraces(0);
  traces[1].rows[3].pop_back();
  Status s = journal->Append(MakeTrial(0), traces);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            "trial 0, interval 1: row 3 has 2 values for 3 columns");
  traces = MakeTraces(0);
  traces[0].trial_index = 4;
  s = journal->Append(MakeTrial(0), traces);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            "trial 0: a trace of interval 0 belongs to trial 4");
  EXPECT_EQ(*journal->NextTrialIndex(), 0);
}

TEST(Journal, CreateRefusesAnExistingSubject) {
  TempDir dir;
  {
    auto journal = Journal::Create(dir.path(), MakeSession("01"));
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    ASSERT_TRUE(journal->Append(MakeTrial(0), MakeTraces(0)).ok());
  }
  SessionInfo other = MakeSession("01");
  other.master_seed = 3;
  auto again = Journal::Create(dir.path(), other);
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.error().message, "sub-01 already exists in " +
                                       dir.path().string() +
                                       "; use --resume to continue it");
  auto kept = Journal::Open(dir.path(), "01");
  ASSERT_TRUE(kept.ok()) << kept.error().message;
  EXPECT_EQ(kept->session(), MakeSession("01"));
  EXPECT_EQ(kept->Trials()->size(), 1u);
}

TEST(Journal, CreateRefusesASubjectFolderWithoutJournal) {
  TempDir dir;
  fs::create_directories(dir.path() / "sub-02" / "beh");
  auto journal = Journal::Create(dir.path(), MakeSession("02"));
  ASSERT_FALSE(journal.ok());
  EXPECT_EQ(journal.error().message,
            (dir.path() / "sub-02").string() +
                " exists but holds no journal; refusing to write into it "
                "(move it away or choose another output folder)");
}

TEST(Journal, CreateRejectsBadSubjectLabels) {
  TempDir dir;
  auto journal = Journal::Create(dir.path(), MakeSession("sub-01"));
  ASSERT_FALSE(journal.ok());
  EXPECT_EQ(journal.error().message,
            "subject label \"sub-01\" includes the \"sub-\" prefix; give only "
            "the label, e.g. \"01\"");
  auto bad = Journal::Open(dir.path(), "../x");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "subject label \"../x\" has '.' at position 1; use letters and "
            "digits only (BIDS sub-<label>)");
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(Journal, OpenWithoutJournalSaysSo) {
  TempDir dir;
  auto journal = Journal::Open(dir.path(), "07");
  ASSERT_FALSE(journal.ok());
  EXPECT_EQ(journal.error().message,
            "no journal for sub-07 in " + dir.path().string() + " (" +
                JournalPath(dir.path(), "07").string() +
                " does not exist); start the session without --resume");
  EXPECT_FALSE(fs::exists(dir.path() / "sub-07"));
}

TEST(Journal, ResumeWithAnotherSeedOrProtocolNamesTheDifference) {
  TempDir dir;
  ASSERT_TRUE(Journal::Create(dir.path(), MakeSession("01")).ok());
  auto journal = Journal::Open(dir.path(), "01");
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  EXPECT_TRUE(journal->CheckSameSession(MakeSession("01")).ok());
  SessionInfo moved = MakeSession("01");
  moved.protocol_path = "elsewhere/same_different.toml";
  moved.started_utc = "2024-05-02T10:00:00Z";
  EXPECT_TRUE(journal->CheckSameSession(moved).ok());

  const std::string prefix =
      "cannot resume sub-01 in " + dir.path().string() + ": ";
  SessionInfo seed = MakeSession("01");
  seed.master_seed = 42;
  Status s = journal->CheckSameSession(seed);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            prefix +
                "the seed differs from the journal's (18446744073709551557 in "
                "the journal, 42 now)");
  SessionInfo protocol = MakeSession("01");
  protocol.protocol_sha256 = std::string(64, 'b');
  s = journal->CheckSameSession(protocol);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, prefix +
                                   "the protocol differs from the journal's "
                                   "(sha256 " +
                                   std::string(64, 'a') + " in the journal, " +
                                   std::string(64, 'b') + " now)");
  protocol.master_seed = 42;
  s = journal->CheckSameSession(protocol);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            prefix + "the protocol differs from the journal's (sha256 " +
                std::string(64, 'a') + " in the journal, " +
                std::string(64, 'b') +
                " now); the seed differs from the journal's "
                "(18446744073709551557 in the journal, 42 now)");
}

TEST(Journal, ResumeChecksTheVersionAndEverySetupFieldByName) {
  TempDir dir;
  SessionInfo kept = MakeSession("01");
  kept.setup = {{"radius_mm", "2"},     {"voxel_mm", "0.3"},
                {"subject_index", "0"}, {"responder", "typed"},
                {"device", "none"},     {"station_file_sha256", "none"},
                {"renderings", "fresh"}};
  ASSERT_TRUE(Journal::Create(dir.path(), kept).ok());
  auto journal = Journal::Open(dir.path(), "01");
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  EXPECT_EQ(journal->session(), kept);
  EXPECT_TRUE(journal->CheckSameSession(kept).ok());
  const std::string prefix =
      "cannot resume sub-01 in " + dir.path().string() + ": ";
  for (std::size_t i = 0; i < kept.setup.size(); ++i) {
    SessionInfo given = kept;
    given.setup[i].value = "other";
    Status s = journal->CheckSameSession(given);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().message,
              prefix + kept.setup[i].name + " differs from the journal's (\"" +
                  kept.setup[i].value + "\" in the journal, \"other\" now)");
    given.setup.erase(given.setup.begin() + static_cast<std::ptrdiff_t>(i));
    s = journal->CheckSameSession(given);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().message,
              prefix + kept.setup[i].name + " differs from the journal's (\"" +
                  kept.setup[i].value + "\" in the journal, not given now)");
  }
  SessionInfo version = kept;
  version.burrlab_version = "0.2.0";
  Status s = journal->CheckSameSession(version);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            prefix +
                "the burrlab version differs from the journal's "
                "(\"0.1.0\" in the journal, \"0.2.0\" now)");
}

TEST(Journal, ASecondOpenOfALiveSessionIsRefusedUntilTheFirstCloses) {
  TempDir dir;
  auto first = Journal::Create(dir.path(), MakeSession("01"));
  ASSERT_TRUE(first.ok()) << first.error().message;
  const std::string lock_file =
      (dir.path() / "sub-01" / "journal.sqlite.lock").string();
  std::ifstream lock(lock_file);
  std::string holder;
  std::getline(lock, holder);
  EXPECT_TRUE(holder.starts_with("pid " + std::to_string(::getpid()) + " on "))
      << holder;
  const std::string refused =
      "sub-01 in " + dir.path().string() + " is in use by another burrlab (" +
      holder +
      "); wait for that run to end, or stop it, before starting another on "
      "this session";
  auto second = Journal::Open(dir.path(), "01");
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.error().message, refused);
  auto again = Journal::Create(dir.path(), MakeSession("01"));
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.error().message, refused);
  first = Error{"closed"};
  EXPECT_TRUE(Journal::Open(dir.path(), "01").ok());
}

// A subject who comes back is recorded as another session: one journal per
// session in sub-<label>/ses-<session>/, each resumed and locked on its own.
TEST(JournalSessions, EachSessionHasItsOwnJournalLockAndResume) {
  TempDir dir;
  const fs::path ses1 = dir.path() / "sub-01" / "ses-1";
  const fs::path ses2 = dir.path() / "sub-01" / "ses-2";
  {
    auto first = Journal::Create(dir.path(), MakeSession("01"), "1");
    ASSERT_TRUE(first.ok()) << first.error().message;
    EXPECT_EQ(first->path(), ses1 / "journal.sqlite");
    ASSERT_TRUE(first->Append(MakeTrial(0), MakeTraces(0)).ok());
    // The second session runs while the first is open: its own lock.
    auto second = Journal::Create(dir.path(), MakeSession("01"), "2");
    ASSERT_TRUE(second.ok()) << second.error().message;
    EXPECT_EQ(second->path(), ses2 / "journal.sqlite");
    auto busy = Journal::Open(dir.path(), "01", "1");
    ASSERT_FALSE(busy.ok());
    EXPECT_TRUE(busy.error().message.starts_with(
        "sub-01 ses-1 in " + dir.path().string() +
        " is in use by another burrlab (pid "))
        << busy.error().message;
  }
  auto again = Journal::Create(dir.path(), MakeSession("01"), "1");
  ASSERT_FALSE(again.ok());
  EXPECT_EQ(again.error().message, "sub-01 ses-1 already exists in " +
                                       dir.path().string() +
                                       "; use --resume to continue it");
  EXPECT_EQ(JournalPath(dir.path(), "01", "2"), ses2 / "journal.sqlite");
  EXPECT_EQ(SessionLockPath(dir.path(), "01", "2"),
            ses2 / "journal.sqlite.lock");
  EXPECT_TRUE(fs::exists(ses1 / "journal.sqlite.lock"));
  EXPECT_FALSE(fs::exists(dir.path() / "sub-01" / "journal.sqlite"));
  auto resumed = Journal::Open(dir.path(), "01", "1");
  ASSERT_TRUE(resumed.ok()) << resumed.error().message;
  EXPECT_EQ(resumed->Trials()->size(), 1u);
  auto other = Journal::Open(dir.path(), "01", "2");
  ASSERT_TRUE(other.ok()) << other.error().message;
  EXPECT_EQ(other->Trials()->size(), 0u);
  SessionInfo changed = MakeSession("01");
  changed.master_seed = 5;
  EXPECT_EQ(resumed->CheckSameSession(changed).error().message,
            "cannot resume sub-01 ses-1 in " + dir.path().string() +
                ": the seed differs from the journal's "
                "(18446744073709551557 in the journal, 5 now)");
  Result<SessionProgress> progress = ReadSessionProgress(dir.path(), "01", "1");
  ASSERT_TRUE(progress.ok()) << progress.error().message;
  EXPECT_EQ(progress->trials, 1);
}

TEST(JournalSessions, ASubjectsSessionsAreAllLabelledOrNoneIs) {
  TempDir dir;
  ASSERT_TRUE(Journal::Create(dir.path(), MakeSession("01")).ok());
  auto labelled = Journal::Create(dir.path(), MakeSession("01"), "2");
  ASSERT_FALSE(labelled.ok());
  EXPECT_EQ(labelled.error().message,
            "sub-01 in " + dir.path().string() +
                " was recorded without a session label (" +
                (dir.path() / "sub-01" / "journal.sqlite").string() +
                " exists); a subject's sessions are all labelled or none is, "
                "so record ses-2 in another output folder or run sub-01 "
                "without --session");
  EXPECT_FALSE(fs::exists(dir.path() / "sub-01" / "ses-2"));
  auto resume = Journal::Open(dir.path(), "01", "2");
  ASSERT_FALSE(resume.ok());
  EXPECT_EQ(resume.error().message,
            "no journal for sub-01 ses-2 in " + dir.path().string() +
                ": sub-01 was recorded without a session label; resume it "
                "without --session");

  ASSERT_TRUE(Journal::Create(dir.path(), MakeSession("02"), "1").ok());
  ASSERT_TRUE(Journal::Create(dir.path(), MakeSession("02"), "a2").ok());
  auto unlabelled = Journal::Create(dir.path(), MakeSession("02"));
  ASSERT_FALSE(unlabelled.ok());
  EXPECT_EQ(unlabelled.error().message,
            "sub-02 in " + dir.path().string() +
                " has labelled sessions (ses-1, ses-a2); give --session LABEL "
                "to record another (a subject's sessions are all labelled or "
                "none is)");
  auto open = Journal::Open(dir.path(), "02");
  ASSERT_FALSE(open.ok());
  EXPECT_EQ(open.error().message,
            "no journal for sub-02 in " + dir.path().string() +
                ": its sessions are labelled (ses-1, ses-a2); give --session "
                "LABEL to resume one");
  auto missing = Journal::Open(dir.path(), "02", "3");
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().message,
            "no journal for sub-02 ses-3 in " + dir.path().string() + " (" +
                JournalPath(dir.path(), "02", "3").string() +
                " does not exist); start the session without --resume");
  auto bad = Journal::Create(dir.path(), MakeSession("03"), "ses-1");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "session label \"ses-1\" includes the \"ses-\" prefix; give only "
            "the label, e.g. \"1\"");
  EXPECT_FALSE(fs::exists(dir.path() / "sub-03"));
}

TEST(Journal, ReadsASchemaVersion1JournalAndRestartsIt) {
  TempDir dir;
  SessionInfo session = MakeSession("01");
  session.setup = {{"radius_mm", "2"}};
  ASSERT_TRUE(Journal::Create(dir.path(), session).ok());
  const fs::path path = JournalPath(dir.path(), "01");
  // A journal as burrlab wrote it before the setup column existed.
  RawSql(path, "ALTER TABLE session DROP COLUMN setup");
  RawSql(path, "ALTER TABLE session DROP COLUMN planned_trials");
  RawSql(path, "ALTER TABLE session DROP COLUMN completed_utc");
  RawSql(path, "ALTER TABLE trial DROP COLUMN source");
  RawSql(path, "ALTER TABLE trial DROP COLUMN practice");
  RawSql(path, "ALTER TABLE trial DROP COLUMN late");
  RawSql(path, "UPDATE schema_version SET version = 1");
  {
    auto journal = Journal::Open(dir.path(), "01");
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    EXPECT_TRUE(journal->session().setup.empty());
    // What it did not record is not checked.
    EXPECT_TRUE(journal->CheckSameSession(session).ok());
    // With no trial it starts again, and records the setup from now on.
    ASSERT_TRUE(journal->Restart(session).ok());
    EXPECT_EQ(journal->Settings()->schema_version, kJournalSchemaVersion);
  }
  auto journal = Journal::Open(dir.path(), "01");
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  EXPECT_EQ(journal->session(), session);
  TrialRecord typed = MakeTrial(0);
  typed.source = "typed";
  ASSERT_TRUE(journal->Append(typed, MakeTraces(0)).ok());
  EXPECT_EQ(journal->Trials()->at(0).source, "typed");
  const Status refused = journal->Restart(session);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().message, "cannot restart sub-01 in " +
                                         dir.path().string() +
                                         ": it already holds 1 trial");
}

TEST(Journal, RefusesANewerSchemaVersion) {
  TempDir dir;
  ASSERT_TRUE(Journal::Create(dir.path(), MakeSession("01")).ok());
  const fs::path path = JournalPath(dir.path(), "01");
  RawSql(path, "UPDATE schema_version SET version = 5");
  auto journal = Journal::Open(dir.path(), "01");
  ASSERT_FALSE(journal.ok());
  EXPECT_EQ(journal.error().message,
            path.string() +
                " was written by a newer burrlab (journal schema version 5; "
                "this burrlab reads up to version 4); use a newer burrlab to "
                "resume or export it");
}

TEST(Journal, RecordsPlannedTrialsAndCompletion) {
  TempDir dir;
  auto journal = Journal::Create(dir.path(), MakeSession("01"));
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  Result<SessionProgress> p = journal->Progress();
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p->trials, 0);
  EXPECT_EQ(p->planned_trials, std::nullopt);
  EXPECT_EQ(p->complete, false);
  ASSERT_TRUE(journal->SetPlannedTrials(10).ok());
  ASSERT_TRUE(journal->Append(MakeTrial(0), MakeTraces(0)).ok());
  p = ReadSessionProgress(dir.path(), "01");  // read beside the open journal
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p->trials, 1);
  EXPECT_EQ(p->planned_trials, 10);
  EXPECT_EQ(p->complete, false);
  ASSERT_TRUE(journal->MarkComplete().ok());
  EXPECT_EQ(ReadSessionProgress(dir.path(), "01")->complete, true);
  ASSERT_TRUE(journal->SetPlannedTrials(0).ok());  // 0: not known
  EXPECT_EQ(journal->Progress()->planned_trials, std::nullopt);
}

// A version 2 journal does not say whether its session ended; resuming it
// upgrades it to version 3, from when on it does.
TEST(Journal, AVersion2JournalLearnsItsCompletionWhenResumed) {
  TempDir dir;
  ASSERT_TRUE(Journal::Create(dir.path(), MakeSession("01")).ok());
  const fs::path path = JournalPath(dir.path(), "01");
  RawSql(path, "ALTER TABLE session DROP COLUMN planned_trials");
  RawSql(path, "ALTER TABLE session DROP COLUMN completed_utc");
  RawSql(path, "UPDATE schema_version SET version = 2");
  EXPECT_EQ(ReadSessionProgress(dir.path(), "01")->complete, std::nullopt);
  auto journal = Journal::Open(dir.path(), "01");
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  EXPECT_EQ(journal->Settings()->schema_version, kJournalSchemaVersion);
  EXPECT_EQ(journal->Progress()->complete, false);
}

// A version 3 journal has no practice or late marks: its trials read as
// scored with lateness unknown, as they are exported without an upgrade;
// resuming it upgrades it to version 4, and new trials keep their marks.
TEST(Journal, AVersion3JournalReadsItsTrialsAsScoredAndLearnsTheMarks) {
  TempDir dir;
  {
    auto journal = Journal::Create(dir.path(), MakeSession("01"));
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    ASSERT_TRUE(journal->Append(MakeTrial(0), MakeTraces(0)).ok());
  }
  const fs::path path = JournalPath(dir.path(), "01");
  RawSql(path, "ALTER TABLE trial DROP COLUMN practice");
  RawSql(path, "ALTER TABLE trial DROP COLUMN late");
  RawSql(path, "UPDATE schema_version SET version = 3");
  // Exported as it is.
  ASSERT_TRUE(ExportBids(dir.path(), "01").ok());
  Result<std::vector<BehFile>> exported = ReadBidsDataset(dir.path());
  ASSERT_TRUE(exported.ok()) << exported.error().message;
  EXPECT_FALSE(exported->at(0).table.trials.at(0).practice);
  EXPECT_EQ(exported->at(0).table.trials.at(0).late, std::nullopt);
  auto journal = Journal::Open(dir.path(), "01");
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  EXPECT_EQ(journal->Settings()->schema_version, 4);
  Result<std::vector<TrialRecord>> trials = journal->Trials();
  ASSERT_TRUE(trials.ok()) << trials.error().message;
  EXPECT_FALSE(trials->at(0).practice);
  EXPECT_EQ(trials->at(0).late, std::nullopt);
  TrialRecord marked = MakeTrial(1);
  marked.practice = true;
  marked.late = true;
  ASSERT_TRUE(journal->Append(marked, MakeTraces(1)).ok());
  trials = journal->Trials();
  ASSERT_TRUE(trials.ok()) << trials.error().message;
  EXPECT_EQ(trials->at(1), marked);
}

TEST(Journal, RefusesFilesThatAreNotJournals) {
  TempDir dir;
  const fs::path path = JournalPath(dir.path(), "01");
  fs::create_directories(path.parent_path());
  RawSql(path, "CREATE TABLE notes (text TEXT)");
  auto journal = Journal::Open(dir.path(), "01");
  ASSERT_FALSE(journal.ok());
  EXPECT_EQ(journal.error().message,
            path.string() +
                " is not a burrlab journal (it has no schema_version table)");

  fs::remove(path);
  std::ofstream(path) << "not a database, just some text that is long enough "
                         "to fill a header of one hundred bytes or so .......";
  journal = Journal::Open(dir.path(), "01");
  ASSERT_FALSE(journal.ok());
  EXPECT_EQ(journal.error().message,
            "cannot read " + path.string() + ": file is not a database");
}

// Runs `body` as another user when this test runs as root (root ignores
// folder permissions); returns what `body` returned.
std::string AsUnprivilegedUser(const std::function<std::string()>& body) {
  if (geteuid() != 0) return body();
  int fds[2];
  if (pipe(fds) != 0) return "pipe failed";
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    std::string out = "cannot drop privileges";
    if (setgid(65534) == 0 && setuid(65534) == 0) out = body();
    ssize_t ignored = write(fds[1], out.data(), out.size());
    (void)ignored;
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  std::string out;
  char buffer[512];
  ssize_t n = 0;
  while ((n = read(fds[0], buffer, sizeof buffer)) > 0) {
    out.append(buffer, static_cast<std::size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return out;
}

TEST(Journal, CreateInAnUnwritableFolderFails) {
  TempDir dir;
  const fs::path locked = dir.path() / "locked";
  fs::create_directory(locked);
  fs::permissions(dir.path(), fs::perms::owner_all | fs::perms::group_read |
                                  fs::perms::group_exec |
                                  fs::perms::others_read |
                                  fs::perms::others_exec);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec |
                              fs::perms::group_read | fs::perms::group_exec |
                              fs::perms::others_read | fs::perms::others_exec);
  const std::string message = AsUnprivilegedUser([&] {
    auto journal = Journal::Create(locked, MakeSession("01"));
    return journal.ok() ? std::string("created") : journal.error().message;
  });
  EXPECT_EQ(message, "cannot create folder " + (locked / "sub-01").string() +
                         ": Permission denied");
  EXPECT_TRUE(fs::is_empty(locked));
}

// Appends trials in a loop until killed (the child side of the crash tests),
// writing one byte to `committed_fd` after each append returns.
[[noreturn]] void AppendForever(const fs::path& dir, int committed_fd) {
  auto journal = Journal::Open(dir, "01");
  if (!journal.ok()) _exit(3);
  auto next = journal->NextTrialIndex();
  if (!next.ok()) _exit(4);
  for (int i = *next; i < 1'000'000; ++i) {
    if (!journal->Append(MakeTrial(i), MakeTraces(i, 2000)).ok()) _exit(5);
    if (write(committed_fd, "c", 1) != 1) _exit(6);
  }
  _exit(0);
}

TEST(Journal, SurvivesSigkillAtRandomPointsWithoutLosingOrDuplicating) {
  TempDir dir;
  ASSERT_TRUE(Journal::Create(dir.path(), MakeSession("01")).ok());
  std::mt19937 rng(20240501);
  std::uniform_int_distribution<int> delay_us(0, 40'000);
  // Kill points are counted in commits, then timed: the child is killed after
  // 0-2 of its appends returned and a random delay, so some kills find
  // commits to keep however slow or loaded the machine is, and the delay
  // lands the kill anywhere in the next append.
  std::uniform_int_distribution<int> commits_before(0, 2);
  constexpr int kKills = 24;
  int expected = 0;  // trials known to be committed
  int kills_with_progress = 0;
  for (int kill_index = 0; kill_index < kKills; ++kill_index) {
    int committed[2];
    ASSERT_EQ(pipe(committed), 0);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      close(committed[0]);
      AppendForever(dir.path(), committed[1]);
    }
    close(committed[1]);
    const int wait_for = commits_before(rng);
    for (int c = 0; c < wait_for; ++c) {
      char byte = 0;
      ASSERT_EQ(read(committed[0], &byte, 1), 1)
          << "the child ended before its append " << c + 1;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(delay_us(rng)));
    ASSERT_EQ(kill(pid, SIGKILL), 0);
    close(committed[0]);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
        << "the child stopped by itself, status " << status;

    auto journal = Journal::Open(dir.path(), "01");
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    Status integrity = journal->CheckIntegrity();
    ASSERT_TRUE(integrity.ok()) << integrity.error().message;
    auto trials = journal->Trials();
    ASSERT_TRUE(trials.ok()) << trials.error().message;
    const int n = static_cast<int>(trials->size());
    ASSERT_GE(n, expected) << "a committed trial was lost";
    if (n > expected) ++kills_with_progress;
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ((*trials)[static_cast<std::size_t>(i)], MakeTrial(i))
          << "trial " << i << " after kill " << kill_index;
    }
    // The trials written since the last check carry all their samples.
    for (int i = std::max(expected - 1, 0); i < n; ++i) {
      auto traces = journal->Traces(i);
      ASSERT_TRUE(traces.ok()) << traces.error().message;
      ASSERT_EQ(*traces, MakeTraces(i, 2000)) << "trial " << i;
    }
    // The parent continues the session with the next trial.
    Status appended = journal->Append(MakeTrial(n), MakeTraces(n, 2000));
    ASSERT_TRUE(appended.ok()) << appended.error().message;
    expected = n + 1;
  }
  EXPECT_GT(kills_with_progress, 0) << "no child committed a trial";
  auto journal = Journal::Open(dir.path(), "01");
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  EXPECT_EQ(*journal->NextTrialIndex(), expected);
  RecordProperty("trials", expected);
  RecordProperty("kills_with_progress", kills_with_progress);
}

TEST(Journal, SigkillDuringCreateLeavesNoHalfJournal) {
  TempDir dir;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> delay_us(0, 8'000);
  int complete = 0;
  for (int k = 0; k < 10; ++k) {
    std::string label = "c";  // (not "c" + ...: GCC 12 -Wrestrict false alarm)
    label += std::to_string(k);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      _exit(Journal::Create(dir.path(), MakeSession(label)).ok() ? 0 : 3);
    }
    std::this_thread::sleep_for(std::chrono::microseconds(delay_us(rng)));
    kill(pid, SIGKILL);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) != 0)
        << "Create failed in the child";
    if (fs::exists(JournalPath(dir.path(), label))) {
      ++complete;
      auto journal = Journal::Open(dir.path(), label);
      ASSERT_TRUE(journal.ok()) << journal.error().message;
      EXPECT_EQ(journal->session(), MakeSession(label));
    } else {
      auto journal = Journal::Create(dir.path(), MakeSession(label));
      ASSERT_TRUE(journal.ok()) << journal.error().message;
    }
  }
  RecordProperty("complete_before_kill", complete);
}

}  // namespace
}  // namespace burrlab::results_schema
