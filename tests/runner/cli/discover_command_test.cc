// `burrlab discover` as a user meets it: a CSV with a hidden motor power
// limit (synthetic generator, surrogate truth) -> report.json with the
// report's fields, report.md, the two plots; --json prints the same JSON; the
// exact text and exit code of bad input; the README's worked example prints
// what the README shows.
#include "cli/discover_command.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../results_schema/temp_dir.h"
#include "burrlab/analysis/model_gap/discover_scenarios.h"
#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/analysis/model_gap/synthetic_measurement.h"
#include "run_cli.h"

namespace burrlab::runner {
namespace {

using ::testing::HasSubstr;

class DiscoverCommand : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& text) {
    const std::filesystem::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  }
  static std::string Read(const std::filesystem::path& path) {
    std::ifstream file(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(file), {});
  }
  results_schema::TempDir temp_;
  const std::filesystem::path& dir_ = temp_.path();
};

// Bone at loads 0.5-1.5 (R = 1 mm), 4 replicates, CV 10 %, a motor power
// limit at projected SNR 8.
std::string PowerLimitedCsv() {
  analysis::ScenarioDesign d;
  d.material.c_e_n_per_mm2 = 2.145;
  d.material.alpha_per_s = 0.087;
  d.full_rig = false;
  const sim::Effects fx =
      analysis::EffectAtSnr(d, "motor_power_limit", 8.0).value();
  const std::vector<double> truth = analysis::TruthVelocitiesMmS(d, fx).value();
  return analysis::ScenarioCsv(d, truth, {}, 3);
}

TEST_F(DiscoverCommand, NamesAHiddenPowerLimitAndWritesTheReport) {
  const std::string csv = Write("power.csv", PowerLimitedCsv());
  const std::filesystem::path out = dir_ / "report";
  const CliRun run = RunBurrlab(
      {"discover", "--measured", csv, "--out", out.string(), "--json"});
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(run.err, "");  // no progress bar off a terminal
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(nlohmann::json::parse(Read(out / "report.json")), j);
  for (const char* key :
       {"verdict", "velocity_definition", "effect", "alias_set", "alias_sets",
        "effect_params", "baseline", "augmented", "gap", "tests"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  // The file has no velocity_definition column: the settled default.
  EXPECT_EQ(j["velocity_definition"], "settled");
  const std::string verdict = j["verdict"];
  ASSERT_TRUE(verdict == "named" || verdict == "ambiguous") << run.out;
  const std::vector<std::string> alias = j["alias_set"];
  EXPECT_EQ(j["alias_sets"], nlohmann::json::array({j["alias_set"]}));
  EXPECT_NE(std::find(alias.begin(), alias.end(), "motor_power_limit"),
            alias.end())
      << run.out;
  for (const char* key : {"c_e", "alpha", "rmse_log_v", "aicc"}) {
    EXPECT_TRUE(j["baseline"][key].is_number()) << key;
    EXPECT_TRUE(j["augmented"][key].is_number()) << key;
  }
  const nlohmann::json& gap = j["gap"];
  EXPECT_LT(gap["rmse_after"].get<double>(), gap["rmse_before"].get<double>());
  EXPECT_LT(gap["cv_rmse_after"].get<double>(),
            gap["cv_rmse_before"].get<double>());
  // One held-out RMSE per force level (six in this file), lowest force
  // first; the pooled cv_rmse lies among them.
  for (const char* when : {"before", "after"}) {
    const std::vector<double> levels =
        gap[std::string("cv_rmse_by_level_") + when];
    ASSERT_EQ(levels.size(), 6u) << when;
    const double pooled = gap[std::string("cv_rmse_") + when];
    EXPECT_LE(*std::min_element(levels.begin(), levels.end()), pooled) << when;
    EXPECT_GE(*std::max_element(levels.begin(), levels.end()), pooled) << when;
  }
  EXPECT_LT(j["tests"]["gap_holm_p"].get<double>(), 0.05);
  EXPECT_LT(j["tests"]["lr_p"].get<double>(), 0.05);
  const std::string md = Read(out / "report.md");
  EXPECT_THAT(md, HasSubstr("**Verdict: " + verdict + "**"));
  EXPECT_THAT(md, HasSubstr("Reference material: human_temporal_bone."));
  for (const char* png : {"fit.png", "residuals.png"}) {
    const std::string bytes = Read(out / png);
    ASSERT_GT(bytes.size(), 8u) << png;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << png;
  }
  // The folder is not overwritten silently.
  const CliRun again =
      RunBurrlab({"discover", "--measured", csv, "--out", out.string()});
  EXPECT_EQ(again.code, 1);
  EXPECT_EQ(again.err, "burrlab: " + out.string() +
                           " already holds a report.json; choose another "
                           "--out or remove it\n");
}

// Bone at loads 0.5-1.5 (R = 1 mm), 4 replicates, CV 10 %, no effect in
// v(F) (surrogate truth; trace-only effects leave it unchanged), and every
// run's trace from the voxel rig (voxel R/12, 5 ms, as `sim measure`) up to
// 4 s after contact with `effects` hidden in it.
struct TracedData {
  std::string csv, traces;
};
TracedData TracedBone(const sim::Effects& effects, std::uint64_t seed) {
  analysis::ScenarioDesign d;
  d.material.c_e_n_per_mm2 = 2.145;
  d.material.alpha_per_s = 0.087;
  d.full_rig = false;
  TracedData out;
  out.csv = analysis::ScenarioCsv(
      d, analysis::TruthVelocitiesMmS(d, {}).value(), {}, seed);
  analysis::SyntheticMeasurementOptions rig;
  rig.material = d.material;
  rig.effects = effects;
  rig.forces_n = d.ForcesN();
  rig.radius_mm = d.radius_mm;
  rig.seed = seed;  // the traces' sensor noise
  analysis::SyntheticMeasurement m;
  for (std::size_t level = 0; level < rig.forces_n.size(); ++level) {
    m.level_traces.push_back(
        analysis::RigTransientTrace(rig, rig.forces_n[level],
                                    seed * 1000 + level, 4.0)
            .value());
  }
  const analysis::MeasuredData measured =
      analysis::ParseMeasuredData("m.csv", out.csv).value();
  for (const analysis::MeasuredRun& r : measured.runs) {
    m.runs.push_back({std::stoi(r.run), r.force_n, r.velocity_mm_s, 0.0});
  }
  out.traces = analysis::FormatTraceCsv(m, rig);
  return out;
}

#ifndef __SANITIZE_ADDRESS__
// Whitespace runs as one space: the README wraps the summary line.
std::string OneSpaced(const std::string& text) {
  std::istringstream in(text);
  std::string word, out;
  while (in >> word) out += (out.empty() ? "" : " ") + word;
  return out;
}

// The README's worked example (README.md, "Worked example — PVC whose motor
// droops") runs as written and prints what the README shows: its commands are
// taken from the README's block ("$ burrlab ..." lines, with continuations and
// "> FILE") and run in a scratch folder (a file under tests/ is read from the
// source tree: the example's data come from the independent truth, whose
// IndependentTruthWorkedExample test regenerates them), and the lines the
// README shows after the last command open what discover prints. The plots it
// points to are written. Not under the sanitizers: its code runs there in the
// other tests, on smaller designs.
TEST_F(DiscoverCommand, TheReadmesWorkedExamplePrintsWhatTheReadmeShows) {
  const std::string readme =
      Read(std::filesystem::path(BURRLAB_SOURCE_DIR) / "README.md");
  const std::size_t start = readme.find("$ burrlab discover --measured tests/");
  ASSERT_NE(start, std::string::npos) << "the worked example has gone";
  const std::size_t end = readme.find("```", start);
  ASSERT_NE(end, std::string::npos);
  std::istringstream block(readme.substr(start, end - start));
  std::vector<std::string> commands;
  std::string shown, line;
  bool continued = false;
  while (std::getline(block, line)) {
    if (continued) {
      commands.back() += " " + line;
    } else if (line.starts_with("$ ")) {
      commands.push_back(line.substr(2));
    } else {
      shown += line + "\n";
      continue;
    }
    continued = !commands.back().empty() && commands.back().back() == '\\';
    if (continued) commands.back().pop_back();
  }
  ASSERT_EQ(commands.size(), 1u) << readme.substr(start, end - start);
  CliRun last;
  for (const std::string& command : commands) {
    std::istringstream words(command);
    std::vector<std::string> args;
    std::string word, redirect;
    while (words >> word) {
      if (word == ">") {
        words >> redirect;
      } else if (word.starts_with("tests/")) {
        args.push_back(
            (std::filesystem::path(BURRLAB_SOURCE_DIR) / word).string());
      } else if (word.ends_with(".csv") || word == "report") {
        args.push_back((dir_ / word).string());  // files in the scratch folder
      } else {
        args.push_back(word);
      }
    }
    ASSERT_EQ(args.front(), "burrlab") << command;
    args.erase(args.begin());
    last = RunBurrlab(args);
    ASSERT_EQ(last.code, 0) << command << "\n" << last.err;
    if (!redirect.empty()) Write(redirect, last.out);
  }
  EXPECT_THAT(OneSpaced(last.out), ::testing::StartsWith(OneSpaced(shown)))
      << "README shows:\n"
      << shown << "discover printed:\n"
      << last.out;
  for (const char* plot : {"fit.png", "residuals.png"}) {
    EXPECT_GT(std::filesystem::file_size(dir_ / "report" / plot), 10000u)
        << plot;
  }
}
#endif  // __SANITIZE_ADDRESS__

TEST_F(DiscoverCommand, NamesAHiddenLoadCellLagOnlyFromTraces) {
  sim::Effects lag;
  lag.load_cell_lag_s = 0.05;
  const TracedData data = TracedBone(lag, 7);
  const std::string csv = Write("lag.csv", data.csv);
  const std::string traces = Write("lag_traces.csv", data.traces);
  const CliRun with =
      RunBurrlab({"discover", "--measured", csv, "--traces", traces, "--out",
                  (dir_ / "with").string(), "--json"});
  ASSERT_EQ(with.code, 0) << with.err;
  const nlohmann::json j = nlohmann::json::parse(with.out);
  EXPECT_EQ(j["verdict"], "named") << with.out;
  EXPECT_EQ(j["effect"], "load_cell_lag") << with.out;
  EXPECT_NEAR(j["effect_params"]["load_cell_lag_s"].get<double>(), 0.05, 0.015);
  EXPECT_LT(
      j["tests"]["trace_effects"]["load_cell_lag"]["lr_p_holm"].get<double>(),
      0.05);
  EXPECT_GT(
      j["tests"]["trace_effects"]["arm_compliance"]["lr_p_holm"].get<double>(),
      0.05);
  EXPECT_LT(j["tests"]["trace_effects"]["load_cell_lag"]["rmse_force_n"]
                .get<double>(),
            j["tests"]["trace_rmse_force_n"].get<double>());
  EXPECT_THAT(Read(dir_ / "with" / "report.md"),
              HasSubstr("## Trace-only effects (24 traced runs"));
  // The same v(F) without the traces: nothing to see.
  const CliRun without = RunBurrlab({"discover", "--measured", csv, "--out",
                                     (dir_ / "without").string(), "--json"});
  ASSERT_EQ(without.code, 0) << without.err;
  const nlohmann::json k = nlohmann::json::parse(without.out);
  EXPECT_EQ(k["verdict"], "none") << without.out;
  EXPECT_FALSE(k["tests"].contains("trace_effects"));
  EXPECT_TRUE(k["tests"]["effects"].contains("porosity"));
  EXPECT_FALSE(k["tests"]["effects"].contains("load_cell_lag"));
}

TEST_F(DiscoverCommand, TracesOfUnknownRunsAreOneErrorAndExitOne) {
  const std::string csv =
      Write("m.csv", "run,force_n,velocity_mm_s\n1,1,0.1\n2,1,0.11\n3,2,0.3\n");
  const std::string traces =
      Write("t.csv",
            "run,t_s,force_n,depth_mm\n1,0,0,-0.2\n1,0.01,0,-0.15\n"
            "9,0,0,-0.2\n9,0.01,0,-0.15\n");
  const CliRun run =
      RunBurrlab({"discover", "--measured", csv, "--radius-mm", "1", "--traces",
                  traces, "--out", (dir_ / "r").string()});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err, "burrlab: " + traces +
                         ":4:1: error: run 9 is not a run of the measured "
                         "data\n9,0,0,-0.2\n^\n");
  EXPECT_FALSE(std::filesystem::exists(dir_ / "r"));
}

TEST_F(DiscoverCommand, BadInputIsOneErrorAndExitOne) {
  const std::string out = (dir_ / "out").string();
  const auto expect_error = [&](const std::vector<std::string>& args,
                                const std::string& text) {
    const CliRun run = RunBurrlab(args);
    EXPECT_EQ(run.code, 1);
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(run.err, text);
  };
  const std::string no_velocity = Write("v.csv", "force_n,speed\n1,0.1\n");
  expect_error({"discover", "--measured", no_velocity, "--out", out},
               "burrlab: " + no_velocity +
                   ":1:1: error: the header has no velocity_mm_s column; "
                   "measured data need the columns force_n and velocity_mm_s "
                   "(comma-separated)\nforce_n,speed\n^\n");
  const std::string one_level =
      Write("one.csv", "force_n,velocity_mm_s\n1,0.1\n1,0.2\n1,0.3\n");
  expect_error(
      {"discover", "--measured", one_level, "--out", out, "--radius-mm", "1"},
      "burrlab: " + one_level +
          ": error: all 3 runs are at one force level (1 N); v(F) "
          "needs at least 2 force levels\n");
  const std::string nan_force =
      Write("nan.csv", "force_n,velocity_mm_s\n1,0.1\nnan,0.2\n3,0.3\n");
  expect_error(
      {"discover", "--measured", nan_force, "--out", out, "--radius-mm", "1"},
      "burrlab: " + nan_force +
          ":3:1: error: force_n 'nan' is not a positive finite "
          "number of N\nnan,0.2\n^\n");
  const std::string two_runs =
      Write("two.csv", "force_n,velocity_mm_s\n1,0.1\n2,0.2\n");
  expect_error(
      {"discover", "--measured", two_runs, "--out", out, "--radius-mm", "1"},
      "burrlab: " + two_runs +
          ": error: only 2 runs: fitting c_e and alpha needs more "
          "runs than parameters (at least 3)\n");
  const std::string no_radius =
      Write("r.csv", "force_n,velocity_mm_s\n1,0.1\n2,0.2\n3,0.3\n");
  expect_error({"discover", "--measured", no_radius, "--out", out},
               "burrlab: no burr radius: give --radius-mm R or a "
               "burr_radius_mm column in " +
                   no_radius + "\n");
  expect_error(
      {"discover", "--measured", no_radius, "--out", out, "--radius-mm", "1",
       "--reference", "granite"},
      "burrlab: --reference: unknown material 'granite': known materials "
      "are human_temporal_bone, pettigrew_temporal_bone, pvc_k70\n");
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace burrlab::runner
