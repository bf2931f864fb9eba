// `burrlab analyze scores|rt|thresholds|kinematics DIR` on the results of
// real simulated studies: the staircase thresholds equal the engine's own
// estimates, the scores JSON carries the tests and the histogram, response
// times skip and count the trials without one, kinematics compares the
// groups of a participants.tsv, and a folder without results is one error
// line and exit 1.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/results_schema/bids_export.h"
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

// Constant stimuli on a ratio axis (fitted in log10 units) with observers too
// coarse for the levels
// (Weber 1.5 against comparisons 1.05-2 x bone): bootstrap refits run into
// the edge of the fit's search range, which the notes name ("alpha = X is at
// the upper limit of the search range"). No interval printed may be that
// edge as a number: such a bound reads "search limit", and is null in JSON
// with ci_at_search_limit saying which side.
TEST_F(AnalyzeResults, NoIntervalIsTheSearchLimitPrintedAsANumber) {
  const std::string results = (dir_ / "coarse").string();
  const CliRun study = RunBurrlab(
      {"study",
       std::string(BURRLAB_SOURCE_DIR) +
           "/protocols/examples/constant_stimuli_ce_ratio.toml",
       "--simulated-subjects", "6", "--out", results, "--seed", "7", "--jobs",
       "1", "--renderings", "4", "--observer", "simulated:weber=1.5"});
  ASSERT_EQ(study.code, 0) << study.err;
  const CliRun text = RunBurrlab({"analyze", "thresholds", results});
  ASSERT_EQ(text.code, 0) << text.err;
  // The edges the notes name: "alpha = X is at the upper limit of the
  // search range" (std::regex is avoided: GCC 12 warns inside it under the
  // sanitizers).
  std::set<std::string> edges;
  const std::string note_start = "alpha = ";
  for (std::size_t at = text.out.find(note_start); at != std::string::npos;
       at = text.out.find(note_start, at + 1)) {
    const std::size_t value = at + note_start.size();
    const std::size_t end = text.out.find(" is at the ", value);
    const std::size_t line_end = text.out.find('\n', value);
    if (end == std::string::npos || end > line_end) continue;
    if (text.out.compare(
            end, 52, " is at the upper limit of the search range: the data") ==
            0 ||
        text.out.compare(
            end, 52, " is at the lower limit of the search range: the data") ==
            0) {
      // alpha is in log10(ratio) (a ratio axis is fitted in log units): the
      // edge as a ratio, printed as the bounds are.
      edges.insert(fmt::format(
          "{:.4g}",
          std::pow(10.0, std::stod(text.out.substr(value, end - value)))));
    }
  }
  ASSERT_FALSE(edges.empty()) << text.out;
  int flagged = 0, numbers = 0;
  std::istringstream lines(text.out);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t ci = line.find("] 95 % CI");
    if (ci == std::string::npos) continue;
    const std::size_t open = line.rfind('[', ci);
    ASSERT_NE(open, std::string::npos) << line;
    const std::string inside = line.substr(open + 1, ci - open - 1);
    const std::size_t comma = inside.find(", ");
    ASSERT_NE(comma, std::string::npos) << line;
    for (const std::string& bound :
         {inside.substr(0, comma), inside.substr(comma + 2)}) {
      if (bound == "search limit") {
        ++flagged;
      } else {
        ++numbers;
        EXPECT_FALSE(edges.contains(bound)) << line;
      }
    }
  }
  EXPECT_GE(flagged, 1) << text.out;
  EXPECT_GE(numbers, 1) << text.out;
  const CliRun json = RunBurrlab({"analyze", "thresholds", results, "--json"});
  ASSERT_EQ(json.code, 0) << json.err;
  int json_flagged = 0;
  const Json doc = Json::parse(json.out);
  for (const Json& t : doc["thresholds"]) {
    if (t["ci"].is_null()) continue;
    for (int side = 0; side < 2; ++side) {
      if (t["ci_at_search_limit"][side].get<bool>()) {
        ++json_flagged;
        EXPECT_TRUE(t["ci"][side].is_null()) << t.dump();
      }
    }
  }
  EXPECT_EQ(json_flagged, flagged);
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
  // --format: the same figure as PDF.
  const CliRun pdf = RunBurrlab({"analyze", "scores", results, "--json",
                                 "--plots", plots, "--format", "pdf"});
  ASSERT_EQ(pdf.code, 0) << pdf.err;
  const std::string histogram =
      Json::parse(pdf.out)["blocks"][0]["histogram"].get<std::string>();
  EXPECT_EQ(fs::path(histogram).extension(), ".pdf");
  EXPECT_TRUE(fs::exists(histogram));
  EXPECT_EQ(RunBurrlab({"analyze", "scores", results, "--format", "jpg"}).err,
            "burrlab: --format must be 'png', 'pdf' or 'svg', got 'jpg'\n");

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

// Kinematics with --groups on a station's traces (3-D position and force
// components), written through the journal and the export: subject k moves
// the burr on a straight line at 13 k mm/s (steps of 0.01 k (3, 4, 12) mm at
// 100 Hz) under a constant force (0.6, 0.8, 2.4) N. Truth computed by hand:
// mean speeds 13, 26, 39, 52 and 65 mm/s, |F| = 2.6 N; experts {13, 39}
// against trainees {26, 52} (sub-05's group is n/a) give Welch's t =
// -13 / sqrt(338 / 2 + 338 / 2) = -1/sqrt(2) with df = 2, whose two-sided p
// is 1 - |t| / sqrt(t^2 + 2) = 1 - 1/sqrt(5) (Student's t with 2 df), and
// W = 1 (the experts' ranks 1 and 3, minus 3), whose exact p is
// 2 P(W <= 1) = 2 x 2/6 (W of 2 against 2 is 0, 1, 2, 2, 3, 4).
TEST_F(AnalyzeResults, KinematicsComparesTheGroupsOfAParticipantsFile) {
  const std::string results = (dir_ / "station").string();
  for (int k = 1; k <= 5; ++k) {
    results_schema::SessionInfo info;
    info.study = "groups";
    info.protocol_path = "p.toml";
    info.protocol_sha256 = std::string(64, 'a');
    info.subject_label = "0" + std::to_string(k);
    info.master_seed = 1;
    info.burrlab_version = "0";
    info.started_utc = "2024-01-01T00:00:00Z";
    auto journal = results_schema::Journal::Create(results, info);
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    results_schema::TrialRecord t;
    t.block = "press";
    t.method = "two_interval";
    t.task = "probe";
    t.interval_materials = {"a"};
    t.response = "1";
    t.correct_answer = "1";
    t.correct = true;
    results_schema::TraceSamples trace;
    trace.sampling_frequency_hz = 100.0;
    trace.columns = {"position_x_mm", "position_y_mm", "position_z_mm",
                     "force_x_n",     "force_y_n",     "force_z_n"};
    for (int r = 0; r < 21; ++r) {
      const double s = 0.01 * k * r;
      trace.rows.push_back({3.0 * s, 4.0 * s, 12.0 * s, 0.6, 0.8, 2.4});
    }
    ASSERT_TRUE(journal->Append(t, {trace}).ok());
    ASSERT_TRUE(journal->MarkComplete().ok());
    ASSERT_TRUE(results_schema::ExportBids(results, info.subject_label).ok());
  }
  const fs::path participants = dir_ / "participants.tsv";
  std::ofstream(participants) << "participant_id\tage\tskill\n"
                                 "sub-01\t41\texpert\n"
                                 "sub-02\t24\ttrainee\n"
                                 "sub-03\t52\texpert\n"
                                 "sub-04\t23\ttrainee\n"
                                 "sub-05\t30\tn/a\n"
                                 "sub-06\t33\ttrainee\n";
  const CliRun run =
      RunBurrlab({"analyze", "kinematics", results, "--json", "--groups",
                  participants.string(), "--group-column", "skill"});
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const Json j = Json::parse(run.out);
  ASSERT_EQ(j["subjects"].size(), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(j["subjects"][k]["speed_measure"],
              "|dp/dt| of position_x_mm, position_y_mm, position_z_mm");
    EXPECT_NEAR(j["subjects"][k]["mean_speed_mm_s"].get<double>(),
                13.0 * (k + 1), 1e-9);
    EXPECT_NEAR(j["subjects"][k]["mean_force_n"].get<double>(), 2.6, 1e-12);
  }
  // The group of the block: speeds 13 k mm/s, k = 1..5, have mean 39 and
  // SEM 13 sqrt(2.5) / sqrt(5) = 13 / sqrt 2.
  // (and of its one material, "a", the same numbers).
  ASSERT_EQ(j["group"].size(), 2u);
  EXPECT_EQ(j["group"][0]["block"], "press");
  EXPECT_EQ(j["group"][0]["material"], nullptr);
  EXPECT_EQ(j["group"][1]["material"], "a");
  EXPECT_EQ(j["group"][1]["mean_speed_mm_s"], j["group"][0]["mean_speed_mm_s"]);
  ASSERT_EQ(j["materials"].size(), 5u);
  EXPECT_EQ(j["materials"][4]["material"], "a");
  EXPECT_EQ(j["group"][0]["subjects"].size(), 5u);
  EXPECT_NEAR(j["group"][0]["mean_speed_mm_s"]["mean"].get<double>(), 39.0,
              1e-9);
  EXPECT_NEAR(j["group"][0]["mean_speed_mm_s"]["sem"].get<double>(),
              13.0 / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(j["group"][0]["mean_force_n"]["mean"].get<double>(), 2.6, 1e-12);
  EXPECT_EQ(j["group"][0]["removal_rate_mm3_per_s"]["n"], 0);
  const CliRun plain = RunBurrlab({"analyze", "kinematics", results});
  EXPECT_NE(plain.out.find("group per block and per material felt, mean ± "
                           "SEM over subjects:\n"
                           "  press            5 subjects  force 2.600 ± "
                           "0.000 N  contact 100.0 ± 0.0 %  speed 39.000 ± "
                           "9.192 mm/s  removal n/a mm3/s\n"
                           "  press:a          5 subjects  force 2.600 ± "
                           "0.000 N  contact 100.0 ± 0.0 %  speed 39.000 ± "
                           "9.192 mm/s  removal n/a mm3/s\n"),
            std::string::npos)
      << plain.out;
  const Json& g = j["group_comparison"];
  EXPECT_EQ(g["column"], "skill");
  EXPECT_EQ(g["x"], "expert");
  EXPECT_EQ(g["y"], "trainee");
  EXPECT_EQ(g["subjects"]["expert"], Json::parse(R"(["01", "03"])"));
  EXPECT_EQ(g["subjects"]["trainee"], Json::parse(R"(["02", "04"])"));
  EXPECT_EQ(g["left_out"], Json::parse(R"(["05"])"));
  // Five measures (no removed_mm3 in a station's traces) for the block, five
  // over all blocks.
  ASSERT_EQ(g["comparisons"].size(), 10u);
  for (std::size_t i : {4u, 9u}) {
    const Json& c = g["comparisons"][i];
    EXPECT_EQ(c["block"], i < 5 ? Json("press") : Json(nullptr));
    EXPECT_EQ(c["measure"], "mean_speed_mm_s");
    ASSERT_TRUE(c["welch"].is_object()) << c["welch_note"];
    EXPECT_NEAR(c["welch"]["mean_x"].get<double>(), 26.0, 1e-9);
    EXPECT_NEAR(c["welch"]["mean_y"].get<double>(), 39.0, 1e-9);
    EXPECT_NEAR(c["welch"]["t"].get<double>(), -1.0 / std::sqrt(2.0), 1e-9);
    EXPECT_NEAR(c["welch"]["df"].get<double>(), 2.0, 1e-9);
    EXPECT_NEAR(c["welch"]["p_two_sided"].get<double>(),
                1.0 - 1.0 / std::sqrt(5.0), 1e-9);
    EXPECT_EQ(c["mann_whitney"]["w"], 1.0);
    EXPECT_NEAR(c["mann_whitney"]["p_two_sided"].get<double>(), 2.0 / 3.0,
                1e-12);
    EXPECT_EQ(c["mann_whitney"]["method"], "exact");
  }
  // Every subject pressed with the same force: no test, and why.
  EXPECT_EQ(g["comparisons"][2]["measure"], "max_force_n");
  EXPECT_TRUE(g["comparisons"][2]["welch"].is_null());
  EXPECT_EQ(g["comparisons"][2]["mann_whitney_note"],
            "all 4 values are equal (2.6): the rank-sum test is undefined");

  // The table explains its columns.
  const CliRun text =
      RunBurrlab({"analyze", "kinematics", results, "--groups",
                  participants.string(), "--group-column", "skill"});
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("x = expert (sub-01, sub-03), y = trainee (sub-02, "
                          "sub-04); left out (n/a): sub-05\n"),
            std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("press      mean_speed_mm_s             2      2 "
                          "        26         39   -0.707    2.00     0.553 "
                          "      1     0.667\n"),
            std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("t, df, p (t): Welch's two-sample t-test"),
            std::string::npos);
  EXPECT_NE(text.out.find("~ marks the approximation"), std::string::npos);
  EXPECT_NE(text.out.find("note: press max_force_n: no W: all 4 values are "
                          "equal (2.6): the rank-sum test is undefined\n"),
            std::string::npos)
      << text.out;

  // Bad group files: one error, exit 1, nothing on stdout.
  const auto groups_error = [&](const std::string& file_text,
                                const std::string& column = "group") {
    std::ofstream(participants, std::ios::trunc) << file_text;
    const CliRun r =
        RunBurrlab({"analyze", "kinematics", results, "--groups",
                    participants.string(), "--group-column", column});
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.out, "");
    return r.err;
  };
  const std::string p = participants.string();
  EXPECT_EQ(groups_error("participant_id\tgroup\nsub-01\texpert\nsub-02\t"
                         "expert\n"),
            "burrlab: --groups: " + p +
                ": error: the group column holds 1 group (expert): a "
                "two-group comparison needs exactly 2\n");
  EXPECT_EQ(groups_error("participant_id\tgroup\n"
                         "sub-01\ta\nsub-02\tb\nsub-03\ta\nsub-05\ta\n"),
            "burrlab: --groups " + p +
                ": sub-04 has traces but no row in the participants file; "
                "add it (n/a in the group column leaves it out)\n");
  EXPECT_EQ(groups_error("participant_id\tgroup\nsub-01\ta\n", "skill"),
            "burrlab: --groups: " + p +
                ":1:1: error: the header has no skill column (it has "
                "participant_id, group)\nparticipant_id\tgroup\n^\n");
  // A spreadsheet's byte-order mark and CR LF line ends read as plain text.
  std::ofstream(participants, std::ios::trunc)
      << "\xEF\xBB\xBFparticipant_id\tgroup\r\nsub-01\ta\r\nsub-02\tb\r\n"
         "sub-03\ta\r\nsub-04\tb\r\nsub-05\tb\r\n";
  const CliRun windows =
      RunBurrlab({"analyze", "kinematics", results, "--groups", p, "--json"});
  ASSERT_EQ(windows.code, 0) << windows.err;
  EXPECT_EQ(Json::parse(windows.out)["group_comparison"]["y"], "b");
  const CliRun alone =
      RunBurrlab({"analyze", "kinematics", results, "--group-column", "x"});
  EXPECT_EQ(alone.code, 1);
  EXPECT_EQ(alone.err, "burrlab: --group-column goes with --groups FILE\n");
  const CliRun empty = RunBurrlab(
      {"analyze", "kinematics", results, "--groups", p, "--group-column", ""});
  EXPECT_EQ(empty.code, 1);
  EXPECT_EQ(empty.err, "burrlab: --group-column must name a column, got ''\n");
}

// Response times: a subject who typed answers into a pipe has no times;
// those trials are skipped and counted by `analyze rt` and `analyze scores`.
// Truth: the median of the times in the _beh.tsv, computed here.
TEST_F(AnalyzeResults, ResponseTimesSkipAndCountTrialsWithoutOne) {
  const std::string results = Study("two_interval_2afc.toml", 2, "rt");
  // sub-02's first three answers untimed, as a pipe's are.
  const fs::path beh =
      fs::path(results) / "sub-02" / "beh" / "sub-02_task-probe2afc_beh.tsv";
  std::ifstream in(beh);
  std::string header, line, edited;
  std::getline(in, header);
  edited = header + "\n";
  std::vector<std::string> columns;
  {
    std::stringstream cells(header);
    for (std::string c; std::getline(cells, c, '\t');) columns.push_back(c);
  }
  const std::size_t rt_at =
      std::find(columns.begin(), columns.end(), "response_time") -
      columns.begin();
  ASSERT_LT(rt_at, columns.size());
  std::vector<double> times;
  for (int row = 0; std::getline(in, line); ++row) {
    std::vector<std::string> cells;
    std::stringstream split(line);
    for (std::string c; std::getline(split, c, '\t');) cells.push_back(c);
    if (row < 3) {
      cells[rt_at] = "n/a";
    } else {
      times.push_back(std::stod(cells[rt_at]));
    }
    std::string joined;
    for (std::size_t k = 0; k < cells.size(); ++k) {
      joined += (k ? "\t" : "") + cells[k];
    }
    edited += joined + "\n";
  }
  in.close();
  std::ofstream(beh, std::ios::trunc) << edited;
  ASSERT_EQ(times.size(), 9u);
  std::sort(times.begin(), times.end());

  const CliRun run = RunBurrlab({"analyze", "rt", results, "--json"});
  ASSERT_EQ(run.code, 0) << run.err;
  const Json j = Json::parse(run.out);
  ASSERT_EQ(j["response_times"].size(), 2u);
  const Json& two = j["response_times"][1];
  EXPECT_EQ(two["subject"], "02");
  EXPECT_EQ(two["block"], "probe2afc");
  const Json& all = two["conditions"][0];
  EXPECT_EQ(all["condition"], "all");
  EXPECT_EQ(all["n"], 9);
  EXPECT_EQ(all["missing"], 3);
  EXPECT_NEAR(all["median_s"].get<double>(), times[4], 1e-12);
  EXPECT_EQ(j["response_times"][0]["conditions"][0]["missing"], 0);
  EXPECT_EQ(two["conditions"].size(), 3u);  // all, AB, BA
  EXPECT_EQ(two["conditions"][1]["condition"], "AB");

  const CliRun scores = RunBurrlab({"analyze", "scores", results, "--json"});
  ASSERT_EQ(scores.code, 0) << scores.err;
  const Json s = Json::parse(scores.out)["blocks"][0]["response_times"];
  EXPECT_EQ(s["conditions"][0]["n"], 21);
  EXPECT_EQ(s["conditions"][0]["missing"], 3);
  EXPECT_NE(s["definition"].get<std::string>().find("R's quantile type 7"),
            std::string::npos);
  const CliRun scores_text = RunBurrlab({"analyze", "scores", results});
  EXPECT_NE(scores_text.out.find("  response time, s: median [Q1, Q3] (R "
                                 "quantile type 7), IQR = Q3 - Q1, n timed "
                                 "trials, n/a trials without a time "
                                 "(skipped)\n    all "),
            std::string::npos)
      << scores_text.out;

  // --tsv: the table and its column descriptions; never overwritten.
  const std::string tsv = (dir_ / "rt.tsv").string();
  const CliRun text = RunBurrlab({"analyze", "rt", results, "--tsv", tsv});
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("n/a: trials without one (e.g. answers typed into "
                          "a pipe), skipped"),
            std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("wrote " + tsv + " (columns described in " +
                          (dir_ / "rt.json").string() + ")"),
            std::string::npos);
  std::ifstream written(tsv);
  std::getline(written, line);
  EXPECT_EQ(line,
            "participant_id\tblock\tmethod\tcondition\tn\tmissing\t"
            "median_s\tq1_s\tq3_s\tiqr_s");
  std::getline(written, line);
  EXPECT_TRUE(line.starts_with("sub-01\tprobe2afc\ttwo_interval\tall\t12\t0\t"))
      << line;
  const Json sidecar = Json::parse(std::ifstream(dir_ / "rt.json"));
  EXPECT_EQ(sidecar["median_s"]["Units"], "s");
  EXPECT_TRUE(sidecar.contains("missing"));
  const CliRun again = RunBurrlab({"analyze", "rt", results, "--tsv", tsv});
  EXPECT_EQ(again.code, 1);
  EXPECT_EQ(again.err, "burrlab: " + tsv +
                           " already exists; choose another --tsv or remove "
                           "it\n");
  const CliRun bad_name =
      RunBurrlab({"analyze", "rt", results, "--tsv", tsv + ".txt"});
  EXPECT_EQ(bad_name.code, 1);
  EXPECT_EQ(bad_name.err, "burrlab: --tsv " + tsv +
                              ".txt: the file name must end in .tsv (its "
                              "column descriptions go to the .json beside "
                              "it)\n");
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
  // A rate of 0 or 1 is starred right after it, and a key says what `*`
  // means (4 "different" and 4 "same" trials per subject: such rates are
  // common).
  bool any_corrected = false;
  for (const Json& subject : j["blocks"][0]["subjects"]) {
    const Json& r = subject["rates"];
    const std::string line_start =
        fmt::format("  sub-{:<8}", subject["subject"].get<std::string>());
    const std::size_t at = text.out.find(line_start);
    ASSERT_NE(at, std::string::npos) << text.out;
    const std::string line = text.out.substr(at, text.out.find('\n', at) - at);
    const auto starred = [](int k, int n) { return k == 0 || k == n; };
    const bool h =
        starred(r["hits"].get<int>(), r["different_trials"].get<int>());
    const bool f =
        starred(r["false_alarms"].get<int>(), r["same_trials"].get<int>());
    EXPECT_EQ(line.find(fmt::format("H {:.3f}{} F {:.3f}{} ",
                                    r["hit_rate"].get<double>(), h ? "*" : "",
                                    r["false_alarm_rate"].get<double>(),
                                    f ? "*" : "")) != std::string::npos,
              true)
        << line;
    any_corrected = any_corrected || h || f;
  }
  EXPECT_TRUE(any_corrected) << "these seeds no longer give a rate of 0 or 1";
  EXPECT_EQ(
      text.out.find("  *          a rate of 0 or 1: d' used 1/(2N) or "
                    "1 - 1/(2N) instead (Macmillan & Kaplan 1985), N "
                    "its trials\n") != std::string::npos,
      any_corrected || j["blocks"][0]["pooled_rates"]["corrected"].get<bool>())
      << text.out;
}

// A practice staircase (familiarization) followed by the scored one: the
// practice block gets no threshold and the output says how many of its
// trials were left out; the scored block's threshold is the engine's own
// estimate (truth: the exported estimate column).
TEST_F(AnalyzeResults, ThresholdsLeaveOutThePracticeStaircase) {
  const std::string protocol = (dir_ / "practice_stairs.toml").string();
  std::ofstream(protocol) << R"(format = "burrlab-protocol/1"
[study]
name = "A practice staircase, then the scored one"
[materials.bone]
builtin = "human_temporal_bone"
[axes.ce_increment]
kind = "increment"
parameter = "c_e_n_per_mm2"
reference = "bone"
[[blocks]]
name = "warmup"
method = "staircase"
task = "probe"
axis = "ce_increment"
response = "2afc"
step_scale = "log10"
step_down = 0.2
step_up = 0.2
floor = 0.01
ceiling = 4.0
start_level = 1.0
max_trials = 6
threshold_reversals = 2
interval_s = 1
practice = true
[[blocks]]
name = "stairs"
method = "staircase"
task = "probe"
axis = "ce_increment"
response = "2afc"
n_down = 3
step_scale = "log10"
step_down = 0.2
step_up = 0.2
floor = 0.01
ceiling = 4.0
start_level = 1.0
max_trials = 30
threshold_reversals = 4
interval_s = 1
)";
  const std::string results = (dir_ / "out").string();
  const CliRun study =
      RunBurrlab({"study", protocol, "--simulated-subjects", "1", "--out",
                  results, "--seed", "5", "--jobs", "1"});
  ASSERT_EQ(study.code, 0) << study.err;
  auto files = results_schema::ReadBidsDataset(results);
  ASSERT_TRUE(files.ok()) << files.error().message;
  int practice = 0;
  std::optional<double> engine;
  for (const auto& file : *files) {  // one file per block (BIDS task)
    for (const auto& t : file.table.trials) {
      practice += t.practice ? 1 : 0;
      if (!t.practice && t.estimate) engine = t.estimate;
    }
  }
  EXPECT_EQ(practice, 6);
  ASSERT_TRUE(engine.has_value());
  const CliRun text = RunBurrlab({"analyze", "thresholds", results});
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_EQ(text.out.find("warmup:"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("sub-01 stairs staircase 0: "), std::string::npos)
      << text.out;
  EXPECT_TRUE(text.out.ends_with(
      "left out 6 practice trials, never estimated: warmup (6)\n"))
      << text.out;
  const CliRun json = RunBurrlab({"analyze", "thresholds", results, "--json"});
  ASSERT_EQ(json.code, 0) << json.err;
  const Json j = Json::parse(json.out);
  EXPECT_EQ(j["practice_left_out"],
            Json::parse(R"([{"block": "warmup", "trials": 6}])"));
  ASSERT_EQ(j["thresholds"].size(), 1u);
  EXPECT_EQ(j["thresholds"][0]["block"], "stairs");
  EXPECT_NEAR(j["thresholds"][0]["value"].get<double>(), *engine, 1e-12);
  // `analyze fit` on the practice block's _beh.tsv has nothing to fit.
  const std::string beh = results + "/sub-01/beh/sub-01_task-warmup_beh.tsv";
  const CliRun fit =
      RunBurrlab({"analyze", "fit", "--data", beh, "--task", "2afc",
                  "--sigmoid", "logistic", "--bootstrap", "0"});
  EXPECT_EQ(fit.code, 1);
  EXPECT_EQ(fit.err, beh +
                         ": error: no trial with a stim_level and a correct "
                         "answer (0 rows with n/a skipped, 6 practice trials "
                         "left out)\n")
      << fit.out;
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
  for (const std::string command :
       {"scores", "rt", "thresholds", "kinematics"}) {
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
  for (const std::string command :
       {"scores", "rt", "thresholds", "kinematics"}) {
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

// Every session of a subject is analysed: scores pool a subject's sessions
// (the subject stays the unit of the t-test), thresholds and kinematics are
// given per session, and warnings name the session and its --session.
TEST_F(AnalyzeResults, EverySessionOfASubjectIsAnalysed) {
  const std::string protocol = (dir_ / "protocol.toml").string();
  std::ofstream(protocol) << TwoBlockProtocol("two sessions", 4, 6, 0.3);
  const std::string results = (dir_ / "out").string();
  for (const char* subject : {"01", "02"}) {
    for (const char* session : {"1", "2"}) {
      const CliRun run =
          RunBurrlab({"run", protocol, "--subject", subject, "--session",
                      session, "--out", results, "--observer", "simulated",
                      "--seed", std::string(subject) + session});
      ASSERT_EQ(run.code, 0) << run.err;
    }
  }
  const CliRun scores = RunBurrlab({"analyze", "scores", results, "--json"});
  ASSERT_EQ(scores.code, 0) << scores.err;
  EXPECT_EQ(scores.err, "");
  const Json sd = Json::parse(scores.out)["blocks"][0];
  EXPECT_EQ(sd["block"], "sd");
  ASSERT_EQ(sd["subjects"].size(), 2u);
  EXPECT_EQ(sd["subjects"][0]["subject"], "01");
  EXPECT_EQ(sd["subjects"][0]["trials"], 8);  // 4 of each session
  EXPECT_EQ(sd["trials_per_subject"], 8);

  const CliRun thresholds = RunBurrlab({"analyze", "thresholds", results});
  ASSERT_EQ(thresholds.code, 0) << thresholds.err;
  std::vector<std::string> who;
  std::istringstream lines(thresholds.out);
  for (std::string line; std::getline(lines, line);) {
    who.push_back(line.substr(0, line.find(':')));
  }
  // Each session's group apart (a session is its own measurement).
  EXPECT_EQ(
      who,
      (std::vector<std::string>{
          "sub-01 ses-1 stairs staircase 0", "sub-01 ses-2 stairs staircase 0",
          "sub-02 ses-1 stairs staircase 0", "sub-02 ses-2 stairs staircase 0",
          "", "group ses-1 stairs staircase 0", "  left out, no threshold",
          "  left out, no threshold", "group ses-2 stairs staircase 0",
          "  left out, no threshold", "  left out, no threshold"}))
      << thresholds.out;
  const Json json =
      Json::parse(RunBurrlab({"analyze", "thresholds", results, "--json"}).out);
  EXPECT_EQ(json["thresholds"][1]["subject"], "01");
  EXPECT_EQ(json["thresholds"][1]["session"], "2");

  const std::string plots = (dir_ / "plots").string();
  const CliRun kinematics =
      RunBurrlab({"analyze", "kinematics", results, "--plots", plots});
  ASSERT_EQ(kinematics.code, 0) << kinematics.err;
  EXPECT_NE(kinematics.out.find("sub-02 ses-2 stairs"), std::string::npos)
      << kinematics.out;
  EXPECT_TRUE(fs::exists(dir_ / "plots" / "sub-01_ses-2_stairs_force.png"));
  EXPECT_TRUE(fs::exists(dir_ / "plots" / "sub-01_ses-1_stairs_speed.png"));

  // ses-2 of sub-02 lost its exports: the warning names it and how to
  // export it again.
  fs::remove_all(dir_ / "out" / "sub-02" / "ses-2" / "beh");
  const CliRun warned = RunBurrlab({"analyze", "scores", results});
  ASSERT_EQ(warned.code, 0) << warned.err;
  EXPECT_EQ(warned.err,
            "burrlab: warning: sub-02 ses-2's journal holds 10 trials but its "
            "exports only 0, and analyses read the exports; `burrlab run "
            "PROTOCOL --subject 02 --session 2 --out " +
                results +
                " --resume` exports them (and finishes the session if it "
                "can)\n");
}

TEST_F(AnalyzeResults, FoldersWithoutResultsAreOneErrorLine) {
  for (const std::string command :
       {"scores", "rt", "thresholds", "kinematics"}) {
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
                    "--no-spread", "--recovery", "3"});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  // --recovery: three published results simulated from the fit and fitted
  // back. By chance, a 95 % interval holds the truth in 2 or 3 of 3 (the
  // 2.5 and 97.5 % points of Binomial(3, 0.95): P(k <= 1) = 0.007, P(k <= 2)
  // = 0.143, by hand).
  const nlohmann::json& recovery = j["fits"][0]["recovery"];
  EXPECT_EQ(recovery["studies"], 3);
  EXPECT_LE(recovery["weber_covered"].get<int>(), 3);
  EXPECT_EQ(recovery["spread_covered"], 3);  // not fitted
  EXPECT_EQ(recovery["both_covered"], recovery["weber_covered"]);
  EXPECT_EQ(recovery["spread_at_limit"], 0);
  EXPECT_EQ(recovery["chance_95"], nlohmann::json::array({2, 3}));
  ASSERT_EQ(j["fits"].size(), 1u);
  EXPECT_EQ(j["fits"][0]["block"], "probe2afc");
  EXPECT_EQ(j["fits"][0]["cue"], "stiffness");
  EXPECT_NEAR(j["fits"][0]["fitted"]["mean"].get<double>(), 9.0, 0.3);
  EXPECT_EQ(j["population"]["weber_stiffness"], j["fits"][0]["weber"]);
  EXPECT_EQ(j["population"]["weber_removal"], j["fits"][0]["weber"]);
  EXPECT_EQ(j["population"]["notes"].size(), 1u);
  EXPECT_EQ(j["observer"]["rule"], "fixed");
  // Each subject's score instead of the mean and SEM.
  run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                    "--observed", "block=probe2afc,scores=12/10/9/9/8/7",
                    "--cue-samples", "1", "--virtual-subjects", "50", "--json",
                    "--no-spread"});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json by_scores = nlohmann::json::parse(run.out);
  EXPECT_EQ(by_scores["fits"][0]["observed"]["scores"],
            nlohmann::json::array({12, 10, 9, 9, 8, 7}));
  EXPECT_EQ(by_scores["fits"][0]["observed"]["n"], 6);
  EXPECT_DOUBLE_EQ(by_scores["fits"][0]["observed"]["mean"].get<double>(),
                   55.0 / 6.0);
  // --observer chooses the model fitted, over the protocol's [observer].
  run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                    "--observed", "block=probe2afc,mean=9,sem=0.4,n=20",
                    "--cue-samples", "1", "--virtual-subjects", "50", "--json",
                    "--no-spread", "--observer",
                    "simulated:rule=likelihood,bias=0.3,force_spread=0.1"});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json model = nlohmann::json::parse(run.out);
  EXPECT_EQ(model["observer"]["rule"], "likelihood");
  EXPECT_EQ(model["observer"]["bias"], 0.3);
  EXPECT_EQ(model["observer"]["force_spread"], 0.1);
  EXPECT_EQ(model["observer"]["subject_force_spread"], 0.0);
  // Named variants, compared by the likelihood of the observed result: an SD
  // of 2.2 (SEM 0.49) from 20 subjects needs a spread of W, so the variant
  // whose subjects are all alike comes last.
  run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                    "--observed", "block=probe2afc,mean=9,sem=0.49,n=20",
                    "--cue-samples", "1", "--virtual-subjects", "20", "--json",
                    "--compare-variants"});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json compared = nlohmann::json::parse(run.out);
  ASSERT_EQ(compared["variants"].size(), 6u);
  double alike_aic = 0.0, best_aic = 1e300;
  for (const nlohmann::json& v : compared["variants"]) {
    const double aic = v["aic"].get<double>();
    EXPECT_NEAR(aic,
                2.0 * v["parameters"].get<int>() -
                    2.0 * v["log_likelihood"].get<double>(),
                1e-9);
    EXPECT_NEAR(v["bic"].get<double>(),
                v["parameters"].get<int>() * std::log(20.0) -
                    2.0 * v["log_likelihood"].get<double>(),
                1e-9);
    EXPECT_GE(v["delta_aic"].get<double>(), 0.0);
    best_aic = std::min(best_aic, aic);
    if (v["variant"] == "likelihood_alike") {
      alike_aic = aic;
      EXPECT_EQ(v["parameters"], 1);
    } else if (v["variant"] == "likelihood_lapse") {
      // W, its spread and the lapse, with the lapse's profile and interval.
      EXPECT_EQ(v["parameters"], 3);
      EXPECT_LE(v["lapse_ci"][0].get<double>(), v["lapse"].get<double>());
      EXPECT_GE(v["lapse_ci"][1].get<double>(), v["lapse"].get<double>());
      EXPECT_GE(v["lapse_profile"].size(), 11u);  // at least its grid
    } else {
      EXPECT_EQ(v["parameters"], 2);
      EXPECT_FALSE(v.contains("lapse"));
    }
  }
  EXPECT_GT(alike_aic, best_aic);
  EXPECT_NE(compared["observer"]["rule"], "");
  run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                    "--observed", "block=probe2afc,mean=9,sem=0.4,n=20",
                    "--recovery", "0"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: --recovery must be a whole number from 1 to 100000, "
            "got '0'\n");
  run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                    "--observed", "block=probe2afc,mean=9,sem=0.4,n=20",
                    "--variant", "optimal"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: --variant: no observer variant \"optimal\" (variants: "
            "fixed, differencing, likelihood, likelihood_varied, "
            "likelihood_alike, likelihood_lapse)\n");
  run = RunBurrlab({"analyze", "fit-observers", "--protocol", protocol,
                    "--observed", "block=probe2afc,mean=9,sem=0.4,n=20",
                    "--observer", "simulated:rule=optimal"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: analyze fit-observers: observer: rule must be fixed, "
            "differencing or likelihood, got \"optimal\"\n");
}

}  // namespace
}  // namespace burrlab::runner
