// Tests of record validation (exact error texts a user sees) and of the JSON
// form of sessions and trials against their schemas.
#include "burrlab/results_schema/records.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "burrlab/results_schema/schemas.h"

namespace burrlab::results_schema {
namespace {

SessionInfo MakeSession() {
  SessionInfo s;
  s.study = "stiffness discrimination";
  s.protocol_path = "protocols/examples/same_different.toml";
  s.protocol_sha256 =
      "9f86d081884c7d659a2feaa0c55ad015a3bf4f1b2b0b822cd15d6c15b0f00a08";
  s.subject_label = "01";
  s.master_seed = 18'446'744'073'709'551'615u;
  s.burrlab_version = "0.1.0";
  s.started_utc = "2024-05-01T09:30:00Z";
  return s;
}

TrialRecord MakeTrial() {
  TrialRecord t;
  t.trial_index = 3;
  t.block = "main";
  t.method = "same_different";
  t.task = "probe";
  t.trial_type = "AB";
  t.interval_materials = {"pvc_k70", "human_temporal_bone"};
  t.correct_answer = "different";
  t.response = "same";
  t.correct = false;
  t.response_time_s = 1.25;
  t.rng_state = "1 2 3";
  return t;
}

std::string Message(const Status& s) {
  return s.ok() ? std::string("ok") : s.error().message;
}

TEST(SubjectLabel, AcceptsLettersAndDigits) {
  EXPECT_TRUE(ValidateSubjectLabel("01").ok());
  EXPECT_TRUE(ValidateSubjectLabel("ctrl7B").ok());
  EXPECT_TRUE(ValidateSubjectLabel(std::string(64, '9')).ok());
}

TEST(SubjectLabel, RejectsWithAPreciseMessage) {
  EXPECT_EQ(Message(ValidateSubjectLabel("")),
            "subject label is empty; use letters and digits only (BIDS "
            "sub-<label>), e.g. 01");
  EXPECT_EQ(Message(ValidateSubjectLabel("sub-07")),
            "subject label \"sub-07\" includes the \"sub-\" prefix; give only "
            "the label, e.g. \"07\"");
  EXPECT_EQ(Message(ValidateSubjectLabel("p_1")),
            "subject label \"p_1\" has '_' at position 2; use letters and "
            "digits only (BIDS sub-<label>)");
  EXPECT_EQ(Message(ValidateSubjectLabel("a b")),
            "subject label \"a b\" has byte 0x20 at position 2; use letters "
            "and digits only (BIDS sub-<label>)");
  EXPECT_EQ(Message(ValidateSubjectLabel("J\xC3\xBCrgen")),
            "subject label \"J\\xC3\\xBCrgen\" has byte 0xC3 at position 2; "
            "use letters and digits only (BIDS sub-<label>)");
  EXPECT_EQ(Message(ValidateSubjectLabel(std::string(65, 'a'))),
            "subject label \"" + std::string(65, 'a') +
                "\" is 65 characters long; at most 64 are allowed");
}

TEST(SessionLabel, AcceptsLettersAndDigitsAndRejectsWithAPreciseMessage) {
  EXPECT_TRUE(ValidateSessionLabel("2").ok());
  EXPECT_TRUE(ValidateSessionLabel("day2").ok());
  EXPECT_EQ(Message(ValidateSessionLabel("")),
            "session label is empty; use letters and digits only (BIDS "
            "ses-<label>), e.g. 2");
  EXPECT_EQ(Message(ValidateSessionLabel("ses-2")),
            "session label \"ses-2\" includes the \"ses-\" prefix; give only "
            "the label, e.g. \"2\"");
  EXPECT_EQ(Message(ValidateSessionLabel("day-2")),
            "session label \"day-2\" has '-' at position 4; use letters and "
            "digits only (BIDS ses-<label>)");
  EXPECT_EQ(Message(ValidateSessionLabel(std::string(65, '2'))),
            "session label \"" + std::string(65, '2') +
                "\" is 65 characters long; at most 64 are allowed");
}

TEST(Session, ChecksTheProtocolHash) {
  EXPECT_TRUE(ValidateSession(MakeSession()).ok());
  SessionInfo s = MakeSession();
  s.protocol_sha256 = "ABC";
  EXPECT_EQ(Message(ValidateSession(s)),
            "session: protocol_sha256 \"ABC\" is not 64 lowercase hex digits");
  s = MakeSession();
  s.study = "";
  EXPECT_EQ(Message(ValidateSession(s)), "session: study name is empty");
}

TEST(Trial, RejectsWhatWouldBreakTheExport) {
  EXPECT_TRUE(ValidateTrial(MakeTrial()).ok());
  TrialRecord t = MakeTrial();
  t.task = "cut";
  EXPECT_EQ(Message(ValidateTrial(t)),
            "trial 3: task \"cut\" is not \"probe\" or \"drill\"");
  t = MakeTrial();
  t.response = "same\tdifferent";
  EXPECT_EQ(Message(ValidateTrial(t)),
            "trial 3: response \"same\\x09different\" contains a tab or line "
            "break");
  t = MakeTrial();
  t.correct_answer = "n/a";
  EXPECT_EQ(Message(ValidateTrial(t)),
            "trial 3: correct_answer \"n/a\" is reserved for missing values; "
            "leave it empty");
  t = MakeTrial();
  t.interval_materials[1] = "bone+resin";
  EXPECT_EQ(Message(ValidateTrial(t)),
            "trial 3: interval material \"bone+resin\" contains '+', which "
            "joins the materials of a trial in exports");
  t = MakeTrial();
  t.stim_level = std::nan("");
  EXPECT_EQ(Message(ValidateTrial(t)), "trial 3: stim_level is not finite");
  t = MakeTrial();
  t.extra = "[1, 2]";
  EXPECT_EQ(Message(ValidateTrial(t)),
            "trial 3: extra \"[1, 2]\" is not a JSON object");
  t = MakeTrial();
  t.block = "caf\xE9";
  EXPECT_EQ(Message(ValidateTrial(t)),
            "trial 3: block \"caf\\xE9\" is not valid UTF-8");
  t = MakeTrial();
  t.response_time_s = -0.5;
  EXPECT_EQ(Message(ValidateTrial(t)),
            "trial 3: response_time_s -0.5 is negative");
}

TEST(Trace, RejectsColumnsTheExportCannotName) {
  TraceSamples trace;
  trace.trial_index = 2;
  trace.interval_index = 1;
  trace.columns = {"force_n", "Depth mm"};
  EXPECT_EQ(Message(ValidateTrace(trace, 2)),
            "trial 2, interval 1: column \"Depth mm\" is not snake_case (a-z, "
            "0-9, '_', starting with a letter)");
  trace.columns = {"force_n", "time"};
  EXPECT_EQ(Message(ValidateTrace(trace, 2)),
            "trial 2, interval 1: column \"time\" is reserved (exports add "
            "trial_index, interval_index and time)");
  trace.columns = {"force_n", "force_n"};
  EXPECT_EQ(Message(ValidateTrace(trace, 2)),
            "trial 2, interval 1: column \"force_n\" appears twice");
  trace.columns = {"force_n"};
  trace.sampling_frequency_hz = 0.0;
  EXPECT_EQ(Message(ValidateTrace(trace, 2)),
            "trial 2, interval 1: sampling_frequency_hz 0 is not positive");
}

TEST(Json, SessionMatchesItsSchemaAndKeepsTheSeedExact) {
  const std::string json = SessionToJson(MakeSession());
  Status s = CheckJsonAgainst("session", json);
  EXPECT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(nlohmann::json::parse(json)["master_seed"], "18446744073709551615");
}

TEST(Json, TrialsMatchTheirSchemaWithAndWithoutOptionalValues) {
  TrialRecord full = MakeTrial();
  full.stim_level = 1.2;
  full.stim_unit = "ratio";
  full.staircase_id = 1;
  full.reversal = true;
  full.step_size = 0.1;
  full.estimate = 1.15;
  full.extra = R"({"quest_sd": 0.2})";
  TrialRecord sparse = MakeTrial();
  sparse.correct.reset();
  sparse.response_time_s.reset();
  sparse.response.clear();
  for (const TrialRecord& t : {full, sparse}) {
    Result<std::string> json = TrialToJson(t);
    ASSERT_TRUE(json.ok()) << json.error().message;
    Status s = CheckJsonAgainst("trial_record", *json);
    EXPECT_TRUE(s.ok()) << s.error().message << "\n" << *json;
  }
  const auto parsed = nlohmann::json::parse(*TrialToJson(sparse));
  EXPECT_TRUE(parsed["correct"].is_null());
  EXPECT_TRUE(parsed["extra"].is_object());
}

TEST(Json, TrialSchemaRejectsAnUnknownTask) {
  auto json = nlohmann::json::parse(*TrialToJson(MakeTrial()));
  json["task"] = "cut";
  EXPECT_EQ(Message(CheckJsonAgainst("trial_record", json.dump())),
            "trial_record.schema.json: /task: \"cut\" is not one of "
            "[\"probe\",\"drill\"]");
}

TEST(Seed, TextKeepsEverySeedAndReadsBack) {
  for (const std::uint64_t seed :
       {0ull, 1ull, 9007199254740993ull, 9223372036854775809ull,
        18446744073709551615ull}) {
    const std::string text = SeedText(seed);
    EXPECT_EQ(text, "seed-" + std::to_string(seed));
    EXPECT_EQ(ParseSeedText(text), seed) << text;
    EXPECT_EQ(ParseSeedText(std::to_string(seed)), seed);  // bare digits
  }
  for (const char* bad :
       {"", "seed-", "seed-x", "-1", "+1", "seed--1", "18446744073709551616",
        "seed-1 ", " 1", "1e3", "0x10", "Seed-1"}) {
    EXPECT_EQ(ParseSeedText(bad), std::nullopt) << bad;
  }
}

}  // namespace
}  // namespace burrlab::results_schema
