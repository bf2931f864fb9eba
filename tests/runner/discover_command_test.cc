// `burrlab discover` as a user meets it: a CSV with a hidden motor power
// limit (synthetic generator, surrogate truth) -> report.json with the
// issue's fields, report.md, the two plots; --json prints the same JSON; the
// exact text and exit code of bad input.
#include "discover_command.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../results_schema/temp_dir.h"
#include "burrlab/analysis/discover_scenarios.h"
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
  for (const char* key : {"verdict", "effect", "alias_set", "effect_params",
                          "baseline", "augmented", "gap", "tests"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  const std::string verdict = j["verdict"];
  ASSERT_TRUE(verdict == "named" || verdict == "ambiguous") << run.out;
  const std::vector<std::string> alias = j["alias_set"];
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
