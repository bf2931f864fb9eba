// `burrlab run --device simulated` end to end, as the experimenter runs it:
// the real executable (ctest wraps this binary in xvfb-run, so the subject
// window is a real GLFW window), a short protocol, a station file with force
// limits, and a station script for the subject's hand and answers. The test
// reads back what the run left: exit code and message, the SQLite journal
// (trials, loop statistics in `extra`, traces), the BIDS files and one
// screenshot per phase. An unplug mid-trial aborts the trial, pauses and
// stops the session with the trials before it saved; --resume completes it.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/results_schema/journal.h"
#include "devices/sim_force_source.h"
#include "studies/session.h"

namespace burrlab::runner {
namespace {

namespace fs = std::filesystem;
namespace rs = results_schema;

// Two 2AFC probe trials of two 0.4 s intervals: PVC (renderable) against a
// material far stiffer than the station allows.
constexpr const char* kProtocol = R"(format = "burrlab-protocol/1"

[study]
name = "Station run check"

[recording]
trace_hz = 100

[materials.pvc]
builtin = "pvc_k70"

[materials.stiff]
c_e_n_per_mm2 = 20.0
alpha_per_s = 0.1
c_mu_n_per_mm2 = 0.5
mu = 0.5
c_i_n_s_per_mm3 = 0.0001

[[blocks]]
name = "probe2afc"
method = "two_interval"
design = "2afc"
task = "probe"
standard = "pvc"
comparison = "stiff"
question = "Which interval was stiffer?"
trials = 2
interval_s = 0.4
)";

// kProtocol paced as with naive subjects (§13.5.1): instructions, a practice
// block with feedback and gaps, then a scored block after a rest break, with
// a response deadline the scripted subject misses.
constexpr const char* kPacedProtocol = R"(format = "burrlab-protocol/1"

[study]
name = "Station pacing check"
instructions = "Press into the block in each interval, then say which was stiffer."
breaks_between_blocks = true

[recording]
trace_hz = 100

[materials.pvc]
builtin = "pvc_k70"

[materials.stiff]
c_e_n_per_mm2 = 20.0
alpha_per_s = 0.1
c_mu_n_per_mm2 = 0.5
mu = 0.5
c_i_n_s_per_mm3 = 0.0001

[[blocks]]
name = "practice"
method = "two_interval"
design = "2afc"
task = "probe"
standard = "pvc"
comparison = "stiff"
question = "Which interval was stiffer?"
trials = 2
interval_s = 0.4
practice = true
instructions = "Two practice trials, with feedback."
isi_s = 0.3
iti_s = 0.3

[[blocks]]
name = "scored"
method = "two_interval"
design = "2afc"
task = "probe"
standard = "pvc"
comparison = "stiff"
question = "Which interval was stiffer?"
trials = 2
interval_s = 0.4
response_deadline_s = 0.2
)";

constexpr const char* kStation = R"(format = "burrlab-station/1"
[device]
backend = "simulated"
max_force_n = 1.5
max_stiffness_n_per_mm = 3.0
[screen]
width = 1024
height = 640
)";

// The burr starts 1 mm above the surface, presses 1.5 mm deep and comes back.
constexpr const char* kPath =
    "path = [[0.0, 0.0, 0.0, 3.0], [0.2, 0.0, 0.0, 0.5], "
    "[0.4, 0.0, 0.0, 3.0]]\n";

const std::string kBurrlab =
    std::string(BURRLAB_BINARY_DIR) + "/runner/burrlab";

struct ProcessRun {
  int code = -1;
  std::string out;
  std::string err;
};

std::string Read(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

void Write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// What a shell command prints.
std::string Output(const std::string& command) {
  std::string text;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[4096];
    std::size_t n = 0;
    while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) {
      text.append(buffer, n);
    }
    pclose(pipe);
  }
  return text;
}

// Runs the executable with `args`; stdout and stderr apart.
ProcessRun Burrlab(const std::vector<std::string>& args, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen(out.c_str(), "w", stdout) ||
        !freopen(err.c_str(), "w", stderr)) {
      _exit(126);
    }
    std::vector<char*> argv{const_cast<char*>(kBurrlab.c_str())};
    for (const std::string& a : args) {
      argv.push_back(const_cast<char*>(a.c_str()));
    }
    argv.push_back(nullptr);
    execv(kBurrlab.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ProcessRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  r.out = Read(out);
  r.err = Read(err);
  return r;
}

class StationRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::getenv("BURRLAB_NO_XVFB") != nullptr) {
      GTEST_SKIP() << "xvfb-run was not found when the build was configured: "
                      "the station run tests need it (Debian package xvfb)";
    }
    if (std::getenv("DISPLAY") == nullptr) {
      GTEST_SKIP() << "no DISPLAY: run this test through ctest (it wraps it "
                      "in xvfb-run)";
    }
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(BURRLAB_BINARY_DIR) / "test_tmp" / "station_run" /
           info->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    Write(dir_ / "protocol.toml", kProtocol);
    Write(dir_ / "station.toml", kStation);
  }

  // `burrlab run` at the simulated station with `script` (its format line
  // and path added).
  ProcessRun RunWith(const std::string& script, bool resume = false) {
    return RunProtocol("protocol.toml", script, resume);
  }
  ProcessRun RunProtocol(const std::string& protocol, const std::string& script,
                         bool resume = false) {
    Write(dir_ / "script.toml", "format = \"burrlab-station-script/1\"\n" +
                                    std::string(kPath) + script);
    std::vector<std::string> args = {
        "run",           (dir_ / protocol).string(),
        "--subject",     "01",
        "--out",         (dir_ / "out").string(),
        "--device",      "simulated",
        "--station",     (dir_ / "station.toml").string(),
        "--script",      (dir_ / "script.toml").string(),
        "--screenshots", (dir_ / "shots").string()};
    if (resume) args.push_back("--resume");
    return Burrlab(args, dir_);
  }

  // The screenshots the run saved, by name (they sort in the order shown).
  std::vector<std::string> Screenshots() const {
    std::vector<std::string> shots;
    for (const auto& e : fs::directory_iterator(dir_ / "shots")) {
      shots.push_back(e.path().filename().string());
    }
    std::sort(shots.begin(), shots.end());
    return shots;
  }

  std::vector<rs::TrialRecord> Trials() {
    auto journal = rs::Journal::Open(dir_ / "out", "01");
    EXPECT_TRUE(journal.ok()) << journal.error().message;
    if (!journal.ok()) return {};
    auto trials = journal->Trials();
    EXPECT_TRUE(trials.ok());
    return trials.ok() ? trials.value() : std::vector<rs::TrialRecord>{};
  }

  fs::path dir_;
};

TEST_F(StationRunTest, RunsTheProtocolAndStoresLoopStatisticsPerInterval) {
  const ProcessRun run = RunWith("answers = [\"1\", \"2\"]\n");
  ASSERT_EQ(run.code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("sub-01: 2 trials (0 resumed, 2 run now)"),
            std::string::npos)
      << run.out;

  const std::vector<rs::TrialRecord> trials = Trials();
  ASSERT_EQ(trials.size(), 2u);
  EXPECT_EQ(trials[0].response, "1");
  EXPECT_EQ(trials[1].response, "2");
  const double stiff_c_e = MaxRenderableCe(2.0, 1.5, 3.0);  // 1.633 N/mm^2
  for (const rs::TrialRecord& t : trials) {
    SCOPED_TRACE(t.trial_index);
    EXPECT_EQ(t.source, "station simulated");
    ASSERT_TRUE(t.response_time_s.has_value());
    EXPECT_GE(*t.response_time_s, 0.1);  // the script's response delay
    EXPECT_LT(*t.response_time_s, 1.0);
    const auto extra = nlohmann::json::parse(t.extra);
    ASSERT_TRUE(extra.contains("intervals")) << t.extra;
    ASSERT_EQ(extra["intervals"].size(), 2u) << t.extra;
    EXPECT_EQ(extra["aborted_presentations"], 0);
    for (int i = 0; i < 2; ++i) {
      SCOPED_TRACE(i);
      const auto& iv = extra["intervals"][i];
      EXPECT_EQ(iv["interval_index"], i);
      const auto& loop = iv["loop"];
      EXPECT_EQ(loop["rate_hz"], 1000.0);
      // A 0.4 s interval lasts 400 ticks of the 1 kHz loop.
      EXPECT_EQ(loop["ticks"], 400);
      const double p50 = loop["period_error_p50_us"];
      const double p99 = loop["period_error_p99_us"];
      const double max = loop["period_error_max_us"];
      EXPECT_GE(p50, 0.0);
      EXPECT_LE(p50, p99);
      EXPECT_LE(p99, max);
      EXPECT_GE(loop["missed_deadlines"].get<int>(), 0);
      EXPECT_EQ(loop["non_finite_forces"], 0);
      EXPECT_EQ(loop["device_errors"], 0);
      EXPECT_EQ(iv["max_force_n"], 1.5);
      // Which interval held the stiff material is the trial's random order.
      if (t.interval_materials[i] == "stiff") {
        EXPECT_NEAR(iv["c_e_n_per_mm2"].get<double>(), stiff_c_e, 1e-12);
        EXPECT_EQ(iv["c_e_limited_from_n_per_mm2"], 20.0);
        // 1.5 mm deep at 1.63 N/mm^2 asks for 4.2 N: clamped to 1.5 N.
        EXPECT_GT(loop["clamped_ticks"].get<int>(), 50);
      } else {
        EXPECT_EQ(iv["c_e_n_per_mm2"], 0.462);
        EXPECT_TRUE(iv["c_e_limited_from_n_per_mm2"].is_null());
        EXPECT_EQ(loop["clamped_ticks"], 0);  // 1.2 N at most
      }
    }
  }

  // The traces: one per interval at 100 Hz, force within the station's limit,
  // the burr's scripted path.
  auto journal = rs::Journal::Open(dir_ / "out", "01");
  ASSERT_TRUE(journal.ok());
  auto traces = journal->Traces(0);
  ASSERT_TRUE(traces.ok()) << traces.error().message;
  ASSERT_EQ(traces->size(), 2u);
  for (const rs::TraceSamples& tr : traces.value()) {
    EXPECT_EQ(tr.sampling_frequency_hz, 100.0);
    ASSERT_EQ(tr.columns.size(), 6u);
    EXPECT_EQ(tr.columns[2], "position_z_mm");
    EXPECT_EQ(tr.columns[5], "force_z_n");
    ASSERT_EQ(tr.rows.size(), 40u);  // 400 ticks in rows of 10
    double deepest_mm = 1e9, strongest_n = 0.0;
    for (const std::vector<double>& row : tr.rows) {
      deepest_mm = std::min(deepest_mm, row[2]);
      strongest_n = std::max(strongest_n,
                             glm::length(glm::dvec3(row[3], row[4], row[5])));
    }
    EXPECT_NEAR(deepest_mm, 0.5, 0.2);
    EXPECT_LE(strongest_n, 1.5 + 1e-9);
    EXPECT_GT(strongest_n, 0.5);
  }
  EXPECT_LT(traces.value()[0].start_time_s, traces.value()[1].start_time_s);

  // BIDS export: both trials, and the four intervals' traces in the block's
  // physio file (40 rows each) with their columns in the sidecar.
  const fs::path beh = dir_ / "out" / "sub-01" / "beh";
  const std::string tsv = Read(beh / "sub-01_task-probe2afc_beh.tsv");
  EXPECT_EQ(std::count(tsv.begin(), tsv.end(), '\n'), 3) << tsv;
  EXPECT_NE(tsv.find("clamped_ticks"), std::string::npos);
  const auto sidecar =
      nlohmann::json::parse(Read(beh / "sub-01_task-probe2afc_physio.json"));
  EXPECT_EQ(sidecar["Columns"],
            nlohmann::json::parse(
                R"(["trial_index", "interval_index", "time", "position_x_mm",
                    "position_y_mm", "position_z_mm", "force_x_n",
                    "force_y_n", "force_z_n"])"));
  const std::string rows =
      Output("gzip -dc '" +
             (beh / "sub-01_task-probe2afc_physio.tsv.gz").string() + "'");
  EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 160);

  // `analyze kinematics` on these traces: the force is |F| of the three
  // components, the speed 3-D. Truth computed by hand from the script: the
  // hand moves at 12.5 mm/s, down for 0.2 s and back up; a row is the mean of
  // 10 ticks, so of an interval's 39 steps between rows 38 are 0.125 mm
  // (12.5 mm/s) and the one across the turn is 0.56875 - 0.55625 mm
  // (1.25 mm/s): mean (38 x 12.5 + 1.25) / 39 mm/s.
  const ProcessRun kinematics = Burrlab(
      {"analyze", "kinematics", (dir_ / "out").string(), "--json"}, dir_);
  ASSERT_EQ(kinematics.code, 0) << kinematics.err;
  const auto k = nlohmann::json::parse(kinematics.out)["kinematics"][0];
  EXPECT_EQ(k["force_measure"], "|F| of force_x_n, force_y_n, force_z_n");
  EXPECT_EQ(k["speed_measure"],
            "|dp/dt| of position_x_mm, position_y_mm, position_z_mm");
  EXPECT_EQ(k["intervals"], 4);
  EXPECT_EQ(k["samples"], 160);
  EXPECT_LE(k["max_force_n"].get<double>(), 1.5 + 1e-9);
  EXPECT_GT(k["max_force_n"].get<double>(), 0.5);
  EXPECT_NEAR(k["mean_speed_mm_s"].get<double>(), (38 * 12.5 + 1.25) / 39, 1e-6)
      << kinematics.out;

  // A screenshot of every phase: ready, two intervals, response per trial,
  // and the end.
  const std::vector<std::string> shots = Screenshots();
  const std::vector<std::string> expected = {
      "001_trial1_ready.png",     "002_trial1_interval1.png",
      "003_trial1_interval2.png", "004_trial1_response.png",
      "005_trial2_ready.png",     "006_trial2_interval1.png",
      "007_trial2_interval2.png", "008_trial2_response.png",
      "009_finished.png"};
  EXPECT_EQ(shots, expected);
}

// The pacing phases at a station, driven by the script: instructions and
// the rest break go on after continue_delay_s, feedback ends at a key after
// end_feedback_after_s; the gaps pass on the clock. Practice trials and late
// answers are marked in the journal.
TEST_F(StationRunTest, PacesTheSessionWithInstructionsGapsFeedbackAndBreaks) {
  Write(dir_ / "paced.toml", kPacedProtocol);
  const ProcessRun run =
      RunProtocol("paced.toml",
                  "answers = [\"2\", \"2\", \"1\", \"2\"]\n"
                  "response_delay_s = 0.3\ncontinue_delay_s = 0.1\n"
                  "end_feedback_after_s = 0.2\n");
  ASSERT_EQ(run.code, 0) << run.out << run.err;
  const std::vector<rs::TrialRecord> trials = Trials();
  ASSERT_EQ(trials.size(), 4u);
  for (const rs::TrialRecord& t : trials) {
    SCOPED_TRACE(t.trial_index);
    const bool practice = t.trial_index < 2;
    EXPECT_EQ(t.practice, practice);
    ASSERT_TRUE(t.response_time_s.has_value());
    EXPECT_GE(*t.response_time_s, 0.3);
    // The scored block's deadline is 0.2 s: the answers after 0.3 s are
    // kept, and late.
    EXPECT_EQ(t.late, practice ? std::nullopt : std::optional<bool>(true));
    ASSERT_TRUE(t.correct.has_value());
    // Two intervals, with the 0.3 s gap between them in the practice block.
    // A trace starts when the session sees its interval begin, up to a
    // frame of the window loop after the controller's schedule, so either
    // start may lag by a frame (under the sanitizers on a 2-core machine
    // the second came 0.044 s closer than scheduled); 0.1 s of slack still
    // tells a 0.7 s spacing from the 0.4 s one without the gap.
    auto journal = rs::Journal::Open(dir_ / "out", "01");
    ASSERT_TRUE(journal.ok());
    auto traces = journal->Traces(t.trial_index);
    ASSERT_TRUE(traces.ok());
    ASSERT_EQ(traces->size(), 2u);
    EXPECT_GE((*traces)[1].start_time_s - (*traces)[0].start_time_s,
              0.4 + (practice ? 0.3 : 0.0) - 0.1);
  }
  // Every screen, in order: the study's and the block's instructions, then
  // per practice trial the gap between intervals, the feedback and the gap
  // after the answer; the rest break before the scored block.
  const std::vector<std::string> shots = Screenshots();
  const std::vector<std::string> expected = {
      "001_trial1_instructions_study.png",
      "002_trial1_instructions_block.png",
      "003_trial1_ready.png",
      "004_trial1_interval1.png",
      "005_trial1_isi1.png",
      "006_trial1_interval2.png",
      "007_trial1_response.png",
      "008_trial1_feedback.png",
      "009_trial1_iti.png",
      "010_trial2_ready.png",
      "011_trial2_interval1.png",
      "012_trial2_isi1.png",
      "013_trial2_interval2.png",
      "014_trial2_response.png",
      "015_trial2_feedback.png",
      "016_trial2_iti.png",
      "017_trial3_break.png",
      "018_trial3_ready.png",
      "019_trial3_interval1.png",
      "020_trial3_interval2.png",
      "021_trial3_response.png",
      "022_trial4_ready.png",
      "023_trial4_interval1.png",
      "024_trial4_interval2.png",
      "025_trial4_response.png",
      "026_finished.png"};
  EXPECT_EQ(shots, expected);
}

// The method of adjustment at the station: the standard (PVC), the
// comparison at twice its stiffness, then UP/DOWN keys (or the +/- buttons)
// each step the comparison's c_e by 10^0.1 and present it again; ENTER ends.
constexpr const char* kAdjustmentProtocol = R"(format = "burrlab-protocol/1"

[study]
name = "Station adjustment check"

[recording]
trace_hz = 100

[materials.pvc]
builtin = "pvc_k70"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "pvc"

[[blocks]]
name = "adjust"
method = "adjustment"
task = "probe"
axis = "ce"
standard_level = 1.0
start_level = 2.0
step = 0.1
step_scale = "log10"
floor = 0.5
ceiling = 4.0
max_steps = 3
interval_s = 0.4
question = "Step the second surface until it feels as stiff as the first."
)";

// Three steps (a key, a clicked button, a key), a fourth refused at
// max_steps, then ENTER: the journal keeps the path and the level it reached
// (closed form: 2 x 10^(0.1 (1 - 2)) = 1.5849), and every comparison felt
// after a step was rendered at the level that step reached, its trace kept.
TEST_F(StationRunTest, AdjustsTheComparisonWithKeysAndRendersEachStep) {
  Write(dir_ / "adjust.toml", kAdjustmentProtocol);
  const ProcessRun run =
      RunProtocol("adjust.toml",
                  "answers = [\"UP\", \"-\", \"DOWN\", \"DOWN\", \"ENTER\"]\n");
  ASSERT_EQ(run.code, 0) << run.out << run.err;
  const std::vector<rs::TrialRecord> trials = Trials();
  ASSERT_EQ(trials.size(), 1u);
  const rs::TrialRecord& t = trials[0];
  EXPECT_EQ(t.method, "adjustment");
  EXPECT_EQ(t.response, "+--=");
  ASSERT_TRUE(t.stim_level.has_value());
  EXPECT_NEAR(*t.stim_level, 2.0 * std::pow(10.0, -0.1), 1e-9);
  // Timed from the first question to ENTER, the three 0.4 s comparisons and
  // five 0.1 s response delays included.
  ASSERT_TRUE(t.response_time_s.has_value());
  EXPECT_GE(*t.response_time_s, 3 * 0.4 + 4 * 0.1);
  EXPECT_LT(*t.response_time_s, 30.0);
  const auto extra = nlohmann::json::parse(t.extra);
  ASSERT_EQ(extra["intervals"].size(), 5u) << t.extra;
  // Levels felt: the standard, the start, then after +, -, -.
  const std::vector<double> levels = {1.0, 2.0, 2.0 * std::pow(10.0, 0.1), 2.0,
                                      2.0 * std::pow(10.0, -0.1)};
  for (std::size_t i = 0; i < levels.size(); ++i) {
    SCOPED_TRACE(i);
    const auto& iv = extra["intervals"][i];
    EXPECT_EQ(iv["interval_index"], static_cast<int>(i));
    EXPECT_EQ(iv["loop"]["ticks"], 400);
    EXPECT_NEAR(iv["c_e_n_per_mm2"].get<double>(), 0.462 * levels[i], 1e-9);
  }
  auto journal = rs::Journal::Open(dir_ / "out", "01");
  ASSERT_TRUE(journal.ok());
  auto traces = journal->Traces(0);
  ASSERT_TRUE(traces.ok());
  ASSERT_EQ(traces->size(), 5u);
  for (std::size_t i = 0; i < traces->size(); ++i) {
    EXPECT_EQ((*traces)[i].interval_index, static_cast<int>(i));
    EXPECT_EQ((*traces)[i].rows.size(), 40u);
    if (i > 0) {
      EXPECT_GT((*traces)[i].start_time_s, (*traces)[i - 1].start_time_s);
    }
  }
  const std::vector<std::string> shots = Screenshots();
  const std::vector<std::string> expected = {
      "001_trial1_ready.png",     "002_trial1_interval1.png",
      "003_trial1_interval2.png", "004_trial1_response.png",
      "005_trial1_interval3.png", "006_trial1_response.png",
      "007_trial1_interval4.png", "008_trial1_response.png",
      "009_trial1_interval5.png", "010_trial1_response.png",
      "011_finished.png"};
  EXPECT_EQ(shots, expected);
}

TEST_F(StationRunTest, UnplugMidTrialPausesStopsAndResumeLosesNothing) {
  // The device goes away 0.1 s into the first interval of the second trial;
  // nobody resumes: the session stops paused with trial 1 saved.
  const ProcessRun stopped = RunWith(
      "answers = [\"1\", \"2\"]\n"
      "[[unplug]]\npresentation = 2\ninterval = 1\nafter_s = 0.1\n");
  EXPECT_EQ(stopped.code, 1) << stopped.out << stopped.err;
  EXPECT_EQ(stopped.out,
            "sub-01: stopped after 1 trials: paused: the simulated device "
            "failed (unplugged: simulated device unplugged). They are saved; "
            "continue with --resume.\n");
  EXPECT_NE(stopped.err.find("burrlab: trial 2 aborted: the simulated device "
                             "failed (unplugged: simulated device "
                             "unplugged); the session is paused"),
            std::string::npos)
      << stopped.err;
  std::vector<rs::TrialRecord> trials = Trials();
  ASSERT_EQ(trials.size(), 1u);
  const rs::TrialRecord first = trials[0];
  EXPECT_EQ(first.response, "1");

  // A resume with another station file (a lower force limit) is refused by
  // name, and adds nothing. Truth: the SHA-256 of the two files' bytes.
  std::string lower(kStation);
  lower.replace(lower.find("max_force_n = 1.5"), 17, "max_force_n = 1.2");
  Write(dir_ / "station.toml", lower);
  const ProcessRun other = RunWith("answers = [\"2\"]\n", true);
  EXPECT_EQ(other.code, 1);
  EXPECT_NE(other.err.find("burrlab: cannot resume sub-01 in " +
                           (dir_ / "out").string() +
                           ": station_file_sha256 differs from the journal's "
                           "(\"" +
                           Sha256Hex(kStation) + "\" in the journal, \"" +
                           Sha256Hex(lower) + "\" now)\n"),
            std::string::npos)
      << other.err;
  EXPECT_EQ(Trials().size(), 1u);
  Write(dir_ / "station.toml", kStation);

  // Resumed with the device back: trial 2 runs from its start.
  const ProcessRun resumed = RunWith("answers = [\"2\"]\n", true);
  ASSERT_EQ(resumed.code, 0) << resumed.out << resumed.err;
  EXPECT_NE(resumed.out.find("sub-01: 2 trials (1 resumed, 1 run now)"),
            std::string::npos)
      << resumed.out;
  trials = Trials();
  ASSERT_EQ(trials.size(), 2u);
  EXPECT_EQ(trials[0], first);  // untouched
  EXPECT_EQ(trials[1].response, "2");
}

TEST_F(StationRunTest, UnplugThenResumePresentsTheTrialAgain) {
  const ProcessRun run = RunWith(
      "answers = [\"2\", \"1\"]\n"
      "[[unplug]]\npresentation = 1\ninterval = 2\nafter_s = 0.05\n"
      "resume = true\n");
  ASSERT_EQ(run.code, 0) << run.out << run.err;
  const std::vector<rs::TrialRecord> trials = Trials();
  ASSERT_EQ(trials.size(), 2u);
  const auto extra = nlohmann::json::parse(trials[0].extra);
  EXPECT_EQ(extra["aborted_presentations"], 1);
  ASSERT_EQ(extra["intervals"].size(), 2u);  // the full second presentation
  EXPECT_EQ(extra["intervals"][1]["loop"]["ticks"], 400);
  EXPECT_EQ(nlohmann::json::parse(trials[1].extra)["aborted_presentations"], 0);
  EXPECT_NE(run.err.find("resumed: trial 1 is presented again"),
            std::string::npos)
      << run.err;
  // The pause was shown, then the trial from its start.
  EXPECT_TRUE(fs::exists(dir_ / "shots" / "004_trial1_paused.png"));
  EXPECT_TRUE(fs::exists(dir_ / "shots" / "005_trial1_ready.png"));
}

TEST_F(StationRunTest, ScriptRunningOutOfAnswersStopsWithTheTrialsSaved) {
  const ProcessRun run = RunWith("answers = [\"1\"]\n");
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.out,
            "sub-01: stopped after 1 trials: the script's answers ran out (1 "
            "given) at trial 2. They are saved; continue with --resume.\n");
  EXPECT_EQ(Trials().size(), 1u);
}

}  // namespace
}  // namespace burrlab::runner
