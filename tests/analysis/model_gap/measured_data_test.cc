// The measured-data CSV of calibrate: what it accepts and the exact
// diagnostics for what it refuses.
#include "burrlab/analysis/model_gap/measured_data.h"

#include <gtest/gtest.h>

#include <string>

namespace burrlab::analysis {
namespace {

std::string ErrorOf(std::string_view text) {
  Result<MeasuredData> data = ParseMeasuredData("m.csv", text);
  return data.ok() ? std::string("(parsed)") : data.error().message;
}

TEST(ParseMeasuredData, ReadsRunsWithOptionalColumnsInAnyOrder) {
  Result<MeasuredData> d = ParseMeasuredData(
      "m.csv",
      "\xEF\xBB\xBFrun, velocity_mm_s ,material,force_n,burr_radius_mm,"
      "spindle_rad_s,note\r\n"
      "1,0.01,pvc,0.5,1,2094,x\n\n2,0.012,pvc,0.5,1,2094,y\n"
      "3,0.05,pvc,1,1,2094,z\n");
  ASSERT_TRUE(d.ok()) << d.error().message;
  ASSERT_EQ(d->runs.size(), 3u);
  EXPECT_EQ(d->force_levels, 2);
  EXPECT_EQ(d->runs[1].force_n, 0.5);
  EXPECT_EQ(d->runs[1].velocity_mm_s, 0.012);
  EXPECT_EQ(d->runs[1].run, "2");
  EXPECT_EQ(d->runs[1].material, "pvc");
  EXPECT_EQ(d->runs[1].line, 4);
  EXPECT_EQ(d->burr_radius_mm, 1.0);
  EXPECT_EQ(d->spindle_rad_s, 2094.0);
}

TEST(ParseMeasuredData, NeedsOnlyForceAndVelocity) {
  Result<MeasuredData> d = ParseMeasuredData(
      "m.csv", "force_n,velocity_mm_s\n1,0.1\n2,0.4\n3,0.9\n");
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_FALSE(d->burr_radius_mm.has_value());
  EXPECT_FALSE(d->spindle_rad_s.has_value());
  EXPECT_EQ(d->runs[2].run, "");
}

TEST(ParseMeasuredData, ReadsCrOnlyLineEndings) {
  Result<MeasuredData> d =
      ParseMeasuredData("m.csv",
                        "\xEF\xBB\xBF"
                        "force_n,velocity_mm_s\r1,0.1\r2,0.4\r3,0.9\r");
  ASSERT_TRUE(d.ok()) << d.error().message;
  ASSERT_EQ(d->runs.size(), 3u);
  EXPECT_EQ(d->runs[2].force_n, 3.0);
  EXPECT_EQ(d->runs[2].line, 4);
}

TEST(ParseMeasuredData, RefusesAnEmptyFile) {
  EXPECT_EQ(ErrorOf(" \n\n"),
            "m.csv: error: the file is empty; expected a header line with "
            "the columns force_n,velocity_mm_s");
}

TEST(ParseMeasuredData, NamesAMissingColumn) {
  EXPECT_EQ(ErrorOf("force_n,speed\n1,2\n"),
            "m.csv:1:1: error: the header has no velocity_mm_s column; "
            "measured data need the columns force_n and velocity_mm_s "
            "(comma-separated)\nforce_n,speed\n^");
  EXPECT_EQ(ErrorOf("force,velocity_mm_s\n1,2\n"),
            "m.csv:1:1: error: the header has no force_n column; measured "
            "data need the columns force_n and velocity_mm_s "
            "(comma-separated)\nforce,velocity_mm_s\n^");
}

TEST(ParseMeasuredData, RefusesADuplicateColumn) {
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s,force_n\n1,2,3\n"),
            "m.csv:1:23: error: the column force_n appears twice in the "
            "header\nforce_n,velocity_mm_s,force_n\n                      ^");
  // A spreadsheet's byte-order mark moves neither the column nor the caret.
  EXPECT_EQ(ErrorOf("\xEF\xBB\xBF"
                    "force_n,velocity_mm_s,force_n\n1,2,3\n"),
            "m.csv:1:23: error: the column force_n appears twice in the "
            "header\nforce_n,velocity_mm_s,force_n\n                      ^");
}

TEST(ParseMeasuredData, RefusesNonPositiveOrNonFiniteForces) {
  // A lone CR (old Mac spreadsheets) ends a line like LF and CR LF do.
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\r1,0.1\r-2,0.4\r"),
            "m.csv:3:1: error: force_n '-2' is not a positive finite number "
            "of N\n-2,0.4\n^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n1,0.1\n-2,0.4\n"),
            "m.csv:3:1: error: force_n '-2' is not a positive finite number "
            "of N\n-2,0.4\n^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n1,0.1\n0,0.4\n"),
            "m.csv:3:1: error: force_n '0' is not a positive finite number "
            "of N\n0,0.4\n^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\ninf,0.1\n"),
            "m.csv:2:1: error: force_n 'inf' is not a positive finite number "
            "of N\ninf,0.1\n^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\nnan,0.1\n"),
            "m.csv:2:1: error: force_n 'nan' is not a positive finite number "
            "of N\nnan,0.1\n^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n1e999,0.1\n"),
            "m.csv:2:1: error: force_n '1e999' is not a positive finite "
            "number of N\n1e999,0.1\n^");
}

TEST(ParseMeasuredData, RefusesNonPositiveOrNonFiniteVelocities) {
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n1,  0\n"),
            "m.csv:2:5: error: velocity_mm_s '0' is not a positive finite "
            "number of mm/s (the fit is on log v; leave out runs that did "
            "not cut)\n1,  0\n    ^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n1,x\n"),
            "m.csv:2:3: error: velocity_mm_s 'x' is not a positive finite "
            "number of mm/s (the fit is on log v; leave out runs that did "
            "not cut)\n1,x\n  ^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n1,-inf\n"),
            "m.csv:2:3: error: velocity_mm_s '-inf' is not a positive finite "
            "number of mm/s (the fit is on log v; leave out runs that did "
            "not cut)\n1,-inf\n  ^");
}

TEST(ParseMeasuredData, RefusesRaggedRows) {
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n1,0.1,7\n"),
            "m.csv:2:1: error: the row has 3 cells, the header 2\n1,0.1,7\n^");
}

TEST(ParseMeasuredData, RefusesMixedBurrs) {
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s,burr_radius_mm\n1,0.1,1\n2,0.2,"
                    "1.5\n"),
            "m.csv:3:7: error: burr_radius_mm 1.5 differs from 1 on line 2; "
            "calibrate one burr at a time\n2,0.2,1.5\n      ^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s,burr_radius_mm\n1,0.1,0\n"),
            "m.csv:2:7: error: burr_radius_mm '0' is not a positive finite "
            "number of mm\n1,0.1,0\n      ^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s,spindle_rad_s\n1,0.1,-1\n"),
            "m.csv:2:7: error: spindle_rad_s '-1' is not a finite number of "
            "at least 0 rad/s\n1,0.1,-1\n      ^");
}

TEST(ParseMeasuredData, ReadsTheVelocityDefinition) {
  Result<MeasuredData> d = ParseMeasuredData(
      "m.csv",
      "force_n,velocity_mm_s,velocity_definition\r\n1,0.1,initial\r\n2,0.4,"
      "initial\r\n3,0.9,initial\r\n");
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->velocity_definition, sim::VelocityDefinition::kInitial);
  EXPECT_EQ(d->velocity_definition_line, 2);
  Result<MeasuredData> bare = ParseMeasuredData(
      "m.csv", "force_n,velocity_mm_s\n1,0.1\n2,0.4\n3,0.9\n");
  ASSERT_TRUE(bare.ok());
  EXPECT_FALSE(bare->velocity_definition);
}

TEST(ParseMeasuredData, RefusesAnUnknownOrMixedVelocityDefinition) {
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s,velocity_definition\n1,0.1,"
                    "steady\n"),
            "m.csv:2:7: error: velocity_definition 'steady' is not one of "
            "initial, settled\n1,0.1,steady\n      ^");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s,velocity_definition\n1,0.1,"
                    "settled\n2,0.2,initial\n"),
            "m.csv:3:7: error: velocity_definition initial differs from "
            "settled on line 2; one file holds one kind of velocity\n"
            "2,0.2,initial\n      ^");
}

// A file that says which velocity it holds is checked against the one the
// model predicts; a file that does not say is taken at its word.
TEST(CheckVelocityDefinition, RefusesAnotherDefinitionNamingBoth) {
  const MeasuredData initial =
      ParseMeasuredData("m.csv",
                        "force_n,velocity_mm_s,velocity_definition\n1,0.1,"
                        "initial\n2,0.4,initial\n3,0.9,initial\n")
          .value();
  const Status s = CheckVelocityDefinition("m.csv", initial,
                                           sim::VelocityDefinition::kSettled);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            "m.csv:2: error: the measured velocities are initial velocities "
            "(velocity_definition column) but the model predicts settled "
            "velocities; the two are different quantities (the initial one "
            "is taken before the density in the burr has settled)");
  EXPECT_TRUE(CheckVelocityDefinition("m.csv", initial,
                                      sim::VelocityDefinition::kInitial)
                  .ok());
  const MeasuredData bare =
      ParseMeasuredData("m.csv", "force_n,velocity_mm_s\n1,0.1\n2,0.4\n3,0.9\n")
          .value();
  EXPECT_TRUE(
      CheckVelocityDefinition("m.csv", bare, sim::VelocityDefinition::kSettled)
          .ok());
}

TEST(ParseMeasuredData, RefusesASingleForceLevel) {
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n2,0.1\n2,0.2\n2,0.15\n"),
            "m.csv: error: all 3 runs are at one force level (2 N); v(F) "
            "needs at least 2 force levels");
}

TEST(ParseMeasuredData, RefusesFewerRunsThanParametersPlusOne) {
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n1,0.1\n2,0.4\n"),
            "m.csv: error: only 2 runs: fitting c_e and alpha needs more runs "
            "than parameters (at least 3)");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n1,0.1\n"),
            "m.csv: error: only 1 run: fitting c_e and alpha needs more runs "
            "than parameters (at least 3)");
  EXPECT_EQ(ErrorOf("force_n,velocity_mm_s\n"),
            "m.csv: error: no data rows after the header");
}

}  // namespace
}  // namespace burrlab::analysis
