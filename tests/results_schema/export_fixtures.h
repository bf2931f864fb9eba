// A small journal with two blocks (a staircase and a same-different block),
// traces and a missed answer, shared by the export and read-back tests.
#ifndef BURRLAB_TESTS_RESULTS_SCHEMA_EXPORT_FIXTURES_H_
#define BURRLAB_TESTS_RESULTS_SCHEMA_EXPORT_FIXTURES_H_

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <string>
#include <vector>

#include "burrlab/results_schema/journal.h"
#include "burrlab/results_schema/records.h"
#include "temp_dir.h"

namespace burrlab::results_schema {

namespace fs = std::filesystem;

inline SessionInfo FixtureSession(const std::string& label) {
  SessionInfo s;
  s.study = "stiffness discrimination";
  s.protocol_path = "protocols/examples/staircase.toml";
  s.protocol_sha256 = std::string(64, 'c');
  s.subject_label = label;
  s.master_seed = 1234567890123u;
  s.burrlab_version = "0.1.0";
  s.started_utc = "2024-05-01T09:30:00Z";
  return s;
}

// Trials 0-3 in block "practice" (practice trials), 4-9 in "same-different
// main" (a response deadline of 2 s: trials 7-9 answered late).
inline TrialRecord FixtureTrial(int i) {
  TrialRecord t;
  t.trial_index = i;
  t.block = i < 4 ? "practice" : "same-different main";
  t.method = i < 4 ? "staircase" : "same_different";
  t.task = i % 2 == 0 ? "probe" : "drill";
  if (i < 4) {
    t.trial_type = "2AFC";
    t.stim_level = 1.0 + 0.1 * i;
    t.stim_unit = "ratio";
    t.staircase_id = 0;
    t.reversal = i == 2;
    t.step_size = 0.05;
    if (i > 1) t.estimate = 1.125;
    t.extra = R"({"quest_sd": 0.25})";
  } else {
    t.trial_type = i % 2 == 0 ? "AB" : "AA";
  }
  t.interval_materials = {"pvc_k70",
                          i % 2 == 0 ? "human_temporal_bone" : "pvc_k70"};
  t.correct_answer = i < 4 ? "2" : (i % 2 == 0 ? "different" : "same");
  if (i != 5) {  // trial 5 timed out
    t.response = i < 4 ? "2" : "same";
    t.correct = t.response == t.correct_answer;
    t.response_time_s = 0.5 + 0.25 * i;
  }
  t.rng_state = "state " + std::to_string(i);
  t.source = "typed";
  t.practice = i < 4;
  if (i >= 4 && t.response_time_s.has_value()) {
    t.late = *t.response_time_s > 2.0;
  }
  return t;
}

inline std::vector<TraceSamples> FixtureTraces(int i) {
  std::vector<TraceSamples> traces;
  for (int interval = 0; interval < 2; ++interval) {
    TraceSamples t;
    t.trial_index = i;
    t.interval_index = interval;
    t.sampling_frequency_hz = 1000.0;
    t.start_time_s = 20.0 * i + 5.0 * interval;
    t.columns = {"force_n", "depth_mm"};
    for (int r = 0; r < 5 + i; ++r) {
      t.rows.push_back({0.125 * r + i, 0.001 * r});
    }
    traces.push_back(std::move(t));
  }
  return traces;
}

// A journal of `trials` fixture trials for sub-<label> (of session
// `session` when it is not empty).
inline void WriteJournal(const fs::path& dir, const std::string& label,
                         int trials, const std::string& session = "") {
  auto journal = Journal::Create(dir, FixtureSession(label), session);
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  for (int i = 0; i < trials; ++i) {
    Status s = journal->Append(FixtureTrial(i), FixtureTraces(i));
    ASSERT_TRUE(s.ok()) << s.error().message;
  }
}

}  // namespace burrlab::results_schema

#endif  // BURRLAB_TESTS_RESULTS_SCHEMA_EXPORT_FIXTURES_H_
