// The burrlab command line as a user meets it: usage, version, "did you
// mean", one-line errors with exit code 1, and the output of the sim commands.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/stimuli/materials.h"
#include "burrlab_version.h"
#include "run_cli.h"

namespace burrlab::runner {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

// Expects exit code 1, nothing on stdout and exactly `line` on stderr.
void ExpectError(const std::vector<std::string>& args,
                 const std::string& line) {
  const CliRun run = RunBurrlab(args);
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.out, "");
  EXPECT_EQ(run.err, line + "\n");
}

std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

std::vector<double> SplitCsvNumbers(const std::string& line) {
  std::vector<double> numbers;
  std::istringstream stream(line);
  for (std::string field; std::getline(stream, field, ',');) {
    numbers.push_back(std::stod(field));
  }
  return numbers;
}

// A force curve with the constants given on the command line.
std::vector<std::string> ForceCurve(std::vector<std::string> more) {
  std::vector<std::string> args = {"sim", "force-curve", "--c-e",
                                   "2",   "--radius-mm", "3"};
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

// A short descent with the constants given on the command line.
std::vector<std::string> Descent(std::vector<std::string> more) {
  std::vector<std::string> args = {
      "sim",       "descent", "--c-e",       "2.145", "--alpha",      "0.087",
      "--force-n", "2",       "--radius-mm", "3",     "--duration-s", "2"};
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

TEST(Cli, BareHelpFlagAndHelpCommandListEveryCommand) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{}, std::vector<std::string>{"--help"},
        std::vector<std::string>{"help"}}) {
    const CliRun run = RunBurrlab(args);
    EXPECT_EQ(run.code, 0);
    EXPECT_EQ(run.err, "");
    EXPECT_THAT(run.out, StartsWith("usage: burrlab <command> [flags]\n"));
    EXPECT_THAT(run.out, HasSubstr("\n  demo "));
    EXPECT_THAT(run.out, HasSubstr("\n  sim "));
    EXPECT_THAT(run.out, HasSubstr("\n  help "));
  }
}

// `discover matrix` is a subcommand of discover; its old top-level name
// still runs it, and the usage list shows only the new one.
TEST(Cli, DiscoverMatrixIsASubcommandAndItsOldNameStillRuns) {
  const CliRun listed = RunBurrlab({"--help"});
  EXPECT_THAT(listed.out, HasSubstr("\n  discover "));
  EXPECT_THAT(listed.out, Not(HasSubstr("discover-matrix")));
  for (const std::vector<std::string>& name :
       {std::vector<std::string>{"discover", "matrix"},
        std::vector<std::string>{"discover-matrix"}}) {
    std::vector<std::string> args = name;
    args.push_back("--help");
    const CliRun help = RunBurrlab(args);
    EXPECT_EQ(help.code, 0);
    EXPECT_THAT(help.out, HasSubstr("Usage: burrlab discover matrix "));
    args.back() = "--sneds";
    ExpectError(args,
                "burrlab: unknown flag '--sneds' for 'burrlab discover "
                "matrix' (did you mean '--seeds'?)");
  }
}

TEST(Cli, HelpOfOneCommandShowsItsFlags) {
  const CliRun run = RunBurrlab({"help", "sim", "force-curve"});
  EXPECT_EQ(run.code, 0);
  EXPECT_THAT(run.out, HasSubstr("--radius-mm"));
  EXPECT_THAT(run.out, HasSubstr("--normal"));
}

TEST(Cli, SimWithoutCommandListsTheSimCommands) {
  const CliRun run = RunBurrlab({"sim"});
  EXPECT_EQ(run.code, 0);
  EXPECT_THAT(run.out, StartsWith("usage: burrlab sim <command> [flags]\n"));
  EXPECT_THAT(run.out, HasSubstr("\n  force-curve "));
  EXPECT_THAT(run.out, HasSubstr("\n  descent "));
  EXPECT_THAT(run.out, HasSubstr("\n  bench "));
}

TEST(Cli, VersionPrintsNameAndVersion) {
  const CliRun run = RunBurrlab({"--version"});
  EXPECT_EQ(run.code, 0);
  EXPECT_EQ(run.out, "burrlab " BURRLAB_VERSION "\n");
  EXPECT_EQ(run.err, "");
}

TEST(Cli, MisspelledCommandGetsDidYouMean) {
  ExpectError({"dmeo"},
              "burrlab: unknown command 'dmeo' (did you mean 'demo'?)");
}

TEST(Cli, MisspelledSimCommandGetsDidYouMean) {
  ExpectError({"sim", "desent"},
              "burrlab: unknown command 'sim desent' (did you mean 'sim "
              "descent'?)");
}

TEST(Cli, UnknownCommandWithNothingCloseGetsNoSuggestion) {
  ExpectError({"xyzzy"},
              "burrlab: unknown command 'xyzzy' (see 'burrlab help')");
}

TEST(Cli, MisspelledFlagGetsDidYouMean) {
  ExpectError(ForceCurve({"--radus-mm", "2"}),
              "burrlab: unknown flag '--radus-mm' for 'burrlab sim "
              "force-curve' (did you mean '--radius-mm'?)");
}

TEST(Cli, UnknownMaterialReportsTheMaterialLibrarysMessage) {
  const std::string message =
      stimuli::LoadBuiltinMaterial("granite").error().message;
  ExpectError(
      {"sim", "force-curve", "--material", "granite", "--radius-mm", "3"},
      "burrlab: " + message);
}

TEST(Cli, RepeatedFlagIsRejected) {
  ExpectError(ForceCurve({"--radius-mm=2"}),
              "burrlab: --radius-mm given 2 times; give it once");
}

TEST(Cli, ZeroRadiusIsRejected) {
  ExpectError({"sim", "force-curve", "--c-e", "2", "--radius-mm", "0"},
              "burrlab: --radius-mm must be a positive number of mm, got '0'");
}

TEST(Cli, NegativeRadiusIsRejected) {
  ExpectError({"sim", "force-curve", "--c-e", "2", "--radius-mm", "-1"},
              "burrlab: --radius-mm must be a positive number of mm, got '-1'");
}

TEST(Cli, RadiusAboveTenMmIsRejected) {
  ExpectError({"sim", "force-curve", "--c-e", "2", "--radius-mm", "11"},
              "burrlab: --radius-mm must be at most 10 mm, got '11'");
}

TEST(Cli, NanElasticConstantIsRejected) {
  ExpectError({"sim", "force-curve", "--c-e", "nan", "--radius-mm", "3"},
              "burrlab: --c-e must be a finite number, got 'nan'");
}

TEST(Cli, InfiniteElasticConstantIsRejected) {
  ExpectError({"sim", "force-curve", "--c-e", "inf", "--radius-mm", "3"},
              "burrlab: --c-e must be a finite number, got 'inf'");
}

TEST(Cli, OverflowingForceIsRejected) {
  ExpectError({"sim", "descent", "--c-e", "2", "--alpha", "0.1", "--force-n",
               "1e999", "--radius-mm", "3"},
              "burrlab: --force-n must be a finite number, got '1e999'");
}

TEST(Cli, NumberWithTrailingCharactersIsRejected) {
  ExpectError({"sim", "force-curve", "--c-e", "2", "--radius-mm", "3mm"},
              "burrlab: --radius-mm must be a finite number, got '3mm'");
}

TEST(Cli, FewerThanTwoPointsAreRejected) {
  ExpectError(ForceCurve({"--points", "1"}),
              "burrlab: --points must be a whole number from 2 to 100000, got "
              "'1'");
}

TEST(Cli, ZeroNormalIsRejected) {
  ExpectError(ForceCurve({"--normal", "0,0,0"}),
              "burrlab: --normal must not be the zero vector, got '0,0,0'");
}

TEST(Cli, NormalWithTwoComponentsIsRejected) {
  ExpectError(ForceCurve({"--normal", "1,2"}),
              "burrlab: --normal must be three comma-separated numbers X,Y,Z, "
              "got '1,2'");
}

TEST(Cli, MaterialAndElasticConstantAreMutuallyExclusive) {
  ExpectError(ForceCurve({"--material", "pvc_k70"}),
              "burrlab: --material and --c-e are mutually exclusive; give "
              "--material NAME or --c-e X");
}

TEST(Cli, ForceCurveNeedsMaterialOrElasticConstant) {
  ExpectError({"sim", "force-curve", "--radius-mm", "3"},
              "burrlab: no material: give --material NAME or --c-e X");
}

TEST(Cli, DescentNeedsAlphaWithElasticConstant) {
  ExpectError(
      {"sim", "descent", "--c-e", "2", "--force-n", "1", "--radius-mm", "3"},
      "burrlab: --c-e needs --alpha Y, the erosion constant in 1/s");
}

TEST(Cli, MissingRequiredFlagIsOneLine) {
  ExpectError({"sim", "force-curve", "--c-e", "2"},
              "burrlab: --radius-mm is required (see 'burrlab sim force-curve "
              "--help')");
}

TEST(Cli, SwitchWithValueIsRejected) {
  ExpectError({"sim", "bench", "--json=5"},
              "burrlab: --json takes no value, got '--json=5'");
}

TEST(ForceCurveCommand, PrintsHeaderAndOneRowPerPoint) {
  const CliRun run = RunBurrlab(ForceCurve({"--points", "5"}));
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const std::vector<std::string> lines = SplitLines(run.out);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0], "depth_mm,h_mm,m0_mm3,force_n");
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<double> row = SplitCsvNumbers(lines[i]);
    ASSERT_EQ(row.size(), 4u) << lines[i];
    // Evenly spaced up to R = 3 mm.
    EXPECT_NEAR(row[0], 0.6 * static_cast<double>(i), 1e-9);
  }
}

TEST(ForceCurveCommand, ForceIsTheElasticLawOfTheEstimatedDepth) {
  // F = c_e R^2 (h/R)^1.5 (eq. 7.3) with c_e = 2 N/mm^2, R = 3 mm; the CSV
  // keeps six significant digits.
  const CliRun run =
      RunBurrlab(ForceCurve({"--points", "4", "--method", "mono"}));
  ASSERT_EQ(run.code, 0) << run.err;
  const std::vector<std::string> lines = SplitLines(run.out);
  ASSERT_EQ(lines.size(), 5u);
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const std::vector<double> row = SplitCsvNumbers(lines[i]);
    ASSERT_EQ(row.size(), 4u);
    const double expected = 2.0 * 9.0 * std::pow(row[1] / 3.0, 1.5);
    EXPECT_NEAR(row[3], expected, 1e-5 * expected + 1e-9) << lines[i];
  }
}

TEST(ForceCurveCommand, MaterialUsesItsElasticConstant) {
  // Waits on the built-in materials: PVC K70, c_e = 0.462 N/mm^2 (§8.7).
  const CliRun run = RunBurrlab({"sim", "force-curve", "--material", "pvc_k70",
                                 "--radius-mm", "3", "--points", "3"});
  ASSERT_EQ(run.code, 0) << run.err;
  const std::vector<std::string> lines = SplitLines(run.out);
  ASSERT_EQ(lines.size(), 4u);
  const std::vector<double> row = SplitCsvNumbers(lines.back());
  ASSERT_EQ(row.size(), 4u);
  const double expected = 0.462 * 9.0 * std::pow(row[1] / 3.0, 1.5);
  EXPECT_NEAR(row[3], expected, 1e-5 * expected);
}

TEST(DescentCommand, JsonHasInputsAndResults) {
  const CliRun run = RunBurrlab(Descent({"--seed", "7", "--json"}));
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  for (const char* key : {"material",
                          "c_e_n_per_mm2",
                          "alpha_per_s",
                          "force_n",
                          "radius_mm",
                          "spindle_rad_s",
                          "voxel_mm",
                          "ell_over_r",
                          "duration_s",
                          "seed",
                          "velocity_definition",
                          "velocity_mm_s",
                          "no_velocity_reason",
                          "contact_s",
                          "transient_end_s",
                          "window_start_s",
                          "window_end_s",
                          "window_start_depth_mm",
                          "window_end_depth_mm",
                          "final_depth_mm",
                          "removed_mm3",
                          "steps"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_TRUE(j["material"].is_null());
  EXPECT_DOUBLE_EQ(j["c_e_n_per_mm2"].get<double>(), 2.145);
  EXPECT_DOUBLE_EQ(j["alpha_per_s"].get<double>(), 0.087);
  EXPECT_DOUBLE_EQ(j["force_n"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["radius_mm"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["duration_s"].get<double>(), 2.0);
  EXPECT_EQ(j["seed"].get<std::uint64_t>(), 7u);
  EXPECT_GT(j["steps"].get<std::int64_t>(), 0);
  // The rig's default at the load F / (c_e R^2) = 2 / (2.145 x 9) = 0.104:
  // 12 (0.5 / 0.104)^0.94 = 52 voxels per radius, at most 40.
  EXPECT_DOUBLE_EQ(j["voxel_mm"].get<double>(), 3.0 / 40.0);
  // And ell follows the skin: 0.3 (0.104 / 0.5)^0.94 = 0.068 of R.
  EXPECT_NEAR(j["ell_over_r"].get<double>(),
              0.3 * std::pow(2.0 / (2.145 * 9.0) / 0.5, 0.94), 1e-12);
  EXPECT_EQ(j["velocity_definition"], "initial");  // the default
  // Two seconds after contact are far too short to measure anything on bone:
  // no velocity, and a warning says why and how long it would take.
  EXPECT_TRUE(j["velocity_mm_s"].is_null());
  EXPECT_THAT(j["no_velocity_reason"].get<std::string>(),
              ::testing::MatchesRegex(
                  "the burr cut [-0-9.e]+ mm in the [0-9.]+ s after the impact "
                  "transient, too short a time to measure \\(the erosion time "
                  "1/alpha is 11.5 s\\)"));
  EXPECT_THAT(run.err, ::testing::EndsWith("(raise --duration-s to at least "
                                           "59, or use a larger --force-n)\n"));
  EXPECT_EQ(SplitLines(run.err).size(), 1u);
}

TEST(DescentCommand, JsonNamesTheBuiltinMaterial) {
  // Waits on the built-in materials.
  const CliRun run =
      RunBurrlab({"sim", "descent", "--material", "pvc_k70", "--force-n", "2",
                  "--radius-mm", "3", "--duration-s", "1", "--json"});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["material"], "pvc_k70");
  EXPECT_DOUBLE_EQ(j["c_e_n_per_mm2"].get<double>(), 0.462);
  EXPECT_DOUBLE_EQ(j["alpha_per_s"].get<double>(), 0.296);
}

TEST(DescentCommand, TraceWritesCsvWithHeader) {
  const std::string path =
      (std::filesystem::path(testing::TempDir()) / "burrlab_cli_trace.csv")
          .string();
  const CliRun run = RunBurrlab(Descent({"--trace", path}));
  ASSERT_EQ(run.code, 0) << run.err;
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  const std::vector<std::string> lines = SplitLines(text.str());
  ASSERT_GT(lines.size(), 10u);
  EXPECT_EQ(lines[0], "t_s,depth_mm,force_n,velocity_mm_s");
  for (std::size_t i = 1; i < lines.size(); ++i) {
    ASSERT_EQ(SplitCsvNumbers(lines[i]).size(), 4u) << lines[i];
  }
  std::filesystem::remove(path);
}

TEST(DescentCommand, UnwritableTraceIsOneErrorLine) {
  const CliRun run =
      RunBurrlab(Descent({"--trace", "/nonexistent-dir/trace.csv"}));
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.out, "");
  EXPECT_THAT(run.err, StartsWith("burrlab: cannot write --trace file "
                                  "'/nonexistent-dir/trace.csv'"));
  EXPECT_EQ(SplitLines(run.err).size(), 1u);
}

TEST(BenchCommand, JsonHasEveryDefaultCase) {
  const CliRun run = RunBurrlab(
      {"sim", "bench", "--json", "--steps", "20", "--interval-s", "1"});
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(run.err, "");  // no progress bar unless stderr is a terminal
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["steps"], 20);
  EXPECT_TRUE(j["hardware_threads"].is_number_integer());
  ASSERT_EQ(j["cases"].size(), 16u);
  for (const nlohmann::json& c : j["cases"]) {
    EXPECT_TRUE(c["method"] == "mono" || c["method"] == "octree") << c;
    EXPECT_TRUE(c["task"] == "probe" || c["task"] == "drill") << c;
    EXPECT_GT(c["radius_mm"].get<double>(), 0.0);
    EXPECT_GT(c["median_us"].get<double>(), 0.0);
    EXPECT_GE(c["p99_us"].get<double>(), c["median_us"].get<double>());
    EXPECT_GE(c["max_us"].get<double>(), c["p99_us"].get<double>());
  }
  // The intervals studies render: probe and drill on each built-in material,
  // 1000 steps of 1 ms each, their real-time factor simulated over wall
  // time.
  ASSERT_EQ(j["intervals"].size(), 6u);
  for (const nlohmann::json& c : j["intervals"]) {
    EXPECT_TRUE(c["task"] == "probe" || c["task"] == "drill") << c;
    EXPECT_EQ(c["steps"], 1000) << c;
    EXPECT_EQ(c["duration_s"], 1.0) << c;
    EXPECT_NEAR(c["real_time_factor"].get<double>() * c["wall_s"].get<double>(),
                1.0, 1e-9)
        << c;
    EXPECT_NEAR(c["us_per_step"].get<double>(),
                1e6 * c["wall_s"].get<double>() / 1000.0, 1e-6)
        << c;
    EXPECT_TRUE(c.contains(c["task"] == "probe" ? "stiffness_n_per_mm"
                                                : "penetration_mm_per_s"))
        << c;
    // Moment reuse (stimuli::IntervalOptions::*_moment_reuse_over_h): some
    // steps compute the moments afresh, not necessarily all.
    EXPECT_GT(c["moments_computed_fraction"].get<double>(), 0.0) << c;
    EXPECT_LE(c["moments_computed_fraction"].get<double>(), 1.0) << c;
  }
  EXPECT_EQ(j["intervals"][0]["material"], "human_temporal_bone");
}

TEST(BenchCommand, IntervalSecondsAndTheLoopAreExclusive) {
  const CliRun run =
      RunBurrlab({"sim", "bench", "--loop", "--interval-s", "1"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: --interval-s and --loop are mutually exclusive; the "
            "loop runs for --seconds\n");
}

}  // namespace
}  // namespace burrlab::runner

namespace burrlab::runner {
namespace {

// A fresh folder under the system's temporary directory, removed with its
// contents when the test ends.
class CliTempDir {
 public:
  explicit CliTempDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("burrlab_cli_" + name + "_" +
               std::to_string(
                   ::testing::UnitTest::GetInstance()->random_seed()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  CliTempDir(const CliTempDir&) = delete;
  CliTempDir& operator=(const CliTempDir&) = delete;
  ~CliTempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

void WriteFile(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary);
  file << bytes;
}

const char kMaterialFile[] = R"(format = "burrlab-material/1"
name = "soft_test"
display_name = "Soft test material"
[parameters.c_e_n_per_mm2]
value = 1.0
unit = "N/mm^2"
source = "test"
[parameters.alpha_per_s]
value = 0.2
unit = "1/s"
source = "test"
[parameters.c_mu_n_per_mm2]
value = 0.3
unit = "N/mm^2"
source = "test"
[parameters.mu]
value = 0.5
unit = "1"
source = "test"
[parameters.c_i_n_s_per_mm3]
value = 0.0
unit = "N*s/mm^3"
source = "test"
)";

TEST(ForceCurveCommand, MaterialMayBeAFile) {
  const CliTempDir temp("material");
  const std::filesystem::path& dir = temp.path();
  WriteFile(dir / "soft.toml", kMaterialFile);
  const CliRun run = RunBurrlab({"sim", "force-curve", "--material",
                                 (dir / "soft.toml").string(), "--radius-mm",
                                 "3", "--points", "2"});
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  const std::vector<std::string> lines = SplitLines(run.out);
  ASSERT_EQ(lines.size(), 3u);
  const std::vector<double> row = SplitCsvNumbers(lines[2]);
  // c_e = 1: F = R^2 (h/R)^1.5 at h = R.
  EXPECT_NEAR(row[3], 9.0 * std::pow(row[1] / 3.0, 1.5), 1e-3);
}

// A material file in the spelling before units joined the keys runs to the
// same output, with a note per old key on stderr.
TEST(ForceCurveCommand, AMaterialFileInTheOldSpellingRunsWithNotes) {
  const CliTempDir temp("old_material");
  const std::filesystem::path& dir = temp.path();
  std::string old = kMaterialFile;
  old.replace(old.find("c_e_n_per_mm2"), std::string("c_e_n_per_mm2").size(),
              "c_e");
  old.replace(old.find("alpha_per_s"), std::string("alpha_per_s").size(),
              "alpha");
  WriteFile(dir / "new.toml", kMaterialFile);
  WriteFile(dir / "old.toml", old);
  const std::vector<std::string> flags = {"--radius-mm", "3", "--points", "4"};
  std::vector<std::string> args = {"sim", "force-curve", "--material",
                                   (dir / "new.toml").string()};
  args.insert(args.end(), flags.begin(), flags.end());
  const CliRun now = RunBurrlab(args);
  args[3] = (dir / "old.toml").string();
  const CliRun before = RunBurrlab(args);
  ASSERT_EQ(before.code, 0) << before.err;
  EXPECT_EQ(before.out, now.out);
  EXPECT_EQ(before.err,
            args[3] +
                ":4:1: note: [parameters.c_e] is the old spelling of "
                "[parameters.c_e_n_per_mm2] (read in N/mm^2); rename it, a "
                "later format will refuse the old spelling\n" +
                args[3] +
                ":8:1: note: [parameters.alpha] is the old spelling of "
                "[parameters.alpha_per_s] (read in 1/s); rename it, a later "
                "format will refuse the old spelling\n");
}

TEST(ForceCurveCommand, MaterialFileWithAMissingKeyIsOneErrorLine) {
  const CliTempDir temp("bad_material");
  const std::filesystem::path& dir = temp.path();
  std::string text = kMaterialFile;
  text.replace(text.find("[parameters.alpha_per_s]"),
               std::string("[parameters.alpha_per_s]").size(),
               "[parameters.alpah]");
  WriteFile(dir / "bad.toml", text);
  const std::string path = (dir / "bad.toml").string();
  ExpectError({"sim", "force-curve", "--material", path, "--radius-mm", "3"},
              "burrlab: " + path +
                  ":8:1: error: unknown key \"alpah\" in [parameters] (did "
                  "you mean \"alpha_per_s\"?)");
}

TEST(VolumeCommand, SummarisesAnNrrdVolume) {
  const CliTempDir temp("volume");
  const std::filesystem::path& dir = temp.path();
  std::string data(4 * 4 * 2, '\0');
  for (std::size_t n = 0; n < 16; ++n)
    data[n] = static_cast<char>(200);  // lower slice
  WriteFile(dir / "scan.nrrd",
            "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 2\n"
            "spacings: 0.5 0.5 0.5\nencoding: raw\n\n" +
                data);
  const CliRun run = RunBurrlab({"sim", "volume", (dir / "scan.nrrd").string(),
                                 "--threshold", "100", "--json"});
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["extents"], nlohmann::json::array({4, 4, 2}));
  EXPECT_DOUBLE_EQ(j["voxel_mm"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j["material_mm3"].get<double>(), 16 * 0.125);
  EXPECT_EQ(j["solid_voxels"].get<int>(), 16);
}

TEST(VolumeCommand, TruncatedNrrdIsOneErrorLine) {
  const CliTempDir temp("truncated");
  const std::filesystem::path& dir = temp.path();
  const std::string path = (dir / "cut.nrrd").string();
  WriteFile(
      path,
      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 2\nencoding: raw\n\n" +
          std::string(20, 'x'));
  ExpectError({"sim", "volume", path, "--range", "0,255"},
              "burrlab: " + path + ": raw data: expected 32 bytes, got 20");
}

TEST(VolumeCommand, NeedsExactlyOneMapping) {
  ExpectError({"sim", "volume", "x.nrrd"},
              "burrlab: give exactly one of --threshold T and --range LO,HI");
  ExpectError({"sim", "volume", "x.nrrd", "--range", "5,1"},
              "burrlab: --range must be LO,HI with LO < HI, got '5,1'");
}

}  // namespace
}  // namespace burrlab::runner

// `sim materials` (nine constant-force descents, 25 s) is checked where the
// README's tour runs it: ReadmeCommands.EveryShellBlockRunsAsWritten.
