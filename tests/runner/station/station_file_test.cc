// station.toml: a full file, defaults, and the exact text of each problem.
#include "station/station_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "run_cli.h"

namespace burrlab::runner {
namespace {

// Every diagnostic of `text`, formatted as `burrlab validate` prints them.
std::string Problems(std::string_view text) {
  const StationParseOutcome o = ParseStation("station.toml", text);
  std::string all;
  for (const auto& d : o.diagnostics) {
    all += protocols::FormatDiagnostic("station.toml", text, d);
  }
  return all;
}

TEST(ParseStation, ReadsAFullStation) {
  const StationParseOutcome o = ParseStation("station.toml", R"(
format = "burrlab-station/1"
[device]
backend = "falcon"
max_force_n = 6.5
max_stiffness_n_per_mm = 2.5
[response_box]
vendor_id = 0x16c0
product_id = 0x05df
serial = "RB7"
buttons = { 1 = "1", 2 = "2", 5 = "SPACE" }
[screen]
width = 1920
height = 1080
fullscreen = true
)");
  ASSERT_TRUE(o.station.has_value());
  const StationConfig& s = *o.station;
  EXPECT_EQ(s.device, "falcon");
  EXPECT_DOUBLE_EQ(s.max_force_n, 6.5);
  EXPECT_DOUBLE_EQ(s.max_stiffness_n_per_mm, 2.5);
  ASSERT_TRUE(s.response_box.has_value());
  EXPECT_EQ(s.response_box->vendor_id, 0x16c0);
  EXPECT_EQ(s.response_box->serial, "RB7");
  ASSERT_EQ(s.response_box->buttons.size(), 3u);
  EXPECT_EQ(s.response_box->buttons[2].number, 5);
  EXPECT_EQ(s.response_box->buttons[2].key, "SPACE");
  EXPECT_TRUE(s.response_box->Validate().ok());
  EXPECT_EQ(s.screen_width, 1920);
  EXPECT_TRUE(s.fullscreen);
}

TEST(ParseStation, DefaultsToTheMouse) {
  const StationParseOutcome o =
      ParseStation("station.toml", "format = \"burrlab-station/1\"\n");
  ASSERT_TRUE(o.station.has_value());
  EXPECT_EQ(o.station->device, "mouse");
  EXPECT_EQ(o.station->screen_width, 1280);
  EXPECT_DOUBLE_EQ(o.station->max_stiffness_n_per_mm, 0.0);  // the device's
}

TEST(ParseStation, NamesEachProblemWithItsPlace) {
  EXPECT_EQ(Problems("format = \"burrlab-station/1\"\n[device]\nbackend = "
                     "\"phantom\"\n"),
            "station.toml:3:11: error: device.backend must be one of mouse, "
            "hid, falcon, simulated, got \"phantom\"\n"
            "backend = \"phantom\"\n"
            "          ^\n");
  EXPECT_EQ(Problems("format = \"burrlab-station/1\"\n[device]\nmax_force_n = "
                     "nan\n"),
            "station.toml:3:15: error: device.max_force_n must be a finite "
            "number, got nan\n"
            "max_force_n = nan\n"
            "              ^\n");
  EXPECT_EQ(Problems("format = \"burrlab-station/1\"\n[device]\n"
                     "max_stiffness_n_per_mm = 0\n"),
            "station.toml:3:26: error: device.max_stiffness_n_per_mm must be "
            "in (0, 50], got 0\n"
            "max_stiffness_n_per_mm = 0\n"
            "                         ^\n");
  EXPECT_EQ(Problems("format = \"burrlab-station/1\"\n[screen]\nwidth = 99\n"
                     "colour = 1\n"),
            "station.toml:4:1: error: unknown key \"colour\" in [screen]; "
            "accepted: width, height, fullscreen\n"
            "colour = 1\n"
            "^\n"
            "station.toml:3:9: error: screen.width must be in [320, 8192], got "
            "99\n"
            "width = 99\n"
            "        ^\n");
  EXPECT_EQ(
      Problems("format = \"burrlab-station/1\"\n[response_box]\nvendor_id "
               "= 1\nproduct_id = 2\nbuttons = { x = \"1\" }\n"),
      "station.toml:5:13: error: button \"x\" must be a number from 1 to "
      "512\n"
      "buttons = { x = \"1\" }\n"
      "            ^\n");
  EXPECT_EQ(Problems("format = \"burrlab-station/1\"\n[device]\nbackend = "
                     "\"hid\"\n"),
            "station.toml:2:1: error: backend \"hid\" needs a [response_box] "
            "table\n"
            "[device]\n"
            "^\n");
}

TEST(ParseStation, BadTomlIsOneLine) {
  const StationParseOutcome o =
      ParseStation("station.toml", "format = \"burrlab-station/1\"\n[device\n");
  ASSERT_FALSE(o.station.has_value());
  ASSERT_EQ(o.diagnostics.size(), 1u);
  EXPECT_EQ(o.diagnostics[0].where.line, 2);
}

TEST(ValidateCommand, ChecksStationFiles) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "burrlab_station_file_test";
  std::filesystem::create_directories(dir);
  const std::string good = (dir / "good.toml").string();
  const std::string bad = (dir / "bad.toml").string();
  std::ofstream(good) << "format = \"burrlab-station/1\"\n[response_box]\n"
                         "vendor_id = 0x16c0\nproduct_id = 0x05df\n"
                         "buttons = { 1 = \"1\", 2 = \"2\" }\n";
  std::ofstream(bad) << "format = \"burrlab-station/1\"\n[device]\n"
                        "max_force_n = -1\n";
  CliRun run = RunBurrlab({"validate", good});
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(run.out, good +
                         ": ok (station: device mouse, max force 8 N, response "
                         "box 16c0:05df with 2 buttons, screen 1280x720)\n");
  run = RunBurrlab({"validate", bad});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err, bad +
                         ":3:15: error: device.max_force_n must be in (0, "
                         "20], got -1\n"
                         "max_force_n = -1\n"
                         "              ^\n");
  std::filesystem::remove_all(dir);
}

TEST(ParseStation, EscapesControlCharactersOfKeysInMessages) {
  // Quoted keys may hold any character; the message (one printable line)
  // shows an ESC or a tab escaped.
  const StationParseOutcome o =
      ParseStation("station.toml",
                   "format = \"burrlab-station/1\"\n\"\\u001b[2J\\t\" = 1\n"
                   "[response_box]\nvendor_id = 1\nproduct_id = 2\n"
                   "buttons = { \"\\u001b\" = \"1\" }\n");
  ASSERT_EQ(o.diagnostics.size(), 2u);
  EXPECT_EQ(o.diagnostics[0].message,
            "unknown key \"\\x1b[2J\\x09\" in the station file; accepted: "
            "format, device, response_box, screen");
  EXPECT_EQ(o.diagnostics[1].message,
            "button \"\\x1b\" must be a number from 1 to 512");
}

}  // namespace
}  // namespace burrlab::runner
