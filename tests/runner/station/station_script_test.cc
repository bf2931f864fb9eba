// Station scripts: what a scripted subject does, read from (path, text) with
// every problem reported at its place.
#include "station/station_script.h"

#include <gtest/gtest.h>

#include <string>

namespace burrlab::runner {
namespace {

std::string ScriptProblems(const std::string& text) {
  const StationScriptParseOutcome o = ParseStationScript("script.toml", text);
  EXPECT_FALSE(o.script.has_value());
  std::string all;
  for (const protocols::Diagnostic& d : o.diagnostics) {
    all += protocols::FormatDiagnostic("script.toml", text, d);
  }
  return all;
}

TEST(ParseStationScript, ReadsPathAnswersDelaysAndUnplugs) {
  const StationScriptParseOutcome o = ParseStationScript("script.toml", R"(
format = "burrlab-station-script/1"
path = [[0.0, 0.0, 0.0, 3.0], [0.25, 1, -2, 0.5]]
answers = ["1", "same"]
start_delay_s = 0.2
response_delay_s = 0.5
[[unplug]]
presentation = 2
interval = 1
after_s = 0.1
resume = true
)");
  ASSERT_TRUE(o.script.has_value());
  const StationScript& s = *o.script;
  ASSERT_EQ(s.path.size(), 2u);
  EXPECT_DOUBLE_EQ(s.path[1].t_s, 0.25);
  EXPECT_EQ(s.path[1].position_mm, glm::dvec3(1.0, -2.0, 0.5));
  EXPECT_EQ(s.answers, (std::vector<std::string>{"1", "same"}));
  EXPECT_DOUBLE_EQ(s.start_delay_s, 0.2);
  EXPECT_DOUBLE_EQ(s.response_delay_s, 0.5);
  ASSERT_EQ(s.unplugs.size(), 1u);
  EXPECT_EQ(s.unplugs[0].presentation, 2);
  EXPECT_EQ(s.unplugs[0].interval, 1);
  EXPECT_DOUBLE_EQ(s.unplugs[0].after_s, 0.1);
  EXPECT_TRUE(s.unplugs[0].resume);
}

TEST(ParseStationScript, DefaultsToNoAnswersAndShortDelays) {
  const StationScriptParseOutcome o = ParseStationScript(
      "script.toml",
      "format = \"burrlab-station-script/1\"\npath = [[0, 0, 0, 3]]\n");
  ASSERT_TRUE(o.script.has_value());
  EXPECT_TRUE(o.script->answers.empty());
  EXPECT_DOUBLE_EQ(o.script->start_delay_s, 0.05);
  EXPECT_DOUBLE_EQ(o.script->response_delay_s, 0.1);
  EXPECT_DOUBLE_EQ(o.script->continue_delay_s, 0.05);
  EXPECT_EQ(o.script->end_feedback_after_s, std::nullopt);
  EXPECT_TRUE(o.script->unplugs.empty());
}

// A scripted subject goes on from instructions and rest breaks after
// continue_delay_s and, when end_feedback_after_s is given, ends feedback
// early with a key.
TEST(ParseStationScript, ReadsHowQuicklyItGoesOnFromInstructionsAndFeedback) {
  const StationScriptParseOutcome o = ParseStationScript("script.toml", R"(
format = "burrlab-station-script/1"
path = [[0, 0, 0, 3]]
continue_delay_s = 0.4
end_feedback_after_s = 0.25
)");
  ASSERT_TRUE(o.script.has_value());
  EXPECT_DOUBLE_EQ(o.script->continue_delay_s, 0.4);
  EXPECT_EQ(o.script->end_feedback_after_s, 0.25);
  EXPECT_EQ(ScriptProblems("format = \"burrlab-station-script/1\"\n"
                           "path = [[0, 0, 0, 1]]\ncontinue_delay_s = -1\n"
                           "end_feedback_after_s = \"soon\"\n"),
            "script.toml:3:20: error: continue_delay_s must be in [0, 60], "
            "got -1\n"
            "continue_delay_s = -1\n"
            "                   ^\n"
            "script.toml:4:24: error: end_feedback_after_s must be a number, "
            "got a string\n"
            "end_feedback_after_s = \"soon\"\n"
            "                       ^\n");
}

TEST(ParseStationScript, NamesEachProblemWithItsPlace) {
  EXPECT_EQ(ScriptProblems("format = \"burrlab-station-script/1\"\n"),
            "script.toml:1:1: error: missing key 'path' (the burr's "
            "waypoints in every interval, e.g. path = [[0.0, 0.0, 0.0, 3.0], "
            "[0.5, 0.0, 0.0, 1.0]])\n"
            "format = \"burrlab-station-script/1\"\n"
            "^\n");
  EXPECT_EQ(ScriptProblems("format = \"burrlab-station-script/1\"\n"
                           "path = [[0, 0, 0]]\n"),
            "script.toml:2:9: error: path[0] must be [t_s, x_mm, y_mm, "
            "z_mm]\n"
            "path = [[0, 0, 0]]\n"
            "        ^\n");
  EXPECT_EQ(ScriptProblems("format = \"burrlab-station-script/1\"\n"
                           "path = [[0, 0, 0, nan]]\n"),
            "script.toml:2:19: error: path[0] z_mm must be a number of mm "
            "from -1000 to 1000\n"
            "path = [[0, 0, 0, nan]]\n"
            "                  ^\n");
  EXPECT_EQ(ScriptProblems("format = \"burrlab-station-script/1\"\n"
                           "path = [[0, 0, 0, 1]]\nanswers = [\"\"]\n"),
            "script.toml:3:12: error: answers[0] must be a key or answer of "
            "1 to 64 characters\n"
            "answers = [\"\"]\n"
            "           ^\n");
  EXPECT_EQ(ScriptProblems("format = \"burrlab-station-script/1\"\n"
                           "path = [[0, 0, 0, 1]]\n[[unplug]]\ninterval = 0\n"
                           "speed = 1\n"),
            "script.toml:5:1: error: unknown key \"speed\" in [[unplug]]; "
            "accepted: presentation, interval, after_s, resume\n"
            "speed = 1\n"
            "^\n"
            "script.toml:3:1: error: [[unplug]] needs presentation\n"
            "[[unplug]]\n"
            "^\n"
            "script.toml:4:12: error: interval must be in [1, 1000000], got "
            "0\n"
            "interval = 0\n"
            "           ^\n");
  EXPECT_EQ(ScriptProblems(
                "format = \"burrlab-protocol/1\"\npath = [[0, 0, 0, 1]]\n"),
            "script.toml:1:10: error: format must be "
            "\"burrlab-station-script/1\"\n"
            "format = \"burrlab-protocol/1\"\n"
            "         ^\n");
}

TEST(ParseStationScript, EscapesControlCharactersOfKeysInMessages) {
  const StationScriptParseOutcome o = ParseStationScript(
      "script.toml",
      "format = \"burrlab-station-script/1\"\npath = [[0.0, 0, 0, 1]]\n"
      "\" \\t f\\t\" = \"p\"\n");
  ASSERT_EQ(o.diagnostics.size(), 1u);
  EXPECT_EQ(o.diagnostics[0].message,
            "unknown key \" \\x09 f\\x09\" in the station script; accepted: "
            "format, path, answers, start_delay_s, response_delay_s, "
            "continue_delay_s, end_feedback_after_s, unplug");
}

}  // namespace
}  // namespace burrlab::runner
