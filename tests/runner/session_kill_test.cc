// Crash safety of `burrlab run`: the real executable is SIGKILLed at random
// points of a 40-trial simulated session at least 20 times and resumed each
// time; the final journal and exports equal those of an uninterrupted run with
// the same seed, with no completed trial lost or duplicated.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "burrlab/results_schema/journal.h"
#include "read_file.h"

namespace {

namespace fs = std::filesystem;
namespace rs = burrlab::results_schema;

constexpr std::string_view kProtocol = R"(format = "burrlab-protocol/1"

[study]
name = "kill test"

[recording]
trace_hz = 100

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "increment"
parameter = "c_e"
reference = "bone"

[[blocks]]
name = "sd"
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = 12
interval_s = 1

[[blocks]]
name = "stairs"
method = "staircase"
task = "drill"
axis = "ce"
interval_s = 1
n_down = 2
start_level = 0.5
step_scale = "log10"
step_down = 0.1
step_up = 0.1
floor = 0.01
ceiling = 2
max_trials = 28
)";

const std::string kBurrlab =
    std::string(BURRLAB_BINARY_DIR) + "/runner/burrlab";

// Starts `burrlab args...` with output to `log`; returns the pid.
pid_t Start(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
    }
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(kBurrlab.c_str()));
    for (const std::string& a : args)
      argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(kBurrlab.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// Waits for `pid`; the exit code, or -signal when killed.
int Wait(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) return -WTERMSIG(status);
  return WEXITSTATUS(status);
}

int StoredTrials(const fs::path& out) {
  auto journal = rs::Journal::Open(out, "01");
  if (!journal.ok()) return -1;
  auto next = journal->NextTrialIndex();
  return next.ok() ? next.value() : -1;
}

using burrlab::runner::ReadFile;

TEST(SessionCrash, TwentyKillsAndResumesGiveTheUninterruptedResults) {
  const fs::path dir = fs::path(BURRLAB_BINARY_DIR) / "test_tmp" / "kill";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string protocol = (dir / "protocol.toml").string();
  std::ofstream(protocol) << kProtocol;
  const fs::path log = dir / "log.txt";
  auto args = [&](const fs::path& out, bool resume) {
    std::vector<std::string> a = {
        "run",        protocol, "--subject", "01",         "--out",
        out.string(), "--seed", "2024",      "--observer", "simulated"};
    if (resume) a.push_back("--resume");
    return a;
  };

  // The uninterrupted reference, timed to choose kill delays.
  const fs::path reference = dir / "reference";
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_EQ(Wait(Start(args(reference, false), log)), 0) << ReadFile(log);
  const double full_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  ASSERT_EQ(StoredTrials(reference), 40);

  // Kill at uniform random delays in (0, full/10]; each restart resumes.
  const fs::path out = dir / "killed";
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> delay(0.0, full_s / 10.0);
  int kills = 0;
  std::set<int> trials_at_kill;
  bool started = false;
  for (int attempt = 0; attempt < 400 && kills < 20; ++attempt) {
    const bool resume = started && StoredTrials(out) >= 0;
    const pid_t pid = Start(args(out, resume), log);
    std::this_thread::sleep_for(std::chrono::duration<double>(delay(rng)));
    ::kill(pid, SIGKILL);
    const int code = Wait(pid);
    started = true;
    if (code == -SIGKILL) {
      ++kills;
      trials_at_kill.insert(StoredTrials(out));
    } else {
      ASSERT_EQ(code, 0) << ReadFile(log);  // finished before the kill
      break;
    }
  }
  EXPECT_GE(kills, 20);
  std::string points;
  for (int n : trials_at_kill) points += std::to_string(n) + " ";
  ::testing::Test::RecordProperty("kills", kills);
  ::testing::Test::RecordProperty("trials_stored_at_kills", points);
  // The kills landed at several points of the session, not all at start-up.
  EXPECT_GE(trials_at_kill.size(), 5u);
  // Resume to the end.
  if (StoredTrials(out) < 40) {
    ASSERT_EQ(Wait(Start(args(out, StoredTrials(out) >= 0), log)), 0)
        << ReadFile(log);
  } else {
    // Finished journal; the export may have been killed: resume re-exports.
    ASSERT_EQ(Wait(Start(args(out, true), log)), 0) << ReadFile(log);
  }

  auto a = rs::Journal::Open(reference, "01");
  auto b = rs::Journal::Open(out, "01");
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_TRUE(b->CheckIntegrity().ok());
  const auto ta = a->Trials().value();
  const auto tb = b->Trials().value();
  ASSERT_EQ(tb.size(), 40u);
  for (int i = 0; i < 40; ++i) {
    EXPECT_EQ(tb[i].trial_index, i);
    EXPECT_EQ(ta[i], tb[i]) << "trial " << i;
    EXPECT_EQ(a->Traces(i).value(), b->Traces(i).value()) << "trial " << i;
  }
  for (const char* file :
       {"sub-01_task-sd_beh.tsv", "sub-01_task-stairs_beh.tsv",
        "sub-01_task-sd_physio.tsv.gz", "sub-01_task-stairs_physio.tsv.gz"}) {
    EXPECT_EQ(ReadFile(reference / "sub-01" / "beh" / file),
              ReadFile(out / "sub-01" / "beh" / file))
        << file;
  }
}

}  // namespace
