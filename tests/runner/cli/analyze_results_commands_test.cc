// `burrlab analyze scores|thresholds|kinematics DIR` on the results of real
// simulated studies: the staircase thresholds equal the engine's own
// estimates, the scores JSON carries the tests and the histogram, and a
// folder without results is one error line and exit 1.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/results_schema/bids_read.h"
#include "burrlab/results_schema/journal.h"
#include "paced_protocol.h"
#include "run_cli.h"
#include "two_block_protocol.h"

namespace burrlab::runner {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class AnalyzeResults : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("burrlab_results_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs `burrlab study` on an example protocol into dir_/name.
  std::string Study(const std::string& example, int subjects,
                    const std::string& name) {
    const std::string out = (dir_ / name).string();
    const CliRun run = RunBurrlab(
        {"study",
         std::string(BURRLAB_SOURCE_DIR) + "/protocols/examples/" + example,
         "--simulated-subjects", std::to_string(subjects), "--out", out,
         "--seed", "7", "--jobs", "1"});
    EXPECT_EQ(run.code, 0) << run.err;
    return out;
  }

  fs::path dir_;
};

TEST_F(AnalyzeResults, StaircaseThresholdsEqualTheEngineEstimates) {
  const std::string results = Study("staircase_1up3down.toml", 1, "stairs");
  const CliRun run = RunBurrlab({"analyze", "thresholds", results, "--json"});
  ASSERT_EQ(run.code, 0) << run.err;
  const Json j = Json::parse(run.out);
  // The engine's estimate after each staircase's last trial.
  auto files = results_schema::ReadBidsDataset(results);
  ASSERT_TRUE(files.ok());
  std::map<int, double> engine;
  for (const auto& t : (*files)[0].table.trials) {
    if (t.estimate) engine[*t.staircase_id] = *t.estimate;
  }
  ASSERT_EQ(j["thresholds"].size(), 2u);
  ASSERT_GE(engine.size(), 1u);
  for (const Json& t : j["thresholds"]) {
    EXPECT_EQ(t["estimator"], "mean of the last 6 reversals (log10 scale)");
    EXPECT_EQ(t["spread_unit"], "log10");
    const int id = t["staircase_id"].get<int>();
    if (engine.contains(id)) {
      EXPECT_NEAR(t["value"].get<double>(), engine.at(id), 1e-12);
      EXPECT_EQ(t["n"], 6);
    } else {  // the track ended before its sixth reversal: no estimate either
      EXPECT_TRUE(t["value"].is_null());
      EXPECT_EQ(t["note"].get<std::string>().substr(0, 5), "only ");
    }
  }
}

TEST_F(AnalyzeResults, ScoresJsonHasTheTestsAndTheHistogram) {
  const std::string results = Study("two_interval_2afc.toml", 2, "twoafc");
  const std::string plots = (dir_ / "plots").string();
  const CliRun run =
      RunBurrlab({"analyze", "scores", results, "--json", "--plots", plots});
  ASSERT_EQ(run.code, 0) << run.err;
  const Json j = Json::parse(run.out);
  ASSERT_EQ(j["blocks"].size(), 1u);
  const Json& b = j["blocks"][0];
  EXPECT_EQ(b["method"], "two_interval");
  EXPECT_EQ(b["chance"], 0.5);
  EXPECT_EQ(b["trials_per_subject"], 12);
  EXPECT_EQ(b["subjects"].size(), 2u);
  int correct = 0;
  for (const Json& s : b["subjects"]) correct += s["correct"].get<int>();
  EXPECT_EQ(b["binomial"]["successes"], correct);
  EXPECT_EQ(b["binomial"]["trials"], 24);
  EXPECT_TRUE(b["t_test"].is_object() || !b["warnings"].empty());
  EXPECT_TRUE(fs::exists(b["histogram"].get<std::string>()));

  const CliRun kin = RunBurrlab({"analyze", "kinematics", results, "--json"});
  ASSERT_EQ(kin.code, 0) << kin.err;
  const Json k = Json::parse(kin.out);
  ASSERT_EQ(k["kinematics"].size(), 2u);
  EXPECT_EQ(k["kinematics"][0]["task"], "probe");
  EXPECT_EQ(k["kinematics"][0]["intervals"], 24);
  EXPECT_NEAR(k["kinematics"][0]["duration_s"].get<double>(), 120.0, 1e-6);
  EXPECT_NEAR(k["kinematics"][0]["removal_rate_mm3_per_s"].get<double>(), 0.0,
              1e-12);  // probing removes nothing
}

// Practice trials are never scored and the output says how many were left
// out; late answers are counted per block (truth: the exported marks).
TEST_F(AnalyzeResults, ScoresLeaveOutPracticeAndCountLateAnswers) {
  const std::string protocol = (dir_ / "paced.toml").string();
  std::ofstream(protocol) << PacedProtocol(0.5, 0.25, 0.5, 1.0);
  const std::string results = (dir_ / "out").string();
  ASSERT_EQ(RunBurrlab({"study", protocol, "--simulated-subjects", "2", "--out",
                        results, "--seed", "3", "--jobs", "1"})
                .code,
            0);
  auto files = results_schema::ReadBidsDataset(results);
  ASSERT_TRUE(files.ok()) << files.error().message;
  int late = 0, practice = 0;
  for (const auto& f : *files) {
    for (const auto& t : f.table.trials) {
      practice += t.practice ? 1 : 0;
      if (!t.practice) {
        ASSERT_TRUE(t.late.has_value()) << t.trial_index;
        late += *t.late ? 1 : 0;
      } else {
        EXPECT_EQ(t.late, std::nullopt);  // no deadline in practice
      }
    }
  }
  EXPECT_EQ(practice, 8);
  EXPECT_GT(late, 0);  // simulated answers take about 1 s: some are late
  EXPECT_LT(late, 16);
  const CliRun text = RunBurrlab({"analyze", "scores", results});
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_TRUE(text.out.starts_with(
      "left out 8 practice trials, never scored: familiarize (8)\n\nblock "
      "main (same_different, probe): 2 subjects, 8 trials each\n"))
      << text.out;
  EXPECT_NE(text.out.find("  late       " + std::to_string(late) +
                          " of 16 answers after the response deadline (kept "
                          "and scored)\n"),
            std::string::npos)
      << text.out;
  const CliRun json = RunBurrlab({"analyze", "scores", results, "--json"});
  ASSERT_EQ(json.code, 0) << json.err;
  const Json j = Json::parse(json.out);
  EXPECT_EQ(j["practice_left_out"],
            Json::parse(R"([{"block": "familiarize", "trials": 8}])"));
  ASSERT_EQ(j["blocks"].size(), 1u);
  EXPECT_EQ(j["blocks"][0]["late_answers"], late);
  EXPECT_EQ(j["blocks"][0]["answers_with_deadline"], 16);
}

// A subject whose run stopped before its export (here: its exports
// removed) is named on every analysis, never left out silently. Truth: the
// journal's own trial count.
TEST_F(AnalyzeResults, SubjectsWithTrialsMissingFromTheExportsAreNamed) {
  // Two subjects of a 10-trial protocol with 0.5 s intervals (a fraction of
  // a second to run); sub-02's exports are then lost.
  const std::string protocol = (dir_ / "protocol.toml").string();
  std::ofstream(protocol) << TwoBlockProtocol("left out", 4, 6, 0.5);
  const std::string results = (dir_ / "out").string();
  for (const std::string subject : {"01", "02"}) {
    ASSERT_EQ(RunBurrlab({"run", protocol, "--subject", subject, "--out",
                          results, "--observer", "simulated"})
                  .code,
              0);
  }
  fs::remove_all(fs::path(results) / "sub-02" / "beh");
  int journal_trials = 0;
  {
    auto journal = results_schema::Journal::Open(results, "02");
    ASSERT_TRUE(journal.ok());
    journal_trials = journal->NextTrialIndex().value();
  }
  ASSERT_GT(journal_trials, 0);
  const std::string warning =
      "burrlab: warning: sub-02's journal holds " +
      std::to_string(journal_trials) +
      " trials but its exports only 0, and analyses read the exports; "
      "`burrlab run PROTOCOL --subject 02 --out " +
      results +
      " --resume` exports them (and finishes the session if it can)\n";
  for (const std::string command : {"scores", "thresholds", "kinematics"}) {
    const CliRun run = RunBurrlab({"analyze", command, results});
    EXPECT_EQ(run.code, 0) << command << run.err;
    EXPECT_EQ(run.err, warning) << command;
  }
  fs::remove_all(fs::path(results) / "sub-01" / "beh");
  const CliRun none = RunBurrlab({"analyze", "thresholds", results});
  EXPECT_EQ(none.code, 1);
  EXPECT_TRUE(none.err.starts_with("burrlab: warning: sub-01's journal holds"))
      << none.err;
  EXPECT_NE(none.err.find(warning + "burrlab: " + results + " holds no "),
            std::string::npos)
      << none.err;
}

// A subject whose session stopped on an error has all its saved trials
// exported, but its session is incomplete: every analysis names it once,
// with the trials done of those planned and the command that finishes it,
// and analyses its trials all the same. Truth: the journal's own trial
// count; 3 levels x 4 repetitions = 12 planned trials.
TEST_F(AnalyzeResults, SubjectsWhoseSessionStoppedEarlyAreNamed) {
  const std::string protocol = (dir_ / "protocol.toml").string();
  std::ofstream(protocol) << R"(format = "burrlab-protocol/1"
[study]
name = "stopped early"
[recording]
trace_hz = 100
[materials.bone]
builtin = "human_temporal_bone"
[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"
[[blocks]]
name = "constant"
method = "constant_stimuli"
task = "probe"
axis = "ce"
standard_level = 1.0
levels = [1.1, 1.3, 1.6]
repetitions = 4
response = "2afc"
interval_s = 0.5
)";
  const std::string results = (dir_ / "out").string();
  ASSERT_EQ(RunBurrlab({"run", protocol, "--subject", "01", "--out", results,
                        "--observer", "simulated"})
                .code,
            0);
  // sub-02's journal fills up part way: the run stops on the error.
  Result<LoadedProtocol> loaded = LoadProtocol(protocol);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  SessionOptions options;
  options.out_dir = results;
  options.subject = "02";
  options.subject_index = 1;
  options.journal_limit_bytes_for_testing = 64 * 1024;
  ASSERT_FALSE(RunSession(*loaded, options).ok());
  int saved = 0;
  {
    auto journal = results_schema::Journal::Open(results, "02");
    ASSERT_TRUE(journal.ok());
    saved = journal->NextTrialIndex().value();
  }
  ASSERT_GT(saved, 0);
  ASSERT_LT(saved, 12);
  const std::string warning =
      "burrlab: warning: sub-02's session is incomplete: it stopped after " +
      std::to_string(saved) + " of 12 planned trials; its " +
      std::to_string(saved) +
      " trials are analysed, and `burrlab run PROTOCOL --subject 02 --out " +
      results + " --resume` finishes it\n";
  for (const std::string command : {"scores", "thresholds", "kinematics"}) {
    const CliRun run = RunBurrlab({"analyze", command, results, "--json"});
    EXPECT_EQ(run.code, 0) << command << run.err;
    EXPECT_EQ(run.err, warning) << command;
    EXPECT_NE(run.out.find("\"02\""), std::string::npos) << command;
  }
  const std::string beh = results + "/sub-02/beh/sub-02_task-constant_beh.tsv";
  const CliRun fit =
      RunBurrlab({"analyze", "fit", "--data", beh, "--task", "2afc",
                  "--sigmoid", "logistic", "--bootstrap", "0"});
  EXPECT_TRUE(fit.err.starts_with(warning)) << fit.err;
  // sub-01 ran to its end: no warning for its file.
  const CliRun fit01 = RunBurrlab(
      {"analyze", "fit", "--data",
       results + "/sub-01/beh/sub-01_task-constant_beh.tsv", "--task", "2afc",
       "--sigmoid", "logistic", "--bootstrap", "0"});
  EXPECT_EQ(fit01.err.find("sub-01"), std::string::npos) << fit01.err;
  // Finishing it ends the warnings.
  options.journal_limit_bytes_for_testing = 0;
  options.resume = true;
  ASSERT_TRUE(RunSession(*loaded, options).ok());
  EXPECT_EQ(RunBurrlab({"analyze", "scores", results}).err, "");
}

TEST_F(AnalyzeResults, FoldersWithoutResultsAreOneErrorLine) {
  for (const std::string command : {"scores", "thresholds", "kinematics"}) {
    const CliRun run = RunBurrlab({"analyze", command, dir_.string()});
    EXPECT_EQ(run.code, 1) << command;
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(run.err, "burrlab: " + dir_.string() +
                           " holds no burrlab results (no "
                           "sub-*/beh/sub-*_task-*_beh.tsv); give the --out "
                           "folder of 'burrlab run' or 'burrlab study'\n");
  }
  const CliRun missing =
      RunBurrlab({"analyze", "scores", (dir_ / "nope").string()});
  EXPECT_EQ(missing.code, 1);
  EXPECT_EQ(missing.err, "burrlab: cannot read " + (dir_ / "nope").string() +
                             ": not a folder\n");
}

}  // namespace
}  // namespace burrlab::runner

namespace burrlab::runner {
namespace {

TEST(AnalyzePower, ReportsPowerWithIntervalsPerScoredBlock) {
  const std::string protocol = std::string(BURRLAB_SOURCE_DIR) +
                               "/protocols/examples/two_interval_2afc.toml";
  const CliRun run =
      RunBurrlab({"analyze", "power", "--protocol", protocol, "--weber", "0.5",
                  "--subjects", "5", "--runs", "50", "--seed", "3", "--json"});
  ASSERT_EQ(run.code, 0) << run.err;
  const Json j = Json::parse(run.out);
  EXPECT_EQ(j["runs"], 50);
  ASSERT_EQ(j["blocks"].size(), 1u);
  const Json& b = j["blocks"][0];
  EXPECT_EQ(b["method"], "two_interval");
  for (const char* test : {"power_t_test", "power_binomial"}) {
    const double p = b[test]["p"].get<double>();
    EXPECT_GE(p, b[test]["ci"][0].get<double>()) << test;
    EXPECT_LE(p, b[test]["ci"][1].get<double>()) << test;
  }
  // Same seed, same answer.
  const CliRun again =
      RunBurrlab({"analyze", "power", "--protocol", protocol, "--weber", "0.5",
                  "--subjects", "5", "--runs", "50", "--seed", "3", "--json"});
  EXPECT_EQ(again.out, run.out);
}

TEST(AnalyzePower, BadInputIsOneErrorLine) {
  const std::string examples =
      std::string(BURRLAB_SOURCE_DIR) + "/protocols/examples/";
  const CliRun adjustment = RunBurrlab(
      {"analyze", "power", "--protocol", examples + "adjustment_alpha.toml",
       "--weber", "0.3", "--subjects", "4", "--runs", "2"});
  EXPECT_EQ(adjustment.code, 1);
  EXPECT_EQ(adjustment.err,
            "burrlab: analyze power: block \"adjust\": adjustment blocks "
            "cannot be simulated virtually (no correct answer to score); "
            "leave them out of a power analysis\n");
  const CliRun one = RunBurrlab({"analyze", "power", "--protocol",
                                 examples + "two_interval_2afc.toml", "--weber",
                                 "0.3", "--subjects", "1", "--runs", "2"});
  EXPECT_EQ(one.code, 1);
  EXPECT_EQ(one.err.substr(0, 21), "burrlab: --subjects m");
  const CliRun weber = RunBurrlab(
      {"analyze", "power", "--protocol", examples + "two_interval_2afc.toml",
       "--weber", "-1", "--subjects", "4", "--runs", "2"});
  EXPECT_EQ(weber.code, 1);
  EXPECT_EQ(weber.out, "");
}

}  // namespace
}  // namespace burrlab::runner

namespace burrlab::runner {
namespace {

TEST(FitObserversCommand, FitsEachNamedBlockAndRefusesAmbiguousFlags) {
  const std::string protocol = ExamplePath("two_interval_2afc.toml");
  CliRun run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                           "--observed", "mean=9,sem=0.4,n=20", "--observed",
                           "block=probe2afc,mean=9,sem=0.4,n=20"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: --observed mean=9,sem=0.4,n=20 needs block=NAME when "
            "--observed is given more than once\n");
  run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                    "--observed", "block=a,mean=9,sem=0.4,n=20", "--observed",
                    "block=b,mean=9,sem=0.4,n=20", "--block", "a"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: --block goes with one --observed; with several, name "
            "each one's block inside it (block=NAME,mean=...)\n");
  run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                    "--observed", "block=nope,mean=9,sem=0.4,n=20",
                    "--cue-samples", "1", "--virtual-subjects", "20"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: analyze fit-observers: the protocol has no block "
            "\"nope\" (blocks: probe2afc)\n");
  run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                    "--observed", "block=probe2afc,mean=9,sem=0.4,n=20",
                    "--cue-samples", "1", "--virtual-subjects", "50", "--json",
                    "--no-spread"});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j["fits"].size(), 1u);
  EXPECT_EQ(j["fits"][0]["block"], "probe2afc");
  EXPECT_EQ(j["fits"][0]["cue"], "stiffness");
  EXPECT_NEAR(j["fits"][0]["fitted"]["mean"].get<double>(), 9.0, 0.3);
  EXPECT_EQ(j["population"]["weber_stiffness"], j["fits"][0]["weber"]);
  EXPECT_EQ(j["population"]["weber_removal"], j["fits"][0]["weber"]);
  EXPECT_EQ(j["population"]["notes"].size(), 1u);
}

}  // namespace
}  // namespace burrlab::runner
