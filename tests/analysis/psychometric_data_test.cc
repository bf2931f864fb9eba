// Reading counts (CSV/TSV) and _beh.tsv trial logs, and the diagnostics for
// files that cannot be read as either.
#include "burrlab/analysis/psychometric_data.h"

#include <gtest/gtest.h>

#include <string>

namespace burrlab::analysis {
namespace {

TEST(ParsePsychometricData, ReadsCountsCsvInFileOrder) {
  Result<PsychometricDataFile> f = ParsePsychometricData(
      "d.csv",
      "level,n_correct,n_total\n1,21,40\n2.5, 30 ,40\r\n\n0.5,20,40\n");
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_EQ(f->format, PsychometricDataFile::Format::kCounts);
  ASSERT_EQ(f->blocks.size(), 3u);
  EXPECT_EQ(f->blocks[1].level, 2.5);
  EXPECT_EQ(f->blocks[1].n_correct, 30);
  EXPECT_EQ(f->blocks[2].level, 0.5);
  EXPECT_EQ(f->lines, (std::vector<int>{2, 3, 5}));
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
  ASSERT_EQ(f->blocks.size(), 2u);
  EXPECT_EQ(f->blocks[0].level, 1.0);
  EXPECT_EQ(f->blocks[0].n_correct, 0);
  EXPECT_EQ(f->blocks[0].n_total, 1);
  EXPECT_EQ(f->blocks[1].level, 2.0);
  EXPECT_EQ(f->blocks[1].n_correct, 2);
  EXPECT_EQ(f->blocks[1].n_total, 3);
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

}  // namespace
}  // namespace burrlab::analysis
