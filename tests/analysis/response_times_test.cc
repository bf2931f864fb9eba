// Response-time medians and quartiles against R's quantile() (type 7, its
// default; fixtures/r/make_two_group_fixtures.R), per condition and block,
// with trials that have no response time skipped and counted.
#include "burrlab/analysis/response_times.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/analysis/scores.h"
#include "fixtures.h"

namespace burrlab::analysis {
namespace {

using results_schema::BehFile;
using results_schema::TrialRecord;
using testing::FixtureDir;
using testing::ReadCsv;

std::vector<double> TimesOf(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  for (std::string v; std::getline(in, v, ';');) values.push_back(std::stod(v));
  return values;
}

// R's quartiles of `values`, found in the fixture by their text.
std::map<std::string, std::string> FixtureRow(const std::string& values) {
  for (const auto& row : ReadCsv(FixtureDir("r") / "quantile_type7.csv")) {
    if (row.at("values") == values) return row;
  }
  ADD_FAILURE() << "no fixture row for " << values;
  return {};
}

void ExpectQuartiles(const ResponseTimeSummary& s,
                     const std::map<std::string, std::string>& r) {
  ASSERT_TRUE(s.median_s.has_value());
  EXPECT_NEAR(*s.q1_s, std::stod(r.at("q1")), 1e-6);
  EXPECT_NEAR(*s.median_s, std::stod(r.at("median")), 1e-6);
  EXPECT_NEAR(*s.q3_s, std::stod(r.at("q3")), 1e-6);
  EXPECT_NEAR(*s.iqr_s, std::stod(r.at("iqr")), 1e-6);
}

TEST(QuantileType7, MatchesRQuantile) {
  const auto rows = ReadCsv(FixtureDir("r") / "quantile_type7.csv");
  ASSERT_EQ(rows.size(), 9u);
  for (const auto& row : rows) {
    SCOPED_TRACE(row.at("values"));
    std::vector<double> x = TimesOf(row.at("values"));
    std::sort(x.begin(), x.end());
    EXPECT_NEAR(QuantileType7(x, 0.25), std::stod(row.at("q1")), 1e-6);
    EXPECT_NEAR(QuantileType7(x, 0.5), std::stod(row.at("median")), 1e-6);
    EXPECT_NEAR(QuantileType7(x, 0.75), std::stod(row.at("q3")), 1e-6);
    EXPECT_EQ(QuantileType7(x, 0.0), x.front());
    EXPECT_EQ(QuantileType7(x, 1.0), x.back());
  }
}

const char* const kAb = "0.5;0.5;0.80000000000000004;1.1000000000000001;0.5";
const char* const kBa =
    "2.2000000000000002;0.70999999999999996;1.05;0.93000000000000005;"
    "3.8999999999999999;1.6000000000000001;1.1799999999999999";
const char* const kBoth =
    "0.5;0.5;0.80000000000000004;1.1000000000000001;0.5;2.2000000000000002;"
    "0.70999999999999996;1.05;0.93000000000000005;3.8999999999999999;"
    "1.6000000000000001;1.1799999999999999";

// A two-interval block: subject 01 answers its AB trials in the times `kAb`
// and subject 02 its BA trials in `kBa`; each also types one answer into a
// pipe (no time, n/a).
std::vector<BehFile> TwoSubjects() {
  std::vector<BehFile> files(2);
  for (int s = 0; s < 2; ++s) {
    files[s].subject = s == 0 ? "01" : "02";
    files[s].task = "probe";
    const std::vector<double> times = TimesOf(s == 0 ? kAb : kBa);
    for (std::size_t i = 0; i <= times.size(); ++i) {
      TrialRecord t;
      t.trial_index = static_cast<int>(i);
      t.block = "probe";
      t.method = "two_interval";
      t.task = "probe";
      t.trial_type = s == 0 ? "AB" : "BA";
      // Copies of one string (GCC 12 at -O3 warns, falsely, that assigning
      // the literal here may overlap: -Wrestrict).
      const std::string one = "1";
      t.correct_answer = one;
      t.response = one;
      t.correct = true;
      if (i < times.size()) t.response_time_s = times[i];
      files[s].table.trials.push_back(t);
    }
  }
  return files;
}

// Truth: R's quantile() of the same times (fixture rows kAb, kBa, kBoth).
TEST(ResponseTimes, ScoresReportEachBlockAndConditionWithTheMissingCounted) {
  const std::vector<BehFile> files = TwoSubjects();
  Result<std::vector<BlockScores>> blocks = ScoreBlocks(files);
  ASSERT_TRUE(blocks.ok()) << blocks.error().message;
  const std::vector<ResponseTimeSummary>& rt = (*blocks)[0].response_times;
  ASSERT_EQ(rt.size(), 3u);
  EXPECT_EQ(rt[0].condition, "all");
  EXPECT_EQ(rt[0].n, 12);
  EXPECT_EQ(rt[0].missing, 2);
  ExpectQuartiles(rt[0], FixtureRow(kBoth));
  EXPECT_EQ(rt[1].condition, "AB");
  EXPECT_EQ(rt[1].n, 5);
  EXPECT_EQ(rt[1].missing, 1);
  ExpectQuartiles(rt[1], FixtureRow(kAb));
  EXPECT_EQ(rt[2].condition, "BA");
  EXPECT_EQ(rt[2].n, 7);
  ExpectQuartiles(rt[2], FixtureRow(kBa));

  const std::vector<SubjectBlockResponseTimes> per_subject =
      ResponseTimesBySubject(files);
  ASSERT_EQ(per_subject.size(), 2u);
  EXPECT_EQ(per_subject[1].subject, "02");
  EXPECT_EQ(per_subject[1].block, "probe");
  EXPECT_EQ(per_subject[1].method, "two_interval");
  ASSERT_EQ(per_subject[1].summaries.size(), 2u);  // all, BA
  EXPECT_EQ(per_subject[1].summaries[0].missing, 1);
  ExpectQuartiles(per_subject[1].summaries[0], FixtureRow(kBa));
}

TEST(ResponseTimes, ConditionsAreLevelsInConstantStimuliBlocks) {
  std::vector<TrialRecord> trials(5);
  const double levels[] = {1.6, 1.1, 1.3, 1.1, 1.6};
  for (std::size_t i = 0; i < trials.size(); ++i) {
    trials[i].method = "constant_stimuli";
    trials[i].trial_type = "2afc";
    trials[i].stim_level = levels[i];
    trials[i].response_time_s = 0.5 + static_cast<double>(i);
  }
  trials[3].response_time_s.reset();
  std::vector<const TrialRecord*> pointers;
  for (const TrialRecord& t : trials) pointers.push_back(&t);
  const std::vector<ResponseTimeSummary> rt = SummarizeResponseTimes(pointers);
  ASSERT_EQ(rt.size(), 4u);
  EXPECT_EQ(rt[1].condition, "level 1.1");
  EXPECT_EQ(rt[1].n, 1);
  EXPECT_EQ(rt[1].missing, 1);
  EXPECT_EQ(*rt[1].median_s, 1.5);
  EXPECT_EQ(rt[2].condition, "level 1.3");
  EXPECT_EQ(rt[3].condition, "level 1.6");
  EXPECT_EQ(*rt[3].median_s, 2.5);  // 0.5 and 4.5
  EXPECT_EQ(*rt[3].iqr_s, 2.0);     // 1.5 to 3.5

  // Every time missing: counted, no quartiles, no crash.
  for (TrialRecord& t : trials) t.response_time_s.reset();
  const ResponseTimeSummary none = SummarizeResponseTimes(pointers)[0];
  EXPECT_EQ(none.n, 0);
  EXPECT_EQ(none.missing, 5);
  EXPECT_FALSE(none.median_s.has_value());
  EXPECT_FALSE(none.iqr_s.has_value());

  TrialRecord adjustment;
  adjustment.method = "adjustment";
  adjustment.trial_type = "adjustment";
  adjustment.stim_level = 1.2;
  EXPECT_EQ(ConditionOf(adjustment), "adjustment");
  adjustment.trial_type = "";
  EXPECT_EQ(ConditionOf(adjustment), "n/a");
}

}  // namespace
}  // namespace burrlab::analysis
