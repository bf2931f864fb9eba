// One subject's session: engine + simulated intervals + responder + journal.
#include "studies/session.h"

#include <fmt/format.h>
#include <nettle/sha2.h>

#include <algorithm>
#include <array>
#include <boost/random/mersenne_twister.hpp>
#include <chrono>
#include <cmath>
#include <ctime>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <utility>
#include <vector>

#include "burrlab/base/printable.h"
#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/streams.h"
#include "burrlab/results_schema/bids_export.h"
#include "burrlab/results_schema/dataset_files.h"
#include "burrlab/results_schema/dataset_layout.h"
#include "burrlab/results_schema/journal.h"
#include "burrlab/results_schema/participants.h"
#include "burrlab/results_schema/records.h"
#include "burrlab/stimuli/interval.h"
#include "burrlab_version.h"
#include "studies/participant_rows.h"

namespace burrlab::runner {
namespace {

namespace rs = results_schema;
using protocols::Engine;
using protocols::PlannedInterval;
using protocols::StreamPurpose;
using protocols::TrialSpec;

// Interval index used for the off-record stand-in of a real reference.
constexpr std::uint64_t kStandInInterval = 1000;
// Offset of the per-block seeds of the remembered yes/no standard.
constexpr std::uint64_t kStandardSeedBase = 1ull << 32;
// Offset of the seeds of the familiarization renderings (same-different
// under the differencing and likelihood rules), and how many of each
// material a subject feels before a block.
constexpr std::uint64_t kFamiliarizationSeedBase = 1ull << 33;
constexpr int kFamiliarizationRenderings = 8;

std::string UtcNow() {
  const std::time_t now =
      std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

// Protocol text (instructions) for the terminal: each line made printable
// (no control byte reaches the terminal) and indented by two spaces.
std::string IndentedLines(std::string_view text) {
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (line.ends_with('\r')) line.remove_suffix(1);
    // Appended in steps: GCC 12 reports a false -Wrestrict for
    // `const char* + std::string&&` in a unity batch.
    out += "  ";
    out += PrintableText(line);
    out += '\n';
    start = end + 1;
  }
  return out;
}

// Waits `seconds` on the real clock (typed sessions; stations wait in their
// own loop, simulated sessions never).
void WaitS(double seconds) {
  if (seconds > 0.0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  }
}

// Everything one trial produced before the response.
struct Presented {
  std::vector<rs::TraceSamples> traces;
  std::vector<double> cues;  // one per interval (stand-in for a real ref.)
  double end_time_s = 0.0;   // session clock after the intervals
};

// The station's part of a trial's `extra`: the loop statistics of every
// simulated interval ("intervals") and how often the trial was cut short
// before this presentation ("aborted_presentations").
nlohmann::ordered_json LiveIntervalsJson(const LiveTrial& live) {
  nlohmann::ordered_json intervals = nlohmann::ordered_json::array();
  for (const LiveIntervalRecord& r : live.intervals) {
    nlohmann::ordered_json loop;
    loop["rate_hz"] = r.rate_hz;
    loop["ticks"] = r.counters.ticks;
    loop["period_error_p50_us"] = r.stats.p50_us;
    loop["period_error_p99_us"] = r.stats.p99_us;
    loop["period_error_max_us"] = r.stats.max_us;
    loop["missed_deadlines"] = r.counters.missed_deadlines;
    loop["non_finite_forces"] = r.counters.non_finite;
    loop["clamped_ticks"] = r.counters.clamped;
    loop["stale_reads"] = r.counters.stale_reads;
    loop["device_errors"] = r.counters.device_errors;
    loop["skipped_ticks"] = r.counters.skipped_ticks;
    nlohmann::ordered_json j;
    j["interval_index"] = r.interval_index;
    j["loop"] = loop;
    j["max_force_n"] = r.max_force_n;
    j["c_e_n_per_mm2"] = r.c_e_n_per_mm2;
    j["c_e_limited_from_n_per_mm2"] =
        r.c_e_limited_from_n_per_mm2.has_value()
            ? nlohmann::ordered_json(*r.c_e_limited_from_n_per_mm2)
            : nlohmann::ordered_json(nullptr);
    intervals.push_back(std::move(j));
  }
  nlohmann::ordered_json out;
  out["intervals"] = std::move(intervals);
  out["aborted_presentations"] = live.aborted_presentations;
  return out;
}

class SessionRunner {
 public:
  SessionRunner(const protocols::LoadedProtocol& loaded,
                const SessionOptions& options, Engine engine,
                rs::Journal journal)
      : loaded_(loaded),
        options_(options),
        engine_(std::move(engine)),
        journal_(std::move(journal)),
        observer_(options.observer) {}

  Status Replay(const std::vector<rs::TrialRecord>& records);
  Result<SessionSummary> Run();
  // Trials in the journal now (0 when it cannot be read).
  // Records in the journal that the session ran to its end.
  Status MarkComplete() { return journal_.MarkComplete(); }
  int StoredTrials() const {
    Result<int> n = journal_.NextTrialIndex();
    return n.ok() ? n.value() : 0;
  }

 private:
  Result<stimuli::IntervalResult> Present(const TrialSpec& trial,
                                          const stimuli::MaterialSet& set,
                                          double duration_s,
                                          std::uint64_t interval) const;
  // The simulator's rendering of `o` as the simulated subject explores it
  // (its exploration stream indexed by a and b, as the erosion seed), or the
  // shared pool's.
  Result<stimuli::IntervalResult> Render(const stimuli::IntervalOptions& o,
                                         std::uint64_t a,
                                         std::uint64_t b) const {
    const protocols::Exploration e = options_.responder == Responder::kSimulated
                                         ? options_.observer.exploration
                                         : protocols::Exploration{};
    if (options_.renderings != nullptr) {
      return options_.renderings->Present(o, e);
    }
    if (!e.Varies()) return stimuli::PresentSimulatedInterval(o);
    boost::random::mt19937 stream =
        protocols::StreamFor(options_.seed, StreamPurpose::kExploration, a, b);
    return stimuli::PresentSimulatedInterval(
        protocols::ExploredInterval(o, e, stream));
  }
  Result<Presented> PresentTrial(const TrialSpec& trial);
  // An adjustment trial's comparison after `path` (LiveStation), or none
  // past the block's max_steps.
  Result<std::optional<PlannedInterval>> AdjustedComparisonAt(
      const TrialSpec& trial, std::string_view path) const;
  // The cue of the standard of a one-interval trial's block, rendered.
  Result<double> StandardCue(const TrialSpec& trial);
  // A same-different block's materials a and b as the subject felt them in
  // familiarization (kFamiliarizationRenderings renderings of each, seeded
  // per block), felt at the block's first trial and remembered.
  Result<std::array<protocols::FeltMaterial, 2>> FamiliarizedMaterials(
      const TrialSpec& trial);
  Result<protocols::Response> SimulatedResponse(const TrialSpec& trial,
                                                Presented& presented);
  // The trial record's `source`: who answered.
  std::string SourceName() const {
    switch (options_.responder) {
      case Responder::kSimulated:
        return "simulated observer";
      case Responder::kTerminal:
        return "typed";
      case Responder::kStation:
        return options_.device.empty() ? "station"
                                       : "station " + options_.device;
    }
    return "";
  }
  Result<protocols::Response> TerminalResponse(const TrialSpec& trial);
  // kTerminal: the study's and the block's instructions and a rest break
  // that come before `trial`, each waiting for Enter when a person types
  // (SessionOptions::answers_timed); false when the input ended.
  bool TerminalIntroduce(const TrialSpec& trial);
  // Prints `prompt` and waits for Enter when a person types; from a pipe or
  // a file, prints `prompt` and `going_on` and goes on (no answer is
  // consumed). False when the input ended.
  bool WaitForEnter(std::string_view prompt, std::string_view going_on);
  rs::TraceSamples ToTrace(const TrialSpec& trial, int interval,
                           stimuli::IntervalResult&& result);

  const protocols::LoadedProtocol& loaded_;
  const SessionOptions& options_;
  Engine engine_;
  rs::Journal journal_;
  protocols::SimulatedObserver observer_;
  double clock_s_ = 0.0;
  protocols::RememberedStandards standards_;
  std::map<int, std::array<protocols::FeltMaterial, 2>> familiarized_;
  int correct_ = 0;
  int scored_ = 0;
};

Status SessionRunner::Replay(const std::vector<rs::TrialRecord>& records) {
  for (const rs::TrialRecord& r : records) {
    if (engine_.finished()) {
      return Error{fmt::format(
          "cannot resume: the journal holds trial {} but the protocol ends "
          "before it",
          r.trial_index)};
    }
    const TrialSpec& t = engine_.current();
    if (t.trial_index != r.trial_index || t.block != r.block) {
      return Error{fmt::format(
          "cannot resume: journal trial {} (block \"{}\") does not match the "
          "protocol's trial {} (block \"{}\")",
          r.trial_index, r.block, t.trial_index, t.block)};
    }
    if (r.correct.has_value() && !r.practice) {  // practice is not scored
      ++scored_;
      correct_ += *r.correct ? 1 : 0;
    }
    Result<protocols::Outcome> outcome =
        engine_.Respond({r.response, r.response_time_s});
    if (!outcome.ok()) {
      return Error{fmt::format("cannot resume at trial {}: {}", r.trial_index,
                               outcome.error().message)};
    }
    if (engine_.RngState() != r.rng_state) {
      return Error{fmt::format(
          "cannot resume: replaying trial {} does not reproduce the journal's "
          "random state (was the journal written by another burrlab "
          "version?)",
          r.trial_index)};
    }
    const auto extra = nlohmann::json::parse(r.extra, nullptr, false);
    if (extra.is_object() && extra.contains("session_time_end_s") &&
        extra["session_time_end_s"].is_number()) {
      clock_s_ = extra["session_time_end_s"].get<double>();
    }
  }
  return {};
}

Result<stimuli::IntervalResult> SessionRunner::Present(
    const TrialSpec& trial, const stimuli::MaterialSet& set, double duration_s,
    std::uint64_t interval) const {
  const std::uint64_t seed = protocols::SeedFor(
      options_.seed, StreamPurpose::kErosion,
      static_cast<std::uint64_t>(trial.trial_index), interval);
  Result<stimuli::IntervalResult> r =
      Render(IntervalOptionsFor(loaded_.protocol, options_.radius_mm, trial,
                                set, duration_s, seed),
             static_cast<std::uint64_t>(trial.trial_index), interval);
  if (!r.ok()) {
    return Error{fmt::format("trial {} interval {}: {}", trial.trial_index,
                             interval + 1, r.error().message)};
  }
  return r;
}

rs::TraceSamples SessionRunner::ToTrace(const TrialSpec& trial, int interval,
                                        stimuli::IntervalResult&& result) {
  rs::TraceSamples trace;
  trace.trial_index = trial.trial_index;
  trace.interval_index = interval;
  trace.sampling_frequency_hz = loaded_.protocol.trace_hz;
  trace.start_time_s = clock_s_;
  trace.columns = std::move(result.columns);
  trace.rows = std::move(result.rows);
  clock_s_ +=
      static_cast<double>(trace.rows.size()) / trace.sampling_frequency_hz;
  return trace;
}

Result<Presented> SessionRunner::PresentTrial(const TrialSpec& trial) {
  Presented p;
  for (std::size_t i = 0; i < trial.intervals.size(); ++i) {
    const PlannedInterval& interval = trial.intervals[i];
    // The blank gap before every interval but the first: on the session
    // clock, never waited for here.
    if (i > 0) clock_s_ += trial.isi_s;
    if (!interval.material.has_value()) {
      // A real sample outside the computer: nothing to render or record.
      // The simulated observer feels a stand-in: the material modelled on
      // the sample (an assumption: the model is right), off the record.
      p.cues.push_back(0.0);
      continue;
    }
    Result<stimuli::IntervalResult> r =
        Present(trial, *interval.material, interval.duration_s, i);
    if (!r.ok()) return r.error();
    p.cues.push_back(protocols::FeltCue(r->cue));
    p.traces.push_back(ToTrace(trial, static_cast<int>(i), std::move(*r)));
  }
  return p;
}

Result<double> SessionRunner::StandardCue(const TrialSpec& trial) {
  Result<stimuli::MaterialSet> standard =
      engine_.MaterialAt(trial.standard_level.value_or(0.0));
  if (!standard.ok()) return standard.error();
  const double duration =
      trial.intervals.empty() ? 10.0 : trial.intervals[0].duration_s;
  stimuli::IntervalOptions o = IntervalOptionsFor(
      loaded_.protocol, options_.radius_mm, trial, *standard, duration,
      protocols::SeedFor(
          options_.seed, StreamPurpose::kErosion,
          kStandardSeedBase + static_cast<std::uint64_t>(trial.block_index)));
  Result<stimuli::IntervalResult> r = Render(
      o, kStandardSeedBase + static_cast<std::uint64_t>(trial.block_index), 0);
  if (!r.ok()) return r.error();
  return protocols::FeltCue(r->cue);
}

Result<std::array<protocols::FeltMaterial, 2>>
SessionRunner::FamiliarizedMaterials(const TrialSpec& trial) {
  if (auto it = familiarized_.find(trial.block_index);
      it != familiarized_.end()) {
    return it->second;
  }
  const protocols::Block& block = loaded_.protocol.blocks[trial.block_index];
  std::array<protocols::FeltMaterial, 2> felt;
  int m = 0;
  for (const std::string& id : {block.material_a, block.material_b}) {
    const protocols::ProtocolMaterial* material =
        loaded_.protocol.FindMaterial(id);
    if (material == nullptr) {
      return Error{fmt::format("block \"{}\": material \"{}\" is missing",
                               block.name, id)};
    }
    std::vector<double> cues;
    for (int i = 0; i < kFamiliarizationRenderings; ++i) {
      const std::uint64_t index =
          kFamiliarizationSeedBase +
          static_cast<std::uint64_t>(
              (trial.block_index * 2 + m) * kFamiliarizationRenderings + i);
      Result<stimuli::IntervalResult> r =
          Render(IntervalOptionsFor(
                     loaded_.protocol, options_.radius_mm, trial, material->set,
                     trial.intervals.at(0).duration_s,
                     protocols::SeedFor(options_.seed, StreamPurpose::kErosion,
                                        index)),
                 index, 0);
      if (!r.ok()) return r.error();
      cues.push_back(protocols::FeltCue(r->cue));
    }
    felt[static_cast<std::size_t>(m++)] = protocols::FeltMaterialOf(cues);
  }
  familiarized_.emplace(trial.block_index, felt);
  return felt;
}

Result<std::optional<PlannedInterval>> SessionRunner::AdjustedComparisonAt(
    const TrialSpec& trial, std::string_view path) const {
  if (trial.method != protocols::Method::kAdjustment ||
      trial.intervals.size() < 2) {
    return Error{
        fmt::format("trial {} is not an adjustment", trial.trial_index + 1)};
  }
  // The path holds only '+' and '-', so the engine refuses it only past the
  // block's max_steps (a step at a bound stays at the bound).
  if (!engine_.PreviewAdjustment(path).ok()) {
    return std::optional<PlannedInterval>();
  }
  Result<PlannedInterval> comparison = engine_.AdjustedComparison(path);
  if (!comparison.ok()) return comparison.error();
  return std::optional<PlannedInterval>(std::move(comparison.value()));
}

Result<protocols::Response> SessionRunner::SimulatedResponse(
    const TrialSpec& trial, Presented& presented) {
  boost::random::mt19937 rng =
      protocols::StreamFor(options_.seed, StreamPurpose::kObserver,
                           static_cast<std::uint64_t>(trial.trial_index));
  const protocols::Block& block = loaded_.protocol.blocks[trial.block_index];
  // A real reference: the observer feels its stand-in.
  for (std::size_t i = 0; i < trial.intervals.size(); ++i) {
    if (trial.intervals[i].material.has_value()) continue;
    Result<const protocols::ProtocolMaterial*> m =
        protocols::ReferenceStandIn(loaded_.protocol, block);
    if (!m.ok()) return m.error();
    Result<stimuli::IntervalResult> r =
        Present(trial, (*m)->set, protocols::ReferenceStandInDuration(trial),
                kStandInInterval + i);
    if (!r.ok()) return r.error();
    presented.cues[i] = protocols::FeltCue(r->cue);
  }
  if (trial.method == protocols::Method::kAdjustment) {
    // Each step is rendered at the level it reaches, its trace kept.
    return observer_.Adjust(
        trial, presented.cues.at(0), presented.cues.at(1),
        block.adjustment.max_steps, rng,
        [&](const std::string& path) -> Result<std::optional<double>> {
          Result<double> level = engine_.PreviewAdjustment(path);
          if (!level.ok()) return std::optional<double>();  // beyond the limit
          Result<stimuli::MaterialSet> set = engine_.MaterialAt(level.value());
          if (!set.ok()) return set.error();
          const int interval = static_cast<int>(path.size()) + 1;
          clock_s_ += trial.isi_s;  // each step is one more interval
          Result<stimuli::IntervalResult> r =
              Present(trial, *set, trial.intervals[1].duration_s,
                      static_cast<std::uint64_t>(interval));
          if (!r.ok()) return r.error();
          const double cue = protocols::FeltCue(r->cue);
          presented.traces.push_back(ToTrace(trial, interval, std::move(*r)));
          return std::optional<double>(cue);
        });
  }
  Result<protocols::TrialCues> cues = standards_.CuesFor(
      trial, presented.cues, [&] { return StandardCue(trial); });
  if (!cues.ok()) return cues.error();
  if (trial.method == protocols::Method::kSameDifferent &&
      observer_.params().rule != protocols::SameDifferentRule::kFixed) {
    Result<std::array<protocols::FeltMaterial, 2>> felt =
        FamiliarizedMaterials(trial);
    if (!felt.ok()) return felt.error();
    cues->materials = *felt;
  }
  return observer_.Decide(trial, *cues, rng);
}

Result<protocols::Response> SessionRunner::TerminalResponse(
    const TrialSpec& trial) {
  std::ostream& out = *options_.prompt;
  // The block name, question and answers come from the protocol file: any
  // control byte in them is escaped, never sent to the terminal.
  out << fmt::format("\ntrial {} - block \"{}\" ({}, {})\n",
                     trial.trial_index + 1, PrintableText(trial.block),
                     protocols::MethodName(trial.method),
                     protocols::TaskName(trial.task));
  for (std::size_t i = 0; i < trial.intervals.size(); ++i) {
    const PlannedInterval& iv = trial.intervals[i];
    if (i > 0 && trial.isi_s > 0.0) {
      out.flush();
      WaitS(trial.isi_s);  // the blank gap between intervals
    }
    out << fmt::format("  interval {}: {}{}\n", i + 1,
                       iv.material.has_value() ? "simulated" : "real sample",
                       iv.duration_s > 0.0
                           ? fmt::format(", {} s", iv.duration_s)
                           : std::string(", as long as you like"));
  }
  std::string options;
  for (const std::string& o : trial.response_options) {
    // Appended in two steps: GCC 12 reports a false -Wrestrict for
    // `const char* + std::string&&` when this file shares a unity batch.
    if (!options.empty()) options += '/';
    options += PrintableText(o);
  }
  const std::string question = PrintableText(trial.question);
  for (;;) {
    if (trial.method == protocols::Method::kAdjustment) {
      out << question << " [path of + and - ending in =]: ";
    } else {
      out << question << " [" << options << "]: ";
    }
    out.flush();
    std::string line;
    const auto start = std::chrono::steady_clock::now();
    if (!std::getline(*options_.in, line)) {
      return Error{"input ended"};
    }
    const double rt =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) {
      line.pop_back();
    }
    const bool known = trial.method == protocols::Method::kAdjustment
                           ? (!line.empty() && line.back() == '=')
                           : std::find(trial.response_options.begin(),
                                       trial.response_options.end(),
                                       line) != trial.response_options.end();
    if (known) {
      // Answers from a pipe or a file were not timed by a person.
      return protocols::Response{line, options_.answers_timed
                                           ? std::optional<double>(rt)
                                           : std::nullopt};
    }
    out << "  please answer one of " << options << '\n';
  }
}

bool SessionRunner::WaitForEnter(std::string_view prompt,
                                 std::string_view going_on) {
  std::ostream& out = *options_.prompt;
  if (!options_.answers_timed) {
    out << prompt << ' ' << going_on << '\n';
    return true;
  }
  out << prompt << ' ';
  out.flush();
  std::string line;
  return static_cast<bool>(std::getline(*options_.in, line));
}

bool SessionRunner::TerminalIntroduce(const TrialSpec& trial) {
  std::ostream& out = *options_.prompt;
  constexpr std::string_view kGoingOn = "(input is not a terminal: going on)";
  if (!trial.study_instructions.empty()) {
    out << '\n' << IndentedLines(trial.study_instructions);
    if (!WaitForEnter("Press Enter to begin.", kGoingOn)) return false;
  }
  if (trial.break_before) {
    out << '\n';
    if (!WaitForEnter("Rest break: press Enter to continue", kGoingOn)) {
      return false;
    }
  }
  if (!trial.block_instructions.empty()) {
    out << fmt::format("\nblock \"{}\"{}:\n", PrintableText(trial.block),
                       trial.practice ? " (practice, not scored)" : "")
        << IndentedLines(trial.block_instructions);
    if (!WaitForEnter("Press Enter to start the block.", kGoingOn)) {
      return false;
    }
  }
  return true;
}

Result<SessionSummary> SessionRunner::Run() {
  SessionSummary summary;
  Result<int> next = journal_.NextTrialIndex();
  if (!next.ok()) return next.error();
  summary.trials_resumed = next.value();
  while (!engine_.finished()) {
    const TrialSpec trial = engine_.current();
    Result<Presented> presented = Presented{};
    Result<protocols::Response> response = protocols::Response{};
    nlohmann::ordered_json live_intervals;
    if (options_.responder == Responder::kStation) {
      Result<LiveTrial> live = options_.station->PresentTrial(
          trial, summary.trials_resumed + summary.trials_run,
          [&](std::string_view path) -> Result<std::optional<PlannedInterval>> {
            return AdjustedComparisonAt(trial, path);
          });
      if (!live.ok()) return live.error();
      if (!live->response.has_value()) {
        summary.stop_reason = live->stop_reason;
        summary.trials_total = summary.trials_resumed + summary.trials_run;
        return summary;
      }
      for (rs::TraceSamples& t : live->traces) {
        t.start_time_s += clock_s_;
        presented->traces.push_back(std::move(t));
      }
      clock_s_ += live->duration_s;
      response = std::move(*live->response);
      live_intervals = LiveIntervalsJson(*live);
    } else {
      if (options_.responder == Responder::kTerminal &&
          !TerminalIntroduce(trial)) {
        summary.trials_total = summary.trials_resumed + summary.trials_run;
        return summary;
      }
      presented = PresentTrial(trial);
      if (!presented.ok()) return presented.error();
      response = options_.responder == Responder::kSimulated
                     ? SimulatedResponse(trial, *presented)
                     : TerminalResponse(trial);
      if (!response.ok()) {
        if (response.error().message == "input ended") {
          summary.trials_total = summary.trials_resumed + summary.trials_run;
          return summary;
        }
        return response.error();
      }
      if (response->response_time_s.has_value()) {
        clock_s_ += *response->response_time_s;
      }
    }
    Result<protocols::Outcome> outcome = engine_.Respond(*response);
    if (!outcome.ok()) return outcome.error();

    rs::TrialRecord r;
    r.trial_index = trial.trial_index;
    r.block = trial.block;
    r.method = std::string(protocols::MethodName(trial.method));
    r.task = std::string(protocols::TaskName(trial.task));
    r.trial_type = trial.trial_type;
    r.stim_level = outcome->presented_level.has_value()
                       ? outcome->presented_level
                       : trial.level;
    r.stim_unit = trial.stim_unit;
    for (const PlannedInterval& iv : trial.intervals) {
      r.interval_materials.push_back(iv.material_id);
    }
    r.correct_answer = trial.correct_answer;
    r.response = response->answer;
    r.correct = outcome->correct;
    r.response_time_s = response->response_time_s;
    r.source = SourceName();
    r.practice = trial.practice;
    r.late = outcome->late;
    r.staircase_id = trial.staircase_id;
    r.reversal = outcome->reversal;
    r.step_size = outcome->step_size;
    r.estimate = outcome->estimate;
    r.rng_state = engine_.RngState();
    // The gap after the answer counts on the session clock (simulated
    // sessions wait for nothing, but model it).
    clock_s_ += trial.iti_s;
    nlohmann::ordered_json extra =
        nlohmann::ordered_json::parse(outcome->extra, nullptr, false);
    if (!extra.is_object()) extra = nlohmann::ordered_json::object();
    extra["session_time_end_s"] = clock_s_;
    extra["master_seed"] = std::to_string(options_.seed);
    if (options_.renderings != nullptr) {
      extra["rendering_pool"] = options_.renderings->renderings();
    }
    if (!live_intervals.is_null()) {
      for (auto& [key, value] : live_intervals.items()) extra[key] = value;
    }
    r.extra = extra.dump();
    if (Status s = journal_.Append(r, presented->traces); !s.ok()) {
      return Error{fmt::format(
          "cannot save trial {}: {} (the journal keeps the {} trials before "
          "it; fix the cause and run again with --resume)",
          trial.trial_index, s.error().message, trial.trial_index)};
    }
    if (r.correct.has_value() && !r.practice) {  // practice is not scored
      ++scored_;
      correct_ += *r.correct ? 1 : 0;
    }
    ++summary.trials_run;
    if (options_.responder == Responder::kStation) {
      const std::string stop =
          options_.station->AfterAnswer(trial, outcome->correct);
      if (!stop.empty()) {
        if (options_.on_trial) {
          options_.on_trial(summary.trials_resumed + summary.trials_run,
                            trial.block);
        }
        summary.stop_reason = stop;
        summary.trials_total = summary.trials_resumed + summary.trials_run;
        return summary;
      }
    }
    if (options_.responder == Responder::kTerminal) {
      if (trial.feedback && outcome->correct.has_value()) {
        // A terminal echoed the answer's line break; a pipe did not.
        *options_.prompt << (options_.answers_timed ? "" : "\n")
                         << (*outcome->correct ? "  correct\n" : "  wrong\n");
        options_.prompt->flush();
      }
      WaitS(trial.iti_s);
    }
    if (options_.on_trial) {
      options_.on_trial(summary.trials_resumed + summary.trials_run,
                        trial.block);
    }
  }
  summary.finished = true;
  summary.trials_total = summary.trials_resumed + summary.trials_run;
  if (options_.station != nullptr) options_.station->Finish();
  if (scored_ > 0) {
    summary.score = static_cast<double>(correct_) / scored_;
  }
  return summary;
}

}  // namespace

stimuli::IntervalOptions IntervalOptionsFor(
    const protocols::Protocol& p, double radius_mm, const TrialSpec& trial,
    const stimuli::MaterialSet& set, double duration_s, std::uint64_t seed) {
  stimuli::IntervalOptions o = protocols::SimulatedIntervalOptions(
      p, radius_mm, trial.task, set.material, duration_s);
  o.seed = seed;
  return o;
}

Status CheckRenderable(const protocols::LoadedProtocol& loaded,
                       double radius_mm) {
  const std::vector<protocols::Diagnostic> diagnostics =
      protocols::CheckSimulatedIntervals(loaded.protocol, radius_mm);
  if (diagnostics.empty()) return {};
  std::string all =
      protocols::FormatDiagnostics(loaded.path, loaded.text, diagnostics);
  if (!all.empty() && all.back() == '\n') all.pop_back();
  return Error{all};
}

std::string Sha256Hex(std::string_view text) {
  sha256_ctx ctx;
  sha256_init(&ctx);
  sha256_update(&ctx, text.size(),
                reinterpret_cast<const std::uint8_t*>(text.data()));
  std::uint8_t digest[SHA256_DIGEST_SIZE];
  sha256_digest(&ctx, SHA256_DIGEST_SIZE, digest);
  std::string hex;
  for (std::uint8_t b : digest) hex += fmt::format("{:02x}", b);
  return hex;
}

int ReportLoadError(std::ostream& err, const Error& error) {
  if (error.message.starts_with("cannot read ")) {
    err << "burrlab: " << error.message << '\n';
  } else {
    err << error.message << '\n';
  }
  return 1;
}

std::vector<rs::SetupField> SessionSetup(const SessionOptions& options) {
  auto or_none = [](const std::string& text) {
    return text.empty() ? std::string("none") : text;
  };
  std::string responder;
  switch (options.responder) {
    case Responder::kTerminal:
      responder = "typed";
      break;
    case Responder::kStation:
      responder = "station";
      break;
    case Responder::kSimulated: {
      const protocols::ObserverParams& o = options.observer;
      responder = fmt::format(
          "simulated weber_stiffness={} weber_removal={} lapse={} "
          "criterion={} rt_median_s={} rt_log_sd={} match_tolerance={}{}{}{}",
          o.weber_stiffness, o.weber_removal, o.lapse, o.criterion,
          o.rt_median_s, o.rt_log_sd, o.match_tolerance,
          o.rule == protocols::SameDifferentRule::kFixed
              ? ""
              : fmt::format(" rule={} bias={}",
                            protocols::SameDifferentRuleName(o.rule), o.bias),
          o.exploration.Varies()
              ? fmt::format(
                    " force_factor={} speed_factor={} force_spread={} "
                    "speed_spread={}",
                    o.exploration.force_factor, o.exploration.speed_factor,
                    o.exploration.force_spread, o.exploration.speed_spread)
              : "",
          o.answers == protocols::AnswerRule::kAlwaysCorrect ? " always=correct"
          : o.answers == protocols::AnswerRule::kAlwaysWrong ? " always=wrong"
                                                             : "");
      break;
    }
  }
  return {
      {"radius_mm", fmt::format("{}", options.radius_mm)},
      {"voxel_mm", fmt::format("{}", stimuli::IntervalOptions{}.voxel_mm)},
      {"subject_index", fmt::format("{}", options.subject_index)},
      {"responder", responder},
      {"device", or_none(options.device)},
      {"station_file_sha256", or_none(options.station_file_sha256)},
      {"renderings", options.renderings != nullptr
                         ? fmt::format("pool of {} per stimulus",
                                       options.renderings->renderings())
                         : std::string("fresh")},
  };
}

int PlannedTrials(const protocols::Protocol& protocol, int subject_index,
                  std::uint64_t seed) {
  for (const protocols::Block& b : protocol.blocks) {
    if (b.method == protocols::Method::kLimits ||
        b.method == protocols::Method::kAdjustment ||
        b.method == protocols::Method::kStaircase ||
        b.method == protocols::Method::kQuest) {
      return 0;
    }
  }
  Result<Engine> engine = Engine::Create(protocol, subject_index, seed);
  if (!engine.ok()) return 0;
  int n = 0;
  while (!engine->finished() && n < 1'000'000) {
    Result<protocols::Response> r =
        protocols::ScriptedResponse(engine->current(), "1");
    if (!r.ok() || !engine->Respond(*r).ok()) return 0;
    ++n;
  }
  return engine->finished() ? n : 0;
}

Status CheckDatasetOptions(const std::vector<std::string>& authors,
                           const std::vector<rs::ParticipantValue>& values) {
  for (const std::string& author : authors) {
    if (Status s = rs::ValidateAuthor(author); !s.ok()) return s;
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    const rs::ParticipantValue& v = values[i];
    if (Status s = rs::CheckParticipantColumn(v.column); !s.ok()) return s;
    if (Status s = rs::CheckParticipantValue(v.column, v.value); !s.ok()) {
      return s;
    }
    if (IsObserverColumn(v.column)) {
      return Error{fmt::format(
          "column {} is burrlab's: observer_* columns hold a simulated "
          "subject's observer parameters",
          v.column)};
    }
    for (std::size_t k = 0; k < i; ++k) {
      if (values[k].column == v.column) {
        return Error{fmt::format(
            "column {} is given twice ({} and {}); give each column once",
            v.column, values[k].value, v.value)};
      }
    }
  }
  return {};
}

rs::DatasetSource DatasetSourceOf(const protocols::LoadedProtocol& loaded) {
  rs::DatasetSource source;
  source.study = loaded.protocol.study_name;
  source.burrlab_version = BURRLAB_VERSION;
  source.protocol_path = loaded.path;
  source.protocol_text = loaded.text;
  source.protocol_sha256 = Sha256Hex(loaded.text);
  return source;
}

rs::ParticipantRow SessionParticipantRow(const SessionOptions& options) {
  rs::ParticipantRow row;
  row.subject = options.subject;
  row.values = options.participant;
  if (options.responder == Responder::kSimulated) {
    for (rs::ParticipantValue& v :
         ObserverParticipantValues(options.observer)) {
      row.values.push_back(std::move(v));
    }
  }
  return row;
}

Status ExportSession(const protocols::LoadedProtocol& loaded,
                     const SessionOptions& options) {
  if (Status s = rs::ExportBids(options.out_dir, options.subject,
                                {options.session, options.authors});
      !s.ok()) {
    return s;
  }
  if (Status s =
          rs::WriteDatasetSource(options.out_dir, DatasetSourceOf(loaded));
      !s.ok()) {
    return s;
  }
  const rs::ParticipantRow row = SessionParticipantRow(options);
  return rs::UpdateParticipants(options.out_dir, {&row, 1},
                                ObserverParticipantColumns());
}

Result<SessionSummary> RunSession(const protocols::LoadedProtocol& loaded,
                                  const SessionOptions& options) {
  rs::SessionInfo info;
  info.study = loaded.protocol.study_name;
  info.protocol_path = loaded.path;
  info.protocol_sha256 = Sha256Hex(loaded.text);
  info.subject_label = options.subject;
  info.master_seed = options.seed;
  info.burrlab_version = BURRLAB_VERSION;
  info.started_utc = UtcNow();
  info.setup = SessionSetup(options);
  if (Status s = rs::ValidateSubjectLabel(options.subject); !s.ok()) {
    return s.error();
  }
  if (!options.session.empty()) {
    if (Status s = rs::ValidateSessionLabel(options.session); !s.ok()) {
      return s.error();
    }
  }
  if (Status s = CheckDatasetOptions(options.authors, options.participant);
      !s.ok()) {
    return s.error();
  }
  // A participants table that cannot be merged is refused before the session
  // starts, not after it.
  if (options.export_bids) {
    if (Status s = rs::CheckParticipantsFiles(options.out_dir); !s.ok()) {
      return s.error();
    }
  }
  if (options.responder == Responder::kSimulated) {
    if (Status s = options.observer.Validate(); !s.ok()) return s.error();
  }
  if ((options.responder == Responder::kStation) !=
      (options.station != nullptr)) {
    return Error{"a station session needs a station (and only it does)"};
  }
  // Every stimulus the protocol can reach renders with this burr, or nothing
  // is written (a station renders in its own loop, on the device).
  if (options.responder != Responder::kStation) {
    if (Status s = CheckRenderable(loaded, options.radius_mm); !s.ok()) {
      return s.error();
    }
  }
  std::vector<rs::TrialRecord> records;
  auto journal = [&]() -> Result<rs::Journal> {
    if (!options.resume) {
      return rs::Journal::Create(options.out_dir, info, options.session);
    }
    Result<rs::Journal> opened =
        rs::Journal::Open(options.out_dir, options.subject, options.session);
    if (!opened.ok()) return opened;
    Result<int> stored = opened->NextTrialIndex();
    if (!stored.ok()) return stored.error();
    // A run that stopped before its first trial starts again as given now.
    Status same =
        *stored == 0 ? opened->Restart(info) : opened->CheckSameSession(info);
    if (!same.ok()) return same.error();
    return opened;
  }();
  if (!journal.ok()) return journal.error();
  if (Status s = journal->SetPlannedTrials(
          PlannedTrials(loaded.protocol, options.subject_index, options.seed));
      !s.ok()) {
    return s.error();
  }
  if (options.journal_limit_bytes_for_testing > 0) {
    if (Status s = journal->LimitSizeForTesting(
            options.journal_limit_bytes_for_testing);
        !s.ok()) {
      return s.error();
    }
  }
  if (options.resume) {
    Result<std::vector<rs::TrialRecord>> stored = journal->Trials();
    if (!stored.ok()) return stored.error();
    records = std::move(stored.value());
  }
  Result<Engine> engine =
      Engine::Create(loaded.protocol, options.subject_index, options.seed);
  if (!engine.ok()) return engine.error();
  SessionRunner runner(loaded, options, std::move(engine.value()),
                       std::move(journal.value()));
  if (Status s = runner.Replay(records); !s.ok()) return s.error();
  Result<SessionSummary> summary = runner.Run();
  if (!summary.ok()) {
    // What the journal holds is exported even so, for analyses to find.
    if (options.export_bids && runner.StoredTrials() > 0 &&
        ExportSession(loaded, options).ok()) {
      return Error{summary.error().message +
                   " (the trials saved so far are exported)"};
    }
    return summary;
  }
  if (summary->finished) {
    if (Status s = runner.MarkComplete(); !s.ok()) return s.error();
  }
  // The journal (and with it the session's lock) stays open through the
  // export, so no other run writes the session meanwhile.
  if (options.export_bids) {
    if (Status s = ExportSession(loaded, options); !s.ok()) {
      return Error{
          fmt::format("the journal is complete but the export "
                      "failed: {}",
                      s.error().message)};
    }
  }
  return summary;
}

}  // namespace burrlab::runner
