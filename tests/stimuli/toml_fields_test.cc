// The TOML field readers every file kind shares: the exact words and places
// of each report (written out here by hand, not taken from the readers), and
// what each getter returns for an absent, a wrong and a right value.
#include "burrlab/stimuli/toml_fields.h"

#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <vector>

namespace burrlab::stimuli {
namespace {

// Every report as "line:col: message".
class Reports {
 public:
  TomlFields Fields() {
    return TomlFields([this](toml::source_position at, std::string message) {
      lines_.push_back(std::to_string(at.line) + ":" +
                       std::to_string(at.column) + ": " + message);
    });
  }
  const std::vector<std::string>& lines() const { return lines_; }

 private:
  std::vector<std::string> lines_;
};

toml::table Parse(std::string_view text) { return toml::parse(text); }

constexpr std::string_view kAllowed[] = {"width", "height", "fullscreen"};

TEST(TomlFields, AnUnknownKeyIsReportedAtTheKeyWithASuggestionOrTheList) {
  const toml::table root =
      Parse("[screen]\nwidht = 1\ncolour = \"red\"\n[other]\n");
  Reports r;
  r.Fields().CheckKeys(*root["screen"].as_table(), "[screen]", kAllowed);
  // toml++ keeps keys sorted: colour before widht.
  EXPECT_EQ(r.lines(),
            (std::vector<std::string>{
                "3:1: unknown key \"colour\" in [screen]; accepted: width, "
                "height, fullscreen",
                "2:1: unknown key \"widht\" in [screen] (did you mean "
                "\"width\"?)"}));
}

TEST(TomlFields, AnUnknownTableIsReportedAtItsHeader) {
  const toml::table root = Parse("width = 1\n\n  [zzz]\nx = 1\n");
  Reports r;
  r.Fields().CheckKeys(root, "the file", kAllowed);
  EXPECT_EQ(r.lines(), (std::vector<std::string>{
                           "3:3: unknown key \"zzz\" in the file; accepted: "
                           "width, height, fullscreen"}));
}

TEST(TomlFields, KeysOfElsewhereGetTheirOwnMessage) {
  const toml::table root = Parse("width = 1\nlevels = [1]\n");
  Reports r;
  constexpr std::string_view kElsewhere[] = {"levels"};
  r.Fields().CheckKeys(root, "blocks[1]", kAllowed, kElsewhere,
                       "does not apply to method same_different");
  EXPECT_EQ(r.lines(),
            (std::vector<std::string>{"2:1: key \"levels\" does not apply to "
                                      "method same_different"}));
}

TEST(TomlFields, AnOldSpellingPassesAndATypoOfItPointsToTheNewOne) {
  const toml::table root = Parse("c_e = 1\nalpah = 2\n");
  Reports r;
  constexpr std::string_view kKeys[] = {"c_e_n_per_mm2", "alpha_per_s"};
  constexpr TomlRename kRenamed[] = {{"c_e", "c_e_n_per_mm2"},
                                     {"alpha", "alpha_per_s"}};
  r.Fields().CheckKeys(root, "[parameters]", kKeys, {}, {}, kRenamed);
  EXPECT_EQ(r.lines(),
            (std::vector<std::string>{"2:1: unknown key \"alpah\" in "
                                      "[parameters] (did you mean "
                                      "\"alpha_per_s\"?)"}));
}

TEST(TomlFields, GettersReturnTheValueOrReportTheTypeAtTheValue) {
  const toml::table t = Parse(
      "s = \"text\"\nn = 2\nf = 0.5\nb = true\nsub = {}\nbad = [1]\n"
      "inf = inf\n");
  Reports r;
  const TomlFields fields = r.Fields();
  EXPECT_EQ(fields.String(t, "s", "x.s"), "text");
  EXPECT_EQ(fields.Number(t, "n", "x.n"), 2.0);
  EXPECT_EQ(fields.Number(t, "f", "x.f"), 0.5);
  EXPECT_EQ(fields.Integer(t, "n", "x.n"), 2);
  EXPECT_EQ(fields.Boolean(t, "b", "x.b"), true);
  EXPECT_NE(fields.Table(t, "sub", "x.sub"), nullptr);
  EXPECT_TRUE(r.lines().empty());
  // Absent: nothing, silently.
  EXPECT_FALSE(fields.String(t, "none", "x.none").has_value());
  EXPECT_EQ(fields.Table(t, "none", "x.none"), nullptr);
  EXPECT_TRUE(r.lines().empty());
  // Wrong: nothing, and why.
  EXPECT_FALSE(fields.String(t, "bad", "x.bad").has_value());
  EXPECT_FALSE(fields.Number(t, "s", "x.s").has_value());
  EXPECT_FALSE(fields.Number(t, "inf", "x.inf").has_value());
  EXPECT_FALSE(fields.Integer(t, "f", "x.f").has_value());
  EXPECT_FALSE(fields.Boolean(t, "n", "x.n").has_value());
  EXPECT_EQ(fields.Table(t, "b", "x.b"), nullptr);
  EXPECT_EQ(r.lines(), (std::vector<std::string>{
                           "6:7: x.bad must be a string, got an array",
                           "1:5: x.s must be a number, got a string",
                           "7:7: x.inf must be a finite number, got inf",
                           "3:5: x.f must be an integer, got a number",
                           "2:5: x.n must be true or false, got an integer",
                           "4:5: x.b must be a table, got a boolean"}));
}

TEST(TomlFields, ChoicesAndRangesNameWhatIsAccepted) {
  const toml::table t = Parse("task = \"prob\"\nn = 0\nw = 99\nf = 21.5\n");
  Reports r;
  const TomlFields fields = r.Fields();
  constexpr std::string_view kTasks[] = {"probe", "drill"};
  EXPECT_FALSE(fields.Choice(t, "task", "b.task", kTasks).has_value());
  EXPECT_FALSE(fields.IntegerIn(t, "w", "screen.width", 320, 8192));
  EXPECT_FALSE(fields.PositiveNumberUpTo(t, "n", "max_force_n", 20.0));
  EXPECT_FALSE(fields.PositiveNumberUpTo(t, "f", "max_force_n", 20.0));
  EXPECT_EQ(fields.IntegerIn(t, "w", "w", 1, 99), 99);
  EXPECT_EQ(fields.PositiveNumberUpTo(t, "f", "f", 21.5), 21.5);
  EXPECT_EQ(r.lines(),
            (std::vector<std::string>{
                "1:8: b.task must be one of probe, drill, got \"prob\" (did "
                "you mean \"probe\"?)",
                "3:5: screen.width must be in [320, 8192], got 99",
                "2:5: max_force_n must be in (0, 20], got 0",
                "4:5: max_force_n must be in (0, 20], got 21.5"}));
}

TEST(TomlFields, EchoedTextIsOneLineAndAtMostSixtyBytes) {
  EXPECT_EQ(EchoText("a\nb\x1b"), "a\\x0ab\\x1b");
  EXPECT_EQ(EchoText(std::string(61, 'x')), std::string(60, 'x') + "...");
  // Cut on a UTF-8 boundary: 59 bytes, then a two-byte é across byte 60.
  EXPECT_EQ(EchoText(std::string(59, 'x') + "\xc3\xa9yz"),
            std::string(59, 'x') + "...");
  EXPECT_EQ(JoinKeys(kAllowed), "width, height, fullscreen");
}

}  // namespace
}  // namespace burrlab::stimuli
