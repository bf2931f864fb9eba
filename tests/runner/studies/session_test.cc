// Sessions as users meet them: `burrlab plan`, `run` (simulated observer and
// typed answers), `study`, resuming, and bad input (existing subject, folder
// that cannot be written, a write that fails, a resume with another protocol,
// seed or set-up) — each a clear error, exit 1, nothing lost.
#include "studies/session.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/results_schema/bids_read.h"
#include "burrlab/results_schema/journal.h"
#include "cli/session_commands.h"
#include "paced_protocol.h"
#include "run_cli.h"
#include "two_block_protocol.h"

namespace burrlab::runner {
namespace {

namespace fs = std::filesystem;
namespace rs = results_schema;
using ::testing::HasSubstr;

// Twelve same-different probe trials, then a 2-down/1-up staircase of eight
// drill trials on the c_e increment over bone: 20 trials of 0.5 s intervals.
const std::string kProtocol = TwoBlockProtocol("session test", 12, 8, 0.5);

class SessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(BURRLAB_BINARY_DIR) / "test_tmp" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    protocol_ = (dir_ / "protocol.toml").string();
    Write(protocol_, kProtocol);
  }
  static void Write(const std::string& path, std::string_view text) {
    std::ofstream(path, std::ios::binary) << text;
  }
  static std::string Read(const fs::path& path) {
    std::ifstream file(path, std::ios::binary);
    std::ostringstream text;
    text << file.rdbuf();
    return text.str();
  }
  std::vector<rs::TrialRecord> Trials(const fs::path& out,
                                      const std::string& subject) {
    auto journal = rs::Journal::Open(out, subject);
    EXPECT_TRUE(journal.ok()) << journal.error().message;
    auto trials = journal->Trials();
    EXPECT_TRUE(trials.ok());
    return trials.value();
  }
  // Options for subject 05 answering at the prompt from `in`.
  SessionOptions Typed(std::istream* in, std::ostream* prompt) const {
    SessionOptions options;
    options.out_dir = dir_ / "typed";
    options.subject = "05";
    options.responder = Responder::kTerminal;
    options.in = in;
    options.prompt = prompt;
    return options;
  }
  fs::path dir_;
  std::string protocol_;
};

TEST_F(SessionTest, SimulatedRunWritesJournalAndBidsExport) {
  const fs::path out = dir_ / "out";
  const CliRun run =
      RunBurrlab({"run", protocol_, "--subject", "01", "--out", out.string(),
                  "--seed", "7", "--observer", "simulated"});
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("sub-01: 20 trials (0 resumed, 20 run now)"));
  const std::vector<rs::TrialRecord> trials = Trials(out, "01");
  ASSERT_EQ(trials.size(), 20u);
  for (int i = 0; i < 12; ++i) {
    EXPECT_EQ(trials[i].method, "same_different");
    EXPECT_EQ(trials[i].source, "simulated observer");
    EXPECT_EQ(trials[i].task, "probe");
    EXPECT_TRUE(trials[i].response == "same" ||
                trials[i].response == "different");
    EXPECT_TRUE(trials[i].correct.has_value());
  }
  for (int i = 12; i < 20; ++i) {
    EXPECT_EQ(trials[i].method, "staircase");
    EXPECT_EQ(trials[i].task, "drill");
    EXPECT_EQ(trials[i].stim_unit, "fraction");
    EXPECT_TRUE(trials[i].step_size.has_value());
  }
  auto journal = rs::Journal::Open(out, "01");
  auto traces = journal->Traces(0);
  ASSERT_TRUE(traces.ok());
  ASSERT_EQ(traces->size(), 2u);             // two simulated intervals
  EXPECT_EQ((*traces)[0].rows.size(), 50u);  // 0.5 s at 100 Hz
  EXPECT_TRUE(fs::exists(out / "sub-01" / "beh" / "sub-01_task-sd_beh.tsv"));
  EXPECT_TRUE(
      fs::exists(out / "sub-01" / "beh" / "sub-01_task-stairs_physio.tsv.gz"));
  EXPECT_TRUE(fs::exists(out / "dataset_description.json"));
}

// A practice block's trials are run and recorded like the others, marked as
// practice and left out of the session's score; answers after a deadline
// are kept and marked late (the simulated observer answers in about 1 s).
TEST_F(SessionTest, PracticeTrialsAndLateAnswersAreMarkedInJournalAndExport) {
  const fs::path out = dir_ / "out";
  Write(protocol_, PacedProtocol(0.5, 0.0, 0.0, 1.0));
  const CliRun run =
      RunBurrlab({"run", protocol_, "--subject", "01", "--out", out.string(),
                  "--seed", "7", "--observer", "simulated"});
  ASSERT_EQ(run.code, 0) << run.err;
  const std::vector<rs::TrialRecord> trials = Trials(out, "01");
  ASSERT_EQ(trials.size(), 12u);
  int late = 0, correct = 0;
  for (const rs::TrialRecord& t : trials) {
    const bool practice = t.block == "familiarize";
    EXPECT_EQ(t.practice, practice) << t.trial_index;
    ASSERT_TRUE(t.response_time_s.has_value());
    if (practice) {
      EXPECT_EQ(t.late, std::nullopt) << t.trial_index;  // no deadline
    } else {
      EXPECT_EQ(t.late, *t.response_time_s > 1.0) << t.trial_index;
      late += t.late == true ? 1 : 0;
      correct += t.correct == true ? 1 : 0;
    }
  }
  EXPECT_GT(late, 0);
  EXPECT_THAT(run.out, HasSubstr(fmt::format("sub-01: 12 trials (0 resumed, 12 "
                                             "run now), {:.1f} % correct",
                                             100.0 * correct / 8)));
  Result<std::vector<rs::BehFile>> files = rs::ReadBidsDataset(out);
  ASSERT_TRUE(files.ok()) << files.error().message;
  ASSERT_EQ(files->size(), 2u);
  for (const rs::BehFile& f : *files) {
    for (const rs::TrialRecord& t : f.table.trials) {
      EXPECT_EQ(t.practice, trials[t.trial_index].practice);
      EXPECT_EQ(t.late, trials[t.trial_index].late);
    }
  }
}

// The seed column holds text that `--seed` takes back as written: a seed
// above 2^63 read from one session's export runs the same session again.
TEST_F(SessionTest, TheExportedSeedRunsTheSessionAgain) {
  const fs::path first = dir_ / "first";
  ASSERT_EQ(
      RunBurrlab({"run", protocol_, "--subject", "04", "--out", first.string(),
                  "--seed", "9223372036854775809", "--observer", "simulated"})
          .code,
      0);
  const std::string tsv = "sub-04/beh/sub-04_task-sd_beh.tsv";
  // The cell as written, between the last two tabs of the first row.
  const std::string text = Read(first / tsv);
  const std::string row = text.substr(text.find('\n') + 1);
  const std::size_t last_tab = row.rfind('\t', row.find('\n'));
  const std::size_t seed_tab = row.rfind('\t', last_tab - 1);
  const std::string cell = row.substr(seed_tab + 1, last_tab - seed_tab - 1);
  EXPECT_EQ(cell, "seed-9223372036854775809");
  const fs::path again = dir_ / "again";
  ASSERT_EQ(
      RunBurrlab({"run", protocol_, "--subject", "04", "--out", again.string(),
                  "--seed", cell, "--observer", "simulated"})
          .code,
      0);
  EXPECT_EQ(Read(first / tsv), Read(again / tsv));
}

TEST_F(SessionTest, SameSeedGivesByteIdenticalExports) {
  for (const char* name : {"a", "b"}) {
    const CliRun run = RunBurrlab({"run", protocol_, "--subject", "03", "--out",
                                   (dir_ / name).string(), "--seed", "99",
                                   "--observer", "simulated"});
    ASSERT_EQ(run.code, 0) << run.err;
  }
  for (const char* file :
       {"sub-03_task-sd_beh.tsv", "sub-03_task-stairs_beh.tsv",
        "sub-03_task-sd_physio.tsv.gz", "sub-03_task-stairs_beh.json"}) {
    const std::string a = Read(dir_ / "a" / "sub-03" / "beh" / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, Read(dir_ / "b" / "sub-03" / "beh" / file)) << file;
  }
  const CliRun other = RunBurrlab({"run", protocol_, "--subject", "03", "--out",
                                   (dir_ / "c").string(), "--seed", "100",
                                   "--observer", "simulated"});
  ASSERT_EQ(other.code, 0);
  EXPECT_NE(Read(dir_ / "a" / "sub-03" / "beh" / "sub-03_task-sd_beh.tsv"),
            Read(dir_ / "c" / "sub-03" / "beh" / "sub-03_task-sd_beh.tsv"));
}

TEST_F(SessionTest, ExistingSubjectIsNeverOverwritten) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(RunBurrlab({"run", protocol_, "--subject", "01", "--out",
                        out.string(), "--observer", "simulated"})
                .code,
            0);
  const std::string before =
      Read(out / "sub-01" / "beh" / "sub-01_task-sd_beh.tsv");
  const CliRun again = RunBurrlab({"run", protocol_, "--subject", "01", "--out",
                                   out.string(), "--observer", "simulated"});
  EXPECT_EQ(again.code, 1);
  EXPECT_EQ(again.err, "burrlab: sub-01 already exists in " + out.string() +
                           "; use --resume to continue it\n");
  EXPECT_EQ(Trials(out, "01").size(), 20u);
  EXPECT_EQ(before, Read(out / "sub-01" / "beh" / "sub-01_task-sd_beh.tsv"));
}

TEST_F(SessionTest, UnwritableFolderIsAClearError) {
  const fs::path file = dir_ / "a_file";
  Write(file.string(), "x");
  const CliRun run =
      RunBurrlab({"run", protocol_, "--subject", "01", "--out",
                  (file / "out").string(), "--observer", "simulated"});
  EXPECT_EQ(run.code, 1);
  EXPECT_THAT(run.err, HasSubstr("burrlab: cannot create folder"));
  EXPECT_THAT(run.err, HasSubstr("Not a directory"));
}

TEST_F(SessionTest, ResumeRefusesEveryChangedFieldByName) {
  const fs::path out = dir_ / "out";
  const std::vector<std::string> base = {
      "run",        protocol_,    "--subject",   "02",
      "--out",      out.string(), "--seed",      "5",
      "--observer", "simulated",  "--radius-mm", "2"};
  ASSERT_EQ(RunBurrlab(base).code, 0);
  // `base` with flag `name` set to `value` (or added), resumed.
  auto with = [&](const std::string& name, const std::string& value) {
    std::vector<std::string> args = base;
    auto it = std::find(args.begin(), args.end(), name);
    if (it != args.end()) {
      *(it + 1) = value;
    } else {
      args.insert(args.end(), {name, value});
    }
    args.push_back("--resume");
    return args;
  };
  const std::string prefix =
      "burrlab: cannot resume sub-02 in " + out.string() + ": ";
  const std::string simulated =
      "\"simulated weber_stiffness=0.2 weber_removal=0.3 lapse=0.02 "
      "criterion=1 rt_median_s=1 rt_log_sd=0.35 match_tolerance=0.5\"";
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  std::string changed(kProtocol);
  changed.replace(changed.find("trials = 12"), 11, "trials = 16");
  const std::string other = (dir_ / "other.toml").string();
  Write(other, changed);
  std::vector<std::string> other_protocol = with("--seed", "5");
  other_protocol[1] = other;
  std::vector<std::string> typed = with("--seed", "5");
  typed.erase(std::find(typed.begin(), typed.end(), "--observer"),
              std::find(typed.begin(), typed.end(), "--observer") + 2);
  const std::vector<Case> cases = {
      {with("--seed", "6"),
       "the seed differs from the journal's (5 in the journal, 6 now)"},
      {other_protocol, "the protocol differs from the journal's (sha256 " +
                           Sha256Hex(kProtocol) + " in the journal, " +
                           Sha256Hex(changed) + " now)"},
      {with("--radius-mm", "1.5"),
       "radius_mm differs from the journal's (\"2\" in the journal, \"1.5\" "
       "now)"},
      {with("--subject-index", "3"),
       "subject_index differs from the journal's (\"1\" in the journal, \"3\" "
       "now)"},
      {with("--observer", "simulated:weber=0.25"),
       "responder differs from the journal's (" + simulated +
           " in the journal, \"simulated weber_stiffness=0.25 "
           "weber_removal=0.25 lapse=0.02 criterion=1 rt_median_s=1 "
           "rt_log_sd=0.35 match_tolerance=0.5\" now)"},
      {typed, "responder differs from the journal's (" + simulated +
                  " in the journal, \"typed\" now)"},
  };
  for (const Case& c : cases) {
    const CliRun run = RunBurrlab(c.args);
    EXPECT_EQ(run.code, 1);
    EXPECT_EQ(run.err, prefix + c.message + "\n");
  }
  EXPECT_EQ(Trials(out, "02").size(), 20u);
  // Unchanged, the resume is accepted (nothing left to run).
  const CliRun same = RunBurrlab(with("--seed", "5"));
  EXPECT_EQ(same.code, 0) << same.err;
  const CliRun missing =
      RunBurrlab({"run", protocol_, "--subject", "09", "--out", out.string(),
                  "--observer", "simulated", "--resume"});
  EXPECT_EQ(missing.code, 1);
  EXPECT_THAT(missing.err, HasSubstr("no journal for sub-09 in"));
}

TEST_F(SessionTest, ARunThatStoppedBeforeItsFirstTrialStartsAgainOnResume) {
  const fs::path out = dir_ / "out";
  // What a run leaves when it fails before its first trial: a journal of
  // another protocol and set-up, with no trial.
  rs::SessionInfo old;
  old.study = "first try";
  old.protocol_path = "old.toml";
  old.protocol_sha256 = std::string(64, 'c');
  old.subject_label = "03";
  old.master_seed = 99;
  old.burrlab_version = "0.0.1";
  old.started_utc = "2026-01-01T00:00:00Z";
  old.setup = {{"radius_mm", "4"}};
  ASSERT_TRUE(rs::Journal::Create(out, old).ok());
  const std::vector<std::string> args = {"run",        protocol_,  "--subject",
                                         "03",         "--out",    out.string(),
                                         "--observer", "simulated"};
  const CliRun plain = RunBurrlab(args);
  EXPECT_EQ(plain.code, 1);
  EXPECT_EQ(plain.err, "burrlab: sub-03 already exists in " + out.string() +
                           " but holds no trials (its run stopped before the "
                           "first trial); use --resume to start it again "
                           "with this protocol and set-up\n");
  std::vector<std::string> resume = args;
  resume.push_back("--resume");
  const CliRun resumed = RunBurrlab(resume);
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  auto journal = rs::Journal::Open(out, "03");
  ASSERT_TRUE(journal.ok());
  EXPECT_EQ(journal->session().protocol_sha256, Sha256Hex(kProtocol));
  EXPECT_EQ(journal->session().master_seed, 1u);
  EXPECT_EQ(journal->session().setup[0].name, "radius_mm");
  EXPECT_EQ(journal->session().setup[0].value, "2");
  EXPECT_EQ(journal->Trials()->size(), 20u);
}

TEST_F(SessionTest, FailingWriteKeepsTheJournalConsistentAndResumes) {
  Result<LoadedProtocol> loaded = LoadProtocol(protocol_);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  SessionOptions options;
  options.out_dir = dir_ / "full";
  options.subject = "04";
  options.seed = 12;
  options.journal_limit_bytes_for_testing = 96 * 1024;
  Result<SessionSummary> failed = RunSession(*loaded, options);
  ASSERT_FALSE(failed.ok());
  EXPECT_THAT(failed.error().message, HasSubstr("cannot save trial "));
  EXPECT_THAT(failed.error().message, HasSubstr("run again with --resume"));
  EXPECT_THAT(failed.error().message,
              HasSubstr("(the trials saved so far are exported)"));
  int saved = 0;
  {
    auto journal = rs::Journal::Open(options.out_dir, "04");
    ASSERT_TRUE(journal.ok());
    EXPECT_TRUE(journal->CheckIntegrity().ok());
    saved = journal->NextTrialIndex().value();
  }
  EXPECT_GT(saved, 0);
  EXPECT_LT(saved, 20);
  // The saved trials are in the exports, for analyses to find.
  auto exported = rs::ReadBidsDataset(options.out_dir);
  ASSERT_TRUE(exported.ok()) << exported.error().message;
  std::size_t rows = 0;
  for (const rs::BehFile& f : *exported) rows += f.table.trials.size();
  EXPECT_EQ(rows, static_cast<std::size_t>(saved));
  // ... and the subject's scans.tsv marks them as an incomplete session (the
  // staircase's trial count depends on the answers: n/a planned).
  const fs::path scans = options.out_dir / "sub-04" / "sub-04_scans.tsv";
  // One row per exported file: the same-different block's (trials 0-11),
  // then the staircase's once a trial of it is saved.
  const auto expected_scans = [](const std::string& status, int trials) {
    std::string text =
        "filename\tsession_status\tsession_trials\tsession_planned_trials\n";
    for (const char* block : {"sd", "stairs"}) {
      if (std::string(block) == "stairs" && trials <= 12) break;
      for (const char* suffix : {"_beh.tsv", "_physio.tsv.gz"}) {
        text += fmt::format("beh/sub-04_task-{}{}\t{}\t{}\tn/a\n", block,
                            suffix, status, trials);
      }
    }
    return text;
  };
  EXPECT_EQ(Read(scans), expected_scans("incomplete", saved));

  options.journal_limit_bytes_for_testing = 0;
  options.resume = true;
  Result<SessionSummary> resumed = RunSession(*loaded, options);
  ASSERT_TRUE(resumed.ok()) << resumed.error().message;
  EXPECT_EQ(resumed->trials_resumed, saved);
  EXPECT_EQ(resumed->trials_total, 20);
  EXPECT_EQ(Read(scans), expected_scans("complete", 20));

  SessionOptions clean = options;
  clean.out_dir = dir_ / "clean";
  clean.resume = false;
  ASSERT_TRUE(RunSession(*loaded, clean).ok());
  EXPECT_EQ(Trials(options.out_dir, "04"), Trials(clean.out_dir, "04"));
}

TEST_F(SessionTest, TypedAnswersAtThePromptAreRecorded) {
  Result<LoadedProtocol> loaded = LoadProtocol(protocol_);
  ASSERT_TRUE(loaded.ok());
  std::istringstream in("maybe\nsame\ndifferent\n");
  std::ostringstream prompt;
  const SessionOptions options = Typed(&in, &prompt);
  Result<SessionSummary> summary = RunSession(*loaded, options);
  ASSERT_TRUE(summary.ok()) << summary.error().message;
  EXPECT_FALSE(summary->finished);  // input ended after two answers
  EXPECT_EQ(summary->trials_total, 2);
  EXPECT_THAT(prompt.str(),
              HasSubstr("Did the two intervals feel the same or different? "
                        "[same/different]: "));
  EXPECT_THAT(prompt.str(), HasSubstr("please answer one of same/different"));
  const std::vector<rs::TrialRecord> trials = Trials(options.out_dir, "05");
  ASSERT_EQ(trials.size(), 2u);
  EXPECT_EQ(trials[0].response, "same");
  EXPECT_EQ(trials[1].response, "different");
  EXPECT_TRUE(trials[0].response_time_s.has_value());
  EXPECT_EQ(trials[0].source, "typed");
}

// Typed answers from a pipe: the study's and the blocks' instructions, the
// rest breaks and the practice block's feedback are printed, and nothing
// waits for an Enter that would take an answer.
TEST_F(SessionTest, TypedAnswersFromAPipePrintInstructionsBreaksAndFeedback) {
  Write(protocol_, PacedProtocol(0.5, 0.0, 0.0, 30.0));
  Result<LoadedProtocol> loaded = LoadProtocol(protocol_);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  std::string answers;
  for (int i = 0; i < 12; ++i) answers += i % 3 == 0 ? "different\n" : "same\n";
  std::istringstream in(answers);
  std::ostringstream prompt;
  SessionOptions options = Typed(&in, &prompt);
  options.answers_timed = false;  // a pipe
  Result<SessionSummary> summary = RunSession(*loaded, options);
  ASSERT_TRUE(summary.ok()) << summary.error().message;
  EXPECT_TRUE(summary->finished);
  const std::string text = prompt.str();
  EXPECT_TRUE(text.starts_with(
      "\n  Feel both intervals, then say whether they felt the same.\n"
      "Press Enter to begin. (input is not a terminal: going on)\n"
      "\nblock \"familiarize\" (practice, not scored):\n"
      "  Practice: you will be told whether you were right.\n"
      "Press Enter to start the block. (input is not a terminal: going "
      "on)\n\ntrial 1 - block \"familiarize\""))
      << text;
  EXPECT_THAT(text, HasSubstr("\nblock \"main\":\n  Now the scored trials, "
                              "without feedback.\n"));
  const std::string rest =
      "Rest break: press Enter to continue (input is not a terminal: going "
      "on)\n";
  // Between the blocks, and after the 4th of main's 8 trials.
  std::size_t breaks = 0;
  for (std::size_t at = text.find(rest); at != std::string::npos;
       at = text.find(rest, at + 1)) {
    ++breaks;
  }
  EXPECT_EQ(breaks, 2u);
  EXPECT_LT(text.find(rest), text.find("block \"main\":"));
  // Feedback after each practice answer, as the engine scored it; none after
  // the scored trials.
  const std::vector<rs::TrialRecord> trials = Trials(options.out_dir, "05");
  ASSERT_EQ(trials.size(), 12u);
  std::string expected_feedback, printed_feedback;
  for (const rs::TrialRecord& t : trials) {
    if (t.practice) expected_feedback += *t.correct ? "correct " : "wrong ";
  }
  for (std::size_t at = text.find("\n  "); at != std::string::npos;
       at = text.find("\n  ", at + 1)) {
    for (const char* word : {"correct\n", "wrong\n"}) {
      if (text.compare(at + 3, std::strlen(word), word) == 0) {
        printed_feedback += std::string(word, std::strlen(word) - 1) + " ";
      }
    }
  }
  EXPECT_EQ(printed_feedback, expected_feedback);
  EXPECT_EQ(std::count(expected_feedback.begin(), expected_feedback.end(), ' '),
            4);
  EXPECT_EQ(trials[0].response, "different");  // no answer went to an Enter
  EXPECT_EQ(trials[1].response, "same");
}

// A person at a terminal reads the instructions and the breaks and goes on
// with Enter; the Enter lines are not taken for answers.
TEST_F(SessionTest,
       TypedAnswersAtATerminalWaitForEnterAtInstructionsAndBreaks) {
  Write(protocol_, PacedProtocol(0.5, 0.0, 0.0, 30.0));
  Result<LoadedProtocol> loaded = LoadProtocol(protocol_);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  // Study instructions, the first block's, 4 answers, a break, the second
  // block's instructions, 4 answers, a break, 4 answers.
  std::string input = "\n\n";
  for (int i = 0; i < 4; ++i) input += "same\n";
  input += "\n\n";
  for (int i = 0; i < 4; ++i) input += "different\n";
  input += "\n";
  for (int i = 0; i < 4; ++i) input += "same\n";
  std::istringstream in(input);
  std::ostringstream prompt;
  SessionOptions options = Typed(&in, &prompt);  // answers_timed: a terminal
  Result<SessionSummary> summary = RunSession(*loaded, options);
  ASSERT_TRUE(summary.ok()) << summary.error().message;
  EXPECT_TRUE(summary->finished);
  const std::string text = prompt.str();
  EXPECT_THAT(text, HasSubstr("Press Enter to begin. "));
  EXPECT_THAT(text, HasSubstr("\nRest break: press Enter to continue "));
  EXPECT_THAT(text, ::testing::Not(HasSubstr("please answer")));
  EXPECT_THAT(text, ::testing::Not(HasSubstr("going on")));
  const std::vector<rs::TrialRecord> trials = Trials(options.out_dir, "05");
  ASSERT_EQ(trials.size(), 12u);
  for (int i = 0; i < 12; ++i) {
    EXPECT_EQ(trials[i].response, i >= 4 && i < 8 ? "different" : "same") << i;
  }
}

// A typed session waits the gaps on the real clock: 12 trials of one
// 0.1 s gap between intervals and 0.15 s after the answer take 3 s at least.
TEST_F(SessionTest, TypedSessionsWaitTheGapsOnTheClock) {
  Write(protocol_, PacedProtocol(0.5, 0.1, 0.15, 30.0));
  Result<LoadedProtocol> loaded = LoadProtocol(protocol_);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  std::string answers;
  for (int i = 0; i < 12; ++i) answers += "same\n";
  std::istringstream in(answers);
  std::ostringstream prompt;
  SessionOptions options = Typed(&in, &prompt);
  options.answers_timed = false;
  const auto start = std::chrono::steady_clock::now();
  Result<SessionSummary> summary = RunSession(*loaded, options);
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  ASSERT_TRUE(summary.ok()) << summary.error().message;
  EXPECT_TRUE(summary->finished);
  EXPECT_GE(elapsed_s, 12 * (0.1 + 0.15));
}

// Simulated sessions wait for no gap but count them on the session clock:
// against the same protocol without gaps (same seed, same answers), each
// trial's second interval starts isi_s later and each trial ends
// isi_s + iti_s later than the one before.
TEST_F(SessionTest, SimulatedSessionsModelTheGapsWithoutWaitingForThem) {
  const auto run = [&](const std::string& name, double isi_s, double iti_s,
                       double* elapsed_s) {
    Write(protocol_, PacedProtocol(0.5, isi_s, iti_s, 1.0));
    const fs::path out = dir_ / name;
    const auto start = std::chrono::steady_clock::now();
    const CliRun cli =
        RunBurrlab({"run", protocol_, "--subject", "01", "--out", out.string(),
                    "--seed", "5", "--observer", "simulated"});
    *elapsed_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    EXPECT_EQ(cli.code, 0) << cli.err;
    return out;
  };
  double plain_s = 0.0, paced_s = 0.0;
  const fs::path plain = run("plain", 0.0, 0.0, &plain_s);
  const fs::path paced = run("paced", 0.4, 0.6, &paced_s);
  const std::vector<rs::TrialRecord> a = Trials(plain, "01");
  const std::vector<rs::TrialRecord> b = Trials(paced, "01");
  ASSERT_EQ(a.size(), 12u);
  ASSERT_EQ(b.size(), 12u);
  auto pa = rs::Journal::Open(plain, "01");
  auto pb = rs::Journal::Open(paced, "01");
  ASSERT_TRUE(pa.ok() && pb.ok());
  for (std::size_t k = 0; k < 12; ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(a[k].response, b[k].response);
    EXPECT_EQ(a[k].response_time_s, b[k].response_time_s);
    const double end_a =
        nlohmann::json::parse(a[k].extra)["session_time_end_s"].get<double>();
    const double end_b =
        nlohmann::json::parse(b[k].extra)["session_time_end_s"].get<double>();
    EXPECT_NEAR(end_b - end_a, static_cast<double>(k + 1) * (0.4 + 0.6), 1e-9);
    auto ta = pa->Traces(static_cast<int>(k));
    auto tb = pb->Traces(static_cast<int>(k));
    ASSERT_TRUE(ta.ok() && tb.ok());
    ASSERT_EQ(tb->size(), 2u);
    EXPECT_NEAR((*tb)[1].start_time_s - (*tb)[0].start_time_s,
                (*ta)[1].start_time_s - (*ta)[0].start_time_s + 0.4, 1e-9);
  }
  // 12 s of gaps were modelled, not waited for.
  EXPECT_LT(paced_s - plain_s, 6.0);
}

// A protocol file may hold any bytes: the block name and question reach the
// prompt with their control characters escaped, never raw.
TEST_F(SessionTest, ThePromptEscapesControlBytesFromTheProtocol) {
  std::string text = kProtocol;
  const std::string name = "name = \"sd\"\n";
  ASSERT_NE(text.find(name), std::string::npos);
  text.replace(text.find(name), name.size(),
               "name = \"sd\\u001b[2J\"\nquestion = \"Same?\\u0007\"\n");
  Write(protocol_, text);
  Result<LoadedProtocol> loaded = LoadProtocol(protocol_);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  std::istringstream in("same\n");
  std::ostringstream prompt;
  ASSERT_TRUE(RunSession(*loaded, Typed(&in, &prompt)).ok());
  EXPECT_THAT(prompt.str(), HasSubstr("block \"sd\\x1b[2J\" (same_different"));
  EXPECT_THAT(prompt.str(), HasSubstr("Same?\\x07 [same/different]: "));
  EXPECT_EQ(prompt.str().find('\x1b'), std::string::npos);
  EXPECT_EQ(prompt.str().find('\x07'), std::string::npos);
}

TEST_F(SessionTest, PlanPrintsTheTrialSequenceAsJson) {
  const CliRun run =
      RunBurrlab({"plan", protocol_, "--seed", "3", "--json", "--responses",
                  "1,1,1,1,1,1,1,1,1,1,1,1,1,1,0,1,1,1,1,1"});
  ASSERT_EQ(run.code, 0) << run.err;
  const auto doc = nlohmann::json::parse(run.out);
  ASSERT_EQ(doc["trials"].size(), 20u);
  const auto& first = doc["trials"][0];
  EXPECT_EQ(first["index"], 0);
  EXPECT_EQ(first["block"], "sd");
  EXPECT_EQ(first["method"], "same_different");
  EXPECT_TRUE(first["level"].is_null());
  EXPECT_EQ(first["intervals"].size(), 2u);
  const auto& stair = doc["trials"][12];
  EXPECT_EQ(stair["method"], "staircase");
  EXPECT_DOUBLE_EQ(stair["level"].get<double>(), 0.5);
  EXPECT_TRUE(stair.contains("estimate"));
  // 1,1 -> down one log10 step of 0.1; then 0 -> up.
  EXPECT_NEAR(doc["trials"][14]["level"].get<double>(), 0.5 / std::pow(10, 0.1),
              1e-12);
  EXPECT_TRUE(doc["note"].is_null());
  // The same seed gives the same text.
  EXPECT_EQ(run.out, RunBurrlab({"plan", protocol_, "--seed", "3", "--json",
                                 "--responses",
                                 "1,1,1,1,1,1,1,1,1,1,1,1,1,1,0,1,1,1,1,1"})
                         .out);
}

TEST_F(SessionTest, PlanStopsWhereAdaptiveResponsesRunOut) {
  const CliRun run = RunBurrlab({"plan", protocol_, "--seed", "3"});
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_THAT(run.out,
              HasSubstr("stopped before trial 12: block \"stairs\" "
                        "(staircase) is adaptive and the scripted responses "
                        "ran out (0 given)"));
}

// The plan shows what surrounds the trials, where it comes: the study's and
// the blocks' instructions, how each block is paced, and the rest breaks
// (between the blocks and after the 4th scored trial).
TEST_F(SessionTest, PlanShowsThePacingBeforeTheTrials) {
  const fs::path protocol = dir_ / "paced.toml";
  std::ofstream(protocol) << PacedProtocol(0.5, 0.25, 0.75, 2.0);
  const CliRun run = RunBurrlab({"plan", protocol.string(), "--seed", "3"});
  ASSERT_EQ(run.code, 0) << run.err;
  std::vector<std::string> pacing;
  std::istringstream lines(run.out);
  for (std::string line; std::getline(lines, line);) {
    if (line.starts_with("   -- ")) {
      pacing.push_back(line.substr(6));
    } else if (!line.starts_with("trial")) {
      pacing.push_back("trial of block " + line.substr(7, 11));
    }
  }
  const std::vector<std::string> expected = {
      "the study's instructions, until SPACE",
      "block familiarize: practice (recorded, never scored), feedback after "
      "each answer, 0.25 s between intervals, 0.75 s after each answer",
      "block familiarize's instructions, until SPACE",
      "trial of block familiarize",
      "trial of block familiarize",
      "trial of block familiarize",
      "trial of block familiarize",
      "a rest break, until a key",
      "block main: 0.25 s between intervals, 0.75 s after each answer, "
      "answers after 2 s are late, a rest break every 4 trials",
      "block main's instructions, until SPACE",
      "trial of block main       ",
      "trial of block main       ",
      "trial of block main       ",
      "trial of block main       ",
      "a rest break, until a key",
      "trial of block main       ",
      "trial of block main       ",
      "trial of block main       ",
      "trial of block main       "};
  EXPECT_EQ(pacing, expected) << run.out;
  const CliRun json =
      RunBurrlab({"plan", protocol.string(), "--seed", "3", "--json"});
  ASSERT_EQ(json.code, 0) << json.err;
  const auto doc = nlohmann::json::parse(json.out);
  EXPECT_EQ(doc["trials"][0]["practice"], true);
  EXPECT_EQ(doc["trials"][0]["before"].size(), 3u);
  EXPECT_FALSE(doc["trials"][1].contains("before"));
  EXPECT_EQ(doc["trials"][8]["before"],
            nlohmann::json::parse(R"(["a rest break, until a key"])"));
}

TEST_F(SessionTest, StudyRunsEverySubjectAndRefusesToOverwrite) {
  const fs::path out = dir_ / "study";
  const CliRun run = RunBurrlab({"study", protocol_, "--simulated-subjects",
                                 "3", "--out", out.string(), "--jobs", "2"});
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("3 of 3 simulated subjects completed"));
  for (const char* s : {"01", "02", "03"}) {
    EXPECT_EQ(Trials(out, s).size(), 20u) << s;
  }
  const CliRun again = RunBurrlab(
      {"study", protocol_, "--simulated-subjects", "3", "--out", out.string()});
  EXPECT_EQ(again.code, 1);
  EXPECT_EQ(again.err, "burrlab: sub-01 already exists in " + out.string() +
                           "; use --resume to continue the study\n");
}

// A subject who comes back is recorded as another session: each session
// has its own folder, journal and resume, and its files carry the
// _ses-<session> entity; nothing else in them differs from a session run
// without a label.
TEST_F(SessionTest, ASubjectsSessionsHaveTheirOwnFoldersJournalsAndResume) {
  const fs::path out = dir_ / "sessions";
  auto run = [&](const std::string& session, const std::string& seed,
                 bool resume) {
    std::vector<std::string> args = {"run",       protocol_,   "--subject",
                                     "01",        "--out",     out.string(),
                                     "--seed",    seed,        "--observer",
                                     "simulated", "--session", session};
    if (resume) args.push_back("--resume");
    return RunBurrlab(args);
  };
  const CliRun first = run("1", "7", false);
  ASSERT_EQ(first.code, 0) << first.err;
  EXPECT_EQ(first.out.substr(0, first.out.find(" run now")),
            "sub-01 ses-1: 20 trials (0 resumed, 20");
  ASSERT_EQ(run("2", "8", false).code, 0);
  const CliRun resumed = run("2", "8", true);
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_THAT(resumed.out,
              HasSubstr("sub-01 ses-2: 20 trials (20 resumed, 0 run now)"));
  auto journal = rs::Journal::Open(out, "01", "2");
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  EXPECT_EQ(journal->Trials()->size(), 20u);
  EXPECT_EQ(journal->path(), out / "sub-01" / "ses-2" / "journal.sqlite");
  journal = Error{"closed"};
  const fs::path beh = out / "sub-01" / "ses-2" / "beh";
  EXPECT_TRUE(fs::exists(beh / "sub-01_ses-2_task-stairs_physio.tsv.gz"));
  EXPECT_TRUE(fs::exists(out / "sub-01" / "ses-2" / "sub-01_ses-2_scans.tsv"));
  EXPECT_FALSE(fs::exists(out / "sub-01" / "beh"));
  const fs::path plain = dir_ / "plain";
  ASSERT_EQ(
      RunBurrlab({"run", protocol_, "--subject", "01", "--out", plain.string(),
                  "--seed", "8", "--observer", "simulated"})
          .code,
      0);
  EXPECT_EQ(Read(beh / "sub-01_ses-2_task-sd_beh.tsv"),
            Read(plain / "sub-01" / "beh" / "sub-01_task-sd_beh.tsv"));

  const CliRun again = run("2", "8", false);
  EXPECT_EQ(again.code, 1);
  EXPECT_EQ(again.err, "burrlab: sub-01 ses-2 already exists in " +
                           out.string() + "; use --resume to continue it\n");
  const CliRun unlabelled =
      RunBurrlab({"run", protocol_, "--subject", "01", "--out", out.string(),
                  "--observer", "simulated"});
  EXPECT_EQ(unlabelled.code, 1);
  EXPECT_EQ(unlabelled.err,
            "burrlab: sub-01 in " + out.string() +
                " has labelled sessions (ses-1, ses-2); give --session LABEL "
                "to record another (a subject's sessions are all labelled or "
                "none is)\n");
  Result<std::vector<rs::BehFile>> files = rs::ReadBidsDataset(out);
  ASSERT_TRUE(files.ok()) << files.error().message;
  std::vector<std::string> read;
  for (const rs::BehFile& f : *files) {
    read.push_back(f.subject + " " + f.session + " " + f.task);
  }
  EXPECT_EQ(read, (std::vector<std::string>{"01 1 sd", "01 1 stairs", "01 2 sd",
                                            "01 2 stairs"}));
}

// `study --session` records every simulated subject's session in its own
// folder, and participants.tsv lists each subject's true observer, the one
// its journal records.
TEST_F(SessionTest, StudySessionsListEachSubjectsTrueObserver) {
  const fs::path out = dir_ / "study";
  const CliRun run = RunBurrlab(
      {"study", protocol_, "--simulated-subjects", "3", "--out", out.string(),
       "--jobs", "2", "--seed", "3", "--weber-spread", "0.5", "--session", "1",
       "--author", "Doe, Jane", "--author", "Roe, Richard"});
  ASSERT_EQ(run.code, 0) << run.err;
  const std::string table = Read(out / "participants.tsv");
  std::istringstream lines(table);
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header,
            "participant_id\tobserver_weber_stiffness\tobserver_weber_removal\t"
            "observer_lapse\tobserver_criterion\tobserver_rule\t"
            "observer_bias\tobserver_force_factor\tobserver_speed_factor\t"
            "observer_force_spread\tobserver_speed_spread\t"
            "observer_rt_median\tobserver_rt_log_sd\tobserver_match_tolerance\t"
            "observer_answers");
  for (const char* label : {"01", "02", "03"}) {
    std::string row;
    ASSERT_TRUE(std::getline(lines, row)) << label;
    std::vector<std::string> cells;
    std::istringstream split(row);
    for (std::string cell; std::getline(split, cell, '\t');) {
      cells.push_back(cell);
    }
    ASSERT_EQ(cells.size(), 15u) << row;
    EXPECT_EQ(cells[0], std::string("sub-") + label);
    auto journal = rs::Journal::Open(out, label, "1");
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    std::string responder;
    for (const rs::SetupField& f : journal->session().setup) {
      if (f.name == "responder") responder = f.value;
    }
    EXPECT_THAT(responder, HasSubstr("weber_stiffness=" + cells[1] +
                                     " weber_removal=" + cells[2] +
                                     " lapse=" + cells[3] + " "));
    EXPECT_EQ(cells[5], "fixed");
    EXPECT_EQ(cells[6], "0");  // no bias
    EXPECT_EQ(cells[7], "1");  // the protocol's forces, the same for all
    EXPECT_EQ(cells[14], "percepts");
  }
  EXPECT_FALSE(std::getline(lines, header));
  const nlohmann::json description =
      nlohmann::json::parse(Read(out / "dataset_description.json"));
  EXPECT_EQ(description["Authors"],
            nlohmann::json::parse(R"(["Doe, Jane", "Roe, Richard"])"));
  EXPECT_EQ(Read(out / "code" / "protocol.toml"), kProtocol);
  EXPECT_TRUE(fs::exists(out / "README"));
  EXPECT_TRUE(fs::exists(out / "sub-03" / "ses-1" / "beh" /
                         "sub-03_ses-1_task-sd_beh.tsv"));
  const CliRun again =
      RunBurrlab({"study", protocol_, "--simulated-subjects", "3", "--out",
                  out.string(), "--session", "1"});
  EXPECT_EQ(again.code, 1);
  EXPECT_EQ(again.err, "burrlab: sub-01 ses-1 already exists in " +
                           out.string() +
                           "; use --resume to continue the study\n");
}

// Everything the runs export, the dataset's own files included (README,
// code/, participants.tsv and .json, dataset_description.json), is the same
// byte for byte for the same runs: no wall-clock time in any of them.
TEST_F(SessionTest, TheSameRunsGiveByteIdenticalDatasets) {
  for (const char* name : {"a", "b"}) {
    const std::string out = (dir_ / name).string();
    for (const char* session : {"1", "2"}) {
      const CliRun run = RunBurrlab(
          {"run", protocol_, "--subject", "01", "--session", session, "--out",
           out, "--seed", session, "--observer", "simulated", "--participant",
           "group=expert", "--author", "Doe, Jane", "--author", "Roe, R."});
      ASSERT_EQ(run.code, 0) << run.err;
    }
  }
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir_ / "a")) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && !name.starts_with("journal.sqlite")) {
      files.push_back(fs::relative(entry.path(), dir_ / "a").string());
    }
  }
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files.size(), 26u);  // 2 x (8 in beh/ + 2 scans) + the 6 below
  for (const char* root :
       {"README", "code/protocol.toml", "participants.tsv", "participants.json",
        "dataset_description.json", ".bidsignore"}) {
    EXPECT_NE(std::find(files.begin(), files.end(), root), files.end()) << root;
  }
  for (const std::string& file : files) {
    EXPECT_EQ(Read(dir_ / "a" / file), Read(dir_ / "b" / file)) << file;
  }
}

TEST(DefaultSubjectIndex, IsTheLabelNumberMinusOne) {
  EXPECT_EQ(DefaultSubjectIndex("01"), 0);
  EXPECT_EQ(DefaultSubjectIndex("12"), 11);
  EXPECT_EQ(DefaultSubjectIndex("pilot"), 0);
}

}  // namespace
}  // namespace burrlab::runner
