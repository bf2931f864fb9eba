// Tests of the BIDS-style export: the TSV reads back with the right columns
// and n/a cells, the physio files decompress to the journaled samples, the
// sidecars satisfy the schemas, and re-exports are byte-identical.
#include "burrlab/results_schema/bids_export.h"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/results_schema/bids_read.h"
#include "burrlab/results_schema/journal.h"
#include "burrlab/results_schema/records.h"
#include "burrlab/results_schema/schemas.h"
#include "export_fixtures.h"

namespace burrlab::results_schema {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using Table = std::vector<std::vector<std::string>>;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::string Gunzip(const fs::path& path) {
  gzFile gz = gzopen(path.c_str(), "rb");
  if (gz == nullptr) return "<cannot open>";
  std::string text;
  char buffer[4096];
  int n = 0;
  while ((n = gzread(gz, buffer, sizeof buffer)) > 0) {
    text.append(buffer, static_cast<std::size_t>(n));
  }
  gzclose(gz);
  return text;
}

std::vector<std::string> Split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, sep)) parts.push_back(part);
  if (!text.empty() && text.back() == sep) parts.push_back("");
  return parts;
}

// Lines split on '\n', cells on '\t'; every line must end with '\n'.
Table ParseTsv(const std::string& text) {
  Table table;
  EXPECT_TRUE(!text.empty() && text.back() == '\n');
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) table.push_back(Split(line, '\t'));
  return table;
}

// Rows of `table` keyed by header name.
std::vector<std::map<std::string, std::string>> Records(const Table& table) {
  std::vector<std::map<std::string, std::string>> rows;
  for (std::size_t r = 1; r < table.size(); ++r) {
    EXPECT_EQ(table[r].size(), table[0].size()) << "row " << r;
    std::map<std::string, std::string> row;
    for (std::size_t c = 0; c < table[0].size() && c < table[r].size(); ++c) {
      row[table[0][c]] = table[r][c];
    }
    rows.push_back(row);
  }
  return rows;
}

TEST(TaskLabel, KeepsLettersAndDigitsInCamelCase) {
  EXPECT_EQ(TaskLabel("same-different 1"), "sameDifferent1");
  EXPECT_EQ(TaskLabel("Block_A"), "BlockA");
  EXPECT_EQ(TaskLabel("practice"), "practice");
  EXPECT_EQ(TaskLabel("  two  interval  "), "twoInterval");
  EXPECT_EQ(TaskLabel("***"), "block");
  EXPECT_EQ(TaskLabel(""), "block");
}

class BidsExport : public testing::Test {
 protected:
  void SetUp() override {
    WriteJournal(dir_.path(), "01", 10);
    Status s = ExportBids(dir_.path(), "01");
    ASSERT_TRUE(s.ok()) << s.error().message;
  }
  fs::path Beh(const std::string& name) const {
    return dir_.path() / "sub-01" / "beh" / name;
  }

  TempDir dir_;
};

TEST_F(BidsExport, WritesTheBidsFileSet) {
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir_.path())) {
    if (entry.is_regular_file()) {
      files.push_back(fs::relative(entry.path(), dir_.path()).string());
    }
  }
  std::sort(files.begin(), files.end());
  const std::vector<std::string> expected = {
      ".bidsignore",
      "dataset_description.json",
      "sub-01/beh/sub-01_task-practice_beh.json",
      "sub-01/beh/sub-01_task-practice_beh.tsv",
      "sub-01/beh/sub-01_task-practice_physio.json",
      "sub-01/beh/sub-01_task-practice_physio.tsv.gz",
      "sub-01/beh/sub-01_task-sameDifferentMain_beh.json",
      "sub-01/beh/sub-01_task-sameDifferentMain_beh.tsv",
      "sub-01/beh/sub-01_task-sameDifferentMain_physio.json",
      "sub-01/beh/sub-01_task-sameDifferentMain_physio.tsv.gz",
      "sub-01/journal.sqlite",
      "sub-01/journal.sqlite.lock",
      "sub-01/sub-01_scans.json",
      "sub-01/sub-01_scans.tsv",
  };
  // The journal's -wal/-shm files are gone once every connection closed.
  EXPECT_EQ(files, expected);
  EXPECT_EQ(ReadFile(dir_.path() / ".bidsignore"), "journal.sqlite*\n");
  // The fixture's session never ran to its end (nothing marked it so), and
  // its plan was not recorded.
  EXPECT_EQ(ReadFile(dir_.path() / "sub-01" / "sub-01_scans.tsv"),
            "filename\tsession_status\tsession_trials\tsession_planned_trials\n"
            "beh/sub-01_task-practice_beh.tsv\tincomplete\t10\tn/a\n"
            "beh/sub-01_task-practice_physio.tsv.gz\tincomplete\t10\tn/a\n"
            "beh/sub-01_task-sameDifferentMain_beh.tsv\tincomplete\t10\tn/a\n"
            "beh/sub-01_task-sameDifferentMain_physio.tsv.gz\tincomplete\t10\t"
            "n/a\n");
  const Json scans =
      Json::parse(ReadFile(dir_.path() / "sub-01" / "sub-01_scans.json"));
  for (const std::string& column : ScansColumns()) {
    EXPECT_TRUE(scans.contains(column)) << column;
  }
}

TEST(BidsExportCases, ScansMarkACompleteSessionAndItsPlan) {
  TempDir dir;
  WriteJournal(dir.path(), "05", 4);
  {
    auto journal = Journal::Open(dir.path(), "05");
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    ASSERT_TRUE(journal->SetPlannedTrials(4).ok());
    ASSERT_TRUE(journal->MarkComplete().ok());
  }
  ASSERT_TRUE(ExportBids(dir.path(), "05").ok());
  EXPECT_EQ(ReadFile(dir.path() / "sub-05" / "sub-05_scans.tsv"),
            "filename\tsession_status\tsession_trials\tsession_planned_trials\n"
            "beh/sub-05_task-practice_beh.tsv\tcomplete\t4\t4\n"
            "beh/sub-05_task-practice_physio.tsv.gz\tcomplete\t4\t4\n");
}

TEST_F(BidsExport, BehTsvReadsBackWithColumnsAndNa) {
  const Table table =
      ParseTsv(ReadFile(Beh("sub-01_task-sameDifferentMain_beh.tsv")));
  ASSERT_EQ(table.size(), 7u);  // header + trials 4..9
  EXPECT_EQ(table[0], BehColumns());
  const std::vector<std::string> must_have = {"trial_index",
                                              "block",
                                              "method",
                                              "task",
                                              "trial_type",
                                              "stim_level",
                                              "interval_materials",
                                              "correct_answer",
                                              "response",
                                              "correct",
                                              "response_time",
                                              "source",
                                              "staircase_id",
                                              "reversal",
                                              "step_size",
                                              "seed"};
  for (const std::string& column : must_have) {
    EXPECT_NE(std::find(table[0].begin(), table[0].end(), column),
              table[0].end())
        << column;
  }
  const auto rows = Records(table);
  const std::map<std::string, std::string> first = {
      {"trial_index", "4"},
      {"block", "same-different main"},
      {"method", "same_different"},
      {"task", "probe"},
      {"trial_type", "AB"},
      {"practice", "0"},
      {"stim_level", "n/a"},
      {"stim_unit", "n/a"},
      {"interval_materials", "pvc_k70+human_temporal_bone"},
      {"correct_answer", "different"},
      {"response", "same"},
      {"correct", "0"},
      {"response_time", "1.5"},
      {"late", "0"},
      {"source", "typed"},
      {"staircase_id", "n/a"},
      {"reversal", "n/a"},
      {"step_size", "n/a"},
      {"estimate", "n/a"},
      {"seed", "seed-1234567890123"},
      {"extra", "n/a"}};
  EXPECT_EQ(rows[0], first);
  // Trial 5 timed out: no response, correctness or time.
  EXPECT_EQ(rows[1].at("trial_index"), "5");
  EXPECT_EQ(rows[1].at("response"), "n/a");
  EXPECT_EQ(rows[1].at("correct"), "n/a");
  EXPECT_EQ(rows[1].at("response_time"), "n/a");
  EXPECT_EQ(rows[1].at("late"), "n/a");  // no answer, no time
  EXPECT_EQ(rows[1].at("correct_answer"), "same");
  EXPECT_EQ(rows[3].at("correct"), "1");  // trial 7: AA answered "same"
}

TEST_F(BidsExport, AdaptiveColumnsKeepTheirValues) {
  const auto rows =
      Records(ParseTsv(ReadFile(Beh("sub-01_task-practice_beh.tsv"))));
  ASSERT_EQ(rows.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    const auto& row = rows[static_cast<std::size_t>(i)];
    EXPECT_EQ(std::stod(row.at("stim_level")), 1.0 + 0.1 * i);
    EXPECT_EQ(row.at("stim_unit"), "ratio");
    EXPECT_EQ(row.at("staircase_id"), "0");
    EXPECT_EQ(row.at("reversal"), i == 2 ? "1" : "0");
    EXPECT_EQ(row.at("step_size"), "0.05");
    EXPECT_EQ(row.at("estimate"), i > 1 ? "1.125" : "n/a");
    EXPECT_EQ(row.at("extra"), R"({"quest_sd":0.25})");
  }
  EXPECT_EQ(rows[1].at("stim_level"), "1.1");
}

// Practice trials and late answers are columns analysts filter on.
TEST_F(BidsExport, PracticeAndLateAreColumnsToFilterOn) {
  const auto practice =
      Records(ParseTsv(ReadFile(Beh("sub-01_task-practice_beh.tsv"))));
  ASSERT_EQ(practice.size(), 4u);
  for (const auto& row : practice) {
    EXPECT_EQ(row.at("practice"), "1");
    EXPECT_EQ(row.at("late"), "n/a");  // the block has no deadline
  }
  const auto main =
      Records(ParseTsv(ReadFile(Beh("sub-01_task-sameDifferentMain_beh.tsv"))));
  std::string late;
  for (const auto& row : main) {
    EXPECT_EQ(row.at("practice"), "0");
    late += row.at("late") + " ";
  }
  // Trials 4-9 answered after 1.5, -, 2, 2.25, 2.5 and 2.75 s; deadline 2 s.
  EXPECT_EQ(late, "0 n/a 0 1 1 1 ");
  const Json sidecar =
      Json::parse(ReadFile(Beh("sub-01_task-sameDifferentMain_beh.json")));
  EXPECT_EQ(sidecar["practice"]["Levels"]["1"], "practice (not scored)");
  EXPECT_EQ(sidecar["late"]["Levels"]["1"], "after the deadline");
}

TEST_F(BidsExport, SidecarsSatisfyTheSchemasAndDescribeEveryColumn) {
  for (const std::string task : {"practice", "sameDifferentMain"}) {
    const std::string stem = "sub-01_task-" + task;
    const std::string beh_json = ReadFile(Beh(stem + "_beh.json"));
    Status s = CheckJsonAgainst("beh_sidecar", beh_json);
    EXPECT_TRUE(s.ok()) << s.error().message;
    Json beh = Json::parse(beh_json);
    const Table table = ParseTsv(ReadFile(Beh(stem + "_beh.tsv")));
    for (const std::string& column : table[0]) {
      ASSERT_TRUE(beh.contains(column)) << column;
      EXPECT_FALSE(beh[column]["Description"].get<std::string>().empty());
    }
    EXPECT_EQ(beh["response_time"]["Units"], "s");
    EXPECT_EQ(beh["task"]["Levels"].size(), 2u);

    const std::string physio_json = ReadFile(Beh(stem + "_physio.json"));
    s = CheckJsonAgainst("physio_sidecar", physio_json);
    EXPECT_TRUE(s.ok()) << s.error().message;
    Json physio = Json::parse(physio_json);
    EXPECT_EQ(physio["Columns"],
              Json::parse(R"(["trial_index", "interval_index", "time",
                               "force_n", "depth_mm"])"));
    EXPECT_EQ(physio["force_n"]["Units"], "N");
    EXPECT_EQ(physio["depth_mm"]["Units"], "mm");
  }
  Json practice = Json::parse(ReadFile(Beh("sub-01_task-practice_beh.json")));
  EXPECT_EQ(practice["TaskName"], "practice");
  EXPECT_EQ(practice["stim_level"]["Units"], "ratio");
  Json main =
      Json::parse(ReadFile(Beh("sub-01_task-sameDifferentMain_beh.json")));
  EXPECT_EQ(main["TaskName"], "same-different main");
  EXPECT_EQ(main["trial_type"]["Levels"],
            Json::parse(R"({"AA": "same material (A) in both intervals",
                            "AB": "material A, then material B"})"));

  const std::string description =
      ReadFile(dir_.path() / "dataset_description.json");
  Status s = CheckJsonAgainst("dataset_description", description);
  EXPECT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(Json::parse(description),
            Json::parse(R"({"Name": "stiffness discrimination",
                            "BIDSVersion": "1.9.0", "DatasetType": "raw",
                            "GeneratedBy": [{"Name": "burrlab",
                                             "Version": "0.1.0"}]})"));
}

TEST_F(BidsExport, PhysioDecompressesToTheJournaledSamples) {
  Json sidecar = Json::parse(ReadFile(Beh("sub-01_task-practice_physio.json")));
  EXPECT_EQ(sidecar["SamplingFrequency"], 1000.0);
  EXPECT_EQ(sidecar["StartTime"], 0.0);
  const Table table =
      ParseTsv(Gunzip(Beh("sub-01_task-practice_physio.tsv.gz")));
  std::vector<std::vector<double>> expected;
  for (int i = 0; i < 4; ++i) {
    for (const TraceSamples& trace : FixtureTraces(i)) {
      for (std::size_t r = 0; r < trace.rows.size(); ++r) {
        expected.push_back(
            {static_cast<double>(i), static_cast<double>(trace.interval_index),
             trace.start_time_s + static_cast<double>(r) / 1000.0,
             trace.rows[r][0], trace.rows[r][1]});
      }
    }
  }
  ASSERT_EQ(table.size(), expected.size());  // no header line
  for (std::size_t r = 0; r < table.size(); ++r) {
    ASSERT_EQ(table[r].size(), sidecar["Columns"].size()) << "line " << r;
    for (std::size_t c = 0; c < table[r].size(); ++c) {
      EXPECT_EQ(std::stod(table[r][c]), expected[r][c])
          << "line " << r << ", column " << c;
    }
  }
}

TEST_F(BidsExport, ReExportIsByteIdenticalAndKeepsADatasetDescription) {
  std::map<fs::path, std::string> before;
  for (const auto& entry : fs::recursive_directory_iterator(dir_.path())) {
    if (entry.is_regular_file() &&
        entry.path().filename() != "journal.sqlite") {
      before[entry.path()] = ReadFile(entry.path());
    }
  }
  const std::string own = "{\"Name\": \"curated by hand\"}\n";
  std::ofstream(dir_.path() / "dataset_description.json") << own;
  before[dir_.path() / "dataset_description.json"] = own;
  Status s = ExportBids(dir_.path(), "01");
  ASSERT_TRUE(s.ok()) << s.error().message;
  for (const auto& [path, bytes] : before) {
    EXPECT_EQ(ReadFile(path), bytes) << path;
  }
}

// Seeds beyond 2^53 (where a double has no room for the last digits) and
// beyond 2^63 (where a signed 64-bit integer ends) are written whole, as
// text no table reader turns into a number, and read back exactly.
TEST(BidsExportCases, SeedsAboveTwoToThe53And63AreWrittenWholeAsText) {
  for (const std::uint64_t seed :
       {9007199254740993ull, 9223372036854775809ull, 18446744073709551615ull}) {
    TempDir dir;
    SessionInfo session = FixtureSession("03");
    session.master_seed = seed;
    auto journal = Journal::Create(dir.path(), session);
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    ASSERT_TRUE(journal->Append(FixtureTrial(0), {}).ok());
    ASSERT_TRUE(ExportBids(dir.path(), "03").ok());
    const auto rows = Records(ParseTsv(ReadFile(
        dir.path() / "sub-03" / "beh" / "sub-03_task-practice_beh.tsv")));
    const std::string cell = rows.at(0).at("seed");
    EXPECT_EQ(cell, "seed-" + std::to_string(seed));
    // What a reader that converts numbers finds there: no number at all.
    char* end = nullptr;
    std::strtod(cell.c_str(), &end);
    EXPECT_EQ(end, cell.c_str()) << cell;
    Result<std::vector<BehFile>> read = ReadBidsDataset(dir.path());
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->at(0).table.seed, seed);
  }
  // The reason: the nearest double to 2^53 + 1 is 2^53.
  EXPECT_NE(
      static_cast<std::uint64_t>(static_cast<double>(9007199254740993ull)),
      9007199254740993ull);
}

TEST(BidsExportCases, DistinctBlocksGetDistinctTaskLabels) {
  TempDir dir;
  auto journal = Journal::Create(dir.path(), FixtureSession("02"));
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  TrialRecord a = FixtureTrial(4);
  a.trial_index = 0;
  a.block = "a b";
  TrialRecord b = a;
  b.trial_index = 1;
  b.block = "aB";
  ASSERT_TRUE(journal->Append(a, {}).ok());
  ASSERT_TRUE(journal->Append(b, {}).ok());
  Status s = ExportBids(dir.path(), "02");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const fs::path beh = dir.path() / "sub-02" / "beh";
  EXPECT_TRUE(fs::exists(beh / "sub-02_task-aB_beh.tsv"));
  EXPECT_TRUE(fs::exists(beh / "sub-02_task-aB2_beh.tsv"));
  EXPECT_EQ(Json::parse(ReadFile(beh / "sub-02_task-aB2_beh.json"))["TaskName"],
            "aB");
  EXPECT_FALSE(fs::exists(beh / "sub-02_task-aB_physio.tsv.gz"));
}

TEST(BidsExportCases, TracesOfDifferentKindsGoToSeparateRecordings) {
  TempDir dir;
  auto journal = Journal::Create(dir.path(), FixtureSession("03"));
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  std::vector<TraceSamples> traces = FixtureTraces(0);
  traces[1].sampling_frequency_hz = 500.0;
  traces[1].rows[1][0] = NAN;
  ASSERT_TRUE(journal->Append(FixtureTrial(0), traces).ok());
  Status s = ExportBids(dir.path(), "03");
  ASSERT_TRUE(s.ok()) << s.error().message;
  const fs::path beh = dir.path() / "sub-03" / "beh";
  Json first = Json::parse(
      ReadFile(beh / "sub-03_task-practice_recording-1_physio.json"));
  Json second = Json::parse(
      ReadFile(beh / "sub-03_task-practice_recording-2_physio.json"));
  EXPECT_EQ(first["SamplingFrequency"], 1000.0);
  EXPECT_EQ(second["SamplingFrequency"], 500.0);
  EXPECT_EQ(second["StartTime"], 5.0);
  const Table table =
      ParseTsv(Gunzip(beh / "sub-03_task-practice_recording-2_physio.tsv.gz"));
  ASSERT_EQ(table.size(), 5u);
  EXPECT_EQ(table[1],
            (std::vector<std::string>{"0", "1", "5.002", "n/a", "0.001"}));
}

// A labelled session's files are in sub-<id>/ses-<session>/ and carry the
// _ses-<session> entity, as BIDS requires; its scans.tsv names them relative
// to the session's folder.
TEST(BidsExportSessions, FilesCarryTheSessionEntity) {
  TempDir dir;
  WriteJournal(dir.path(), "01", 4, "1");
  WriteJournal(dir.path(), "01", 10, "2");
  ASSERT_TRUE(ExportBids(dir.path(), "01", {"1", {}}).ok());
  Status s = ExportBids(dir.path(), "01", {"2", {}});
  ASSERT_TRUE(s.ok()) << s.error().message;
  std::vector<std::string> files;
  for (const auto& entry :
       fs::recursive_directory_iterator(dir.path() / "sub-01" / "ses-2")) {
    if (entry.is_regular_file()) {
      files.push_back(fs::relative(entry.path(), dir.path()).string());
    }
  }
  std::sort(files.begin(), files.end());
  const std::vector<std::string> expected = {
      "sub-01/ses-2/beh/sub-01_ses-2_task-practice_beh.json",
      "sub-01/ses-2/beh/sub-01_ses-2_task-practice_beh.tsv",
      "sub-01/ses-2/beh/sub-01_ses-2_task-practice_physio.json",
      "sub-01/ses-2/beh/sub-01_ses-2_task-practice_physio.tsv.gz",
      "sub-01/ses-2/beh/sub-01_ses-2_task-sameDifferentMain_beh.json",
      "sub-01/ses-2/beh/sub-01_ses-2_task-sameDifferentMain_beh.tsv",
      "sub-01/ses-2/beh/sub-01_ses-2_task-sameDifferentMain_physio.json",
      "sub-01/ses-2/beh/sub-01_ses-2_task-sameDifferentMain_physio.tsv.gz",
      "sub-01/ses-2/journal.sqlite",
      "sub-01/ses-2/journal.sqlite.lock",
      "sub-01/ses-2/sub-01_ses-2_scans.json",
      "sub-01/ses-2/sub-01_ses-2_scans.tsv",
  };
  EXPECT_EQ(files, expected);
  EXPECT_EQ(
      ReadFile(dir.path() / "sub-01" / "ses-1" / "sub-01_ses-1_scans.tsv"),
      "filename\tsession_status\tsession_trials\tsession_planned_trials\n"
      "beh/sub-01_ses-1_task-practice_beh.tsv\tincomplete\t4\tn/a\n"
      "beh/sub-01_ses-1_task-practice_physio.tsv.gz\tincomplete\t4\tn/a\n");
  // Nothing of a session directly in the subject's folder.
  std::vector<std::string> top;
  for (const auto& entry : fs::directory_iterator(dir.path() / "sub-01")) {
    top.push_back(entry.path().filename().string());
  }
  std::sort(top.begin(), top.end());
  EXPECT_EQ(top, (std::vector<std::string>{"ses-1", "ses-2"}));
  const Json scans = Json::parse(
      ReadFile(dir.path() / "sub-01" / "ses-2" / "sub-01_ses-2_scans.json"));
  EXPECT_NE(scans["session_status"]["Description"].get<std::string>().find(
                "--subject <id> --session <session> --out DIR --resume"),
            std::string::npos);
  // The beh files hold the same rows as an unlabelled session's.
  TempDir plain;
  WriteJournal(plain.path(), "01", 10);
  ASSERT_TRUE(ExportBids(plain.path(), "01").ok());
  EXPECT_EQ(ReadFile(dir.path() / "sub-01" / "ses-2" / "beh" /
                     "sub-01_ses-2_task-practice_beh.tsv"),
            ReadFile(plain.path() / "sub-01" / "beh" /
                     "sub-01_task-practice_beh.tsv"));
  EXPECT_EQ(ExportBids(dir.path(), "01", {"3", {}}).error().message,
            "no journal for sub-01 ses-3 in " + dir.path().string() + " (" +
                JournalPath(dir.path(), "01", "3").string() +
                " does not exist); nothing to export");
  EXPECT_EQ(ExportBids(dir.path(), "01", {"a b", {}}).error().message,
            "session label \"a b\" has byte 0x20 at position 2; use letters "
            "and digits only (BIDS ses-<label>)");
}

TEST(BidsExportAuthors, AreWrittenThenAddedToAndNeverInvented) {
  TempDir dir;
  WriteJournal(dir.path(), "01", 2);
  WriteJournal(dir.path(), "02", 2);
  const fs::path description = dir.path() / "dataset_description.json";
  ASSERT_TRUE(ExportBids(dir.path(), "01", {"", {"Doe, Jane", "Roe R."}}).ok());
  EXPECT_EQ(ReadFile(description),
            "{\n"
            "  \"Name\": \"stiffness discrimination\",\n"
            "  \"BIDSVersion\": \"1.9.0\",\n"
            "  \"DatasetType\": \"raw\",\n"
            "  \"Authors\": [\n"
            "    \"Doe, Jane\",\n"
            "    \"Roe R.\"\n"
            "  ],\n"
            "  \"GeneratedBy\": [\n"
            "    {\n"
            "      \"Name\": \"burrlab\",\n"
            "      \"Version\": \"0.1.0\"\n"
            "    }\n"
            "  ]\n"
            "}\n");
  Status s = CheckJsonAgainst("dataset_description", ReadFile(description));
  EXPECT_TRUE(s.ok()) << s.error().message;
  // A later run's new author is added; one without authors changes nothing.
  ASSERT_TRUE(ExportBids(dir.path(), "02", {"", {"Roe R.", "Poe P."}}).ok());
  ASSERT_TRUE(ExportBids(dir.path(), "01").ok());
  EXPECT_EQ(Json::parse(ReadFile(description))["Authors"],
            Json::parse(R"(["Doe, Jane", "Roe R.", "Poe P."])"));
  // A curated file keeps everything else.
  std::ofstream(description) << R"({"Name": "curated", "Funding": ["x"]})";
  ASSERT_TRUE(ExportBids(dir.path(), "01", {"", {"Doe, Jane"}}).ok());
  EXPECT_EQ(Json::parse(ReadFile(description)),
            Json::parse(R"({"Name": "curated", "Funding": ["x"],
                            "Authors": ["Doe, Jane"]})"));
  std::ofstream(description) << "not json";
  EXPECT_EQ(ExportBids(dir.path(), "01", {"", {"Doe, Jane"}}).error().message,
            "cannot add the authors to " + description.string() +
                ": it is not a JSON object; fix or remove the file and export "
                "again");
  EXPECT_EQ(ReadFile(description), "not json");
}

TEST(BidsExportAuthors, AnAuthorIsOneNameOnOneLine) {
  EXPECT_TRUE(ValidateAuthor("Doe, Jane").ok());
  EXPECT_TRUE(ValidateAuthor("J\xC3\xBCrgen M\xC3\xBCller").ok());
  EXPECT_EQ(ValidateAuthor("Doe, Jane, Roe, Richard").error().message,
            "author \"Doe, Jane, Roe, Richard\" has 3 commas; give one name "
            "per --author (\"Surname, Given names\" at most: BIDS validators "
            "read more commas as several authors in one entry)");
  EXPECT_EQ(ValidateAuthor(" ").error().message,
            "an author's name is empty; give one name per --author");
  EXPECT_EQ(ValidateAuthor("Doe\tJane").error().message,
            "author \"Doe\\x09Jane\" has byte 0x09 at position 4; a name is "
            "one line of text");
  TempDir dir;
  WriteJournal(dir.path(), "01", 1);
  EXPECT_EQ(ExportBids(dir.path(), "01", {"", {"A, B, C"}}).error().message,
            ValidateAuthor("A, B, C").error().message);
  EXPECT_FALSE(fs::exists(dir.path() / "dataset_description.json"));
}

TEST(BidsExportCases, MissingJournalIsAnError) {
  TempDir dir;
  Status s = ExportBids(dir.path(), "09");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, "no journal for sub-09 in " +
                                   dir.path().string() + " (" +
                                   JournalPath(dir.path(), "09").string() +
                                   " does not exist); nothing to export");
  s = ExportBids(dir.path(), "sub-09");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            "subject label \"sub-09\" includes the \"sub-\" prefix; give only "
            "the label, e.g. \"09\"");
}

}  // namespace
}  // namespace burrlab::results_schema
