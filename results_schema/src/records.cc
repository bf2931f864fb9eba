// Validation and JSON form of the session, trial and trace records.
#include "burrlab/results_schema/records.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <exception>
#include <nlohmann/json.hpp>
#include <set>

#include "text.h"

namespace burrlab::results_schema {
namespace {

using OrderedJson = nlohmann::ordered_json;

bool IsAsciiAlnum(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
         (c >= '0' && c <= '9');
}

bool IsLowerHex(std::string_view text) {
  for (char c : text) {
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

// A TSV cell must not break the table: no tab, CR or LF, and not the literal
// "n/a" that marks a missing value.
Status CheckCell(int trial_index, std::string_view field,
                 std::string_view value) {
  if (value.find_first_of("\t\r\n") != std::string_view::npos) {
    return Error{fmt::format("trial {}: {} {} contains a tab or line break",
                             trial_index, field, Quoted(value))};
  }
  if (!IsValidUtf8(value)) {
    return Error{fmt::format("trial {}: {} {} is not valid UTF-8", trial_index,
                             field, Quoted(value))};
  }
  if (value == "n/a") {
    return Error{fmt::format(
        "trial {}: {} \"n/a\" is reserved for missing values; leave it empty",
        trial_index, field)};
  }
  return {};
}

Status CheckFinite(int trial_index, std::string_view field,
                   const std::optional<double>& value) {
  if (value && !std::isfinite(*value)) {
    return Error{fmt::format("trial {}: {} is not finite", trial_index, field)};
  }
  return {};
}

template <typename T>
OrderedJson OptionalJson(const std::optional<T>& value) {
  if (!value) return nullptr;
  return *value;
}

}  // namespace

bool IsKnownTask(std::string_view task) {
  return task == "probe" || task == "drill";
}

namespace {

// A BIDS label of `kind` ("subject", "session") written after `prefix`
// ("sub-", "ses-") in names: 1..64 ASCII letters or digits.
Status ValidateLabel(std::string_view kind, std::string_view prefix,
                     std::string_view example, std::string_view label) {
  if (label.empty()) {
    return Error{fmt::format(
        "{} label is empty; use letters and digits only (BIDS {}<label>), "
        "e.g. {}",
        kind, prefix, example)};
  }
  if (label.starts_with(prefix)) {
    return Error{fmt::format(
        "{} label {} includes the \"{}\" prefix; give only the label, "
        "e.g. {}",
        kind, Quoted(label), prefix, Quoted(label.substr(prefix.size())))};
  }
  if (label.size() > kMaxSubjectLabelLength) {
    return Error{
        fmt::format("{} label {} is {} characters long; at most {} are allowed",
                    kind, Quoted(label), label.size(), kMaxSubjectLabelLength)};
  }
  for (std::size_t i = 0; i < label.size(); ++i) {
    if (!IsAsciiAlnum(label[i])) {
      return Error{fmt::format(
          "{} label {} has {} at position {}; use letters and digits "
          "only (BIDS {}<label>)",
          kind, Quoted(label), DescribeChar(label[i]), i + 1, prefix)};
    }
  }
  return {};
}

}  // namespace

Status ValidateSubjectLabel(std::string_view label) {
  return ValidateLabel("subject", "sub-", "01", label);
}

Status ValidateSessionLabel(std::string_view label) {
  return ValidateLabel("session", "ses-", "2", label);
}

Status ValidateSession(const SessionInfo& session) {
  if (Status s = ValidateSubjectLabel(session.subject_label); !s) return s;
  if (session.study.empty()) return Error{"session: study name is empty"};
  const std::pair<std::string_view, const std::string*> texts[] = {
      {"study", &session.study},
      {"protocol_path", &session.protocol_path},
      {"burrlab_version", &session.burrlab_version},
      {"started_utc", &session.started_utc}};
  for (const auto& [field, value] : texts) {
    if (!IsValidUtf8(*value)) {
      return Error{fmt::format("session: {} {} is not valid UTF-8", field,
                               Quoted(*value))};
    }
  }
  if (session.protocol_sha256.size() != 64 ||
      !IsLowerHex(session.protocol_sha256)) {
    return Error{fmt::format(
        "session: protocol_sha256 {} is not 64 lowercase hex digits",
        Quoted(session.protocol_sha256))};
  }
  if (session.burrlab_version.empty()) {
    return Error{"session: burrlab_version is empty"};
  }
  for (std::size_t i = 0; i < session.setup.size(); ++i) {
    const SetupField& f = session.setup[i];
    if (!IsSnakeCase(f.name)) {
      return Error{fmt::format("session: setup field name {} is not snake_case",
                               Quoted(f.name))};
    }
    if (!IsValidUtf8(f.value) ||
        f.value.find_first_of("\r\n") != std::string::npos) {
      return Error{fmt::format(
          "session: setup field {} has the value {}, which is not one line "
          "of UTF-8",
          f.name, Quoted(f.value))};
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (session.setup[j].name == f.name) {
        return Error{
            fmt::format("session: setup field {} appears twice", f.name)};
      }
    }
  }
  return {};
}

Status ValidateTrial(const TrialRecord& trial) {
  const int t = trial.trial_index;
  if (t < 0) return Error{fmt::format("trial_index {} is negative", t)};
  if (trial.block.empty()) {
    return Error{fmt::format("trial {}: block name is empty", t)};
  }
  if (trial.method.empty()) {
    return Error{fmt::format("trial {}: method is empty", t)};
  }
  if (!IsKnownTask(trial.task)) {
    return Error{fmt::format("trial {}: task {} is not \"probe\" or \"drill\"",
                             t, Quoted(trial.task))};
  }
  const std::pair<std::string_view, const std::string*> cells[] = {
      {"block", &trial.block},
      {"method", &trial.method},
      {"trial_type", &trial.trial_type},
      {"stim_unit", &trial.stim_unit},
      {"correct_answer", &trial.correct_answer},
      {"response", &trial.response},
      {"source", &trial.source}};
  for (const auto& [field, value] : cells) {
    if (Status s = CheckCell(t, field, *value); !s) return s;
  }
  for (const std::string& material : trial.interval_materials) {
    if (material.empty()) {
      return Error{fmt::format("trial {}: an interval material is empty", t)};
    }
    if (Status s = CheckCell(t, "interval material", material); !s) return s;
    if (material.find('+') != std::string::npos) {
      return Error{fmt::format(
          "trial {}: interval material {} contains '+', which joins the "
          "materials of a trial in exports",
          t, Quoted(material))};
    }
  }
  if (Status s = CheckFinite(t, "stim_level", trial.stim_level); !s) return s;
  if (Status s = CheckFinite(t, "response_time_s", trial.response_time_s); !s) {
    return s;
  }
  if (trial.response_time_s && *trial.response_time_s < 0.0) {
    return Error{fmt::format("trial {}: response_time_s {} is negative", t,
                             *trial.response_time_s)};
  }
  if (Status s = CheckFinite(t, "step_size", trial.step_size); !s) return s;
  if (Status s = CheckFinite(t, "estimate", trial.estimate); !s) return s;
  if (trial.staircase_id && *trial.staircase_id < 0) {
    return Error{fmt::format("trial {}: staircase_id {} is negative", t,
                             *trial.staircase_id)};
  }
  const auto extra = nlohmann::json::parse(trial.extra, nullptr, false);
  if (extra.is_discarded() || !extra.is_object()) {
    return Error{fmt::format("trial {}: extra {} is not a JSON object", t,
                             Quoted(trial.extra))};
  }
  return {};
}

Status ValidateTrace(const TraceSamples& trace, int trial_index) {
  const int t = trial_index;
  if (trace.trial_index != trial_index) {
    return Error{
        fmt::format("trial {}: a trace of interval {} belongs to trial {}", t,
                    trace.interval_index, trace.trial_index)};
  }
  const std::string where =
      fmt::format("trial {}, interval {}", t, trace.interval_index);
  if (trace.interval_index < 0) {
    return Error{fmt::format("{}: interval_index is negative", where)};
  }
  if (!std::isfinite(trace.sampling_frequency_hz) ||
      trace.sampling_frequency_hz <= 0.0) {
    return Error{fmt::format("{}: sampling_frequency_hz {} is not positive",
                             where, trace.sampling_frequency_hz)};
  }
  if (!std::isfinite(trace.start_time_s)) {
    return Error{fmt::format("{}: start_time_s is not finite", where)};
  }
  if (trace.columns.empty()) {
    return Error{fmt::format("{}: the trace has no columns", where)};
  }
  std::set<std::string_view> seen;
  for (const std::string& column : trace.columns) {
    if (!IsSnakeCase(column)) {
      return Error{fmt::format(
          "{}: column {} is not snake_case (a-z, 0-9, '_', starting with a "
          "letter)",
          where, Quoted(column))};
    }
    if (column == "trial_index" || column == "interval_index" ||
        column == "time") {
      return Error{
          fmt::format("{}: column {} is reserved (exports add trial_index, "
                      "interval_index and time)",
                      where, Quoted(column))};
    }
    if (!seen.insert(column).second) {
      return Error{
          fmt::format("{}: column {} appears twice", where, Quoted(column))};
    }
  }
  const std::uint64_t values =
      static_cast<std::uint64_t>(trace.rows.size()) * trace.columns.size();
  if (values > kMaxTraceValues) {
    return Error{fmt::format("{}: {} values exceed the limit of {}", where,
                             values, kMaxTraceValues)};
  }
  for (std::size_t i = 0; i < trace.rows.size(); ++i) {
    if (trace.rows[i].size() != trace.columns.size()) {
      return Error{fmt::format("{}: row {} has {} values for {} columns", where,
                               i, trace.rows[i].size(), trace.columns.size())};
    }
  }
  return {};
}

std::string SeedText(std::uint64_t seed) {
  return fmt::format("{}{}", kSeedPrefix, seed);
}

std::optional<std::uint64_t> ParseSeedText(std::string_view text) {
  if (text.starts_with(kSeedPrefix)) text.remove_prefix(kSeedPrefix.size());
  if (text.empty() || text.front() < '0' || text.front() > '9') {
    return std::nullopt;
  }
  std::uint64_t seed = 0;
  const auto [end, ec] =
      std::from_chars(text.data(), text.data() + text.size(), seed);
  if (ec != std::errc() || end != text.data() + text.size()) {
    return std::nullopt;
  }
  return seed;
}

std::string SessionToJson(const SessionInfo& session) {
  OrderedJson j;
  j["study"] = session.study;
  j["protocol_path"] = session.protocol_path;
  j["protocol_sha256"] = session.protocol_sha256;
  j["subject_label"] = session.subject_label;
  j["master_seed"] = std::to_string(session.master_seed);
  j["burrlab_version"] = session.burrlab_version;
  j["started_utc"] = session.started_utc;
  if (!session.setup.empty()) {
    OrderedJson setup = OrderedJson::object();
    for (const SetupField& f : session.setup) setup[f.name] = f.value;
    j["setup"] = std::move(setup);
  }
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
}

Result<std::string> TrialToJson(const TrialRecord& trial) {
  try {
    const auto extra = nlohmann::json::parse(trial.extra, nullptr, false);
    if (extra.is_discarded() || !extra.is_object()) {
      return Error{fmt::format("trial {}: extra {} is not a JSON object",
                               trial.trial_index, Quoted(trial.extra))};
    }
    OrderedJson j;
    j["trial_index"] = trial.trial_index;
    j["block"] = trial.block;
    j["method"] = trial.method;
    j["task"] = trial.task;
    j["trial_type"] = trial.trial_type;
    j["stim_level"] = OptionalJson(trial.stim_level);
    j["stim_unit"] = trial.stim_unit;
    j["interval_materials"] = trial.interval_materials;
    j["correct_answer"] = trial.correct_answer;
    j["response"] = trial.response;
    j["correct"] = OptionalJson(trial.correct);
    j["response_time_s"] = OptionalJson(trial.response_time_s);
    j["staircase_id"] = OptionalJson(trial.staircase_id);
    j["reversal"] = OptionalJson(trial.reversal);
    j["step_size"] = OptionalJson(trial.step_size);
    j["estimate"] = OptionalJson(trial.estimate);
    j["rng_state"] = trial.rng_state;
    j["source"] = trial.source;
    j["practice"] = trial.practice;
    j["late"] = OptionalJson(trial.late);
    j["extra"] = OrderedJson::parse(extra.dump());
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  } catch (const std::exception& e) {
    return Error{fmt::format("trial {}: cannot write JSON: {}",
                             trial.trial_index, e.what())};
  }
}

}  // namespace burrlab::results_schema
