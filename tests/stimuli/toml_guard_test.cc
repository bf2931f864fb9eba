// toml_guard: toml++'s syntax errors reworded as one printable line.
#include "burrlab/stimuli/toml_guard.h"

#include <gtest/gtest.h>

#include <string>

namespace burrlab::stimuli {
namespace {

// SyntaxMessage of what toml++ says about `text`.
std::string SyntaxErrorOf(std::string_view text) {
  try {
    const toml::table root = toml::parse(text, std::string_view("t.toml"));
    return root.empty() ? "parsed (empty)" : "parsed";
  } catch (const toml::parse_error& e) {
    return SyntaxMessage(e.description());
  }
  return "parsed";
}

TEST(SyntaxMessage, EscapesTheC1ControlTomlQuotes) {
  // U+0085 (NEL) after a value: toml++ quotes it raw; the message does not.
  EXPECT_EQ(SyntaxErrorOf("a = 1\xc2\x85\n"),
            "invalid TOML in key-value pair: expected a comment or "
            "whitespace, saw '\\u0085'");
}

TEST(SyntaxMessage, DropsTomlsPrefix) {
  EXPECT_EQ(SyntaxMessage("Error while parsing value: bad"),
            "invalid TOML in value: bad");
  EXPECT_EQ(SyntaxMessage("Unexpected end"), "invalid TOML: unexpected end");
  EXPECT_EQ(SyntaxMessage(""), "invalid TOML");
}

}  // namespace
}  // namespace burrlab::stimuli
