// Protocol files that are valid: every example parses, and the fields land
// where the engine reads them; plus the fuzzing of the parser.
#include <gtest/gtest.h>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/base/file_text.h"
#include "burrlab/protocols/protocol.h"
#include "burrlab/sim/model.h"
#include "burrlab/stimuli/materials.h"

namespace burrlab::protocols {
namespace {

namespace fs = std::filesystem;

// The example file's text (an empty text, which fails to parse, when it
// cannot be read).
std::string Read(const fs::path& path) {
  Result<std::string> text = ReadTextFile(path.string());
  EXPECT_TRUE(text.ok()) << text.error().message;
  return text.ok() ? *text : std::string();
}

std::vector<fs::path> Examples() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(fs::path(BURRLAB_SOURCE_DIR) /
                                                  "protocols" / "examples")) {
    if (entry.path().extension() == ".toml") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ProtocolParse, EveryExampleIsValidAndEveryMethodHasOne) {
  std::set<Method> methods;
  std::set<TwoIntervalDesign> designs;
  for (const fs::path& file : Examples()) {
    const std::string text = Read(file);
    const ParseOutcome outcome = ParseProtocol(file.string(), text);
    std::string all;
    for (const Diagnostic& d : outcome.diagnostics) {
      all += FormatDiagnostic(file.string(), text, d);
    }
    ASSERT_TRUE(outcome.protocol.has_value()) << all;
    for (const Block& b : outcome.protocol->blocks) {
      methods.insert(b.method);
      if (b.method == Method::kTwoInterval) designs.insert(b.design);
    }
  }
  EXPECT_EQ(methods.size(), 7u);
  EXPECT_EQ(designs.size(), 2u);
}

// One rule for a parameter of 0 in the three places that take materials: a
// protocol's [materials], a material file and the simulator itself
// (sim::Material::Validate, the truth the two file kinds follow): c_e must
// be > 0; alpha, c_mu, mu and c_i may be 0 (no erosion, no friction, no
// impact damping).
TEST(ProtocolParse, AParameterOfZeroFollowsTheSimulatorsRuleInBothFileKinds) {
  struct Parameter {
    const char* protocol_key;
    const char* material_key;
    const char* unit;
    double sim::Material::*field;
  };
  const Parameter kParameters[] = {
      {"c_e_n_per_mm2", "c_e", "N/mm^2", &sim::Material::c_e_n_per_mm2},
      {"alpha_per_s", "alpha", "1/s", &sim::Material::alpha_per_s},
      {"c_mu_n_per_mm2", "c_mu", "N/mm^2", &sim::Material::c_mu_n_per_mm2},
      {"mu", "mu", "1", &sim::Material::mu},
      {"c_i_n_s_per_mm3", "c_i", "N*s/mm^3", &sim::Material::c_i_n_s_per_mm3},
  };
  for (const Parameter& zero : kParameters) {
    sim::Material material;
    material.*zero.field = 0.0;
    const bool simulator_accepts = material.Validate().ok();
    EXPECT_EQ(simulator_accepts, zero.field != &sim::Material::c_e_n_per_mm2)
        << zero.protocol_key;

    std::string protocol =
        "format = \"burrlab-protocol/1\"\n[study]\nname = \"t\"\n"
        "[materials.m]\n";
    std::string material_file =
        "format = \"burrlab-material/1\"\nname = \"m\"\n"
        "display_name = \"M\"\n";
    for (const Parameter& p : kParameters) {
      const double value = &p == &zero ? 0.0 : 0.5;
      protocol +=
          std::string(p.protocol_key) + " = " + std::to_string(value) + "\n";
      material_file += std::string("[parameters.") + p.material_key +
                       "]\nvalue = " + std::to_string(value) + "\nunit = \"" +
                       p.unit + "\"\nsource = \"test\"\n";
    }
    protocol +=
        "[[blocks]]\nmethod = \"same_different\"\ntask = \"probe\"\n"
        "a = \"m\"\nb = \"bone\"\n[materials.bone]\n"
        "builtin = \"human_temporal_bone\"\n";
    const ParseOutcome parsed = ParseProtocol("zero.toml", protocol);
    EXPECT_EQ(parsed.protocol.has_value(), simulator_accepts)
        << zero.protocol_key << ": "
        << FormatDiagnostics("zero.toml", protocol, parsed.diagnostics);
    const Result<stimuli::MaterialSet> file =
        stimuli::ParseMaterial("m.toml", material_file);
    EXPECT_EQ(file.ok(), simulator_accepts)
        << zero.material_key << ": " << (file.ok() ? "" : file.error().message);
  }
}

TEST(ProtocolParse, DissertationSameDifferentExampleMapsToTheModel) {
  const fs::path file = fs::path(BURRLAB_SOURCE_DIR) /
                        "protocols/examples/same_different_pvc_vs_bone.toml";
  const ParseOutcome outcome = ParseProtocol("x", Read(file));
  ASSERT_TRUE(outcome.protocol.has_value());
  const Protocol& p = *outcome.protocol;
  EXPECT_EQ(p.trace_hz, 100);
  ASSERT_EQ(p.materials.size(), 2u);
  EXPECT_EQ(p.materials[0].id, "pvc");
  EXPECT_EQ(p.materials[0].builtin, "pvc_k70");
  EXPECT_DOUBLE_EQ(p.materials[0].set.material.c_e_n_per_mm2, 0.462);
  EXPECT_DOUBLE_EQ(p.materials[1].set.material.alpha_per_s, 0.087);
  ASSERT_EQ(p.blocks.size(), 2u);
  EXPECT_EQ(p.blocks[0].name, "probe");
  EXPECT_EQ(p.blocks[0].task, Task::kProbe);
  EXPECT_EQ(p.blocks[1].task, Task::kDrill);
  EXPECT_EQ(p.blocks[1].same_different.n_trials, 12);
  EXPECT_EQ(p.blocks[1].interval_s, (std::vector<double>{20.0, 20.0}));
  EXPECT_EQ(p.blocks[0].material_a, "pvc");
  EXPECT_EQ(p.blocks[0].material_b, "bone");
}

// Pacing keys land in the block; feedback defaults to on in a practice block
// whose design has a correct answer, off elsewhere.
TEST(ProtocolParse, PacingKeysLandInTheBlockAndFeedbackFollowsPractice) {
  const ParseOutcome outcome = ParseProtocol("pacing.toml", R"toml(
format = "burrlab-protocol/1"

[study]
name = "t"
instructions = "Feel, then answer."
breaks_between_blocks = true

[materials.pvc]
builtin = "pvc_k70"

[materials.bone]
builtin = "human_temporal_bone"

[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"

[[blocks]]
name = "familiarize"
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = 4
practice = true
isi_s = 1.5
iti_s = 2
response_deadline_s = 8
break_every = 2

[[blocks]]
name = "familiarize_quiet"
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
trials = 4
practice = true
feedback = false

[[blocks]]
name = "scored"
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"

[[blocks]]
name = "scored_told"
method = "same_different"
task = "probe"
a = "pvc"
b = "bone"
feedback = true

[[blocks]]
name = "adjust_practice"
method = "adjustment"
task = "probe"
axis = "ce"
start_level = 1.2
step = 0.05
floor = 0.5
ceiling = 2
practice = true
)toml");
  std::string all;
  for (const Diagnostic& d : outcome.diagnostics) all += d.message + "\n";
  ASSERT_TRUE(outcome.protocol.has_value()) << all;
  const Protocol& p = *outcome.protocol;
  EXPECT_TRUE(p.breaks_between_blocks);
  ASSERT_EQ(p.blocks.size(), 5u);
  const Block& practice = p.blocks[0];
  EXPECT_TRUE(practice.practice);
  EXPECT_TRUE(practice.feedback);
  EXPECT_EQ(practice.isi_s, 1.5);
  EXPECT_EQ(practice.iti_s, 2.0);
  EXPECT_EQ(practice.response_deadline_s, 8.0);
  EXPECT_EQ(practice.break_every, 2);
  EXPECT_TRUE(p.blocks[1].practice);
  EXPECT_FALSE(p.blocks[1].feedback);
  const Block& scored = p.blocks[2];
  EXPECT_FALSE(scored.practice);
  EXPECT_FALSE(scored.feedback);
  EXPECT_EQ(scored.isi_s, 0.0);
  EXPECT_EQ(scored.iti_s, 0.0);
  EXPECT_EQ(scored.response_deadline_s, std::nullopt);
  EXPECT_EQ(scored.break_every, std::nullopt);
  EXPECT_TRUE(p.blocks[3].feedback);
  // An adjustment has no correct answer: practice without feedback.
  EXPECT_TRUE(p.blocks[4].practice);
  EXPECT_FALSE(p.blocks[4].feedback);
}

TEST(ProtocolParse, StaircaseEntriesOverrideBlockDefaults) {
  const fs::path file = fs::path(BURRLAB_SOURCE_DIR) /
                        "protocols/examples/staircase_1up3down.toml";
  const ParseOutcome outcome = ParseProtocol("x", Read(file));
  ASSERT_TRUE(outcome.protocol.has_value());
  const Block& b = outcome.protocol->blocks[0];
  ASSERT_EQ(b.staircases.size(), 2u);
  for (const StaircaseOptions& o : b.staircases) {
    EXPECT_EQ(o.n_down, 3);
    EXPECT_EQ(o.step_scale, StepScale::kLog10);
    EXPECT_EQ(o.max_trials, 60);
    ASSERT_EQ(o.step_schedule.size(), 1u);
    EXPECT_EQ(o.step_schedule[0].after_reversals, 2);
    EXPECT_DOUBLE_EQ(o.step_schedule[0].step_down, 0.1);
  }
  EXPECT_DOUBLE_EQ(b.staircases[0].start_level, 1.0);
  EXPECT_DOUBLE_EQ(b.staircases[1].start_level, 0.1);
  EXPECT_EQ(b.threshold_reversals, 6);
  EXPECT_DOUBLE_EQ(b.standard_level, 0.0);  // increment axis default
}

TEST(ProtocolParse, QuestKeysUseQuestCreateNames) {
  const fs::path file =
      fs::path(BURRLAB_SOURCE_DIR) / "protocols/examples/quest_ce.toml";
  const ParseOutcome outcome = ParseProtocol("x", Read(file));
  ASSERT_TRUE(outcome.protocol.has_value());
  const QuestOptions& q = outcome.protocol->blocks[0].quest;
  EXPECT_DOUBLE_EQ(q.t_guess, -0.52);
  EXPECT_DOUBLE_EQ(q.t_guess_sd, 1.0);
  EXPECT_DOUBLE_EQ(q.p_threshold, 0.82);
  EXPECT_DOUBLE_EQ(q.beta, 3.5);
  EXPECT_EQ(outcome.protocol->blocks[0].quest_trials, 40);
}

TEST(ProtocolParse, RealReferenceIsSubjectPaced) {
  const fs::path file = fs::path(BURRLAB_SOURCE_DIR) /
                        "protocols/examples/reference_pettigrew.toml";
  const ParseOutcome outcome = ParseProtocol("x", Read(file));
  ASSERT_TRUE(outcome.protocol.has_value());
  const Block& b = outcome.protocol->blocks[0];
  EXPECT_EQ(b.design, TwoIntervalDesign::kReference);
  EXPECT_EQ(b.interval_s, (std::vector<double>{0.0, 10.0, 10.0}));
  EXPECT_TRUE(b.reference_material.empty());
  EXPECT_EQ(b.reference.n_trials, 10);
}

TEST(ProtocolParse, OversizedFileIsRefusedUnread) {
  const std::string text(kMaxProtocolBytes + 1, '#');
  const ParseOutcome outcome = ParseProtocol("big.toml", text);
  ASSERT_EQ(outcome.diagnostics.size(), 1u);
  EXPECT_EQ(FormatDiagnostic("big.toml", text, outcome.diagnostics[0]),
            "big.toml: error: the file is 1048577 bytes; protocol files are "
            "limited to 1048576 bytes\n");
}

TEST(ProtocolParse, DeepNestingIsRefusedBeforeParsing) {
  std::string text = "format = \"burrlab-protocol/1\"\na";
  for (int i = 0; i < 100000; ++i) text += ".a";
  text += " = 1\n";
  const ParseOutcome outcome = ParseProtocol("deep.toml", text);
  ASSERT_EQ(outcome.diagnostics.size(), 1u);
  EXPECT_EQ(outcome.diagnostics[0].message,
            "more than 4096 '.' outside strings and comments; nesting this "
            "deep is refused");
}

// Mutates the examples (byte flips, deletions, insertions of TOML-significant
// characters, duplicated lines, truncation): the parser must return a
// protocol or at least one diagnostic, never crash, and every diagnostic
// must format.
TEST(ProtocolFuzz, MutatedExamplesNeverCrashTheParser) {
  boost::random::mt19937 rng(20261122);
  constexpr std::string_view kAlphabet = "[]=\"\n#.,{}0123456789-+ aeq'\t";
  int mutated = 0;
  int accepted = 0;
  for (const fs::path& file : Examples()) {
    const std::string original = Read(file);
    for (int round = 0; round < 500; ++round) {
      std::string text = original;
      boost::random::uniform_int_distribution<int> kind(0, 4);
      boost::random::uniform_int_distribution<int> count(1, 4);
      for (int m = count(rng); m > 0 && !text.empty(); --m) {
        boost::random::uniform_int_distribution<std::size_t> at(
            0, text.size() - 1);
        boost::random::uniform_int_distribution<std::size_t> pick(
            0, kAlphabet.size() - 1);
        const std::size_t i = at(rng);
        switch (kind(rng)) {
          case 0:
            text[i] = static_cast<char>(text[i] ^ (1 << (i % 8)));
            break;
          case 1:
            text.erase(i, std::min<std::size_t>(text.size() - i, 1 + i % 7));
            break;
          case 2:
            text.insert(i, 1, kAlphabet[pick(rng)]);
            break;
          case 3: {
            const std::size_t start = text.rfind('\n', i);
            const std::size_t s = start == std::string::npos ? 0 : start + 1;
            const std::size_t e = text.find('\n', i);
            text.insert(
                s, text.substr(
                       s, (e == std::string::npos ? text.size() : e + 1) - s));
            break;
          }
          default:
            text.resize(i);
        }
      }
      const ParseOutcome outcome = ParseProtocol("fuzz.toml", text);
      ++mutated;
      if (outcome.protocol.has_value()) {
        ++accepted;
        EXPECT_TRUE(outcome.diagnostics.empty());
        EXPECT_FALSE(outcome.protocol->blocks.empty());
      } else {
        ASSERT_FALSE(outcome.diagnostics.empty()) << text;
      }
      for (const Diagnostic& d : outcome.diagnostics) {
        const std::string formatted = FormatDiagnostic("fuzz.toml", text, d);
        EXPECT_TRUE(formatted.starts_with("fuzz.toml:"));
        EXPECT_EQ(formatted.back(), '\n');
      }
    }
  }
  EXPECT_GE(mutated, 3000);
  EXPECT_GT(accepted, 0);  // some mutations land in comments or values
  EXPECT_LT(accepted, mutated);
}

}  // namespace
}  // namespace burrlab::protocols
