// Reading counts (CSV/TSV) and _beh.tsv trial logs, and the diagnostics for
// files that cannot be read as either.
#include "burrlab/analysis/psychometric_data.h"

#include <gtest/gtest.h>

#include <string>

namespace burrlab::analysis {
namespace {

TEST(ParsePsychometricData, PoolsCountRowsByLevelInIncreasingOrder) {
  Result<PsychometricDataFile> f = ParsePsychometricData(
      "d.csv",
      "level,n_correct,n_total\n1,21,40\n2.5, 30 ,40\r\n\n0.5,20,40\n"
      "1,5,10\n");
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_EQ(f->format, PsychometricDataFile::Format::kCounts);
  EXPECT_EQ(f->rows, 4u);
  ASSERT_EQ(f->blocks.size(), 3u);
  EXPECT_EQ(f->blocks[0].level, 0.5);
  EXPECT_EQ(f->blocks[1].level, 1.0);
  EXPECT_EQ(f->blocks[1].n_correct, 26);
  EXPECT_EQ(f->blocks[1].n_total, 50);
  EXPECT_EQ(f->blocks[2].level, 2.5);
  EXPECT_EQ(f->blocks[2].n_correct, 30);
  // The line of each level's first row, for diagnostics.
  EXPECT_EQ(f->lines, (std::vector<int>{5, 2, 3}));
}

TEST(ParsePsychometricData, OneRowPerTrialAndPooledCountsGiveTheSameBlocks) {
  // 6 levels with 40 trials each, as pooled counts, as one count row per
  // trial and as a _beh.tsv, both in a scrambled order.
  const int correct[6] = {26, 19, 25, 32, 40, 39};
  std::string counts = "level,n_correct,n_total\n";
  for (int k = 0; k < 6; ++k) {
    counts +=
        std::to_string(k + 1) + "," + std::to_string(correct[k]) + ",40\n";
  }
  std::string rows = "level,n_correct,n_total\n";
  std::string beh = "trial_index\tstim_level\tcorrect\n";
  for (int t = 0; t < 240; ++t) {
    const int scrambled = (t * 37) % 240;
    const int k = scrambled / 40, i = scrambled % 40;
    const int answer = i < correct[k] ? 1 : 0;
    const std::string level = std::to_string(k + 1);
    rows += level + "," + std::to_string(answer) + ",1\n";
    beh +=
        std::to_string(t) + "\t" + level + "\t" + std::to_string(answer) + "\n";
  }
  Result<PsychometricDataFile> pooled = ParsePsychometricData("c.csv", counts);
  Result<PsychometricDataFile> per_row = ParsePsychometricData("r.csv", rows);
  Result<PsychometricDataFile> trials = ParsePsychometricData("t.tsv", beh);
  ASSERT_TRUE(pooled.ok() && per_row.ok() && trials.ok());
  EXPECT_EQ(pooled->rows, 6u);
  EXPECT_EQ(per_row->rows, 240u);
  EXPECT_EQ(trials->rows, 240u);
  for (const PsychometricDataFile* f : {&*per_row, &*trials}) {
    ASSERT_EQ(f->blocks.size(), 6u);
    for (std::size_t k = 0; k < 6; ++k) {
      EXPECT_EQ(f->blocks[k].level, pooled->blocks[k].level);
      EXPECT_EQ(f->blocks[k].n_correct, pooled->blocks[k].n_correct);
      EXPECT_EQ(f->blocks[k].n_total, pooled->blocks[k].n_total);
    }
  }
}

TEST(ParsePsychometricData, RefusesALevelOfMoreTrialsThanItCanCount) {
  EXPECT_EQ(ParsePsychometricData(
                "d.csv", "level,n_correct,n_total\n1,0,2147483647\n1,0,1\n")
                .error()
                .message,
            "d.csv:3:5: error: the rows with level 1 add up to more than "
            "2147483647 trials\n1,0,1\n    ^");
}

// Line endings from any spreadsheet: LF, CR LF, a lone CR (old Mac exports),
// with or without a byte-order mark, give the same blocks, and a bad cell is
// placed on the same line and column. Truth: the LF file, read as before.
TEST(ParsePsychometricData, ReadsEveryLineEndingAlike) {
  const std::string lf = "level,n_correct,n_total\n1,21,40\n2.5,30,40\n";
  const std::string bad = "level,n_correct,n_total\n1,21,40\n2,abc,40\n";
  const auto with = [](std::string text, const std::string& ending) {
    std::string out;
    for (char c : text) out += c == '\n' ? ending : std::string(1, c);
    return out;
  };
  Result<PsychometricDataFile> expected = ParsePsychometricData("d.csv", lf);
  ASSERT_TRUE(expected.ok());
  for (const std::string ending : {"\r\n", "\r"}) {
    for (const std::string bom : {"", "\xEF\xBB\xBF"}) {
      SCOPED_TRACE(ending == "\r" ? "CR" : "CRLF");
      Result<PsychometricDataFile> f =
          ParsePsychometricData("d.csv", bom + with(lf, ending));
      ASSERT_TRUE(f.ok()) << f.error().message;
      ASSERT_EQ(f->blocks.size(), 2u);
      EXPECT_EQ(f->blocks[1].level, expected->blocks[1].level);
      EXPECT_EQ(f->blocks[1].n_correct, expected->blocks[1].n_correct);
      EXPECT_EQ(f->lines, expected->lines);
      EXPECT_EQ(ParsePsychometricData("d.csv", bom + with(bad, ending))
                    .error()
                    .message,
                "d.csv:3:3: error: n_correct 'abc' is not a whole number of at "
                "least 0\n2,abc,40\n  ^");
    }
  }
}

TEST(ParsePsychometricData, ReadsTsvWithColumnsInAnyOrder) {
  Result<PsychometricDataFile> f = ParsePsychometricData(
      "d.tsv", "\xEF\xBB\xBFn_total\tlevel\tnote\tn_correct\n40\t1\tx\t21\n");
  ASSERT_TRUE(f.ok()) << f.error().message;
  ASSERT_EQ(f->blocks.size(), 1u);
  EXPECT_EQ(f->blocks[0].level, 1.0);
  EXPECT_EQ(f->blocks[0].n_correct, 21);
  EXPECT_EQ(f->blocks[0].n_total, 40);
}

TEST(ParsePsychometricData, PoolsBehTsvTrialsByLevelSkippingNa) {
  const std::string text =
      "trial_index\tblock\tstim_level\tcorrect\tresponse_time\n"
      "0\tb\t2\t1\t0.5\n"
      "1\tb\t1\t0\t0.6\n"
      "2\tb\t2\t0\tn/a\n"
      "3\tb\tn/a\t1\t0.4\n"
      "4\tb\t1\tn/a\tn/a\n"
      "5\tb\t2\t1\t0.3\n";
  Result<PsychometricDataFile> f = ParsePsychometricData("s_beh.tsv", text);
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_EQ(f->format, PsychometricDataFile::Format::kTrials);
  EXPECT_EQ(f->skipped_rows, 2);
  EXPECT_EQ(f->rows, 4u);
  ASSERT_EQ(f->blocks.size(), 2u);
  EXPECT_EQ(f->blocks[0].level, 1.0);
  EXPECT_EQ(f->blocks[0].n_correct, 0);
  EXPECT_EQ(f->blocks[0].n_total, 1);
  EXPECT_EQ(f->blocks[1].level, 2.0);
  EXPECT_EQ(f->blocks[1].n_correct, 2);
  EXPECT_EQ(f->blocks[1].n_total, 3);
}

// Familiarization trials (practice = 1) are never fitted: left out and
// counted; a practice column of 0 keeps the row.
TEST(ParsePsychometricData, LeavesOutPracticeTrialsOfABehTsv) {
  const std::string text =
      "trial_index\tblock\tpractice\tstim_level\tcorrect\n"
      "0\twarm\t1\t2\t1\n"
      "1\twarm\t1\t1\t0\n"
      "2\tmain\t0\t2\t0\n"
      "3\tmain\t0\t1\t1\n";
  Result<PsychometricDataFile> f = ParsePsychometricData("s_beh.tsv", text);
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_EQ(f->practice_rows, 2);
  EXPECT_EQ(f->rows, 2u);
  ASSERT_EQ(f->blocks.size(), 2u);
  EXPECT_EQ(f->blocks[0].n_correct, 1);  // level 1: the scored trial 3
  EXPECT_EQ(f->blocks[1].n_correct, 0);  // level 2: the scored trial 2
  Result<PsychometricDataFile> only = ParsePsychometricData(
      "p_beh.tsv", "practice\tstim_level\tcorrect\n1\t2\t1\n");
  ASSERT_FALSE(only.ok());
  EXPECT_NE(only.error().message.find(
                "no trial with a stim_level and a correct answer (0 rows with "
                "n/a skipped, 1 practice trials left out)"),
            std::string::npos)
      << only.error().message;
}

TEST(ParsePsychometricData, ControlBytesOfACellAreEscapedInTheMessage) {
  // The exact text: an ESC sequence and a BEL in a cell reach the terminal
  // as \x1b and \x07, in the message and in the quoted line alike.
  EXPECT_EQ(ParsePsychometricData("d.csv",
                                  "level,n_correct,n_total\n\x1b[2J\x07,1,2\n")
                .error()
                .message,
            "d.csv:2:1: error: level '\\x1b[2J\\x07' is not a finite number\n"
            "\\x1b[2J\\x07,1,2\n"
            "^");
  EXPECT_EQ(FormatDataDiagnostic("d.csv", "x\n\xc3\xa9,\x1b,2\n", 2, 4, "bad"),
            "d.csv:2:4: error: bad\n\xc3\xa9,\\x1b,2\n  ^");
}

TEST(ParsePsychometricData, NamesLineAndColumnOfABadCell) {
  EXPECT_EQ(ParsePsychometricData(
                "d.csv", "level,n_correct,n_total\n1,21,40\n2,abc,40\n")
                .error()
                .message,
            "d.csv:3:3: error: n_correct 'abc' is not a whole number of at "
            "least 0\n2,abc,40\n  ^");
  EXPECT_EQ(ParsePsychometricData("d.csv", "level,n_correct,n_total\n1,41,40\n")
                .error()
                .message,
            "d.csv:2:3: error: n_correct = 41 exceeds n_total = 40\n1,41,40\n"
            "  ^");
  EXPECT_EQ(ParsePsychometricData("d.csv", "level,n_correct,n_total\nx,1,2\n")
                .error()
                .message,
            "d.csv:2:1: error: level 'x' is not a finite number\nx,1,2\n^");
  EXPECT_EQ(
      ParsePsychometricData("d.csv", "level,n_correct,n_total\n1,1,0\n")
          .error()
          .message,
      "d.csv:2:5: error: n_total '0' is not a whole number of at least 1\n"
      "1,1,0\n    ^");
  EXPECT_EQ(ParsePsychometricData("d.csv", "level,n_correct,n_total\n1,2\n")
                .error()
                .message,
            "d.csv:2:1: error: the row has 2 cells, the header 3\n1,2\n^");
  EXPECT_EQ(
      ParsePsychometricData("b.tsv", "stim_level\tcorrect\n1\tyes\n")
          .error()
          .message,
      "b.tsv:2:3: error: correct 'yes' must be 1, 0 or n/a\n1\tyes\n \t^");
}

TEST(ParsePsychometricData, RejectsEmptyFilesAndUnknownHeaders) {
  EXPECT_EQ(ParsePsychometricData("e.csv", "").error().message,
            "e.csv: error: the file is empty; expected a header line "
            "level,n_correct,n_total (CSV or TSV) or a _beh.tsv with "
            "stim_level and correct columns");
  EXPECT_EQ(ParsePsychometricData("e.csv", " \n\n").error().message,
            ParsePsychometricData("e.csv", "").error().message);
  EXPECT_EQ(ParsePsychometricData("h.csv", "x,n,N\n1,2,3\n").error().message,
            "h.csv:1:1: error: the header names neither level, n_correct and "
            "n_total nor stim_level and correct (a _beh.tsv); columns are "
            "separated by commas\nx,n,N\n^");
  EXPECT_EQ(ParsePsychometricData("h.csv", "level,n_correct,n_total\n")
                .error()
                .message,
            "h.csv: error: no data rows after the header");
  EXPECT_EQ(
      ParsePsychometricData("b.tsv", "stim_level\tcorrect\nn/a\t1\n")
          .error()
          .message,
      "b.tsv: error: no trial with a stim_level and a correct answer (1 rows "
      "with n/a skipped)");
}

TEST(ReadPsychometricData, NamesAFileItCannotRead) {
  EXPECT_EQ(ReadPsychometricData("/nonexistent/d.csv").error().message,
            "cannot read /nonexistent/d.csv: No such file or directory");
  EXPECT_EQ(ReadPsychometricData("/tmp").error().message,
            "cannot read /tmp: it is a directory");
}

// --by: the rows of each condition pooled apart, in order of first
// appearance, beside the pooled blocks; a _beh.tsv's unit is kept; a BOM and
// CR LF line ends as from a spreadsheet.
TEST(ParsePsychometricData, SplitsTheRowsByAColumn) {
  const std::string text =
      "\xEF\xBB\xBFstim_level\tstim_unit\tblock\tcorrect\r\n"
      "1.2\tratio\tlight\t1\r\n1.2\tratio\theavy\t0\r\n"
      "1.5\tratio\tlight\t0\r\n1.2\tratio\tlight\t1\r\n";
  Result<PsychometricDataFile> f =
      ParsePsychometricData("t_beh.tsv", text, "block");
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_EQ(f->stim_unit, "ratio");
  ASSERT_EQ(f->blocks.size(), 2u);
  EXPECT_EQ(f->blocks[0].n_total, 3);
  ASSERT_EQ(f->conditions.size(), 2u);
  EXPECT_EQ(f->conditions[0].name, "light");
  ASSERT_EQ(f->conditions[0].blocks.size(), 2u);
  EXPECT_EQ(f->conditions[0].blocks[0].level, 1.2);
  EXPECT_EQ(f->conditions[0].blocks[0].n_correct, 2);
  EXPECT_EQ(f->conditions[0].blocks[0].n_total, 2);
  EXPECT_EQ(f->conditions[1].name, "heavy");
  EXPECT_EQ(f->conditions[1].blocks[0].n_correct, 0);
  EXPECT_EQ(ParsePsychometricData(
                "t_beh.tsv", "stim_level\tblock\tcorrect\n1\t\t1\n", "block")
                .error()
                .message,
            "t_beh.tsv:2:3: error: the block cell is empty: every row needs "
            "a condition\n1\t\t1\n \t^");
}

}  // namespace
}  // namespace burrlab::analysis
