// plan, run and study.
#include "cli/session_commands.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "burrlab/base/file_text.h"
#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/observer.h"
#include "burrlab/protocols/protocol_file.h"
#include "burrlab/results_schema/bids_export.h"
#include "burrlab/results_schema/dataset_layout.h"
#include "burrlab/results_schema/journal.h"
#include "burrlab/results_schema/participants.h"
#include "burrlab/results_schema/records.h"
#include "burrlab/stimuli/interval.h"
#include "cli/flags.h"
#include "station/station_devices.h"
#include "station/station_file.h"
#include "station/station_script.h"
#include "station/station_session.h"
#include "station/window.h"
#include "studies/participant_rows.h"
#include "studies/progress.h"
#include "studies/rendering_pool.h"
#include "studies/session.h"
#include "studies/study.h"
#include "studies/virtual_study.h"

namespace burrlab::runner {
namespace {

using Json = nlohmann::ordered_json;

// "1,0,1" -> {"1","0","1"}; empty text -> none.
std::vector<std::string> SplitCommas(const std::string& text) {
  std::vector<std::string> items;
  if (text.empty()) return items;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    items.push_back(text.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

std::string FormatLevel(const std::optional<double>& level) {
  return level.has_value() ? fmt::format("{:.6g}", *level) : "n/a";
}

bool IsAdaptive(protocols::Method m) {
  return m == protocols::Method::kLimits ||
         m == protocols::Method::kAdjustment ||
         m == protocols::Method::kStaircase || m == protocols::Method::kQuest;
}

// Resolves the observer flag for a protocol.
Result<protocols::ObserverParams> ObserverFor(
    const protocols::Protocol& protocol, const std::string& spec) {
  const protocols::ObserverParams base =
      protocols::ObserverParamsFrom(protocol.observer);
  if (spec.empty()) return base;
  return protocols::ParseObserverSpec(spec, base);
}

// Station files and scripts are small; larger ones are refused unread.
constexpr std::uintmax_t kMaxStationFileBytes = 1 << 20;

// The text of a small file `what` names (e.g. "station file").
Result<std::string> ReadSmallFile(const std::string& path,
                                  std::string_view what) {
  std::variant<std::string, FileReadFailure> read =
      ReadFileBytes(path, kMaxStationFileBytes);
  if (std::string* text = std::get_if<std::string>(&read)) {
    return std::move(*text);
  }
  const FileReadFailure& failure = std::get<FileReadFailure>(read);
  if (failure.problem == FileProblem::kTooLarge) {
    return Error{
        fmt::format("{}: error: the file is {} bytes; a {} is "
                    "limited to {} bytes",
                    path, failure.size, what, kMaxStationFileBytes)};
  }
  return Error{
      failure.reason.empty()
          ? fmt::format("cannot read {} {}", what, path)
          : fmt::format("cannot read {} {}: {}", what, path, failure.reason)};
}

// The diagnostics of a parsed file, formatted as `burrlab validate` prints
// them (at most kMaxPrintedDiagnostics, then a count; without the final
// line break).
std::string Diagnostics(const std::string& path, const std::string& text,
                        const std::vector<protocols::Diagnostic>& all) {
  std::string out = protocols::FormatDiagnostics(path, text, all);
  if (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

// The dataset flags of `run` and `study`: --session, --author and (run only)
// --participant and --participants.
struct DatasetFlags {
  std::string session;
  std::vector<std::string> authors;
  std::vector<std::string> participant;  // KEY=VALUE, as given
  std::string participants_path;
};

// Declares --session (with `session_help`) and --author on `app`.
void AddSessionFlags(CLI::App& app, FlagSet& flags,
                     const std::string& session_help, DatasetFlags* f) {
  flags.AddText("--session", session_help, &f->session)->type_name("LABEL");
  app.add_option("--author", f->authors,
                 "an author of the dataset for dataset_description.json, one "
                 "name each (repeatable; BIDS validators warn of fewer than "
                 "two)")
      ->type_name("NAME")
      ->allow_extra_args(false);
}

// Checks --session and --author; the error, if any.
std::optional<std::string> CheckSessionFlags(const DatasetFlags& f) {
  if (!f.session.empty()) {
    if (Status s = results_schema::ValidateSessionLabel(f.session); !s.ok()) {
      return "--session: " + s.error().message;
    }
  }
  for (const std::string& author : f.authors) {
    if (Status s = results_schema::ValidateAuthor(author); !s.ok()) {
      return "--author: " + s.error().message;
    }
  }
  return std::nullopt;
}

// The subject's participants.tsv values from --participants FILE (its row)
// and --participant KEY=VALUE (given later, so a flag's value wins).
Result<std::vector<results_schema::ParticipantValue>> ParticipantValues(
    const DatasetFlags& f, const std::string& subject) {
  std::vector<results_schema::ParticipantValue> values;
  if (!f.participants_path.empty()) {
    Result<std::string> text = ReadTextFile(
        f.participants_path, results_schema::kMaxParticipantsBytes);
    if (!text.ok()) return text.error();
    Result<std::vector<results_schema::ParticipantRow>> rows =
        results_schema::ParseParticipantsTable(f.participants_path, *text);
    if (!rows.ok()) return rows.error();
    const auto row = std::find_if(rows->begin(), rows->end(),
                                  [&](const results_schema::ParticipantRow& r) {
                                    return r.subject == subject;
                                  });
    if (row == rows->end()) {
      return Error{fmt::format(
          "{}: error: no row for sub-{} (no participant_id is sub-{} or "
          "{})",
          f.participants_path, subject, subject, subject)};
    }
    for (const results_schema::ParticipantValue& v : row->values) {
      if (IsObserverColumn(v.column)) {
        return Error{fmt::format(
            "{}: error: column {} is burrlab's: observer_* columns hold a "
            "simulated subject's observer parameters",
            f.participants_path, v.column)};
      }
    }
    values = row->values;
  }
  std::vector<results_schema::ParticipantValue> given;
  for (const std::string& text : f.participant) {
    Result<results_schema::ParticipantValue> v =
        results_schema::ParseParticipantPair(text);
    if (!v.ok()) return v.error();
    given.push_back(std::move(v.value()));
  }
  if (Status s = CheckDatasetOptions({}, given); !s.ok()) {
    return Error{"--participant: " + s.error().message};
  }
  for (results_schema::ParticipantValue& v : given) {
    const auto same =
        std::find_if(values.begin(), values.end(),
                     [&](const results_schema::ParticipantValue& w) {
                       return w.column == v.column;
                     });
    if (same != values.end()) {
      same->value = std::move(v.value);
    } else {
      values.push_back(std::move(v));
    }
  }
  return values;
}

}  // namespace

int DefaultSubjectIndex(std::string_view label) {
  if (label.empty() || label.size() > 9) return 0;
  int value = 0;
  for (char c : label) {
    if (c < '0' || c > '9') return 0;
    value = value * 10 + (c - '0');
  }
  return value > 0 ? value - 1 : 0;
}

namespace {

// What the subject meets before trial `t` besides the trial itself, in order
// (protocols/README.md, "Pacing, practice and breaks"): the study's
// instructions, a rest break, and at a block's first trial how the block is
// paced and its instructions.
std::vector<std::string> PacingBefore(const protocols::TrialSpec& t,
                                      const protocols::Block& block) {
  std::vector<std::string> lines;
  if (!t.study_instructions.empty()) {
    lines.push_back("the study's instructions, until SPACE");
  }
  if (t.break_before) lines.push_back("a rest break, until a key");
  if (t.trial_in_block == 0) {
    std::vector<std::string> pacing;
    if (block.practice) pacing.push_back("practice (recorded, never scored)");
    if (block.feedback) pacing.push_back("feedback after each answer");
    if (block.isi_s > 0.0) {
      pacing.push_back(fmt::format("{} s between intervals", block.isi_s));
    }
    if (block.iti_s > 0.0) {
      pacing.push_back(fmt::format("{} s after each answer", block.iti_s));
    }
    if (block.response_deadline_s.has_value()) {
      pacing.push_back(fmt::format("answers after {} s are late",
                                   *block.response_deadline_s));
    }
    if (block.break_every.has_value()) {
      pacing.push_back(
          fmt::format("a rest break every {} trials", *block.break_every));
    }
    if (!pacing.empty()) {
      lines.push_back(
          fmt::format("block {}: {}", t.block, fmt::join(pacing, ", ")));
    }
    if (!t.block_instructions.empty()) {
      lines.push_back(
          fmt::format("block {}'s instructions, until SPACE", t.block));
    }
  }
  return lines;
}

}  // namespace

int RunPlanCommand(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Print the trial sequence a protocol produces for one subject and "
      "seed; adaptive blocks (limits, adjustment, staircase, QUEST) follow "
      "the scripted responses (1 = correct or yes, 0 = wrong or no; an "
      "adjustment takes a path like ++-=).",
      "burrlab plan"};
  std::string path;
  std::uint64_t seed = 1;
  std::string subject = "01";
  int subject_index = -1;
  std::string responses;
  bool json = false;
  app.add_option("file", path, "the protocol file")->required();
  FlagSet flags(&app);
  flags.AddSeed("--seed",
                "master seed (default 1; seed-N, as the exports write it, "
                "also works)",
                &seed);
  flags.AddText("--subject", "subject label (default 01)", &subject);
  flags.AddInteger("--subject-index",
                   "counterbalancing row (default: the label's number - 1)", 0,
                   1000000, &subject_index);
  flags.AddText("--responses", "scripted responses, comma separated",
                &responses);
  flags.AddSwitch("--json", "print the plan as JSON", &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  Result<protocols::LoadedProtocol> loaded = protocols::LoadProtocol(path);
  if (!loaded.ok()) return ReportLoadError(err, loaded.error());
  err << loaded->notes;
  if (subject_index < 0) subject_index = DefaultSubjectIndex(subject);
  Result<protocols::Engine> engine =
      protocols::Engine::Create(loaded->protocol, subject_index, seed);
  if (!engine.ok()) return Fail(err, engine.error().message);
  const std::vector<std::string> script = SplitCommas(responses);

  Json trials = Json::array();
  std::string stopped;
  std::size_t used = 0;
  std::string table = fmt::format(
      "{:>5}  {:<14} {:<16} {:<6} {:<10} {:>8}  {:<32} {:<8} {:<8} {:>9}\n",
      "trial", "block", "method", "task", "type", "level", "intervals",
      "correct", "response", "estimate");
  while (!engine->finished()) {
    const protocols::TrialSpec t = engine->current();
    const std::vector<std::string> before =
        PacingBefore(t, loaded->protocol.blocks[t.block_index]);
    protocols::Response response;
    if (used < script.size()) {
      Result<protocols::Response> r =
          protocols::ScriptedResponse(t, script[used]);
      if (!r.ok()) return Fail(err, r.error().message);
      response = std::move(r.value());
      ++used;
    } else if (IsAdaptive(t.method)) {
      stopped = fmt::format(
          "stopped before trial {}: block \"{}\" ({}) is adaptive and the "
          "scripted responses ran out ({} given)",
          t.trial_index, t.block, protocols::MethodName(t.method),
          script.size());
      break;
    }
    Result<protocols::Outcome> outcome = engine->Respond(response);
    if (!outcome.ok()) return Fail(err, outcome.error().message);
    std::vector<std::string> ids;
    for (const auto& iv : t.intervals) ids.push_back(iv.material_id);
    const std::optional<double> level = outcome->presented_level.has_value()
                                            ? outcome->presented_level
                                            : t.level;
    Json j;
    j["index"] = t.trial_index;
    j["block"] = t.block;
    j["method"] = std::string(protocols::MethodName(t.method));
    j["task"] = std::string(protocols::TaskName(t.task));
    j["trial_type"] = t.trial_type;
    j["level"] = level.has_value() ? Json(*level) : Json(nullptr);
    j["intervals"] = ids;
    j["correct_answer"] =
        t.correct_answer.empty() ? Json(nullptr) : Json(t.correct_answer);
    j["response"] =
        response.answer.empty() ? Json(nullptr) : Json(response.answer);
    j["correct"] =
        outcome->correct.has_value() ? Json(*outcome->correct) : Json(nullptr);
    if (t.staircase_id.has_value()) j["staircase_id"] = *t.staircase_id;
    if (outcome->reversal.has_value()) j["reversal"] = *outcome->reversal;
    if (IsAdaptive(t.method)) {
      j["estimate"] = outcome->estimate.has_value() ? Json(*outcome->estimate)
                                                    : Json(nullptr);
    }
    if (t.practice) j["practice"] = true;
    if (!before.empty()) j["before"] = before;
    trials.push_back(j);
    for (const std::string& line : before) table += "   -- " + line + '\n';
    std::string joined;
    for (const std::string& id : ids)
      joined += (joined.empty() ? "" : "|") + id;
    table += fmt::format(
        "{:>5}  {:<14} {:<16} {:<6} {:<10} {:>8}  {:<32} {:<8} {:<8} {:>9}\n",
        t.trial_index, t.block, protocols::MethodName(t.method),
        protocols::TaskName(t.task), t.trial_type, FormatLevel(level), joined,
        t.correct_answer.empty() ? "n/a" : t.correct_answer,
        response.answer.empty() ? "n/a" : response.answer,
        FormatLevel(outcome->estimate));
  }
  if (used < script.size()) {
    stopped = fmt::format("{} scripted responses were left over",
                          script.size() - used);
  }
  if (json) {
    Json doc;
    doc["protocol"] = path;
    doc["study"] = loaded->protocol.study_name;
    doc["seed"] = std::to_string(seed);
    doc["subject"] = subject;
    doc["subject_index"] = subject_index;
    Json order = Json::array();
    for (int b : engine->block_order()) {
      order.push_back(loaded->protocol.blocks[b].name);
    }
    doc["block_order"] = order;
    doc["trials"] = trials;
    doc["note"] = stopped.empty() ? Json(nullptr) : Json(stopped);
    out << doc.dump(2) << '\n';
  } else {
    out << table;
    if (!stopped.empty()) out << stopped << '\n';
  }
  return 0;
}

namespace {

// `burrlab run ... --device ...`: the flags a station run needs, checked.
struct StationFlags {
  std::string device;  // empty: no station
  std::string station_path;
  std::string script_path;
  std::string firmware_path;
  std::string screenshots_dir;
};

// The error for a bad combination of run flags, if any.
std::optional<std::string> CheckRunFlags(const StationFlags& f,
                                         const std::string& observer) {
  if (!f.device.empty() && f.device != "mouse" && f.device != "hid" &&
      f.device != "falcon" && f.device != "simulated") {
    return fmt::format(
        "--device must be one of mouse, hid, falcon, simulated, got '{}'",
        f.device);
  }
  const bool station = !f.device.empty() || !f.station_path.empty();
  if (station && !observer.empty()) {
    return std::string(
        "--observer cannot be combined with --device or --station: the "
        "simulated observer answers without a station");
  }
  if (!f.script_path.empty() && f.device != "simulated") {
    return std::string("--script needs --device simulated");
  }
  if (f.device == "simulated" && f.script_path.empty()) {
    return std::string(
        "--device simulated needs --script FILE (the burr's path and the "
        "answers)");
  }
  if (!f.firmware_path.empty() && f.device != "falcon") {
    return std::string("--firmware needs --device falcon");
  }
  if (!f.screenshots_dir.empty() && !station) {
    return std::string("--screenshots needs --device");
  }
  return std::nullopt;
}

// Runs the session at a station; prints like RunRunCommand.
int RunAtStation(const protocols::LoadedProtocol& loaded,
                 SessionOptions options, const StationFlags& f,
                 std::ostream& out, std::ostream& err) {
  std::optional<StationConfig> station;
  if (!f.station_path.empty()) {
    Result<std::string> text = ReadSmallFile(f.station_path, "station file");
    if (!text.ok()) return Fail(err, text.error().message);
    options.station_file_sha256 = Sha256Hex(*text);
    StationParseOutcome parsed = ParseStation(f.station_path, *text);
    if (!parsed.station.has_value()) {
      err << Diagnostics(f.station_path, *text, parsed.diagnostics) << '\n';
      return 1;
    }
    station = std::move(parsed.station);
  }
  const std::string backend = !f.device.empty() ? f.device : station->device;
  if (backend == "simulated" && f.script_path.empty()) {
    return Fail(err, fmt::format("{}: the simulated backend needs --script "
                                 "FILE (the burr's path and the answers)",
                                 f.station_path));
  }
  std::optional<StationScript> script;
  if (!f.script_path.empty()) {
    Result<std::string> text = ReadSmallFile(f.script_path, "station script");
    if (!text.ok()) return Fail(err, text.error().message);
    StationScriptParseOutcome parsed = ParseStationScript(f.script_path, *text);
    if (!parsed.script.has_value()) {
      err << Diagnostics(f.script_path, *text, parsed.diagnostics) << '\n';
      return 1;
    }
    script = std::move(parsed.script);
  }
  StationDeviceRequest request;
  request.backend = backend;
  request.station = station ? &*station : nullptr;
  request.script = script ? &*script : nullptr;
  request.firmware_path = f.firmware_path;
  if (backend == "hid" && (!station || !station->response_box.has_value())) {
    return Fail(err,
                "--device hid needs --station FILE with a "
                "[response_box] table (the box's ids and buttons)");
  }
  Result<StationDevices> devices = OpenStationDevices(request);
  if (!devices.ok()) return Fail(err, devices.error().message);

  const DeviceSpec& spec = devices->haptic->spec();
  RenderLimits limits;
  limits.max_force_n = station
                           ? std::min(station->max_force_n, spec.max_force_n)
                           : spec.max_force_n;
  limits.max_stiffness_n_per_mm = spec.max_stiffness_n_per_mm;
  if (station && station->max_stiffness_n_per_mm > 0.0) {
    limits.max_stiffness_n_per_mm =
        limits.max_stiffness_n_per_mm > 0.0
            ? std::min(limits.max_stiffness_n_per_mm,
                       station->max_stiffness_n_per_mm)
            : station->max_stiffness_n_per_mm;
  }
  WindowOptions window_options;
  if (station) {
    window_options.width = station->screen_width;
    window_options.height = station->screen_height;
  }
  window_options.title = fmt::format(
      "burrlab - {}",
      results_schema::SessionName(options.subject, options.session));
  Result<std::unique_ptr<StationWindow>> window =
      StationWindow::Open(window_options);
  if (!window.ok()) return Fail(err, window.error().message);

  StationSessionOptions so;
  so.device_name = backend;
  so.device = devices->haptic;
  so.mouse = devices->mouse.get();
  so.simulated = devices->simulated.get();
  so.box = devices->box.get();
  so.script = script ? &*script : nullptr;
  so.window = window->get();
  so.trials_total =
      PlannedTrials(loaded.protocol, options.subject_index, options.seed);
  so.radius_mm = options.radius_mm;
  so.trace_hz = loaded.protocol.trace_hz;
  so.limits = limits;
  so.screenshots_dir = f.screenshots_dir;
  so.log = &err;
  StationSession session(std::move(so));
  options.responder = Responder::kStation;
  options.station = &session;
  options.device = backend;
  Result<SessionSummary> summary = RunSession(loaded, options);
  if (!summary.ok()) return Fail(err, summary.error().message);
  const SessionSummary& s = summary.value();
  if (!s.finished) {
    out << fmt::format(
        "{}: stopped after {} trials: {}. They are saved; continue with "
        "--resume.\n",
        results_schema::SessionName(options.subject, options.session),
        s.trials_total, s.stop_reason);
    return 1;
  }
  out << fmt::format(
      "{}: {} trials ({} resumed, {} run now){}; results in {}\n",
      results_schema::SessionName(options.subject, options.session),
      s.trials_total, s.trials_resumed, s.trials_run,
      s.score.has_value() ? fmt::format(", {:.1f} % correct", 100.0 * *s.score)
                          : std::string(),
      options.out_dir.string());
  return 0;
}

}  // namespace

int RunRunCommand(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Run one subject's session. At a station (--device) a person feels "
      "every interval through the haptic device, rendered by the simulator "
      "in a 1 kHz loop, and answers in the subject window or on the "
      "response box; without one, every interval is rendered by the "
      "simulator and answers come from the simulated observer or are typed "
      "at the prompt. Each completed trial is saved before the next starts; "
      "--resume continues an interrupted session. The output folder is a "
      "BIDS dataset; its README says what each file holds.",
      "burrlab run"};
  std::string path;
  std::string subject;
  std::string out_dir;
  std::uint64_t seed = 1;
  int subject_index = -1;
  std::string observer;
  bool resume = false;
  double radius_mm = stimuli::kDefaultBurrRadiusMm;
  StationFlags station;
  DatasetFlags dataset;
  app.add_option("file", path, "the protocol file")->required();
  FlagSet flags(&app);
  flags.AddText("--subject", "subject label: letters and digits (required)",
                &subject);
  flags.AddText("--out", "output folder (required)", &out_dir);
  AddSessionFlags(app, flags,
                  "session label, letters and digits (e.g. 2 for the "
                  "subject's second visit): results go to "
                  "DIR/sub-<id>/ses-<label>/, and --resume continues that "
                  "session",
                  &dataset);
  app.add_option("--participant", dataset.participant,
                 "KEY=VALUE for the subject's row of participants.tsv, e.g. "
                 "age=34 or group=expert (repeatable; no names or dates of "
                 "birth)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  flags
      .AddText("--participants",
               "the experimenter's participants table (CSV or TSV, a "
               "participant_id column and one row per subject): the "
               "subject's row goes to participants.tsv",
               &dataset.participants_path)
      ->type_name("FILE");
  flags.AddSeed("--seed",
                "master seed (default 1; seed-N, as the exports write it, "
                "also works)",
                &seed);
  flags.AddInteger("--subject-index",
                   "counterbalancing row (default: the label's number - 1)", 0,
                   1000000, &subject_index);
  flags.AddText("--observer",
                "simulated[:weber=W,lapse=L,...] (default: answers typed at "
                "the prompt); keys weber, weber_stiffness, weber_removal, "
                "lapse, criterion, bias, rt_median_s, rule=fixed|differencing|"
                "likelihood (how a same-different observer decides), "
                "exploration=fixed|varied, force_spread, speed_spread, "
                "subject_force_spread, subject_speed_spread (how the "
                "simulated hand's force and speed vary), and "
                "always=correct or always=wrong: every answer right (or "
                "wrong), to dry-run a protocol to the ends of its levels",
                &observer);
  flags.AddSwitch("--resume", "continue the subject's interrupted session",
                  &resume);
  flags.AddPositive(
      "--radius-mm",
      fmt::format("burr radius (default {:g})", stimuli::kDefaultBurrRadiusMm),
      "mm", &radius_mm, 5.0);
  flags.AddText("--device",
                "mouse|hid|falcon|simulated: run at a station with this "
                "haptic device (overrides the station file's backend)",
                &station.device);
  flags.AddText("--station",
                "station file (burrlab-station/1): device, force limits, "
                "response box, screen",
                &station.station_path);
  flags.AddText("--script",
                "station script (burrlab-station-script/1) for --device "
                "simulated: the burr's path and the answers",
                &station.script_path);
  flags.AddText("--firmware",
                "Falcon firmware file, loaded when no firmware runs",
                &station.firmware_path);
  flags.AddText("--screenshots",
                "folder for a PNG of the subject window at each phase",
                &station.screenshots_dir);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  if (subject.empty()) return Fail(err, "--subject is required");
  if (out_dir.empty()) return Fail(err, "--out is required");
  if (std::optional<std::string> e = CheckRunFlags(station, observer)) {
    return Fail(err, *e);
  }
  if (std::optional<std::string> e = CheckSessionFlags(dataset)) {
    return Fail(err, *e);
  }
  Result<std::vector<results_schema::ParticipantValue>> participant =
      ParticipantValues(dataset, subject);
  if (!participant.ok()) return Fail(err, participant.error().message);
  if (Status s = results_schema::CheckParticipantsFiles(out_dir); !s.ok()) {
    return Fail(err, s.error().message);
  }
  Result<protocols::LoadedProtocol> loaded = protocols::LoadProtocol(path);
  if (!loaded.ok()) return ReportLoadError(err, loaded.error());
  err << loaded->notes;
  SessionOptions options;
  options.out_dir = out_dir;
  options.subject = subject;
  options.session = dataset.session;
  options.authors = dataset.authors;
  options.participant = std::move(participant.value());
  options.subject_index =
      subject_index >= 0 ? subject_index : DefaultSubjectIndex(subject);
  options.seed = seed;
  options.resume = resume;
  options.radius_mm = radius_mm;
  if (!station.device.empty() || !station.station_path.empty()) {
    return RunAtStation(loaded.value(), options, station, out, err);
  }
  if (Status s = CheckRenderable(loaded.value(), radius_mm); !s.ok()) {
    return ReportLoadError(err, s.error());
  }
  if (observer.empty()) {
    options.responder = Responder::kTerminal;
    options.in = &std::cin;
    options.prompt = &out;
    options.answers_timed = ::isatty(STDIN_FILENO) != 0;
  } else {
    Result<protocols::ObserverParams> params =
        ObserverFor(loaded->protocol, observer);
    if (!params.ok()) return Fail(err, params.error().message);
    options.observer = params.value();
  }
  Result<SessionSummary> summary = RunSession(loaded.value(), options);
  if (!summary.ok()) return Fail(err, summary.error().message);
  const SessionSummary& s = summary.value();
  if (!s.finished) {
    out << fmt::format(
        "{}: input ended after {} trials; they are saved. Continue with "
        "--resume.\n",
        results_schema::SessionName(subject, dataset.session), s.trials_total);
    return 1;
  }
  out << fmt::format(
      "{}: {} trials ({} resumed, {} run now){}; results "
      "in {}\n",
      results_schema::SessionName(subject, dataset.session), s.trials_total,
      s.trials_resumed, s.trials_run,
      s.score.has_value() ? fmt::format(", {:.1f} % correct", 100.0 * *s.score)
                          : std::string(),
      out_dir);
  return 0;
}

int RunStudyCommand(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Run a simulated population: N simulated subjects (labels 01, 02, "
      "...), each with its own seed derived from --seed and its own "
      "counterbalancing row, in parallel.",
      "burrlab study"};
  std::string path;
  int n_subjects = 0;
  std::string out_dir;
  std::uint64_t seed = 1;
  int jobs = 0;
  std::string observer;
  bool resume = false;
  double radius_mm = stimuli::kDefaultBurrRadiusMm;
  double weber_spread = 0.0;
  int renderings = 0;
  DatasetFlags dataset;
  app.add_option("file", path, "the protocol file")->required();
  FlagSet flags(&app);
  flags.AddInteger("--simulated-subjects", "number of subjects (required)", 1,
                   10000, &n_subjects);
  flags.AddText("--out", "output folder (required)", &out_dir);
  AddSessionFlags(app, flags,
                  "session label of every subject, letters and digits: "
                  "results go to DIR/sub-<id>/ses-<label>/",
                  &dataset);
  flags.AddUnsigned("--seed", "study seed (default 1)", &seed);
  flags.AddInteger("--jobs", "parallel sessions (default: the core count)", 1,
                   256, &jobs);
  flags.AddText("--observer",
                "simulated[:weber=W,lapse=L,...]; keys as for run, "
                "always=correct|wrong included",
                &observer);
  flags.AddSwitch("--resume",
                  "continue interrupted subjects and run the missing ones",
                  &resume);
  flags.AddPositive(
      "--radius-mm",
      fmt::format("burr radius (default {:g})", stimuli::kDefaultBurrRadiusMm),
      "mm", &radius_mm, 5.0);
  flags.AddNonNegative(
      "--weber-spread",
      "SD of ln(Weber fraction) across subjects: subject i's observer has "
      "the Weber fractions times exp(z spread), z ~ N(0,1) drawn from the "
      "seed and i (default 0: all alike)",
      "", &weber_spread);
  flags.AddInteger(
      "--renderings",
      "render each distinct stimulus K times and let all intervals share "
      "these renderings, picked by their erosion seeds (fast pilots and "
      "demos; default: every interval rendered afresh)",
      1, 100000, &renderings);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  if (n_subjects <= 0) return Fail(err, "--simulated-subjects is required");
  if (out_dir.empty()) return Fail(err, "--out is required");
  if (std::optional<std::string> e = CheckSessionFlags(dataset)) {
    return Fail(err, *e);
  }
  if (Status s = results_schema::CheckParticipantsFiles(out_dir); !s.ok()) {
    return Fail(err, s.error().message);
  }
  Result<protocols::LoadedProtocol> loaded = protocols::LoadProtocol(path);
  if (!loaded.ok()) return ReportLoadError(err, loaded.error());
  err << loaded->notes;
  if (Status s = CheckRenderable(loaded.value(), radius_mm); !s.ok()) {
    return ReportLoadError(err, s.error());
  }
  Result<protocols::ObserverParams> params =
      ObserverFor(loaded->protocol, observer.empty() ? "simulated" : observer);
  if (!params.ok()) return Fail(err, params.error().message);
  VirtualStudyOptions population;
  population.seed = seed;
  population.observer = params.value();
  population.spread_stiffness = weber_spread;
  population.spread_removal = weber_spread;
  std::unique_ptr<RenderingPool> pool;
  if (renderings > 0) pool = std::make_unique<RenderingPool>(renderings, seed);
  if (jobs <= 0) {
    jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }
  SimulatedStudyOptions study;
  study.out_dir = out_dir;
  study.labels = SubjectLabels(n_subjects);
  study.session = dataset.session;
  study.authors = dataset.authors;
  for (int i = 0; i < n_subjects; ++i) {
    study.observers.push_back(SubjectObserver(population, i));
  }
  study.seed = seed;
  study.jobs = jobs;
  study.radius_mm = radius_mm;
  study.resume = resume;
  study.renderings = pool.get();
  // Refuse before running anything when a subject exists (never overwrite).
  if (Status s = CheckNoSubjectExists(study); !s.ok()) {
    return Fail(err, s.error().message);
  }
  ProgressBar bar(err, n_subjects);
  study.progress = [&](int done, const std::string& label) {
    bar.Update(done, results_schema::SessionName(label, study.session));
  };
  const SimulatedStudyResult result = RunSimulatedStudy(loaded.value(), study);
  const int failed = result.failed();
  for (std::size_t i = 0; i < study.labels.size(); ++i) {
    if (!result.failures[i].empty()) {
      err << fmt::format(
          "burrlab: {}: {}\n",
          results_schema::SessionName(study.labels[i], study.session),
          result.failures[i]);
    }
  }
  const std::vector<std::optional<double>>& scores = result.scores;
  double sum = 0.0;
  int scored = 0;
  for (const auto& s : scores) {
    if (s.has_value()) {
      sum += *s;
      ++scored;
    }
  }
  out << fmt::format(
      "{} of {} simulated subjects completed{}; results in {}\n",
      n_subjects - failed, n_subjects,
      scored > 0 ? fmt::format(", mean {:.1f} % correct", 100.0 * sum / scored)
                 : std::string(),
      out_dir);
  return failed == 0 ? 0 : 1;
}

}  // namespace burrlab::runner
