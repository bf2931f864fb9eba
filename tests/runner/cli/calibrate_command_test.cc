// `burrlab sim measure` and `burrlab calibrate` as a user meets them: the
// built-in materials recovered from the full rig's synthetic data within the
// reported intervals, the JSON keys, and the exact text of bad input.
#include "cli/calibrate_command.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../results_schema/temp_dir.h"
#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "run_cli.h"

namespace burrlab::runner {
namespace {

using ::testing::HasSubstr;

class CalibrateCommand : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& text) {
    const std::filesystem::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  }
  results_schema::TempDir temp_;
  const std::filesystem::path& dir_ = temp_.path();
};

// Not in the sanitizer build, where the rig is several times slower (settling
// PVC alone took 50 s, fitting its initial velocities 20 s): `sim measure` runs
// there in sim_commands_test.cc, the settled rig in descent_surrogate_test.cc
// and calibrate's fit of initial velocities in NamesASecondMinimumOfTheProfile.
#if !defined(__SANITIZE_ADDRESS__)
struct BuiltIn {
  const char* name;
  double c_e_n_per_mm2, alpha_per_s;  // stimuli/materials/<name>.toml
  const char* forces_n;  // loads F / (c_e R^2) of 0.7, 0.95, 1.2, 1.45
};
constexpr BuiltIn kBuiltIns[] = {
    {"human_temporal_bone", 2.145, 0.087, "1.5,2.04,2.57,3.11"},
    {"pettigrew_temporal_bone", 1.504, 0.116, "1.05,1.43,1.8,2.18"},
    {"pvc_k70", 0.462, 0.296, "0.323,0.439,0.554,0.67"},
};

// Truth: the full voxel rig (sim measure), another discretisation of the
// physics than the surrogate the fit uses, under either definition; the file
// names its definition and calibrate fits that one. Bone's initial velocities
// are the README's modeller tour (the same command), measured and checked
// there by ReadmeCommands.
TEST_F(CalibrateCommand, RecoversTheBuiltInMaterialsFromSimMeasureData) {
  for (const char* definition : {"settled", "initial"}) {
    for (std::size_t k = 0; k < std::size(kBuiltIns); ++k) {
      const BuiltIn& m = kBuiltIns[k];
      if (k == 0 && std::string(definition) == "initial") continue;
      const CliRun measure =
          RunBurrlab({"sim", "measure", "--material", m.name, "--forces",
                      m.forces_n, "--replicates", "4", "--noise-cv", "0.05",
                      "--seed", "11", "--velocity-definition", definition});
      ASSERT_EQ(measure.code, 0) << measure.err;
      EXPECT_EQ(measure.err, "");
      const std::string csv = Write(std::string(m.name) + ".csv", measure.out);
      const CliRun fit = RunBurrlab({"calibrate", "--measured", csv, "--json"});
      ASSERT_EQ(fit.code, 0) << fit.err;
      const nlohmann::json j = nlohmann::json::parse(fit.out);
      EXPECT_EQ(j["velocity_definition"], definition);
      const double c_e = j["c_e"], alpha = j["alpha"];
      std::printf(
          "%s, %s: c_e %.4g (truth %.4g) %s, alpha %.4g (truth %.4g) %s, "
          "rmse_log_v %.3g\n",
          definition, m.name, c_e, m.c_e_n_per_mm2,
          j["ci"]["c_e"].dump().c_str(), alpha, m.alpha_per_s,
          j["ci"]["alpha"].dump().c_str(), j["rmse_log_v"].get<double>());
      ASSERT_TRUE(j["identifiable"]["both"].get<bool>()) << fit.out;
      ASSERT_TRUE(j["ci"]["c_e"].is_array());
      ASSERT_TRUE(j["ci"]["alpha"].is_array());
      EXPECT_LE(j["ci"]["c_e"][0].get<double>(), m.c_e_n_per_mm2) << m.name;
      EXPECT_GE(j["ci"]["c_e"][1].get<double>(), m.c_e_n_per_mm2) << m.name;
      EXPECT_LE(j["ci"]["alpha"][0].get<double>(), m.alpha_per_s) << m.name;
      EXPECT_GE(j["ci"]["alpha"][1].get<double>(), m.alpha_per_s) << m.name;
      EXPECT_LT(j["rmse_log_v"].get<double>(), 0.2);
    }
  }
}
#endif  // !__SANITIZE_ADDRESS__

TEST_F(CalibrateCommand, JsonSaysWhenOnlyACombinationIsIdentified) {
  // Shallow immersion: bone (c_e 2.145, alpha 0.087, R 1 mm) at loads
  // 0.01-0.045 of c_e R^2 through the surrogate, with +-8 % scatter. The
  // log-log slope of v(F) hardly changes there, so only alpha * c_e^b is
  // determined. The surrogate's velocities are settled ones, and the file says
  // so.
  std::string text =
      "force_n,velocity_mm_s,burr_radius_mm,velocity_definition\n";
  for (double load : {0.01, 0.015, 0.02, 0.03, 0.045}) {
    analysis::DescentSurrogateInput in;
    in.force_n = load * 2.145;
    in.c_e_n_per_mm2 = 2.145;
    in.alpha_per_s = 0.087;
    in.radius_mm = 1.0;
    for (double factor : {1.08, 0.92, 1.0}) {
      text += fmt::format("{},{},1,settled\n", in.force_n,
                          analysis::SteadyVelocityMmS(in) * factor);
    }
  }
  const std::string csv = Write("shallow.csv", text);
  const CliRun fit = RunBurrlab({"calibrate", "--measured", csv, "--json"});
  ASSERT_EQ(fit.code, 0) << fit.err;
  const nlohmann::json j = nlohmann::json::parse(fit.out);
  EXPECT_TRUE(j["ci"]["c_e"].is_null()) << fit.out;
  EXPECT_TRUE(j["ci"]["alpha"].is_null());
  EXPECT_FALSE(j["identifiable"]["both"].get<bool>());
  EXPECT_THAT(j["identifiable"]["sentence"].get<std::string>(),
              HasSubstr("v(F) determines only the combination alpha * c_e^"));
  EXPECT_TRUE(j["identifiable"]["combination"]["ci"].is_array());
  for (const char* key : {"c_e", "alpha", "ci", "identifiable", "rmse_log_v"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
}

// A profile with two minima is said in the text, with what would decide
// between them. The fixture and its two minima are described in
// tests/analysis/model_gap/calibration_test.cc (ReportsASecondMinimum...);
// with the bootstrap-calibrated threshold the second lies inside c_e's
// interval.
TEST_F(CalibrateCommand, NamesASecondMinimumOfTheProfile) {
  const CliRun fit = RunBurrlab(
      {"calibrate", "--measured",
       std::string(BURRLAB_SOURCE_DIR) +
           "/tests/analysis/model_gap/fixtures/bone_initial_two_minima.csv"});
  ASSERT_EQ(fit.code, 0) << fit.err;
  EXPECT_THAT(
      fit.out,
      HasSubstr("second minimum   c_e 2.028 N/mm^2, alpha 0.07893 1/s: RSS of "
                "log v 0.04405 against 0.04238 at the fit, inside the 95 % "
                "interval of c_e; the data do not decide between the two "
                "(forces nearer the full-immersion force c_e R^2 2^(3/2) or an "
                "indentation (probe) measurement would).\n"));
}

TEST_F(CalibrateCommand, BadInputIsOneErrorAndExitOne) {
  const auto expect_error = [](const std::vector<std::string>& args,
                               const std::string& text) {
    const CliRun run = RunBurrlab(args);
    EXPECT_EQ(run.code, 1);
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(run.err, text);
  };
  const std::string one_level =
      Write("one.csv", "force_n,velocity_mm_s\n1,0.1\n1,0.2\n1,0.3\n");
  expect_error({"calibrate", "--measured", one_level, "--radius-mm", "1"},
               "burrlab: " + one_level +
                   ": error: all 3 runs are at one force level (1 N); v(F) "
                   "needs at least 2 force levels\n");
  const std::string no_radius =
      Write("r.csv", "force_n,velocity_mm_s\n1,0.1\n2,0.2\n3,0.3\n");
  expect_error({"calibrate", "--measured", no_radius},
               "burrlab: no burr radius: give --radius-mm R or a "
               "burr_radius_mm column in " +
                   no_radius + "\n");
  const std::string negative =
      Write("n.csv", "force_n,velocity_mm_s\n1,0.1\n2,-0.2\n3,0.3\n");
  expect_error({"calibrate", "--measured", negative, "--radius-mm", "1"},
               "burrlab: " + negative +
                   ":3:3: error: velocity_mm_s '-0.2' is not a positive "
                   "finite number of mm/s (the fit is on log v; leave out "
                   "runs that did not cut)\n2,-0.2\n  ^\n");
  const std::string missing = (dir_ / "absent.csv").string();
  expect_error(
      {"calibrate", "--measured", missing, "--radius-mm", "1"},
      "burrlab: cannot read " + missing + ": No such file or directory\n");
  const std::string through =
      Write("t.csv",
            "force_n,velocity_mm_s,burr_radius_mm\n1,0.1,1\n5000,"
            "0.2,1\n3,0.3,1\n");
  expect_error({"calibrate", "--measured", through},
               "burrlab: calibrate: the largest force 5000 N exceeds the "
               "full-immersion force c_e R^2 2^(3/2) of every c_e up to 1000 "
               "N/mm^2 with R = 1 mm: no steady descent in the model\n");
  // A file that names its velocity: fitted as that kind unless the flag asks
  // for another, which is refused naming both (calibrate and discover alike).
  const std::string initial =
      Write("i.csv",
            "force_n,velocity_mm_s,burr_radius_mm,velocity_definition\n1,0.1,1,"
            "initial\n2,0.2,1,initial\n3,0.3,1,initial\n");
  const std::string mismatch =
      "burrlab: " + initial +
      ":2: error: the measured velocities are initial velocities "
      "(velocity_definition column) but the model predicts settled "
      "velocities; the two are different quantities (the initial one is "
      "taken before the density in the burr has settled); "
      "--velocity-definition settled asked for the latter (leave the flag "
      "out to fit the file's own kind)\n";
  expect_error(
      {"calibrate", "--measured", initial, "--velocity-definition", "settled"},
      mismatch);
  expect_error({"discover", "--measured", initial, "--out",
                (dir_ / "d").string(), "--velocity-definition", "settled"},
               mismatch);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "d"));
  const CliRun own = RunBurrlab({"calibrate", "--measured", initial});
  EXPECT_EQ(own.code, 0) << own.err;
  EXPECT_THAT(own.out, HasSubstr("R = 1 mm, initial velocity\n"));
}

TEST_F(CalibrateCommand, SimMeasureRefusesUnknownEffects) {
  const CliRun run =
      RunBurrlab({"sim", "measure", "--material", "pvc_k70", "--forces",
                  "0.2,0.4", "--replicates", "2", "--effect", "motor_limit=1"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err,
            "burrlab: --effect: unknown effect 'motor_limit'; known effects: "
            "motor_power_limit, motor_power_limit_droop, spindle_slowdown, "
            "spindle_slowdown_exponential, cutting_threshold, "
            "cutting_threshold_soft, viscous_resistance, "
            "viscous_resistance_sqrt, friction_erosion, "
            "friction_erosion_quadratic, contact_exponent, "
            "contact_exponent_stiff, porosity, "
            "load_cell_lag, arm_compliance\n");
  const CliRun bad = RunBurrlab({"sim", "measure", "--material", "pvc_k70",
                                 "--forces", "0.2,0.4", "--replicates", "2",
                                 "--effect", "cutting_threshold=-1"});
  EXPECT_EQ(bad.code, 1);
  EXPECT_EQ(bad.err,
            "burrlab: --effect: cutting_threshold must be a finite force of "
            "at least 0 N, got -1\n");
}

}  // namespace
}  // namespace burrlab::runner
