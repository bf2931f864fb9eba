// ParseMaterial on hostile input: thousands of random byte strings, TOML-ish
// token soups and mutations (bit flips, truncations, line deletions,
// duplications and swaps, insertions) of the built-in files, from a fixed
// seed. Every call must return, an accepted file must hold a valid material,
// and every failure must be one non-empty line naming the file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/stimuli/materials.h"

namespace burrlab::stimuli {
namespace {

std::vector<std::string> SeedFiles() {
  const std::filesystem::path dir =
      std::filesystem::path(BURRLAB_SOURCE_DIR) / "stimuli" / "materials";
  std::vector<std::string> files;
  for (const std::string& name : BuiltinMaterialNames()) {
    std::ifstream in(dir / (name + ".toml"), std::ios::binary);
    files.emplace_back(std::istreambuf_iterator<char>(in),
                       std::istreambuf_iterator<char>());
  }
  files.push_back(
      "format = \"burrlab-material/1\"\nname = \"m\"\ndisplay_name = \"M\"\n"
      "[parameters]\n"
      "c_e = { value = 1, unit = \"N/mm^2\", source = \"a\" }\n"
      "alpha = { value = 0.1, unit = \"1/s\", source = \"b\" }\n"
      "c_mu = { value = 0.2, unit = \"N/mm^2\", source = \"c\" }\n"
      "mu = { value = 0.5, unit = \"1\", source = \"d\" }\n"
      "c_i = { value = 0.0, unit = \"N*s/mm^3\", source = \"e\" }\n");
  return files;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) {
      lines.push_back(text.substr(start));
      break;
    }
    lines.push_back(text.substr(start, end - start + 1));
    start = end + 1;
  }
  return lines;
}

std::string Join(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line;
  return text;
}

class Mutator {
 public:
  explicit Mutator(unsigned seed) : rng_(seed) {}

  std::size_t Below(std::size_t n) {
    return n == 0 ? 0
                  : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_);
  }

  std::string RandomBytes(std::size_t max_length) {
    std::string bytes(Below(max_length + 1), '\0');
    for (char& c : bytes) c = static_cast<char>(Below(256));
    return bytes;
  }

  // Fragments that a TOML lexer and the schema care about.
  std::string TokenSoup(std::size_t tokens) {
    static constexpr std::string_view kTokens[] = {"[",
                                                   "]",
                                                   "[[",
                                                   "]]",
                                                   "{",
                                                   "}",
                                                   "=",
                                                   ".",
                                                   ",",
                                                   "\"",
                                                   "'",
                                                   "\"\"\"",
                                                   "'''",
                                                   "#",
                                                   "\n",
                                                   " ",
                                                   "\\",
                                                   "\r\n",
                                                   "value",
                                                   "unit",
                                                   "source",
                                                   "c_e",
                                                   "alpha",
                                                   "mu",
                                                   "c_i",
                                                   "c_mu",
                                                   "parameters",
                                                   "format",
                                                   "name",
                                                   "nan",
                                                   "inf",
                                                   "-1",
                                                   "1e999",
                                                   "0x1f",
                                                   "2.145",
                                                   "true",
                                                   "1979-05-27T07:32:00Z",
                                                   "\"burrlab-material/1\"",
                                                   "\"N/mm^2\"",
                                                   "\xc3\xa9",
                                                   "\xff",
                                                   std::string_view("\0", 1)};
    std::string text;
    for (std::size_t i = 0; i < tokens; ++i) {
      text += kTokens[Below(std::size(kTokens))];
    }
    return text;
  }

  std::string Mutate(std::string text) {
    switch (Below(7)) {
      case 0: {  // bit flips
        const std::size_t flips = 1 + Below(8);
        for (std::size_t i = 0; i < flips && !text.empty(); ++i) {
          text[Below(text.size())] ^= static_cast<char>(1u << Below(8));
        }
        return text;
      }
      case 1:  // truncation
        text.resize(Below(text.size() + 1));
        return text;
      case 2: {  // line deletions
        std::vector<std::string> lines = Lines(text);
        const std::size_t deletions = 1 + Below(3);
        for (std::size_t i = 0; i < deletions && !lines.empty(); ++i) {
          lines.erase(lines.begin() +
                      static_cast<std::ptrdiff_t>(Below(lines.size())));
        }
        return Join(lines);
      }
      case 3: {  // line duplication
        std::vector<std::string> lines = Lines(text);
        const std::size_t from = Below(lines.size());
        const std::string line = lines[from];
        lines.insert(lines.begin() +
                         static_cast<std::ptrdiff_t>(Below(lines.size() + 1)),
                     line);
        return Join(lines);
      }
      case 4: {  // line swap
        std::vector<std::string> lines = Lines(text);
        std::swap(lines[Below(lines.size())], lines[Below(lines.size())]);
        return Join(lines);
      }
      case 5:  // insertion of tokens
        return text.insert(Below(text.size() + 1), TokenSoup(1 + Below(4)));
      default:  // insertion of bytes
        return text.insert(Below(text.size() + 1), RandomBytes(8));
    }
  }

 private:
  std::mt19937 rng_;
};

TEST(ParseMaterialFuzz, HostileInputGivesOneLineErrorsOrValidMaterials) {
  const std::vector<std::string> seeds = SeedFiles();
  ASSERT_EQ(seeds.size(), 4u);
  Mutator mutator(20240611u);
  int accepted = 0;
  int rejected = 0;
  constexpr int kCases = 6000;
  for (int i = 0; i < kCases; ++i) {
    std::string text;
    switch (i % 8) {
      case 0:
        text = mutator.RandomBytes(512);
        break;
      case 1:
        text = mutator.TokenSoup(mutator.Below(200));
        break;
      default: {
        text = seeds[mutator.Below(seeds.size())];
        const std::size_t rounds = 1 + mutator.Below(i % 8 == 7 ? 4 : 1);
        for (std::size_t r = 0; r < rounds; ++r) text = mutator.Mutate(text);
      }
    }
    Result<MaterialSet> set = ParseMaterial("fuzz.toml", text);
    if (set.ok()) {
      ++accepted;
      EXPECT_TRUE(set->material.Validate().ok()) << "case " << i;
      EXPECT_FALSE(set->name.empty()) << "case " << i;
      EXPECT_FALSE(set->display_name.empty()) << "case " << i;
    } else {
      ++rejected;
      const std::string& message = set.error().message;
      EXPECT_TRUE(message.starts_with("fuzz.toml:")) << message;
      EXPECT_GT(message.size(),
                std::string_view("fuzz.toml:1:1: error: ").size())
          << "case " << i;
      EXPECT_EQ(message.find_first_of("\n\r"), std::string::npos)
          << "case " << i << ": " << message;
    }
  }
  // Both outcomes must be exercised, or the mutations test nothing.
  EXPECT_GT(accepted, 100);
  EXPECT_GT(rejected, 1000);
}

}  // namespace
}  // namespace burrlab::stimuli
