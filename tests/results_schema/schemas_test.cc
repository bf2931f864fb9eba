// Tests of the embedded JSON Schemas and the small checker: each keyword it
// claims to check, its refusal of keywords it does not know, and that the
// schema files use nothing else.
#include "burrlab/results_schema/schemas.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace burrlab::results_schema {
namespace {

using Json = nlohmann::json;

std::string Check(const std::string& schema, const std::string& instance) {
  Status s = CheckJson(schema, instance);
  return s.ok() ? std::string("ok") : s.error().message;
}

TEST(Schemas, EmbedsOneSchemaPerRecordAndSidecar) {
  const std::vector<std::string_view> expected = {
      "beh_sidecar", "dataset_description", "physio_sidecar", "session",
      "trial_record"};
  EXPECT_EQ(SchemaNames(), expected);
  for (std::string_view name : SchemaNames()) {
    Result<std::string_view> text = SchemaText(name);
    ASSERT_TRUE(text.ok()) << text.error().message;
    const Json schema = Json::parse(*text, nullptr, false);
    ASSERT_FALSE(schema.is_discarded()) << name;
    EXPECT_EQ(schema["$schema"], "https://json-schema.org/draft/2020-12/schema")
        << name;
  }
  Result<std::string_view> unknown = SchemaText("events");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().message,
            "unknown schema \"events\"; known: beh_sidecar, "
            "dataset_description, physio_sidecar, session, trial_record");
}

// Every keyword in every (sub)schema is one the checker checks or an
// annotation it may ignore, so no rule is skipped silently.
void ExpectOnlyCheckedKeywords(const Json& schema, const std::string& where) {
  static const std::set<std::string> kChecked = {
      "type",       "enum",
      "const",      "required",
      "properties", "additionalProperties",
      "items",      "minItems",
      "minimum",    "exclusiveMinimum",
      "maximum",    "minLength",
      "pattern",    "$ref",
      "$schema",    "$id",
      "$defs",      "$comment",
      "title",      "default",
      "examples",   "description"};
  if (schema.is_boolean()) return;
  ASSERT_TRUE(schema.is_object()) << where;
  for (const auto& [key, value] : schema.items()) {
    EXPECT_TRUE(kChecked.contains(key)) << where << ": " << key;
    if (key == "properties" || key == "$defs") {
      for (const auto& [name, sub] : value.items()) {
        ExpectOnlyCheckedKeywords(sub, where + "/" + key + "/" + name);
      }
    } else if (key == "items" || key == "additionalProperties") {
      ExpectOnlyCheckedKeywords(value, where + "/" + key);
    }
  }
}

TEST(Schemas, UseOnlyKeywordsTheCheckerChecks) {
  for (std::string_view name : SchemaNames()) {
    ExpectOnlyCheckedKeywords(Json::parse(*SchemaText(name)),
                              std::string(name));
  }
}

TEST(CheckJson, RequiredAndTypes) {
  const std::string schema = R"({
    "type": "object",
    "required": ["Name", "Count"],
    "properties": {
      "Name": {"type": "string", "minLength": 2},
      "Count": {"type": "integer", "minimum": 0},
      "Rate": {"type": ["number", "null"], "exclusiveMinimum": 0}
    }})";
  EXPECT_EQ(Check(schema, R"({"Name": "ab", "Count": 3})"), "ok");
  EXPECT_EQ(Check(schema, R"({"Name": "ab", "Count": 3.0, "Rate": null})"),
            "ok");
  EXPECT_EQ(Check(schema, R"({"Name": "ab"})"),
            "/: missing required property \"Count\"");
  EXPECT_EQ(Check(schema, R"({"Name": 5, "Count": 3})"),
            "/Name: 5 is not of type \"string\"");
  EXPECT_EQ(Check(schema, R"({"Name": "ab", "Count": 3.5})"),
            "/Count: 3.5 is not of type \"integer\"");
  EXPECT_EQ(Check(schema, R"({"Name": "ab", "Count": -1})"),
            "/Count: -1 breaks minimum 0");
  EXPECT_EQ(Check(schema, R"({"Name": "ab", "Count": 1, "Rate": 0})"),
            "/Rate: 0 breaks exclusiveMinimum 0");
  EXPECT_EQ(Check(schema, R"({"Name": "ab", "Count": 1, "Rate": "fast"})"),
            "/Rate: \"fast\" is not of type [\"number\",\"null\"]");
  // Two characters, four bytes.
  EXPECT_EQ(Check(schema, R"({"Name": "\u00e9\u00e9", "Count": 1})"), "ok");
  EXPECT_EQ(Check(schema, R"({"Name": "\u00e9", "Count": 1})"),
            "/Name: \"\u00e9\" is shorter than 2 characters");
  EXPECT_EQ(Check(schema, "[]"), "/: [] is not of type \"object\"");
}

TEST(CheckJson, EnumConstPatternItemsAndAdditionalProperties) {
  const std::string schema = R"({
    "type": "object",
    "properties": {
      "Kind": {"enum": ["raw", "derivative"]},
      "Version": {"const": "1.9.0"},
      "Columns": {"type": "array", "minItems": 2,
                  "items": {"type": "string", "pattern": "^[a-z_]+$"}}
    },
    "additionalProperties": false})";
  EXPECT_EQ(Check(schema, R"({"Kind": "raw", "Columns": ["a", "b_c"]})"), "ok");
  EXPECT_EQ(Check(schema, R"({"Kind": "cooked"})"),
            "/Kind: \"cooked\" is not one of [\"raw\",\"derivative\"]");
  EXPECT_EQ(Check(schema, R"({"Version": "1.8.0"})"),
            "/Version: \"1.8.0\" is not \"1.9.0\"");
  EXPECT_EQ(Check(schema, R"({"Columns": ["a"]})"),
            "/Columns: 1 items, fewer than the 2 required");
  EXPECT_EQ(Check(schema, R"({"Columns": ["a", "B"]})"),
            "/Columns/1: \"B\" does not match pattern \"^[a-z_]+$\"");
  EXPECT_EQ(Check(schema, R"({"Extra": 1})"),
            "/: property \"Extra\" is not allowed");
}

TEST(CheckJson, PatternsAreAnchoredClassesAndQuantifiers) {
  const std::string hex = R"({"pattern": "^[0-9a-f]{4}$"})";
  EXPECT_EQ(Check(hex, R"("09af")"), "ok");
  EXPECT_EQ(Check(hex, R"("09a")"),
            "/: \"09a\" does not match pattern \"^[0-9a-f]{4}$\"");
  EXPECT_EQ(Check(hex, R"("09afa")"),
            "/: \"09afa\" does not match pattern \"^[0-9a-f]{4}$\"");
  const std::string cell = R"({"pattern": "^[^+\\t]*$"})";
  EXPECT_EQ(Check(cell, R"("pvc k70")"), "ok");
  EXPECT_EQ(Check(cell, R"("")"), "ok");
  EXPECT_EQ(Check(cell, R"("a\tb")"),
            "/: \"a\\tb\" does not match pattern \"^[^+\\\\t]*$\"");
  EXPECT_EQ(Check(cell, R"("a+b")"),
            "/: \"a+b\" does not match pattern \"^[^+\\\\t]*$\"");
  const std::string mixed = R"({"pattern": "^a?b+\\.c{1,2}d*$"})";
  EXPECT_EQ(Check(mixed, R"("bb.cc")"), "ok");
  EXPECT_EQ(Check(mixed, R"("ab.cddd")"), "ok");
  EXPECT_NE(Check(mixed, R"("ab.cccd")"), "ok");
  EXPECT_NE(Check(mixed, R"("abxc")"), "ok");
  EXPECT_EQ(Check(R"({"pattern": "burr"})", R"("burr")"),
            "/: unsupported pattern \"burr\" (only anchored ^...$ patterns "
            "of literals, classes and quantifiers)");
  EXPECT_EQ(Check(R"({"pattern": "^(a|b)$"})", R"("a")"),
            "/: unsupported pattern \"^(a|b)$\" (only anchored ^...$ "
            "patterns of literals, classes and quantifiers)");
}

TEST(CheckJson, FollowsLocalReferences) {
  const std::string schema = R"({
    "type": "object",
    "additionalProperties": {"$ref": "#/$defs/column"},
    "$defs": {"column": {"type": "object", "required": ["Description"]}}})";
  EXPECT_EQ(Check(schema, R"({"a/b": {"Description": "x"}})"), "ok");
  EXPECT_EQ(Check(schema, R"({"a/b": {}})"),
            "/a~1b: missing required property \"Description\"");
  EXPECT_EQ(Check(R"({"$ref": "#/$defs/none"})", "{}"),
            "/: $ref \"#/$defs/none\" names no definition");
  EXPECT_EQ(Check(R"({"$ref": "other.json"})", "{}"),
            "/: unsupported $ref \"other.json\" (only \"#/$defs/name\")");
  EXPECT_EQ(
      Check(R"({"$ref": "#/$defs/a", "$defs": {"a": {"$ref": "#/$defs/a"}}})",
            "{}"),
      "/: schema nesting deeper than 64");
}

TEST(CheckJson, RefusesKeywordsItDoesNotCheck) {
  EXPECT_EQ(Check(R"({"oneOf": [{"type": "string"}]})", "1"),
            "/: unsupported schema keyword \"oneOf\"");
  EXPECT_EQ(Check(R"({"type": "object"})", "{"),
            "the document is not valid JSON");
  EXPECT_EQ(Check("{", "{}"), "the schema is not valid JSON");
}

TEST(CheckJson, DatasetDescriptionSchemaCatchesMistakes) {
  const Json good = Json::parse(R"({
    "Name": "stiffness", "BIDSVersion": "1.9.0", "DatasetType": "raw",
    "GeneratedBy": [{"Name": "burrlab", "Version": "0.1.0"}]})");
  EXPECT_TRUE(CheckJsonAgainst("dataset_description", good.dump()).ok());
  Json bad = good;
  bad["GeneratedBy"][0].erase("Name");
  Status s = CheckJsonAgainst("dataset_description", bad.dump());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message,
            "dataset_description.schema.json: /GeneratedBy/0: missing "
            "required property \"Name\"");
}

}  // namespace
}  // namespace burrlab::results_schema
