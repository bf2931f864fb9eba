// `burrlab run` at a station: the flag combinations it refuses (exact error
// text, exit 1, nothing written) and the devices it cannot find. The runs
// that open the subject window are in station/station_run_test.cc (under
// Xvfb).
#include "cli/session_commands.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "devices/libusb_transport.h"
#include "read_file.h"
#include "run_cli.h"
#include "two_block_protocol.h"

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

// Session labels, authors and participants are checked before anything
// runs: a clear error saying where and what, exit 1, no output folder.
TEST_F(RunAtStationTest, RefusesBadSessionsAuthorsAndParticipants) {
  ExpectRefused({"--session", "ses-2"},
                "burrlab: --session: session label \"ses-2\" includes the "
                "\"ses-\" prefix; give only the label, e.g. \"2\"\n");
  ExpectRefused({"--session", "day 1"},
                "burrlab: --session: session label \"day 1\" has byte 0x20 at "
                "position 4; use letters and digits only (BIDS "
                "ses-<label>)\n");
  ExpectRefused({"--author", "Doe, Jane", "--author", "Doe, J., Roe, R."},
                "burrlab: --author: author \"Doe, J., Roe, R.\" has 3 commas; "
                "give one name per --author (\"Surname, Given names\" at "
                "most: BIDS validators read more commas as several authors in "
                "one entry)\n");
  ExpectRefused({"--participant", "age34"},
                "burrlab: --participant \"age34\": expected key=value, e.g. "
                "age=34\n");
  ExpectRefused({"--participant", "first_name=Ada"},
                "burrlab: --participant \"first_name=Ada\": column "
                "\"first_name\" looks like a personal name; burrlab keeps "
                "subjects pseudonymous (sub-<label>) and stores no names or "
                "dates of birth: leave the column out\n");
  ExpectRefused({"--participant", "date_of_birth=1990-01-01"},
                "burrlab: --participant \"date_of_birth=1990-01-01\": column "
                "\"date_of_birth\" looks like a date of birth; burrlab keeps "
                "subjects pseudonymous (sub-<label>) and stores no names or "
                "dates of birth: leave the column out (age in years is "
                "fine)\n");
  ExpectRefused({"--participant", "age=34", "--participant", "age=35"},
                "burrlab: --participant: column age is given twice (34 and "
                "35); give each column once\n");
  ExpectRefused({"--participant", "observer_lapse=0"},
                "burrlab: --participant: column observer_lapse is burrlab's: "
                "observer_* columns hold a simulated subject's observer "
                "parameters\n");
  // The experimenter's table, as a spreadsheet saves it (BOM, CRLF).
  const fs::path names =
      Write("names.csv",
            "\xEF\xBB\xBFparticipant_id,age,surname\r\nsub-01,34,Doe\r\n");
  ExpectRefused({"--participants", names.string()},
                "burrlab: " + names.string() +
                    ":1:20: error: column \"surname\" looks like a personal "
                    "name; burrlab keeps subjects pseudonymous (sub-<label>) "
                    "and stores no names or dates of birth: leave the column "
                    "out\n");
  const fs::path twice =
      Write("twice.tsv", "participant_id\tage\r\n01\t34\r\nsub-01\t35\r\n");
  ExpectRefused({"--participants", twice.string()},
                "burrlab: " + twice.string() +
                    ":3:1: error: participant_id sub-01 appears twice (lines 2 "
                    "and 3); give each subject one row\n");
  const fs::path others =
      Write("others.csv", "participant_id,age\r\n02,41\r\n");
  ExpectRefused({"--participants", others.string()},
                "burrlab: " + others.string() +
                    ": error: no row for sub-01 (no participant_id is sub-01 "
                    "or 01)\n");
  ExpectRefused({"--participants", (dir_ / "missing.csv").string()},
                "burrlab: cannot read " + (dir_ / "missing.csv").string() +
                    ": No such file or directory\n");
}

// A results folder whose participants.tsv cannot be merged is refused before
// the session starts, and kept as it is.
TEST_F(RunAtStationTest, RefusesAParticipantsTsvThatCannotBeMerged) {
  fs::create_directories(out());
  const std::string bad = "participant_id\tage\tname\nsub-09\t3\tAda\n";
  std::ofstream(out() / "participants.tsv", std::ios::binary) << bad;
  const CliRun r = Run({"--observer", "simulated"});
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.err, "burrlab: " + (out() / "participants.tsv").string() +
                       ":1:20: error: column \"name\" looks like a personal "
                       "name; burrlab keeps subjects pseudonymous "
                       "(sub-<label>) and stores no names or dates of birth: "
                       "leave the column out\n");
  EXPECT_FALSE(fs::exists(out() / "sub-01"));
  const CliRun study = RunBurrlab({"study", protocol_, "--simulated-subjects",
                                   "1", "--out", out().string()});
  EXPECT_EQ(study.code, 1);
  EXPECT_EQ(study.err, r.err);
  EXPECT_FALSE(fs::exists(out() / "sub-01"));
}

// The subject's row of the experimenter's table and the --participant
// values (a flag wins) go to the dataset's participants.tsv with the
// simulated observer's parameters; a later session updates its subject's
// row and keeps the others.
TEST_F(RunAtStationTest, ParticipantsFromATableAndFlagsMergeIntoTheDataset) {
  protocol_ =
      Write("short.toml", TwoBlockProtocol("short", 4, 4, 0.3)).string();
  const fs::path roster =
      Write("roster.csv",
            "\xEF\xBB\xBFparticipant_id,age,group,handedness\r\n"
            "sub-01,34,\"expert, ENT\",R\r\n02,41,novice,\r\n,,,\r\n");
  auto run = [&](const std::string& subject, const std::string& session,
                 std::vector<std::string> extra) {
    std::vector<std::string> args = {
        "run",          protocol_,   "--subject", subject,      "--out",
        out().string(), "--session", session,     "--observer", "simulated"};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliRun r = RunBurrlab(args);
    EXPECT_EQ(r.code, 0) << r.err;
  };
  run("01", "1",
      {"--participants", roster.string(), "--participant", "group=surgeon",
       "--participant", "years_of_practice=6"});
  run("02", "1", {"--participants", roster.string()});
  const std::string observer =
      "0.2\t0.3\t0.02\t1\tfixed\t0\t1\t1\t0\t0\t1\t0.35\t0.5\tpercepts";
  const std::string columns =
      "participant_id\tage\tgroup\thandedness\tyears_of_practice\t"
      "observer_weber_stiffness\tobserver_weber_removal\tobserver_lapse\t"
      "observer_criterion\tobserver_rule\tobserver_bias\t"
      "observer_force_factor\t"
      "observer_speed_factor\tobserver_force_spread\tobserver_speed_spread\t"
      "observer_rt_median\tobserver_rt_log_sd\t"
      "observer_match_tolerance\tobserver_answers\n";
  EXPECT_EQ(ReadFile(out() / "participants.tsv"),
            columns + "sub-01\t34\tsurgeon\tR\t6\t" + observer + "\n" +
                "sub-02\t41\tnovice\tn/a\tn/a\t" + observer + "\n");
  // Day 2 of sub-01, a year older by then: only that cell changes.
  run("01", "2", {"--participant", "age=35"});
  EXPECT_EQ(ReadFile(out() / "participants.tsv"),
            columns + "sub-01\t35\tsurgeon\tR\t6\t" + observer + "\n" +
                "sub-02\t41\tnovice\tn/a\tn/a\t" + observer + "\n");
  const nlohmann::json sidecar =
      nlohmann::json::parse(ReadFile(out() / "participants.json"));
  EXPECT_EQ(sidecar["age"]["Units"], "year");
  EXPECT_EQ(sidecar["observer_rt_median"]["Units"], "s");
  EXPECT_EQ(sidecar["observer_rule"]["Levels"].size(), 3u);
  EXPECT_EQ(sidecar.size(), 19u);
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
