// `burrlab run` at a station: the flag combinations it refuses (exact error
// text, exit 1, nothing written) and the devices it cannot find. The runs
// that open the subject window are in station/station_run_test.cc (under
// Xvfb).
#include "cli/session_commands.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "devices/libusb_transport.h"
#include "run_cli.h"

namespace burrlab::runner {
namespace {

namespace fs = std::filesystem;

class RunAtStationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(BURRLAB_BINARY_DIR) / "test_tmp" / "run_station" /
           info->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    protocol_ = ExamplePath("same_different_pvc_vs_bone.toml");
  }

  // `burrlab run PROTOCOL --subject 01 --out DIR extra...`.
  CliRun Run(std::vector<std::string> extra) {
    std::vector<std::string> args = {"run", protocol_, "--subject",
                                     "01",  "--out",   out().string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return RunBurrlab(args);
  }

  // Expects exit 1 with exactly `message` and no output folder.
  void ExpectRefused(const std::vector<std::string>& extra,
                     const std::string& message) {
    const CliRun r = Run(extra);
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, message);
    EXPECT_EQ(r.out, "");
    EXPECT_FALSE(fs::exists(out()));
  }

  fs::path Write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  fs::path out() const { return dir_ / "out"; }

  fs::path dir_;
  std::string protocol_;
};

TEST_F(RunAtStationTest, RefusesBadFlagCombinationsWithExactErrors) {
  ExpectRefused({"--device", "simulated", "--observer", "simulated"},
                "burrlab: --observer cannot be combined with --device or "
                "--station: the simulated observer answers without a "
                "station\n");
  ExpectRefused({"--station", "station.toml", "--observer", "simulated"},
                "burrlab: --observer cannot be combined with --device or "
                "--station: the simulated observer answers without a "
                "station\n");
  ExpectRefused({"--device", "phantom"},
                "burrlab: --device must be one of mouse, hid, falcon, "
                "simulated, got 'phantom'\n");
  ExpectRefused({"--device", "mouse", "--script", "script.toml"},
                "burrlab: --script needs --device simulated\n");
  ExpectRefused({"--script", "script.toml"},
                "burrlab: --script needs --device simulated\n");
  ExpectRefused({"--device", "simulated"},
                "burrlab: --device simulated needs --script FILE (the burr's "
                "path and the answers)\n");
  ExpectRefused({"--device", "mouse", "--firmware", "falcon.bin"},
                "burrlab: --firmware needs --device falcon\n");
  ExpectRefused({"--screenshots", "shots"},
                "burrlab: --screenshots needs --device\n");
  ExpectRefused({"--device", "hid"},
                "burrlab: --device hid needs --station FILE with a "
                "[response_box] table (the box's ids and buttons)\n");
}

TEST_F(RunAtStationTest, ReportsABadStationFileAndScriptWithTheirPlaces) {
  const fs::path station = Write("station.toml",
                                 "format = \"burrlab-station/1\"\n[device]\n"
                                 "max_force_n = 30\n");
  ExpectRefused({"--device", "mouse", "--station", station.string()},
                station.string() +
                    ":3:15: error: device.max_force_n must be in (0, 20], got "
                    "30\nmax_force_n = 30\n              ^\n");
  const fs::path script = Write("script.toml",
                                "format = \"burrlab-station-script/1\"\n"
                                "path = [[0.5, 0, 0, 3], [0.2, 0, 0, 1]]\n");
  ExpectRefused({"--device", "simulated", "--script", script.string()},
                script.string() +
                    ":2:26: error: path[1] t_s = 0.2 comes before the "
                    "previous waypoint's 0.5 (times must not decrease)\n"
                    "path = [[0.5, 0, 0, 3], [0.2, 0, 0, 1]]\n"
                    "                         ^\n");
  ExpectRefused(
      {"--device", "mouse", "--station", (dir_ / "missing.toml").string()},
      "burrlab: cannot read station file " + (dir_ / "missing.toml").string() +
          ": No such file or directory\n");
}

TEST_F(RunAtStationTest, RefusesAnAdjustmentProtocolAtAStation) {
  protocol_ = ExamplePath("adjustment_alpha.toml");
  ExpectRefused({"--device", "mouse"},
                "burrlab: " + protocol_ +
                    ": block \"adjust\" uses the adjustment method, which a "
                    "station does not run yet (run it with --observer or at "
                    "the prompt)\n");
}

TEST_F(RunAtStationTest, FalconWithoutHardwareSaysWhatIsMissing) {
  const Result<int> falcons = falcon::LibusbTransport::CountFalcons();
  if (falcons.ok() && falcons.value() > 0) {
    GTEST_SKIP() << "a Falcon is connected";
  }
  const CliRun r = Run({"--device", "falcon", "--firmware", "falcon.bin"});
  EXPECT_EQ(r.code, 1);
  EXPECT_FALSE(fs::exists(out()));
  if (falcons.ok()) {
    EXPECT_EQ(r.err,
              "burrlab: cannot use the Falcon: no Novint Falcon (USB "
              "0403:cb48) number 0 on the bus (0 found); connect it and "
              "check that `burrlab devices` lists it\n");
  } else {  // libusb itself cannot start here
    EXPECT_EQ(r.err.rfind("burrlab: cannot use the Falcon: libusb cannot "
                          "start: ",
                          0),
              0u)
        << r.err;
  }
}

TEST_F(RunAtStationTest, WithoutADisplayTheWindowErrorComesBeforeAnyJournal) {
  const char* display = std::getenv("DISPLAY");
  const std::optional<std::string> saved =
      display != nullptr ? std::optional<std::string>(display) : std::nullopt;
  unsetenv("DISPLAY");
  const CliRun r = Run({"--device", "mouse"});
  if (saved.has_value()) setenv("DISPLAY", saved->c_str(), 1);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err.rfind("burrlab: cannot open the subject window: ", 0), 0u)
      << r.err;
  EXPECT_NE(r.err.find("DISPLAY"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out()));
}

}  // namespace
}  // namespace burrlab::runner
