// Tests of participants.tsv and participants.json: the experimenter's table
// as spreadsheets save it (CSV or TSV, BOM, CRLF, quotes), the refusal of
// personal columns and of a subject listed twice with the exact message, and
// the merge of later runs into the dataset's table, byte for byte.
#include "burrlab/results_schema/participants.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "temp_dir.h"

namespace burrlab::results_schema {
namespace {

namespace fs = std::filesystem;
using SidecarJson = nlohmann::ordered_json;

std::string TableText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

std::string Why(const Status& s) { return s.ok() ? "ok" : s.error().message; }

template <typename T>
std::string Why(const Result<T>& r) {
  return r.ok() ? "ok" : r.error().message;
}

TEST(ParticipantColumn, RefusesNamesAndDatesOfBirthSayingWhich) {
  for (const char* name :
       {"name", "first_name", "surname", "full_name", "last_name", "FirstName",
        "First Name", "patient_name", "initials"}) {
    EXPECT_EQ(Why(CheckParticipantColumn(name)),
              "column \"" + std::string(name) +
                  "\" looks like a personal name; burrlab keeps subjects "
                  "pseudonymous (sub-<label>) and stores no names or dates "
                  "of birth: leave the column out")
        << name;
  }
  for (const char* name : {"dob", "birth_date", "date_of_birth", "birthday",
                           "DateOfBirth", "dob_iso"}) {
    EXPECT_EQ(Why(CheckParticipantColumn(name)),
              "column \"" + std::string(name) +
                  "\" looks like a date of birth; burrlab keeps subjects "
                  "pseudonymous (sub-<label>) and stores no names or dates "
                  "of birth: leave the column out (age in years is fine)")
        << name;
  }
  for (const char* name : {"age", "sex", "handedness", "group",
                           "years_of_practice", "dominant_hand", "doberman"}) {
    EXPECT_TRUE(CheckParticipantColumn(name).ok()) << name;
  }
  EXPECT_EQ(Why(CheckParticipantColumn("Age")),
            "column \"Age\" is not snake_case; use lower-case letters, digits "
            "and underscores, starting with a letter (e.g. age, "
            "years_of_practice)");
  EXPECT_EQ(Why(CheckParticipantColumn("participant_id")),
            "column \"participant_id\" is the subject's label, which burrlab "
            "writes itself");
}

TEST(ParticipantPair, ReadsKeyEqualsValueAndSaysWhatIsWrong) {
  Result<ParticipantValue> v = ParseParticipantPair("group=expert=senior");
  ASSERT_TRUE(v.ok()) << v.error().message;
  EXPECT_EQ(*v, (ParticipantValue{"group", "expert=senior"}));
  EXPECT_EQ(Why(ParseParticipantPair("age34")),
            "--participant \"age34\": expected key=value, e.g. age=34");
  EXPECT_EQ(Why(ParseParticipantPair("age=")),
            "--participant \"age=\": the value of age is empty (write n/a "
            "for none)");
  EXPECT_EQ(Why(ParseParticipantPair("=34")),
            "--participant \"=34\": a column name is empty");
  EXPECT_EQ(Why(ParseParticipantPair("name=Ada")),
            "--participant \"name=Ada\": column \"name\" looks like a "
            "personal name; burrlab keeps subjects pseudonymous (sub-<label>) "
            "and stores no names or dates of birth: leave the column out");
  EXPECT_EQ(Why(ParseParticipantPair("note=a\tb")),
            "--participant \"note=a\\x09b\": the value of note \"a\\x09b\" "
            "has a tab or line break");
}

// A spreadsheet's CSV: byte order mark, CRLF, quoted cells with commas and
// quotes, empty cells and an empty row at the end.
TEST(ParticipantsTable, ReadsASpreadsheetsCsvWithBomAndCrlf) {
  const std::string csv =
      "\xEF\xBB\xBFparticipant_id,age,group,note\r\n"
      "sub-01,34,expert,\"trained, left \"\"A\"\" hand\"\r\n"
      "02 , 41 ,novice,\r\n"
      ",,,\r\n";
  Result<std::vector<ParticipantRow>> rows =
      ParseParticipantsTable("roster.csv", csv);
  ASSERT_TRUE(rows.ok()) << rows.error().message;
  ASSERT_EQ(rows->size(), 2u);
  EXPECT_EQ((*rows)[0],
            (ParticipantRow{"01",
                            {{"age", "34"},
                             {"group", "expert"},
                             {"note", "trained, left \"A\" hand"}}}));
  EXPECT_EQ((*rows)[1],
            (ParticipantRow{
                "02", {{"age", "41"}, {"group", "novice"}, {"note", "n/a"}}}));
  // The same table as TSV and with semicolons (spreadsheets in locales with
  // a decimal comma) reads the same.
  Result<std::vector<ParticipantRow>> tsv = ParseParticipantsTable(
      "roster.tsv",
      "participant_id\tage\tgroup\tnote\n01\t34\texpert\ttrained, left "
      "\"A\" hand\n02\t41\tnovice\t\n");
  ASSERT_TRUE(tsv.ok()) << tsv.error().message;
  EXPECT_EQ(*tsv, *rows);
  Result<std::vector<ParticipantRow>> semicolons =
      ParseParticipantsTable("roster.csv", "age;participant_id\r\n34;01\r\n");
  ASSERT_TRUE(semicolons.ok()) << semicolons.error().message;
  EXPECT_EQ(*semicolons,
            (std::vector<ParticipantRow>{{"01", {{"age", "34"}}}}));
}

TEST(ParticipantsTable, ErrorsNameFileLineAndColumn) {
  EXPECT_EQ(Why(ParseParticipantsTable(
                "roster.csv",
                "\xEF\xBB\xBFparticipant_id,age,first_name\r\n01,3,Ada\r\n")),
            "roster.csv:1:20: error: column \"first_name\" looks like a "
            "personal name; burrlab keeps subjects pseudonymous (sub-<label>) "
            "and stores no names or dates of birth: leave the column out");
  EXPECT_EQ(Why(ParseParticipantsTable(
                "roster.tsv",
                "participant_id\tage\n01\t34\nsub-02\t41\nsub-01\t35\n")),
            "roster.tsv:4:1: error: participant_id sub-01 appears twice "
            "(lines 2 and 4); give each subject one row");
  EXPECT_EQ(Why(ParseParticipantsTable("roster.csv", "age,group\n34,x\n")),
            "roster.csv:1:1: error: the header has no participant_id column "
            "(the subjects' labels, e.g. sub-01 or 01)");
  EXPECT_EQ(Why(ParseParticipantsTable("roster.csv",
                                       "participant_id,age\n01,34,x\n")),
            "roster.csv:2:1: error: 3 cells, but the header has 2 columns");
  EXPECT_EQ(
      Why(ParseParticipantsTable("roster.csv", "participant_id,age\n0 1,34\n")),
      "roster.csv:2:1: error: participant_id \"0 1\": subject label "
      "\"0 1\" has byte 0x20 at position 2; use letters and digits "
      "only (BIDS sub-<label>)");
  EXPECT_EQ(Why(ParseParticipantsTable(
                "roster.csv", "participant_id,note\n01,\"open quote\n")),
            "roster.csv:2:4: error: a quoted cell runs past the end of the "
            "line (a cell is one line)");
  EXPECT_EQ(Why(ParseParticipantsTable("roster.csv", "\xEF\xBB\xBF\r\n")),
            "roster.csv: error: the file is empty; expected a header line "
            "naming the columns, participant_id first");
  EXPECT_EQ(Why(ParseParticipantsTable("roster.csv",
                                       "participant_id,age,age\n01,3,4\n")),
            "roster.csv:1:20: error: column \"age\" is named twice");
}

class ParticipantsFile : public ::testing::Test {
 protected:
  Status Update(const std::vector<ParticipantRow>& rows,
                const std::vector<ParticipantColumn>& columns = {}) {
    return UpdateParticipants(dir_.path(), rows, columns);
  }
  std::string Tsv() const {
    return TableText(dir_.path() / "participants.tsv");
  }
  SidecarJson Sidecar() const {
    return SidecarJson::parse(TableText(dir_.path() / "participants.json"));
  }
  TempDir dir_;
};

// A later run updates its subject's cells and keeps every other row and
// cell; columns are the union, n/a where a subject has none; rows are
// sorted by label whatever order the runs came in.
TEST_F(ParticipantsFile, LaterRunsUpdateTheirRowAndKeepTheOthers) {
  ASSERT_TRUE(Update({{"02", {{"age", "41"}, {"group", "novice"}}}}).ok());
  EXPECT_EQ(Tsv(),
            "participant_id\tage\tgroup\n"
            "sub-02\t41\tnovice\n");
  ASSERT_TRUE(
      Update({{"01", {{"group", "expert"}, {"handedness", "R"}}}}).ok());
  ASSERT_TRUE(Update({{"02", {{"age", "42"}}}, {"03", {}}}).ok());
  EXPECT_EQ(Tsv(),
            "participant_id\tage\tgroup\thandedness\n"
            "sub-01\tn/a\texpert\tR\n"
            "sub-02\t42\tnovice\tn/a\n"
            "sub-03\tn/a\tn/a\tn/a\n");
  const std::string tsv = Tsv();
  const std::string json = TableText(dir_.path() / "participants.json");
  ASSERT_TRUE(Update({{"01", {{"group", "expert"}}}}).ok());
  EXPECT_EQ(Tsv(), tsv);
  EXPECT_EQ(TableText(dir_.path() / "participants.json"), json);
}

TEST_F(ParticipantsFile, TheSidecarDescribesEveryColumnAndKeepsItsOwnWords) {
  const std::vector<ParticipantColumn> observer = {
      {"observer_rt_median", "Median response time", "s", {}},
      {"observer_answers", "Answer rule", "", {{"percepts", "noisy"}}}};
  ASSERT_TRUE(Update({{"01",
                       {{"age", "34"},
                        {"years_of_practice", "6"},
                        {"observer_rt_median", "1"},
                        {"observer_answers", "percepts"}}}},
                     observer)
                  .ok());
  const SidecarJson j = Sidecar();
  std::vector<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.push_back(key);
  EXPECT_EQ(keys, (std::vector<std::string>{
                      "participant_id", "age", "years_of_practice",
                      "observer_rt_median", "observer_answers"}));
  EXPECT_EQ(j["age"],
            SidecarJson::parse(R"({"Description": "Age of the participant",
                                      "Units": "year"})"));
  EXPECT_EQ(j["observer_rt_median"],
            SidecarJson::parse(R"({"Description": "Median response time",
                            "Units": "s"})"));
  EXPECT_EQ(j["observer_answers"]["Levels"],
            SidecarJson::parse(R"({"percepts": "noisy"})"));
  EXPECT_EQ(j["years_of_practice"]["Description"],
            "years_of_practice, as the experimenter recorded it for the "
            "subject (burrlab run --participant years_of_practice=VALUE, or a "
            "column of the --participants table)");
  // An entry the experimenter wrote stays as written.
  std::ofstream(dir_.path() / "participants.json")
      << R"({"years_of_practice": {"Description": "Years of surgery",
             "Units": "year"}, "extra_note": {"Description": "kept"}})";
  ASSERT_TRUE(Update({{"02", {{"sex", "F"}}}}).ok());
  const SidecarJson k = Sidecar();
  EXPECT_EQ(k["years_of_practice"],
            SidecarJson::parse(R"({"Description": "Years of surgery",
                            "Units": "year"})"));
  EXPECT_EQ(k["extra_note"]["Description"], "kept");
  EXPECT_TRUE(k.contains("sex"));
  EXPECT_TRUE(k.contains("observer_answers"));
}

TEST_F(ParticipantsFile, ATableThatCannotBeMergedIsRefusedAndKept) {
  const std::string bad =
      "\xEF\xBB\xBFparticipant_id\tage\tname\r\nsub-01\t3\tAda\r\n";
  std::ofstream(dir_.path() / "participants.tsv", std::ios::binary) << bad;
  const std::string path = (dir_.path() / "participants.tsv").string();
  const std::string why =
      path +
      ":1:20: error: column \"name\" looks like a personal name; burrlab "
      "keeps subjects pseudonymous (sub-<label>) and stores no names or "
      "dates of birth: leave the column out";
  EXPECT_EQ(Why(CheckParticipantsFiles(dir_.path())), why);
  EXPECT_EQ(Why(Update({{"02", {{"age", "4"}}}})), why);
  EXPECT_EQ(Tsv(), bad);
  EXPECT_FALSE(fs::exists(dir_.path() / "participants.json"));
  fs::remove(dir_.path() / "participants.tsv");
  std::ofstream(dir_.path() / "participants.json") << "[1]";
  EXPECT_EQ(Why(CheckParticipantsFiles(dir_.path())),
            (dir_.path() / "participants.json").string() +
                ": error: not a JSON object (BIDS: one description per "
                "column of participants.tsv); fix or remove the file");
  // A table kept with CRLF and a BOM (edited in a spreadsheet) is merged.
  fs::remove(dir_.path() / "participants.json");
  std::ofstream(dir_.path() / "participants.tsv", std::ios::binary)
      << "\xEF\xBB\xBFparticipant_id\tage\r\nsub-01\t3\r\n";
  ASSERT_TRUE(Update({{"02", {{"age", "4"}}}}).ok());
  EXPECT_EQ(Tsv(), "participant_id\tage\nsub-01\t3\nsub-02\t4\n");
}

}  // namespace
}  // namespace burrlab::results_schema
