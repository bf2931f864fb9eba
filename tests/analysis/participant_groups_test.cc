// participants.tsv read as subject -> group: the columns named, n/a left
// out, spreadsheet line ends and byte-order marks read as plain text, and
// every bad file one diagnostic naming the line, the column and the rule.
#include "burrlab/analysis/participant_groups.h"

#include <gtest/gtest.h>

#include <string>

namespace burrlab::analysis {
namespace {

constexpr const char* kFile =
    "participant_id\tage\tgroup\n"
    "sub-01\t41\texpert\n"
    "sub-02\t24\ttrainee\n"
    "\n"
    "sub-03\t52\texpert\n"
    "sub-04\tn/a\tn/a\n";

TEST(ParticipantGroups, ReadsTheGroupColumnAndLeavesOutNa) {
  Result<ParticipantGroups> g =
      ParseParticipantGroups("participants.tsv", kFile, "group");
  ASSERT_TRUE(g.ok()) << g.error().message;
  EXPECT_EQ(g->column, "group");
  EXPECT_EQ(g->groups, (std::vector<std::string>{"expert", "trainee"}));
  EXPECT_EQ(g->group_of,
            (std::map<std::string, std::string>{
                {"01", "expert"}, {"02", "trainee"}, {"03", "expert"}}));
  EXPECT_EQ(g->left_out, (std::vector<std::string>{"04"}));
}

// A spreadsheet's CR LF line ends and UTF-8 byte-order mark are read as
// every analysis data file reads them: the same groups, no "trainee\r".
TEST(ParticipantGroups, CrLfAndByteOrderMarkReadTheSame) {
  std::string windows = "\xEF\xBB\xBF";
  for (const char* c = kFile; *c != '\0'; ++c) {
    if (*c == '\n') windows += '\r';
    windows += *c;
  }
  Result<ParticipantGroups> g =
      ParseParticipantGroups("participants.tsv", windows, "group");
  ASSERT_TRUE(g.ok()) << g.error().message;
  EXPECT_EQ(g->groups, (std::vector<std::string>{"expert", "trainee"}));
  EXPECT_EQ(g->group_of.at("02"), "trainee");
  EXPECT_EQ(g->left_out, (std::vector<std::string>{"04"}));
  // Diagnostics count lines and columns after the mark as a reader sees them.
  EXPECT_EQ(ParseParticipantGroups("p.tsv", windows, "level").error().message,
            "p.tsv:1:1: error: the header has no level column (it has "
            "participant_id, age, group)\nparticipant_id\tage\tgroup\n^");
}

TEST(ParticipantGroups, BadFilesAreOneDiagnostic) {
  const auto error = [](const std::string& text,
                        const std::string& column = "group") {
    Result<ParticipantGroups> g = ParseParticipantGroups("p.tsv", text, column);
    return g.ok() ? std::string("(no error)") : g.error().message;
  };
  EXPECT_EQ(error(""),
            "p.tsv: error: the file is empty; expected a header line with "
            "participant_id and group");
  EXPECT_EQ(error("id\tgroup\nsub-01\ta\n"),
            "p.tsv:1:1: error: the header has no participant_id column (it "
            "has id, group)\nid\tgroup\n^");
  EXPECT_EQ(error("participant_id\tgroup\n01\ta\n"),
            "p.tsv:2:1: error: participant_id '01' is not sub-<label> with a "
            "label of letters and digits\n01\ta\n^");
  EXPECT_EQ(error("participant_id\tgroup\nsub-0_1\ta\n"),
            "p.tsv:2:1: error: participant_id 'sub-0_1' is not sub-<label> "
            "with a label of letters and digits\nsub-0_1\ta\n^");
  EXPECT_EQ(error("participant_id\tgroup\nsub-01\ta\nsub-02\tb\nsub-01\tb\n"),
            "p.tsv:4:1: error: sub-01 is listed twice (first on line 2)\n"
            "sub-01\tb\n^");
  EXPECT_EQ(error("participant_id\tgroup\nsub-01\t\nsub-02\tb\n"),
            "p.tsv:2:8: error: sub-01 has an empty group; write n/a to leave "
            "it out of the comparison\nsub-01\t\n      \t^");
  EXPECT_EQ(error("participant_id\tgroup\nsub-01\ta\tx\n"),
            "p.tsv:2:1: error: the row has 3 cells, the header 2\n"
            "sub-01\ta\tx\n^");
  EXPECT_EQ(error("participant_id\tgroup\nsub-01\texpert\nsub-02\texpert\n"),
            "p.tsv: error: the group column holds 1 group (expert): a "
            "two-group comparison needs exactly 2");
  EXPECT_EQ(error("participant_id\tgroup\nsub-01\ta\nsub-02\tb\nsub-03\tc\n"),
            "p.tsv: error: the group column holds 3 groups (a, b, c): a "
            "two-group comparison needs exactly 2");
  EXPECT_EQ(error("participant_id\tgroup\nsub-01\tn/a\n"),
            "p.tsv: error: the group column holds 0 groups: a two-group "
            "comparison needs exactly 2");
  EXPECT_EQ(error("participant_id\tgroup\tgroup\nsub-01\ta\tb\n"),
            "p.tsv:1:22: error: the column group appears twice in the "
            "header\nparticipant_id\tgroup\tgroup\n"
            "              \t     \t^");
  EXPECT_EQ(ReadParticipantGroups("/nonexistent/p.tsv", "group")
                .error()
                .message.substr(0, 38),
            "cannot read /nonexistent/p.tsv: No suc");
}

}  // namespace
}  // namespace burrlab::analysis
