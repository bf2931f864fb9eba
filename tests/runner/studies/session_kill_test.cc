// Crash safety of `burrlab run` and one process per session. The real
// executable is SIGKILLed at random points of a 40-trial simulated session at
// least 20 times and resumed each time; the final journal and exports equal
// those of an uninterrupted run with the same seed, with no completed trial
// lost or duplicated; kills during the export leave temporary files that the
// next run removes. A second process on a live session is refused and the lock
// of a killed one is taken over.
#include <fcntl.h>
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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
#include "two_block_protocol.h"

namespace {

namespace fs = std::filesystem;
namespace rs = burrlab::results_schema;

const std::string kProtocol =
    burrlab::runner::TwoBlockProtocol("kill test", 12, 28, 1.0);

const std::string kBurrlab =
    std::string(BURRLAB_BINARY_DIR) + "/runner/burrlab";

// Starts `burrlab args...` with output to `log` (and input from `in` when
// it is not -1); returns the pid.
pid_t Start(const std::vector<std::string>& args, const fs::path& log,
            int in = -1) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (in >= 0) dup2(in, 0);
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

// Waits up to 60 s for `text` to appear in `log`.
bool WaitForText(const fs::path& log, const std::string& text) {
  for (int i = 0; i < 6000; ++i) {
    if (burrlab::runner::ReadFile(log).find(text) != std::string::npos) {
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// Trials stored in a running session's journal, read without its lock (a
// reader holding the lock would refuse the run it watches); -1 when there is
// no journal yet.
int RunningTrials(const fs::path& out) {
  auto progress = rs::ReadSessionProgress(out, "01");
  return progress.ok() ? progress->trials : -1;
}

int StoredTrials(const fs::path& out) {
  auto journal = rs::Journal::Open(out, "01");
  if (!journal.ok()) return -1;
  auto next = journal->NextTrialIndex();
  return next.ok() ? next.value() : -1;
}

// Temporary files under `out`: exports and journal creations cut short.
std::vector<std::string> TempFiles(const fs::path& out) {
  std::vector<std::string> found;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(out, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.find(".tmp-") != std::string::npos ||
        name.find(".creating-") != std::string::npos) {
      found.push_back(name);
    }
  }
  return found;
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

  // A resume of the finished session replays it and rewrites the exports;
  // timed to choose the kill delays once the session is complete.
  const auto t1 = std::chrono::steady_clock::now();
  ASSERT_EQ(Wait(Start(args(reference, true), log)), 0) << ReadFile(log);
  const double resume_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t1)
          .count();

  // Where each restart is killed is chosen from the journal's progress, not
  // from wall-clock guesses: a guess cannot know how a build's start-up and
  // replay compare with its trials (ASan on a 2-core machine: most of a
  // restart is start-up and replay, and delays drawn from the session's length
  // killed nearly every restart before it stored one more trial). Each restart
  // is killed either during its start-up and replay (a uniform delay within
  // `resume`, one restart in four) or once it has stored 1-5 more trials, a
  // uniform fraction of a trial later, so the kills fall while a trial runs or
  // commits. Once all 40 are stored, restarts replay and export, and are
  // killed at uniform delays within `resume`. Go on until 20 kills landed and
  // at least 2 of them cut an export short (a temporary file was left behind).
  const fs::path out = dir / "killed";
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> more_trials(1, 5);
  const double trial_s = full_s / 40.0;
  int kills = 0;
  int kills_in_export = 0;
  std::set<int> trials_at_kill;
  bool started = false;
  for (int attempt = 0; attempt < 200 && (kills < 20 || kills_in_export < 2);
       ++attempt) {
    const int stored = started ? StoredTrials(out) : -1;
    const bool at_start = stored == 40 || unit(rng) < 0.25;
    const int target = std::min(40, std::max(stored, 0) + more_trials(rng));
    const double wait_s = (at_start ? resume_s : trial_s) * unit(rng);
    const pid_t pid = Start(args(out, stored >= 0), log);
    started = true;
    // Polls until `target` trials are stored (60 s at most); false when the
    // run ended first, with its exit code in `code`.
    int code = 0;
    auto reach_target = [&] {
      const auto poll_end =
          std::chrono::steady_clock::now() + std::chrono::seconds(60);
      while (RunningTrials(out) < target) {
        int status = 0;
        if (waitpid(pid, &status, WNOHANG) == pid) {
          code = WIFSIGNALED(status) ? -WTERMSIG(status) : WEXITSTATUS(status);
          return false;
        }
        if (std::chrono::steady_clock::now() > poll_end) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      return true;
    };
    if (at_start || reach_target()) {
      std::this_thread::sleep_for(std::chrono::duration<double>(wait_s));
      ::kill(pid, SIGKILL);
      code = Wait(pid);
    }
    if (code == -SIGKILL) {
      ++kills;
      trials_at_kill.insert(StoredTrials(out));
      if (!TempFiles(out).empty()) ++kills_in_export;
    } else {
      ASSERT_EQ(code, 0) << ReadFile(log);  // finished before the kill
    }
  }
  EXPECT_GE(kills, 20);
  EXPECT_GE(kills_in_export, 2);
  std::string points;
  for (int n : trials_at_kill) points += std::to_string(n) + " ";
  ::testing::Test::RecordProperty("kills", kills);
  ::testing::Test::RecordProperty("kills_in_export", kills_in_export);
  ::testing::Test::RecordProperty("trials_stored_at_kills", points);
  // The kills landed at several points of the session, not all at start-up.
  EXPECT_GE(trials_at_kill.size(), 5u);
  // Resume to the end (or re-export a finished journal); nothing temporary
  // is left.
  ASSERT_EQ(Wait(Start(args(out, StoredTrials(out) >= 0), log)), 0)
      << ReadFile(log);
  EXPECT_EQ(TempFiles(out), std::vector<std::string>{});

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
  // Every export file, byte for byte.
  std::vector<std::string> exported;
  for (const auto& entry : fs::recursive_directory_iterator(reference)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && !name.starts_with("journal.sqlite")) {
      exported.push_back(fs::relative(entry.path(), reference).string());
    }
  }
  // 8 in beh/, the scans.tsv and .json in sub-01/, 5 at the root
  // (dataset_description.json, .bidsignore, README, participants.tsv and
  // .json) and the protocol's copy in code/.
  EXPECT_EQ(exported.size(), 16u);
  for (const std::string& file : exported) {
    EXPECT_EQ(ReadFile(reference / file), ReadFile(out / file)) << file;
  }
}

TEST(SessionLock, ASecondRunIsRefusedAndAKilledRunsLockIsTakenOver) {
  const fs::path dir = fs::path(BURRLAB_BINARY_DIR) / "test_tmp" / "lock";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string protocol = (dir / "protocol.toml").string();
  std::ofstream(protocol) << kProtocol;
  const fs::path out = dir / "out";
  const std::vector<std::string> typed = {
      "run", protocol, "--subject", "01", "--out", out.string(), "--seed", "7"};

  // A person types three answers and then pauses at the fourth trial.
  int answers[2];
  ASSERT_EQ(::pipe(answers), 0);
  const fs::path first_log = dir / "first.txt";
  const pid_t first = Start(typed, first_log, answers[0]);
  ::close(answers[0]);
  const std::string three = "same\ndifferent\nsame\n";
  ASSERT_EQ(::write(answers[1], three.data(), three.size()),
            static_cast<ssize_t>(three.size()));
  ASSERT_TRUE(WaitForText(first_log, "trial 4 - block")) << ReadFile(first_log);

  // A second run on the same session, simulated or typed, resumed or not,
  // is refused and names the first.
  const std::string holder = ReadFile(out / "sub-01" / "journal.sqlite.lock");
  char host[256] = {};
  ::gethostname(host, sizeof(host) - 1);
  EXPECT_TRUE(
      holder.starts_with(fmt::format("pid {} on {} since 20", first, host)))
      << holder;
  const std::string refused = fmt::format(
      "burrlab: sub-01 in {} is in use by another burrlab ({}); wait for that "
      "run to end, or stop it, before starting another on this session\n",
      out.string(), holder.substr(0, holder.find('\n')));
  std::vector<std::string> simulated = typed;
  simulated.insert(simulated.end(), {"--observer", "simulated", "--resume"});
  for (const auto& args : {simulated, typed}) {
    const fs::path second_log = dir / "second.txt";
    fs::remove(second_log);
    EXPECT_EQ(Wait(Start(args, second_log)), 1);
    EXPECT_EQ(ReadFile(second_log), refused);
  }

  // The first is killed; its lock is free and a resume takes it over. The
  // journal holds the first's three answers, typed, and nothing else.
  ::kill(first, SIGKILL);
  EXPECT_EQ(Wait(first), -SIGKILL);
  ::close(answers[1]);
  {
    auto journal = rs::Journal::Open(out, "01");
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    const auto trials = journal->Trials().value();
    ASSERT_EQ(trials.size(), 3u);
    EXPECT_EQ(trials[0].response, "same");
    EXPECT_EQ(trials[1].response, "different");
    EXPECT_EQ(trials[2].response, "same");
    // Answers from a pipe: typed, but not timed by a person.
    for (const auto& t : trials) {
      EXPECT_EQ(t.source, "typed");
      EXPECT_EQ(t.response_time_s, std::nullopt);
    }
  }
  const fs::path rest = dir / "rest.txt";
  {
    std::ofstream answers_file(rest);
    // Trials 4-12 of the same-different block, then the 28 of the staircase.
    for (int i = 3; i < 40; ++i) answers_file << (i < 12 ? "same\n" : "1\n");
  }
  const int rest_fd = ::open(rest.c_str(), O_RDONLY);
  std::vector<std::string> resume = typed;
  resume.push_back("--resume");
  const fs::path third_log = dir / "third.txt";
  const pid_t third = Start(resume, third_log, rest_fd);
  ::close(rest_fd);
  EXPECT_EQ(Wait(third), 0) << ReadFile(third_log);
  EXPECT_THAT(ReadFile(third_log), ::testing::HasSubstr("3 resumed"));
  EXPECT_EQ(StoredTrials(out), 40);
}

}  // namespace
