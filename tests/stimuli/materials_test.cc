// Material files: the built-in sets carry the dissertation's §8.7 numbers, and
// every malformed file gets one exact "path:line:col: error: ..." line.
#include "burrlab/stimuli/materials.h"

#include <gtest/gtest.h>
#include <stdlib.h>  // mkdtemp

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/sim/moments.h"
#include "burrlab/sim/octree.h"
#include "burrlab/sim/step.h"
#include "burrlab/sim/volume.h"

namespace burrlab::stimuli {
namespace {

// A valid file; tests replace parts of it. Line numbers matter to the
// expected messages.
constexpr std::string_view kValid = R"(format = "burrlab-material/1"
name = "test_material"
display_name = "Test material"

[parameters.c_e_n_per_mm2]
value = 2.145
unit = "N/mm^2"
source = "elastic source"

[parameters.alpha_per_s]
value = 0.087
unit = "1/s"
source = "erosion source"

[parameters.c_mu_n_per_mm2]
value = 0.5
unit = "N/mm^2"
source = "cheap friction source"

[parameters.mu]
value = 0.5
unit = "1"
source = "friction source"

[parameters.c_i_n_s_per_mm3]
value = 0
unit = "N*s/mm^3"
source = "impact source"
)";

// kValid with the first `from` replaced by `to`.
std::string Edit(std::string_view from, std::string_view to,
                 std::string text = std::string(kValid)) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The error message of parsing `text` as "x.toml", or "<ok>".
std::string ParseError(std::string_view text) {
  Result<MaterialSet> set = ParseMaterial("x.toml", text);
  return set.ok() ? "<ok>" : set.error().message;
}

void WriteFile(const std::filesystem::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
}

// A fresh directory under the test temp dir, removed at the end.
class TempDir {
 public:
  TempDir() {
    std::string pattern = ::testing::TempDir() + "burrlab_materials_XXXXXX";
    path_ = mkdtemp(pattern.data()) != nullptr ? pattern : "";
    EXPECT_FALSE(path_.empty());
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  std::filesystem::path operator/(std::string_view name) const {
    return path_ / name;
  }

 private:
  std::filesystem::path path_;
};

const std::filesystem::path kMaterialsDir =
    std::filesystem::path(BURRLAB_SOURCE_DIR) / "stimuli" / "materials";

// --- Built-in materials --------------------------------------------------

TEST(BuiltinMaterials, HumanTemporalBoneHasTheFittedValuesOfSection87) {
  Result<MaterialSet> set = LoadBuiltinMaterial("human_temporal_bone");
  ASSERT_TRUE(set.ok()) << set.error().message;
  EXPECT_EQ(set->name, "human_temporal_bone");
  EXPECT_EQ(set->display_name, "Human temporal bone");
  EXPECT_EQ(set->description.rfind(
                "Human temporal (petrous) bone, fitted in §8.7", 0),
            0u);
  EXPECT_EQ(set->material.c_e_n_per_mm2, 2.145);
  EXPECT_EQ(set->material.alpha_per_s, 0.087);
  EXPECT_EQ(set->material.mu, 0.5);
  EXPECT_EQ(set->material.c_mu_n_per_mm2, 0.6420);
  EXPECT_DOUBLE_EQ(set->material.c_i_n_s_per_mm3, 0.005 * 2.145);
}

TEST(BuiltinMaterials, PettigrewTemporalBoneHasTheFittedValuesOfSection87) {
  Result<MaterialSet> set = LoadBuiltinMaterial("pettigrew_temporal_bone");
  ASSERT_TRUE(set.ok()) << set.error().message;
  EXPECT_EQ(set->name, "pettigrew_temporal_bone");
  EXPECT_EQ(set->display_name, "Pettigrew plastic temporal bone");
  EXPECT_EQ(set->material.c_e_n_per_mm2, 1.504);
  EXPECT_EQ(set->material.alpha_per_s, 0.116);
  EXPECT_EQ(set->material.mu, 0.5);
  EXPECT_EQ(set->material.c_mu_n_per_mm2, 0.4502);
  EXPECT_DOUBLE_EQ(set->material.c_i_n_s_per_mm3, 0.005 * 1.504);
}

TEST(BuiltinMaterials, PvcK70HasTheFittedValuesOfSection87) {
  Result<MaterialSet> set = LoadBuiltinMaterial("pvc_k70");
  ASSERT_TRUE(set.ok()) << set.error().message;
  EXPECT_EQ(set->name, "pvc_k70");
  EXPECT_EQ(set->display_name, "PVC K70 resin");
  EXPECT_EQ(set->material.c_e_n_per_mm2, 0.462);
  EXPECT_EQ(set->material.alpha_per_s, 0.296);
  EXPECT_EQ(set->material.mu, 0.5);
  EXPECT_EQ(set->material.c_mu_n_per_mm2, 0.1383);
  EXPECT_DOUBLE_EQ(set->material.c_i_n_s_per_mm3, 0.005 * 0.462);
}

TEST(BuiltinMaterials, ChosenFrictionMatchesMuTimesElasticForceAtQuarterDepth) {
  // Through the simulator: a burr at h = R/4 in a half-space, spinning about an
  // axis along the surface; the cheap friction of eq. 7.13 is mu |F_e| within
  // the voxelisation error, and eq. 7.14's impact force at 10 mm/s is 10 % of
  // the elastic force.
  const double radius = 3.0, v = 0.3;
  sim::Volume volume = sim::Volume::Create(40, 40, 40, v).value();
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) volume.Set(i, j, k, 255);
  const sim::MomentOctree tree = sim::MomentOctree::Build(volume);
  for (const std::string& name : BuiltinMaterialNames()) {
    Result<MaterialSet> set = LoadBuiltinMaterial(name);
    ASSERT_TRUE(set.ok()) << set.error().message;
    sim::Model model;
    model.material = set->material;
    model.radius_mm = radius;
    sim::Input input;
    input.position_mm = glm::dvec3(6.01, 5.98, 6.0 + radius - 0.25 * radius);
    input.spindle_rad_s = glm::dvec3(2000.0, 0.0, 0.0);
    input.velocity_mm_s = glm::dvec3(0.0, 10.0, 0.0);
    const sim::Output out = sim::EvaluateForce(model, volume, tree, input);
    const double elastic = glm::length(out.elastic_n);
    EXPECT_NEAR(glm::length(out.friction_n) / (set->material.mu * elastic), 1.0,
                0.03)
        << name;
    EXPECT_NEAR(glm::length(out.impact_n) / (0.1 * elastic), 1.0, 0.03) << name;
  }
}

TEST(BuiltinMaterials, SourcesGiveUnitsAndSayWhatIsChosen) {
  for (const std::string& name : BuiltinMaterialNames()) {
    Result<MaterialSet> set = LoadBuiltinMaterial(name);
    ASSERT_TRUE(set.ok()) << set.error().message;
    EXPECT_NE(set->source.find("c_e: Dissertation §8.7"), std::string::npos)
        << set->source;
    EXPECT_NE(set->source.find("burrlab reads it as N/mm^2"),
              std::string::npos);
    EXPECT_NE(set->source.find("burrlab reads it as 1/s"), std::string::npos);
    EXPECT_NE(set->source.find("c_mu: Chosen, not measured"),
              std::string::npos);
    EXPECT_NE(set->source.find("mu: Chosen, not measured"), std::string::npos);
    EXPECT_NE(set->source.find("c_i: Chosen, not measured"), std::string::npos);
    EXPECT_EQ(set->source.find('\n'), std::string::npos);
  }
}

TEST(BuiltinMaterials, NamesAreSorted) {
  EXPECT_EQ(BuiltinMaterialNames(),
            (std::vector<std::string>{"human_temporal_bone",
                                      "pettigrew_temporal_bone", "pvc_k70"}));
}

TEST(BuiltinMaterials, EmbeddedSetsEqualTheFilesInStimuliMaterials) {
  std::vector<std::string> stems;
  for (const auto& entry : std::filesystem::directory_iterator(kMaterialsDir)) {
    if (entry.path().extension() == ".toml") {
      stems.push_back(entry.path().stem().string());
    }
  }
  std::sort(stems.begin(), stems.end());
  EXPECT_EQ(stems, BuiltinMaterialNames());
  for (const std::string& name : stems) {
    Result<MaterialSet> embedded = LoadBuiltinMaterial(name);
    Result<MaterialSet> file =
        LoadMaterialFile((kMaterialsDir / (name + ".toml")).string());
    ASSERT_TRUE(embedded.ok()) << embedded.error().message;
    ASSERT_TRUE(file.ok()) << file.error().message;
    EXPECT_EQ(file->name, name);  // the name equals the file stem
    EXPECT_EQ(embedded->display_name, file->display_name);
    EXPECT_EQ(embedded->source, file->source);
    EXPECT_EQ(embedded->material.c_e_n_per_mm2, file->material.c_e_n_per_mm2);
    EXPECT_EQ(embedded->material.alpha_per_s, file->material.alpha_per_s);
    EXPECT_EQ(embedded->material.c_mu_n_per_mm2, file->material.c_mu_n_per_mm2);
    EXPECT_EQ(embedded->material.mu, file->material.mu);
    EXPECT_EQ(embedded->material.c_i_n_s_per_mm3,
              file->material.c_i_n_s_per_mm3);
  }
}

TEST(BuiltinMaterials, UnknownNameListsTheKnownOnesAndSuggestsTheClosest) {
  EXPECT_EQ(LoadBuiltinMaterial("pvc").error().message,
            "unknown material 'pvc': known materials are human_temporal_bone, "
            "pettigrew_temporal_bone, pvc_k70 (did you mean 'pvc_k70'?)");
  EXPECT_EQ(LoadBuiltinMaterial("human_temporal_bon").error().message,
            "unknown material 'human_temporal_bon': known materials are "
            "human_temporal_bone, pettigrew_temporal_bone, pvc_k70 (did you "
            "mean 'human_temporal_bone'?)");
  EXPECT_EQ(LoadBuiltinMaterial("granite").error().message,
            "unknown material 'granite': known materials are "
            "human_temporal_bone, pettigrew_temporal_bone, pvc_k70");
  EXPECT_EQ(LoadBuiltinMaterial("").error().message,
            "unknown material '': known materials are human_temporal_bone, "
            "pettigrew_temporal_bone, pvc_k70");
}

TEST(BuiltinMaterials, UnknownNameErrorIsOneLine) {
  EXPECT_EQ(LoadBuiltinMaterial("a\nb").error().message,
            "unknown material 'a\\x0ab': known materials are "
            "human_temporal_bone, pettigrew_temporal_bone, pvc_k70");
}

// --- ParseMaterial: valid files -------------------------------------------

TEST(ParseMaterial, ReadsEveryField) {
  Result<MaterialSet> set = ParseMaterial("x.toml", kValid);
  ASSERT_TRUE(set.ok()) << set.error().message;
  EXPECT_EQ(set->name, "test_material");
  EXPECT_EQ(set->display_name, "Test material");
  EXPECT_EQ(set->source,
            "c_e: elastic source; alpha: erosion source; c_mu: cheap friction "
            "source; mu: friction source; c_i: impact source");
  EXPECT_EQ(set->material.c_e_n_per_mm2, 2.145);
  EXPECT_EQ(set->material.alpha_per_s, 0.087);
  EXPECT_EQ(set->material.c_mu_n_per_mm2, 0.5);
  EXPECT_EQ(set->material.mu, 0.5);
  EXPECT_EQ(set->material.c_i_n_s_per_mm3, 0.0);
}

TEST(ParseMaterial, AcceptsIntegersInlineTablesAndADescription) {
  const std::string text = R"(format = "burrlab-material/1"
name = "inline_7"
display_name = "Inline"
description = "Any text."
[parameters]
c_e = { value = 3, unit = "N/mm^2", source = "a" }
alpha = { value = 1e-1, unit = "1/s", source = "b" }
c_mu = { value = 0, unit = "N/mm^2", source = "c" }
mu = { value = 1, unit = "1", source = "d" }
c_i = { value = 0.25, unit = "N*s/mm^3", source = "e" }
)";
  Result<MaterialSet> set = ParseMaterial("x.toml", text);
  ASSERT_TRUE(set.ok()) << set.error().message;
  EXPECT_EQ(set->material.c_e_n_per_mm2, 3.0);
  EXPECT_EQ(set->material.alpha_per_s, 0.1);
  EXPECT_EQ(set->material.mu, 1.0);
  EXPECT_EQ(set->material.c_i_n_s_per_mm3, 0.25);
}

TEST(ParseMaterial, NegativeZeroReadsAsZero) {
  Result<MaterialSet> set =
      ParseMaterial("x.toml", Edit("value = 0\n", "value = -0.0\n"));
  ASSERT_TRUE(set.ok()) << set.error().message;
  EXPECT_FALSE(std::signbit(set->material.c_i_n_s_per_mm3));
}

TEST(ParseMaterial, DotsInStringsAndCommentsDoNotCountAsNesting) {
  const std::string dots(5000, '.');
  Result<MaterialSet> set = ParseMaterial(
      "x.toml", "# " + dots + "\n" +
                    Edit("display_name = \"Test material\"",
                         "display_name = \"Test material\"\ndescription = \"" +
                             dots + "\"\nname_note_ = '''" + dots + "'''"));
  ASSERT_FALSE(set.ok());  // name_note_ is unknown: the dots passed the guard
  EXPECT_EQ(set.error().message,
            "x.toml:6:1: error: unknown key \"name_note_\" in the material "
            "file; accepted: format, name, display_name, description, "
            "parameters");
}

// --- ParseMaterial: malformed files, one exact message each -------------

TEST(ParseMaterial, MissingParameterIsReportedAtTheParametersTable) {
  EXPECT_EQ(ParseError(Edit("[parameters.alpha_per_s]\nvalue = 0.087\nunit = "
                            "\"1/s\"\nsource = \"erosion source\"\n",
                            "")),
            "x.toml:5:1: error: missing key 'parameters.alpha_per_s'");
}

TEST(ParseMaterial, MissingValueIsReportedAtItsTable) {
  EXPECT_EQ(ParseError(Edit("value = 0.087\n", "")),
            "x.toml:10:1: error: missing key 'parameters.alpha_per_s.value'");
}

TEST(ParseMaterial, TheUnitIsOptionalSinceTheKeySpellsIt) {
  Result<MaterialSet> set =
      ParseMaterial("x.toml", Edit("unit = \"N*s/mm^3\"\n", ""));
  ASSERT_TRUE(set.ok()) << set.error().message;
  EXPECT_EQ(set->material.c_i_n_s_per_mm3, 0.0);
  EXPECT_TRUE(set->notes.empty());
}

// Material files spelled the parameters without units (c_e, alpha, c_mu,
// c_i) until both file kinds took the protocol files' spelling; such a file
// still reads, to the same numbers, with one note per old key.
TEST(ParseMaterial, TheOldSpellingReadsWithANotePerKey) {
  std::string old = Edit("[parameters.c_e_n_per_mm2]", "[parameters.c_e]");
  old = Edit("[parameters.c_i_n_s_per_mm3]", "[parameters.c_i]", old);
  Result<MaterialSet> set = ParseMaterial("x.toml", old);
  ASSERT_TRUE(set.ok()) << set.error().message;
  Result<MaterialSet> now = ParseMaterial("x.toml", kValid);
  ASSERT_TRUE(now.ok()) << now.error().message;
  EXPECT_EQ(set->material.c_e_n_per_mm2, now->material.c_e_n_per_mm2);
  EXPECT_EQ(set->material.c_i_n_s_per_mm3, now->material.c_i_n_s_per_mm3);
  EXPECT_EQ(set->source, now->source);
  EXPECT_TRUE(now->notes.empty());
  EXPECT_EQ(set->notes,
            (std::vector<std::string>{
                "x.toml:5:1: note: [parameters.c_e] is the old spelling of "
                "[parameters.c_e_n_per_mm2] (read in N/mm^2); rename it, a "
                "later format will refuse the old spelling",
                "x.toml:25:1: note: [parameters.c_i] is the old spelling of "
                "[parameters.c_i_n_s_per_mm3] (read in N*s/mm^3); rename it, a "
                "later format will refuse the old spelling"}));
  // The old key's own fields are named with the old key.
  EXPECT_EQ(ParseError(Edit("value = 2.145", "value = -1", old)),
            "x.toml:6:9: error: parameters.c_e.value must be positive, got -1");
}

TEST(ParseMaterial, BothSpellingsOfOneParameterAreRefused) {
  EXPECT_EQ(ParseError(std::string(kValid) +
                       "\n[parameters.alpha]\nvalue = 1\nsource = \"s\"\n"),
            "x.toml:30:1: error: [parameters.alpha] and "
            "[parameters.alpha_per_s] are the same parameter; keep "
            "[parameters.alpha_per_s]");
}

TEST(BuiltinMaterials, UseTheCurrentSpelling) {
  for (const std::string& name : BuiltinMaterialNames()) {
    Result<MaterialSet> set = LoadBuiltinMaterial(name);
    ASSERT_TRUE(set.ok()) << set.error().message;
    EXPECT_TRUE(set->notes.empty()) << name << ": " << set->notes.front();
  }
}

TEST(ParseMaterial, MissingFormatSaysHowFilesStart) {
  EXPECT_EQ(ParseError(Edit("format = \"burrlab-material/1\"\n", "")),
            "x.toml:1:1: error: missing key 'format' (material files start "
            "with format = \"burrlab-material/1\")");
  EXPECT_EQ(ParseError(""),
            "x.toml:1:1: error: missing key 'format' (material files start "
            "with format = \"burrlab-material/1\")");
}

TEST(ParseMaterial, MissingParametersTable) {
  EXPECT_EQ(ParseError("format = \"burrlab-material/1\"\nname = \"a\"\n"
                       "display_name = \"A\"\n"),
            "x.toml:1:1: error: missing key 'parameters'");
}

TEST(ParseMaterial, StringValueIsNotANumber) {
  EXPECT_EQ(ParseError(Edit("value = 2.145", "value = \"2.145\"")),
            "x.toml:6:9: error: parameters.c_e_n_per_mm2.value must be a "
            "number, got a string");
}

TEST(ParseMaterial, BooleanValueIsNotANumber) {
  EXPECT_EQ(ParseError(Edit("value = 0.5\nunit = \"1\"",
                            "value = true\nunit = \"1\"")),
            "x.toml:21:9: error: parameters.mu.value must be a number, got "
            "a boolean");
}

TEST(ParseMaterial, ParameterGivenAsABareNumberMustBeATable) {
  EXPECT_EQ(ParseError("format = \"burrlab-material/1\"\nname = \"a\"\n"
                       "display_name = \"A\"\n[parameters]\n"
                       "c_e_n_per_mm2 = 2.145\n"),
            "x.toml:5:17: error: parameters.c_e_n_per_mm2 must be a table "
            "with value and source, got a number");
}

TEST(ParseMaterial, WrongUnitNamesTheExpectedOne) {
  EXPECT_EQ(
      ParseError(Edit("unit = \"N/mm^2\"", "unit = \"N/m^2\"")),
      "x.toml:7:8: error: parameters.c_e_n_per_mm2.unit must be 'N/mm^2', got "
      "'N/m^2'");
  EXPECT_EQ(ParseError(Edit("unit = \"N/mm^2\"",
                            "unit = \"" + std::string(100, 'x') + "\"")),
            "x.toml:7:8: error: parameters.c_e_n_per_mm2.unit must be "
            "'N/mm^2', got '" +
                std::string(60, 'x') + "...'");
  EXPECT_EQ(ParseError(Edit("unit = \"1/s\"", "unit = 1")),
            "x.toml:12:8: error: parameters.alpha_per_s.unit must be a "
            "string, got an integer");
}

TEST(ParseMaterial, UnknownParameterSuggestsTheClosestKey) {
  EXPECT_EQ(ParseError(Edit("[parameters.alpha_per_s]", "[parameters.alpah]")),
            "x.toml:10:1: error: unknown key \"alpah\" in [parameters] (did "
            "you mean \"alpha_per_s\"?)");
}

TEST(ParseMaterial, UnknownKeysAreNamedWithTheirPath) {
  EXPECT_EQ(ParseError(Edit("unit = \"1/s\"", "units = \"1/s\"")),
            "x.toml:12:1: error: unknown key \"units\" in "
            "[parameters.alpha_per_s] (did you mean \"unit\"?)");
  EXPECT_EQ(ParseError(Edit("display_name", "colour = \"red\"\ndisplay_name")),
            "x.toml:3:1: error: unknown key \"colour\" in the material file; "
            "accepted: format, name, display_name, description, parameters");
  EXPECT_EQ(
      ParseError(Edit("display_name", "descripton = \"x\"\ndisplay_name")),
      "x.toml:3:1: error: unknown key \"descripton\" in the material file "
      "(did you mean \"description\"?)");
}

TEST(ParseMaterial, TheFirstUnknownKeyInTheFileIsReported) {
  EXPECT_EQ(
      ParseError(Edit("display_name", "zeta = 1\nbeta = 2\ndisplay_name")),
      "x.toml:3:1: error: unknown key \"zeta\" in the material file; "
      "accepted: format, name, display_name, description, parameters");
}

TEST(ParseMaterial, NanIsRejected) {
  EXPECT_EQ(ParseError(Edit("value = 2.145", "value = nan")),
            "x.toml:6:9: error: parameters.c_e_n_per_mm2.value must be a "
            "finite number, got nan");
}

TEST(ParseMaterial, InfinityIsRejected) {
  EXPECT_EQ(ParseError(Edit("value = 0.087", "value = +inf")),
            "x.toml:11:9: error: parameters.alpha_per_s.value must be a finite "
            "number, got inf");
  EXPECT_EQ(ParseError(Edit("value = 0\n", "value = -inf\n")),
            "x.toml:26:9: error: parameters.c_i_n_s_per_mm3.value must be a "
            "finite number, got -inf");
}

TEST(ParseMaterial, NegativeValueIsRejected) {
  EXPECT_EQ(ParseError(Edit("value = 0.087", "value = -0.087")),
            "x.toml:11:9: error: parameters.alpha_per_s.value must be zero or "
            "positive, got -0.087");
}

TEST(ParseMaterial, ZeroElasticConstantIsRejected) {
  EXPECT_EQ(ParseError(Edit("value = 2.145", "value = 0")),
            "x.toml:6:9: error: parameters.c_e_n_per_mm2.value must be "
            "positive, got 0");
}

TEST(ParseMaterial, EmptySourceIsRejected) {
  EXPECT_EQ(ParseError(Edit("source = \"friction source\"", "source = \" \"")),
            "x.toml:23:10: error: parameters.mu.source must not be empty");
}

TEST(ParseMaterial, WrongFormatIdIsRejected) {
  EXPECT_EQ(ParseError(Edit("burrlab-material/1", "burrlab-material/2")),
            "x.toml:1:10: error: format must be 'burrlab-material/1', got "
            "'burrlab-material/2'");
  EXPECT_EQ(ParseError(Edit("\"burrlab-material/1\"", "1")),
            "x.toml:1:10: error: format must be a string, got an integer");
}

TEST(ParseMaterial, NameMustBeAnIdentifier) {
  EXPECT_EQ(ParseError(Edit("\"test_material\"", "\"Test material\"")),
            "x.toml:2:8: error: name must be lowercase letters, digits and "
            "underscores ([a-z0-9_]+), got 'Test material'");
  EXPECT_EQ(ParseError(Edit("display_name = \"Test material\"\n", "")),
            "x.toml:1:1: error: missing key 'display_name'");
}

TEST(ParseMaterial, SyntaxErrorsKeepTheirPosition) {
  EXPECT_EQ(ParseError(Edit("value = 2.145", "value = 2.145.0")),
            "x.toml:6:14: error: invalid TOML in floating-point: expected "
            "decimal digit or exponent, saw '.'");
  EXPECT_EQ(ParseError(Edit("[parameters.mu]", "[parameters.mu")),
            "x.toml:20:15: error: invalid TOML in table header: expected ']', "
            "saw '\\n'");
  EXPECT_EQ(ParseError(Edit("name = \"test_material\"",
                            "name = \"test_material\"\nname = \"b\"")),
            "x.toml:3:8: error: invalid TOML in key-value pair: cannot "
            "redefine existing string 'name'");
}

TEST(ParseMaterial, InvalidUtf8IsASyntaxError) {
  EXPECT_EQ(ParseError(Edit("Test material", "Test \xff material")),
            "x.toml:3:21: error: invalid TOML: encountered invalid utf-8 "
            "sequence");
}

TEST(ParseMaterial, ControlCharactersInMessagesAreEscaped) {
  EXPECT_EQ(ParseError(Edit("display_name", "\"a\\nb\" = 1\ndisplay_name")),
            "x.toml:3:1: error: unknown key \"a\\x0ab\" in the material file; "
            "accepted: format, name, display_name, description, parameters");
}

TEST(ParseMaterial, DeeplyNestedDottedKeysAreRefusedBeforeParsing) {
  std::string deep;
  for (int i = 0; i < 200000; ++i) deep += "a.";
  EXPECT_EQ(ParseError("format = \"burrlab-material/1\"\n" + deep + "a = 1\n"),
            "x.toml:2:514: error: more than 256 '.' outside strings and "
            "comments; nesting this deep is refused");
}

TEST(ParseMaterial, NestingAtTheLimitsIsRejectedWithoutCrashing) {
  // 256 dots (the most accepted) and 254 nested arrays and inline tables
  // (toml++ refuses 256) in one key-value pair.
  std::string deep = "format = \"burrlab-material/1\"\n";
  for (int i = 0; i < 256; ++i) deep += "a.";
  deep += "a = ";
  for (int i = 0; i < 127; ++i) deep += "[{b = ";
  deep += "1";
  for (int i = 0; i < 127; ++i) deep += "}]";
  deep += "\n";
  EXPECT_EQ(ParseError(deep),
            "x.toml:2:1: error: unknown key \"a\" in the material file; "
            "accepted: format, name, display_name, description, parameters");
}

TEST(ParseMaterial, TextOverOneMebibyteIsRefused) {
  std::string text(kValid);
  text.resize((1 << 20) + 1, '\n');
  EXPECT_EQ(ParseError(text),
            "x.toml:1:1: error: material text is larger than 1 MiB (1048577 "
            "bytes)");
  text.resize(1 << 20);
  EXPECT_EQ(ParseError(text), "<ok>");
}

// --- LoadMaterialFile -------------------------------------------------------

TEST(LoadMaterialFile, ReadsAFileFromDisk) {
  TempDir dir;
  const std::filesystem::path path = dir / "mine.toml";
  WriteFile(path, kValid);
  Result<MaterialSet> set = LoadMaterialFile(path.string());
  ASSERT_TRUE(set.ok()) << set.error().message;
  EXPECT_EQ(set->name, "test_material");
  EXPECT_EQ(set->material.c_e_n_per_mm2, 2.145);
}

TEST(LoadMaterialFile, ErrorsNameThePathGiven) {
  TempDir dir;
  const std::filesystem::path path = dir / "bad.toml";
  WriteFile(path, Edit("value = 2.145", "value = nan"));
  EXPECT_EQ(LoadMaterialFile(path.string()).error().message,
            path.string() +
                ":6:9: error: parameters.c_e_n_per_mm2.value must be a finite "
                "number, got nan");
}

TEST(LoadMaterialFile, MissingFileCannotBeRead) {
  TempDir dir;
  const std::string path = (dir / "absent.toml").string();
  EXPECT_EQ(LoadMaterialFile(path).error().message,
            path + ": cannot read file: No such file or directory");
}

TEST(LoadMaterialFile, DirectoryCannotBeRead) {
  TempDir dir;
  const std::filesystem::path path = dir / "folder.toml";
  std::filesystem::create_directory(path);
  EXPECT_EQ(LoadMaterialFile(path.string()).error().message,
            path.string() + ": cannot read file: is a directory");
}

TEST(LoadMaterialFile, FileOverOneMebibyteIsRefused) {
  TempDir dir;
  const std::filesystem::path path = dir / "big.toml";
  std::string text(kValid);
  text.resize((1 << 20) + 1, '\n');
  WriteFile(path, text);
  EXPECT_EQ(LoadMaterialFile(path.string()).error().message,
            path.string() + ": cannot read file: larger than 1 MiB");
  text.resize(1 << 20);
  WriteFile(path, text);
  EXPECT_TRUE(LoadMaterialFile(path.string()).ok());
}

}  // namespace
}  // namespace burrlab::stimuli
