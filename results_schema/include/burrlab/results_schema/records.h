// The records burrlab keeps for one session: who and what was run
// (SessionInfo), one row per completed trial (TrialRecord) and the force and
// position traces of each interval (TraceSamples); their validation rules and
// their JSON form (described by results_schema/session.schema.json and
// results_schema/trial_record.schema.json).
#ifndef BURRLAB_RESULTS_SCHEMA_RECORDS_H_
#define BURRLAB_RESULTS_SCHEMA_RECORDS_H_

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::results_schema {

// Longest subject (or session) label accepted (characters).
inline constexpr std::size_t kMaxSubjectLabelLength = 64;

// Largest trace accepted by Journal::Append: rows x columns values (1 GB of
// doubles stays under SQLite's default 1e9-byte blob limit).
inline constexpr std::uint64_t kMaxTraceValues = 120'000'000;

// One named part of a session's set-up: e.g. {"radius_mm", "2"}.
struct SetupField {
  std::string name;   // snake_case
  std::string value;  // text, no line breaks

  // Field-by-field equality.
  bool operator==(const SetupField&) const = default;
};

// Who and what one session runs; written once when the journal is created.
struct SessionInfo {
  std::string study;            // study name from the protocol file
  std::string protocol_path;    // protocol file as given on the command line
  std::string protocol_sha256;  // SHA-256 of the protocol file, lowercase hex
  std::string subject_label;    // BIDS label without "sub-": letters and digits
  std::uint64_t master_seed = 0;  // every random stream derives from this
  std::string burrlab_version;    // version of the burrlab that created it
  std::string started_utc;        // ISO 8601 UTC, e.g. 2024-05-01T09:30:00Z
  // Everything else that shapes the results (burr radius, voxel size, who
  // answers, the device, the station file, ...), in the order the runner
  // gives it; names are distinct. Journals of schema version 1 have none.
  std::vector<SetupField> setup;

  // Field-by-field equality.
  bool operator==(const SessionInfo&) const = default;
};

// One completed trial. Text fields must not contain tabs or line breaks (they
// become TSV cells); an empty correct_answer, response or stim_unit means
// "none" and is exported as n/a.
struct TrialRecord {
  int trial_index = 0;     // 0-based, contiguous over the whole session
  std::string block;       // block name from the protocol (any text)
  std::string method;      // e.g. "same_different", "staircase", "quest"
  std::string task;        // "probe" or "drill"
  std::string trial_type;  // method-specific kind, e.g. "AB", "ascending"
  std::optional<double> stim_level;  // the varied level; none for AA/AB designs
  std::string stim_unit;  // unit of stim_level, e.g. "ratio", "N/mm^2"
  std::vector<std::string> interval_materials;  // one per interval; no '+'
  std::string correct_answer;   // the answer counted as correct; empty = none
  std::string response;         // the subject's answer; empty = missed
  std::optional<bool> correct;  // none when the design has no correct answer
  std::optional<double> response_time_s;  // s from the response prompt
  std::optional<int> staircase_id;  // which interleaved staircase (0-based)
  std::optional<bool> reversal;     // adaptive methods: did this trial reverse
  std::optional<double> step_size;  // adaptive methods: step after this trial
  std::optional<double> estimate;   // adaptive methods: threshold estimate now
  std::string rng_state;  // serialized random engines needed to resume (opaque)
  std::string extra = "{}";  // JSON object with method-specific fields
  // Who answered: "typed" (at the prompt), "station <device>" (a person at a
  // station, e.g. "station falcon") or "simulated observer"; empty = not
  // recorded (journals of schema version 1).
  std::string source;
  // A practice (familiarization) trial: recorded, never scored. Journals
  // before schema version 4 and exports before the column had none.
  bool practice = false;
  // The answer came after the block's response deadline (it is kept and
  // scored); none when the block has no deadline or the time is unknown.
  std::optional<bool> late;

  // Field-by-field equality (extra compared as text).
  bool operator==(const TrialRecord&) const = default;
};

// The samples of one interval of one trial, row-major: rows[i][j] is column j
// at time start_time_s + i / sampling_frequency_hz.
struct TraceSamples {
  int trial_index = 0;                    // the trial this interval belongs to
  int interval_index = 0;                 // 0-based interval within the trial
  double sampling_frequency_hz = 1000.0;  // samples per second, > 0
  double start_time_s = 0.0;         // first sample, s on the session clock
  std::vector<std::string> columns;  // snake_case with units, e.g. force_n
  std::vector<std::vector<double>> rows;  // each row has columns.size() values

  // Field-by-field equality (NaN samples compare unequal).
  bool operator==(const TraceSamples&) const = default;
};

// OK when `label` is a BIDS subject label: 1..64 ASCII letters or digits.
Status ValidateSubjectLabel(std::string_view label);

// OK when `label` is a BIDS session label (ses-<label>): 1..64 ASCII letters
// or digits, e.g. "2" for a subject's second visit.
Status ValidateSessionLabel(std::string_view label);

// OK when every field of `session` is acceptable (label, 64-hex hash, ...).
Status ValidateSession(const SessionInfo& session);

// OK when `trial` can be journaled and exported (task, text cells, extra).
Status ValidateTrial(const TrialRecord& trial);

// OK when `trace` is well formed and belongs to trial `trial_index`.
Status ValidateTrace(const TraceSamples& trace, int trial_index);

// JSON object for `session` (session.schema.json); master_seed is a decimal
// string because JSON readers lose integers above 2^53.
std::string SessionToJson(const SessionInfo& session);

// Prefix of a master seed written as text (SeedText).
inline constexpr std::string_view kSeedPrefix = "seed-";

// A master seed as the exports write it: "seed-" and its decimal digits
// ("seed-18446744073709551615"). A seed is any 64-bit number, but R's
// read.delim reads a long integer as a double (exact only below 2^53), and
// so does pandas once a column holds n/a; every reader leaves this text as
// text, and `burrlab run --seed` takes it as written.
std::string SeedText(std::uint64_t seed);

// The seed written as SeedText does or as its bare decimal digits (0 to
// 2^64 - 1); none for anything else.
std::optional<std::uint64_t> ParseSeedText(std::string_view text);

// JSON object for `trial` (trial_record.schema.json); absent optionals are
// null.
Result<std::string> TrialToJson(const TrialRecord& trial);

// True for the two TrialRecord::task values, "probe" and "drill".
bool IsKnownTask(std::string_view task);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_RECORDS_H_
