// Tests of reading the exports back: every journaled field survives the
// _beh.tsv round trip, physio rows stream back as journaled, datasets are
// found per subject and block in run order, and malformed files get errors
// naming the file, line and column.
#include "burrlab/results_schema/bids_read.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "burrlab/results_schema/bids_export.h"
#include "burrlab/results_schema/journal.h"
#include "export_fixtures.h"

namespace burrlab::results_schema {
namespace {

TEST(BidsRead, ExportedTrialsReadBackFieldForField) {
  TempDir dir;
  WriteJournal(dir.path(), "07", 10);
  ASSERT_TRUE(ExportBids(dir.path(), "07").ok());
  Result<std::vector<BehFile>> files = ReadBidsDataset(dir.path());
  ASSERT_TRUE(files.ok()) << files.error().message;
  ASSERT_EQ(files->size(), 2u);
  EXPECT_EQ((*files)[0].task, "practice");
  EXPECT_EQ((*files)[1].task, "sameDifferentMain");
  int next = 0;
  for (const BehFile& f : *files) {
    EXPECT_EQ(f.subject, "07");
    EXPECT_EQ(f.table.seed, 1234567890123u);
    for (const TrialRecord& read : f.table.trials) {
      TrialRecord expected = FixtureTrial(next++);
      EXPECT_EQ(nlohmann::json::parse(read.extra),
                nlohmann::json::parse(expected.extra));
      expected.rng_state.clear();  // not exported
      expected.extra = read.extra;
      EXPECT_EQ(read, expected) << "trial " << read.trial_index;
    }
  }
  EXPECT_EQ(next, 10);
}

TEST(BidsRead, PhysioRowsStreamBackAsJournaled) {
  TempDir dir;
  WriteJournal(dir.path(), "07", 4);
  ASSERT_TRUE(ExportBids(dir.path(), "07").ok());
  Result<std::vector<BehFile>> files = ReadBidsDataset(dir.path());
  ASSERT_TRUE(files.ok()) << files.error().message;
  ASSERT_EQ((*files)[0].physio.size(), 1u);
  const PhysioFile& physio = (*files)[0].physio[0];
  EXPECT_EQ(physio.sampling_frequency_hz, 1000.0);
  EXPECT_EQ(physio.columns,
            (std::vector<std::string>{"trial_index", "interval_index", "time",
                                      "force_n", "depth_mm"}));
  std::vector<std::vector<double>> expected;
  for (int i = 0; i < 4; ++i) {
    for (const TraceSamples& t : FixtureTraces(i)) {
      for (std::size_t r = 0; r < t.rows.size(); ++r) {
        expected.push_back({double(i), double(t.interval_index),
                            t.start_time_s + double(r) / 1000.0, t.rows[r][0],
                            t.rows[r][1]});
      }
    }
  }
  std::vector<std::vector<double>> rows;
  ASSERT_TRUE(ForEachPhysioRow(physio, [&](std::span<const double> row) {
                rows.emplace_back(row.begin(), row.end());
                return true;
              }).ok());
  EXPECT_EQ(rows, expected);
  int seen = 0;  // stopping early
  ASSERT_TRUE(ForEachPhysioRow(physio, [&](std::span<const double>) {
                return ++seen < 3;
              }).ok());
  EXPECT_EQ(seen, 3);
}

TEST(BidsRead, SubjectsAreSortedAndOtherFilesIgnored) {
  TempDir dir;
  WriteJournal(dir.path(), "b2", 3);
  WriteJournal(dir.path(), "a1", 3);
  ASSERT_TRUE(ExportBids(dir.path(), "b2").ok());
  ASSERT_TRUE(ExportBids(dir.path(), "a1").ok());
  std::ofstream(dir.path() / "sub-a1" / "beh" / "notes.txt") << "x";
  std::ofstream(dir.path() / "sub-a1" / "beh" / "sub-a1_task-x_events.tsv")
      << "onset\n";
  Result<std::vector<BehFile>> files = ReadBidsDataset(dir.path());
  ASSERT_TRUE(files.ok()) << files.error().message;
  ASSERT_EQ(files->size(), 2u);
  EXPECT_EQ((*files)[0].subject, "a1");
  EXPECT_EQ((*files)[1].subject, "b2");
}

// A subject with two sessions is read as both, in session order, beside a
// subject without sessions; the journals are found in the session folders.
TEST(BidsRead, ASubjectWithTwoSessionsIsReadAsBoth) {
  TempDir dir;
  WriteJournal(dir.path(), "01", 10, "2");
  WriteJournal(dir.path(), "01", 4, "1");
  WriteJournal(dir.path(), "02", 3);
  ASSERT_TRUE(ExportBids(dir.path(), "01", {"2", {}}).ok());
  ASSERT_TRUE(ExportBids(dir.path(), "01", {"1", {}}).ok());
  ASSERT_TRUE(ExportBids(dir.path(), "02").ok());
  Result<std::vector<BehFile>> files = ReadBidsDataset(dir.path());
  ASSERT_TRUE(files.ok()) << files.error().message;
  std::vector<std::string> read;
  for (const BehFile& f : *files) {
    read.push_back(f.subject + "/" + f.session + "/" + f.task + "/" +
                   std::to_string(f.table.trials.size()) + "/" +
                   std::to_string(f.physio.size()));
  }
  EXPECT_EQ(read, (std::vector<std::string>{
                      "01/1/practice/4/1", "01/2/practice/4/1",
                      "01/2/sameDifferentMain/6/1", "02//practice/3/1"}));
  EXPECT_EQ((*files)[1].path, dir.path() / "sub-01" / "ses-2" / "beh" /
                                  "sub-01_ses-2_task-practice_beh.tsv");
  EXPECT_TRUE(FindUnexportedTrials(dir.path(), *files).empty());
  // Each session's journal counts against its own files: session 1 gets a
  // trial its exports lack; every fixture session is incomplete.
  {
    auto journal = Journal::Open(dir.path(), "01", "1");
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    ASSERT_TRUE(journal->Append(FixtureTrial(4), {}).ok());
  }
  const std::vector<UnexportedTrials> unexported =
      FindUnexportedTrials(dir.path(), *files);
  ASSERT_EQ(unexported.size(), 1u);
  EXPECT_EQ(unexported[0].subject, "01");
  EXPECT_EQ(unexported[0].session, "1");
  EXPECT_EQ(unexported[0].journal_trials, 5);
  EXPECT_EQ(unexported[0].exported_trials, 4);
  std::vector<std::string> incomplete;
  for (const IncompleteSession& s : FindIncompleteSessions(dir.path())) {
    incomplete.push_back(s.subject + "/" + s.session + "/" +
                         std::to_string(s.trials));
  }
  EXPECT_EQ(incomplete,
            (std::vector<std::string>{"01/1/5", "01/2/10", "02//3"}));
}

TEST(BidsRead, EmptyFolderSaysWhatItWants) {
  TempDir dir;
  Result<std::vector<BehFile>> files = ReadBidsDataset(dir.path());
  ASSERT_FALSE(files.ok());
  EXPECT_EQ(
      files.error().message,
      dir.path().string() +
          " holds no burrlab results (no sub-*/beh/sub-*_task-*_beh.tsv); "
          "give the --out folder of 'burrlab run' or 'burrlab study'");
  EXPECT_EQ(
      ReadBidsDataset(dir.path() / "missing").error().message,
      "cannot read " + (dir.path() / "missing").string() + ": not a folder");
}

const char kHeader[] =
    "trial_index\tblock\tmethod\ttask\ttrial_type\tstim_level\tstim_unit\t"
    "interval_materials\tcorrect_answer\tresponse\tcorrect\tresponse_time\t"
    "staircase_id\treversal\tstep_size\testimate\tseed\textra\n";

std::string Row(std::string stim_level, std::string correct,
                std::string seed = "5") {
  return "0\tb\tconstant_stimuli\tprobe\tn/a\t" + stim_level +
         "\tratio\tx+y\t1\t1\t" + correct + "\t0.5\tn/a\tn/a\tn/a\tn/a\t" +
         seed + "\tn/a\n";
}

TEST(BidsRead, MalformedTablesNameFileLineAndColumn) {
  const auto error = [](const std::string& text) {
    Result<BehTable> t = ParseBehTsv("b.tsv", text);
    return t.ok() ? std::string("ok") : t.error().message;
  };
  EXPECT_EQ(error(""),
            "b.tsv: error: the file is empty; expected a _beh.tsv with the "
            "header trial_index\tblock\t...");
  EXPECT_EQ(error(kHeader),
            "b.tsv: error: the file has a header but no trials");
  EXPECT_EQ(error(std::string(kHeader) + Row("1.5", "yes")),
            "b.tsv:2:50: error: correct \"yes\" is not 1, 0 or n/a");
  EXPECT_EQ(error(std::string(kHeader) + Row("big", "1")),
            "b.tsv:2:32: error: stim_level \"big\" is not a finite number or "
            "n/a");
  EXPECT_EQ(error(std::string(kHeader) + Row("inf", "1")),
            "b.tsv:2:32: error: stim_level \"inf\" is not a finite number or "
            "n/a");
  EXPECT_EQ(error(std::string(kHeader) + "0\tb\n"),
            "b.tsv:2:1: error: 2 cells, but the header has 18 columns");
  std::string two = std::string(kHeader) + Row("1", "1");
  two += Row("1", "1");
  EXPECT_EQ(error(two),
            "b.tsv:3:1: error: trial_index \"0\" does not follow trial 0 (rows "
            "are in trial order)");
  std::string seeds = std::string(kHeader) + Row("1", "1");
  seeds += "1" + Row("1", "1", "6").substr(1);
  EXPECT_EQ(error(seeds),
            "b.tsv:3:70: error: seed \"6\" differs from the seed 5 of the rows "
            "above (one file holds one session)");
  std::string bad_seed = std::string(kHeader) + Row("1", "1", "seed-1.5");
  EXPECT_EQ(
      error(bad_seed),
      "b.tsv:2:70: error: seed \"seed-1.5\" is not seed-N (or N) with N a "
      "whole number from 0 to 18446744073709551615");
  // Exports before the seed became text wrote the bare number.
  Result<BehTable> bare = ParseBehTsv(
      "b.tsv", std::string(kHeader) + Row("1", "1", "18446744073709551615"));
  ASSERT_TRUE(bare.ok()) << bare.error().message;
  EXPECT_EQ(bare->seed, 18446744073709551615ull);
  std::string no_task = kHeader;
  no_task.replace(no_task.find("\ttask\t"), 6, "\tjob\t");
  EXPECT_EQ(error(no_task + Row("1", "1")).substr(0, 50),
            "b.tsv:1:1: error: the header has no column 'task' ");
  Result<BehTable> ok =
      ParseBehTsv("b.tsv", std::string(kHeader) + Row("1.5", "1"));
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(ok->trials[0].stim_level, 1.5);
  // kHeader is an export from before the source column: still read.
  EXPECT_EQ(ok->trials[0].source, "");
  EXPECT_EQ(ok->trials[0].interval_materials,
            (std::vector<std::string>{"x", "y"}));
  EXPECT_EQ(ok->trials[0].extra, "{}");
  // ... and from before practice and late: scored, lateness unknown.
  EXPECT_FALSE(ok->trials[0].practice);
  EXPECT_EQ(ok->trials[0].late, std::nullopt);
}

TEST(BidsRead, PracticeAndLateColumnsAreReadAndChecked) {
  const std::string header =
      "trial_index\tblock\tmethod\ttask\ttrial_type\tpractice\tstim_level\t"
      "stim_unit\tinterval_materials\tcorrect_answer\tresponse\tcorrect\t"
      "response_time\tlate\tsource\tstaircase_id\treversal\tstep_size\t"
      "estimate\tseed\textra\n";
  const auto row = [](int index, std::string practice, std::string late) {
    return std::to_string(index) + "\tb\tsame_different\tprobe\tAB\t" +
           practice + "\tn/a\tn/a\tx+y\tdifferent\tsame\t0\t2.5\t" + late +
           "\ttyped\tn/a\tn/a\tn/a\tn/a\tseed-5\tn/a\n";
  };
  Result<BehTable> ok =
      ParseBehTsv("b.tsv", header + row(0, "1", "1") + row(1, "0", "0") +
                               row(2, "0", "n/a"));
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  ASSERT_EQ(ok->trials.size(), 3u);
  EXPECT_TRUE(ok->trials[0].practice);
  EXPECT_EQ(ok->trials[0].late, true);
  EXPECT_FALSE(ok->trials[1].practice);
  EXPECT_EQ(ok->trials[1].late, false);
  EXPECT_EQ(ok->trials[2].late, std::nullopt);
  Result<BehTable> bad = ParseBehTsv("b.tsv", header + row(0, "n/a", "0"));
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "b.tsv:2:29: error: practice \"n/a\" is not 1 or 0");
  bad = ParseBehTsv("b.tsv", header + row(0, "0", "yes"));
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "b.tsv:2:64: error: late \"yes\" is not 1, 0 or n/a");
}

TEST(BidsRead, PhysioTextRowsNameTheLineCountingBlankLines) {
  const std::vector<std::string> columns = {"trial_index", "time"};
  std::vector<std::vector<double>> rows;
  const auto collect = [&](std::span<const double> row) {
    rows.emplace_back(row.begin(), row.end());
    return true;
  };
  ASSERT_TRUE(
      ForEachPhysioRowOfText("p.tsv", columns, "0\t0.5\r\n\n1\tn/a", collect)
          .ok());
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1][0], 1.0);
  EXPECT_TRUE(std::isnan(rows[1][1]));
  // Blank lines count: the bad cell is on line 3.
  const Status bad =
      ForEachPhysioRowOfText("p.tsv", columns, "0\t1\n\n0\tx\x1b", collect);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "p.tsv:3:3: error: \"time\" \"x\\x1B\" is not a number or n/a");
}

TEST(BidsRead, PhysioLineLongerThanTheLimitIsRefusedBeforeItIsHeld) {
  const std::vector<std::string> columns = {"time"};
  // What a few kilobytes of gzip inflate to: no line break for 2 MiB.
  const std::string text = "0\n" + std::string(2u << 20, '7');
  const Status s = ForEachPhysioRowOfText(
      "p.tsv", columns, text, [](std::span<const double>) { return true; });
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            "p.tsv:2:1: error: the line is longer than 1048576 bytes (a physio "
            "row has one number per column)");
}

TEST(BidsRead, PhysioSidecarTextNamesTheFile) {
  const Result<PhysioFile> f = ParsePhysioSidecar(
      "d/sub-1_task-a_physio.json",
      R"({"SamplingFrequency": 500, "Columns": ["trial_index", "time"]})");
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f->data_path, "d/sub-1_task-a_physio.tsv.gz");
  EXPECT_EQ(f->sampling_frequency_hz, 500.0);
  EXPECT_EQ(
      ParsePhysioSidecar("d/x_physio.json", "{\"Columns\": 1}").error().message,
      "d/x_physio.json: error: SamplingFrequency must be a number above "
      "0");
}

}  // namespace
}  // namespace burrlab::results_schema
