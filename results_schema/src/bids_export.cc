// BIDS-style export of one subject's journal: behavioural TSV + sidecar per
// block, physiological traces as headerless .tsv.gz + sidecar, and the
// dataset description.
#include "burrlab/results_schema/bids_export.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <system_error>

#include "burrlab/base/file_text.h"
#include "burrlab/results_schema/dataset_layout.h"
#include "burrlab/results_schema/journal.h"
#include "burrlab/results_schema/records.h"
#include "file_writes.h"
#include "journal_db.h"
#include "text.h"

namespace burrlab::results_schema {
namespace fs = std::filesystem;
namespace {

using OrderedJson = nlohmann::ordered_json;

std::string OrNa(std::string_view text) {
  return text.empty() ? std::string(kNa) : std::string(text);
}

std::string OrNa(const std::optional<double>& value) {
  return value ? FormatDouble(*value) : std::string(kNa);
}

std::string OrNa(const std::optional<int>& value) {
  return value ? std::to_string(*value) : std::string(kNa);
}

std::string OrNa(const std::optional<bool>& value) {
  return value ? (*value ? "1" : "0") : std::string(kNa);
}

std::string Joined(const std::vector<std::string>& items,
                   std::string_view sep) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += sep;
    out += items[i];
  }
  return out;
}

std::string MethodDescription(const std::string& method) {
  static const std::map<std::string, std::string, std::less<>> kKnown = {
      {"same_different",
       "same-different: two intervals; the subject answers whether they felt "
       "the same"},
      {"two_interval",
       "two-interval forced choice, or the three-interval reference design"},
      {"constant_stimuli", "method of constant stimuli"},
      {"limits", "method of limits (ascending and descending series)"},
      {"adjustment", "method of adjustment"},
      {"staircase", "adaptive staircase (n-down/1-up)"},
      {"quest", "QUEST adaptive method (Watson & Pelli)"}};
  const auto it = kKnown.find(method);
  return it != kKnown.end() ? it->second : method;
}

std::string TrialTypeDescription(const std::string& type) {
  static const std::map<std::string, std::string, std::less<>> kKnown = {
      {"AA", "same material (A) in both intervals"},
      {"BB", "same material (B) in both intervals"},
      {"AB", "material A, then material B"},
      {"BA", "material B, then material A"}};
  const auto it = kKnown.find(type);
  return it != kKnown.end() ? it->second : fmt::format("trial type {}", type);
}

// The unit given by a snake_case column name's suffix (burrlab's names carry
// their units), longest suffix first; empty when none is recognised.
std::string UnitsFromName(std::string_view column) {
  static constexpr std::pair<std::string_view, std::string_view> kSuffixes[] = {
      {"_n_per_mm2", "N/mm^2"},
      {"_mm_per_s", "mm/s"},
      {"_rad_per_s", "rad/s"},
      {"_n_per_mm", "N/mm"},
      {"_mm3", "mm^3"},
      {"_per_s", "1/s"},
      {"_mm", "mm"},
      {"_hz", "Hz"},
      {"_rad", "rad"},
      {"_n", "N"},
      {"_s", "s"}};
  for (const auto& [suffix, units] : kSuffixes) {
    if (column.size() > suffix.size() && column.ends_with(suffix)) {
      return std::string(units);
    }
  }
  return {};
}

OrderedJson Column(std::string_view description) {
  OrderedJson column;
  column["Description"] = description;
  return column;
}

// The value of every _beh.tsv column for one trial, in BehColumns() order.
Result<std::vector<std::string>> BehRow(const TrialRecord& t,
                                        const SessionInfo& session) {
  const auto extra = nlohmann::json::parse(t.extra, nullptr, false);
  if (extra.is_discarded() || !extra.is_object()) {
    return Error{
        fmt::format("trial {}: extra is not a JSON object", t.trial_index)};
  }
  return std::vector<std::string>{
      std::to_string(t.trial_index),
      t.block,
      t.method,
      t.task,
      OrNa(t.trial_type),
      t.practice ? std::string("1") : std::string("0"),
      OrNa(t.stim_level),
      OrNa(t.stim_unit),
      t.interval_materials.empty() ? std::string(kNa)
                                   : Joined(t.interval_materials, "+"),
      OrNa(t.correct_answer),
      OrNa(t.response),
      OrNa(t.correct),
      OrNa(t.response_time_s),
      OrNa(t.late),
      OrNa(t.source),
      OrNa(t.staircase_id),
      OrNa(t.reversal),
      OrNa(t.step_size),
      OrNa(t.estimate),
      SeedText(session.master_seed),
      extra.empty() ? std::string(kNa)
                    : extra.dump(-1, ' ', false,
                                 nlohmann::json::error_handler_t::replace)};
}

std::string BehSidecar(const std::string& block,
                       const std::vector<const TrialRecord*>& trials) {
  std::set<std::string> methods;
  std::set<std::string> trial_types;
  std::set<std::string> units;
  for (const TrialRecord* t : trials) {
    methods.insert(t->method);
    if (!t->trial_type.empty()) trial_types.insert(t->trial_type);
    units.insert(t->stim_unit);
  }
  const std::optional<std::string> uniform_units =
      units.size() == 1 && !units.begin()->empty()
          ? std::optional<std::string>(*units.begin())
          : std::nullopt;
  OrderedJson j;
  j["TaskName"] = block;
  j["trial_index"] = Column(
      "0-based index of the trial within the session, counted over all blocks");
  j["block"] = Column("Block name from the protocol file");
  j["method"] = Column("Psychophysical method of the block");
  for (const std::string& m : methods)
    j["method"]["Levels"][m] = MethodDescription(m);
  j["task"] = Column("What the subject did with the burr in each interval");
  j["task"]["Levels"]["probe"] =
      "burr not rotating: press into the material and judge it";
  j["task"]["Levels"]["drill"] = "burr rotating: cut into the material";
  j["trial_type"] =
      Column("Method-specific kind of trial (n/a when the method has none)");
  for (const std::string& type : trial_types) {
    j["trial_type"]["Levels"][type] = TrialTypeDescription(type);
  }
  j["practice"] = Column(
      "Whether the trial belongs to a practice block: a familiarization "
      "trial, run and recorded like the others but left out of scores");
  j["practice"]["Levels"]["1"] = "practice (not scored)";
  j["practice"]["Levels"]["0"] = "scored";
  j["stim_level"] = Column(
      "Level of the varied stimulus parameter in this trial (n/a when the "
      "design has none)");
  if (uniform_units) j["stim_level"]["Units"] = *uniform_units;
  j["stim_unit"] = Column("Unit of stim_level (n/a when none)");
  j["interval_materials"] =
      Column("Material presented in each interval, in order, joined with '+'");
  j["correct_answer"] =
      Column("Answer counted as correct (n/a when the design has none)");
  j["response"] = Column("The subject's answer (n/a when missed)");
  j["correct"] = Column(
      "Whether the response was correct (n/a when the "
      "design has no correct answer)");
  j["correct"]["Levels"]["1"] = "correct";
  j["correct"]["Levels"]["0"] = "incorrect";
  j["response_time"] =
      Column("Time from the response prompt to the answer (n/a when missed)");
  j["response_time"]["Units"] = "s";
  j["late"] = Column(
      "Whether the answer came after the block's response deadline; a late "
      "answer is kept and scored like the others (n/a when the block has no "
      "deadline or the response time is unknown)");
  j["late"]["Levels"]["1"] = "after the deadline";
  j["late"]["Levels"]["0"] = "in time";
  j["source"] = Column(
      "Who answered: typed (at the prompt), station <device> (a person at a "
      "station with that haptic device) or simulated observer (n/a when the "
      "journal did not record it)");
  j["staircase_id"] = Column(
      "Which interleaved staircase the trial belongs to, 0-based (n/a for "
      "other methods)");
  j["reversal"] = Column(
      "Whether this trial reversed the direction of its staircase (n/a for "
      "other methods)");
  j["reversal"]["Levels"]["1"] = "reversal";
  j["reversal"]["Levels"]["0"] = "no reversal";
  j["step_size"] = Column(
      "Adaptive step size in effect after this trial, on the staircase's step "
      "scale (linear, log or dB; n/a for other methods)");
  j["estimate"] = Column(
      "Threshold estimate after this trial (n/a for non-adaptive methods)");
  if (uniform_units) j["estimate"]["Units"] = *uniform_units;
  j["seed"] = Column(
      "Master seed of the session; every random stream derives from it. "
      "Written as text, \"seed-\" and the decimal digits of the 64-bit "
      "number, so that no reader rounds it (R's read.delim and pandas read a "
      "long integer as a double, exact only below 2^53); `burrlab run "
      "--seed` takes it as written to run the session again");
  j["extra"] =
      Column("Method-specific fields as a compact JSON object (n/a when none)");
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

// Describes the columns of sub-<id>[_ses-<session>]_scans.tsv.
std::string ScansSidecar(bool labelled_session) {
  OrderedJson j;
  j["filename"] = Column("A data file of the subject, relative to its folder");
  j["session_status"] = Column(
      "Whether the session that produced the file ran to its end; a file of "
      "an incomplete session holds the trials saved before it stopped (on an "
      "error, a stop or a kill), and `burrlab run PROTOCOL --subject <id> " +
      std::string(labelled_session ? "--session <session> " : "") +
      "--out DIR --resume` finishes it (n/a: the journal predates this "
      "record)");
  j["session_status"]["Levels"]["complete"] = "the session ran to its end";
  j["session_status"]["Levels"]["incomplete"] =
      "the session stopped before its end";
  j["session_trials"] = Column("Trials the session has saved");
  j["session_planned_trials"] = Column(
      "Trials the session presents when it runs to its end (n/a when its "
      "adaptive blocks decide)");
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

// Traces of one kind (same sampling frequency and columns) within a block.
struct TraceGroup {
  double sampling_frequency_hz = 0.0;
  std::vector<std::string> columns;
  double start_time_s = 0.0;              // of the first trace
  std::set<std::pair<int, int>> members;  // (trial_index, interval_index)
};

std::string PhysioSidecar(const TraceGroup& group) {
  OrderedJson j;
  j["SamplingFrequency"] = group.sampling_frequency_hz;
  j["StartTime"] = group.start_time_s;
  std::vector<std::string> columns = PhysioLeadingColumns();
  columns.insert(columns.end(), group.columns.begin(), group.columns.end());
  j["Columns"] = columns;
  j["trial_index"] =
      Column("Trial (trial_index in the _beh.tsv) of the sample");
  j["interval_index"] = Column("0-based interval within the trial");
  j["time"] = Column(
      "Sample time on the session clock (virtual time for simulated subjects)");
  j["time"]["Units"] = "s";
  for (const std::string& column : group.columns) {
    j[column] = Column(
        fmt::format("Trace column {} recorded during the interval", column));
    const std::string units = UnitsFromName(column);
    if (!units.empty()) j[column]["Units"] = units;
  }
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

// Streams one group's samples into a gzip file, then renames it into place.
Status WritePhysio(sqlite3* db, const fs::path& journal_path,
                   const fs::path& path, const TraceGroup& group,
                   const std::vector<const TrialRecord*>& trials) {
  const fs::path temp = TempPathFor(path);
  const std::string mode = "wb" + std::to_string(kTraceDeflateLevel);
  gzFile gz = gzopen(temp.c_str(), mode.c_str());
  if (gz == nullptr) return WriteError(temp, errno != 0 ? errno : ENOMEM);
  auto fail = [&](Error error) {
    gzclose(gz);
    std::remove(temp.c_str());
    return error;
  };
  std::string line;
  for (const TrialRecord* trial : trials) {
    Result<std::vector<TraceSamples>> traces =
        db::ReadTraces(db, journal_path, trial->trial_index);
    if (!traces) return fail(traces.error());
    for (const TraceSamples& trace : *traces) {
      if (!group.members.contains({trace.trial_index, trace.interval_index})) {
        continue;
      }
      for (std::size_t i = 0; i < trace.rows.size(); ++i) {
        line = fmt::format(
            "{}\t{}\t{}", trace.trial_index, trace.interval_index,
            FormatDouble(trace.start_time_s +
                         static_cast<double>(i) / trace.sampling_frequency_hz));
        for (double value : trace.rows[i]) {
          line += '\t';
          line += std::isfinite(value) ? FormatDouble(value) : std::string(kNa);
        }
        line += '\n';
        if (gzwrite(gz, line.data(), static_cast<unsigned>(line.size())) !=
            static_cast<int>(line.size())) {
          int errnum = 0;
          const char* message = gzerror(gz, &errnum);
          return fail(Error{
              fmt::format("cannot write {}: {}", temp.string(),
                          errnum == Z_ERRNO ? std::strerror(errno) : message)});
        }
      }
    }
  }
  if (gzclose(gz) != Z_OK) {
    std::remove(temp.c_str());
    return WriteError(temp, errno != 0 ? errno : EIO);
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    std::remove(temp.c_str());
    return WriteError(path, err);
  }
  return {};
}

// Ends the read transaction that gives the export one consistent snapshot.
struct ReadTransaction {
  sqlite3* db;
  ~ReadTransaction() { db::RollbackIfOpen(db); }
};

// Largest dataset_description.json read back to add authors (bytes).
constexpr std::uintmax_t kMaxDescriptionBytes = 1 << 20;

// Writes DIR/dataset_description.json when absent; when present, adds the
// `authors` its Authors list lacks (in order, after its own) and keeps the
// rest of the file as it is.
Status WriteDatasetDescription(const fs::path& dir,
                               const OrderedJson& description,
                               const std::vector<std::string>& authors) {
  const fs::path path = dir / "dataset_description.json";
  std::error_code ec;
  if (fs::symlink_status(path, ec).type() == fs::file_type::not_found) {
    return WriteIfAbsent(
        path, description.dump(2, ' ', false,
                               nlohmann::json::error_handler_t::replace) +
                  "\n");
  }
  if (authors.empty()) return {};
  Result<std::string> text = ReadTextFile(path.string(), kMaxDescriptionBytes);
  if (!text) return text.error();
  OrderedJson kept = OrderedJson::parse(*text, nullptr, false);
  const auto refuse = [&](std::string_view why) {
    return Error{fmt::format(
        "cannot add the authors to {}: {}; fix or remove the file and export "
        "again",
        path.string(), why)};
  };
  if (kept.is_discarded() || !kept.is_object()) {
    return refuse("it is not a JSON object");
  }
  if (kept.contains("Authors") && !kept["Authors"].is_array()) {
    return refuse("its Authors is not a list");
  }
  OrderedJson& listed = kept["Authors"];
  if (listed.is_null()) listed = OrderedJson::array();
  bool added = false;
  for (const std::string& author : authors) {
    if (std::find(listed.begin(), listed.end(), OrderedJson(author)) ==
        listed.end()) {
      listed.push_back(author);
      added = true;
    }
  }
  if (!added) return {};
  return ReplaceFile(
      path, kept.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
                "\n");
}

Status Export(const fs::path& dir, std::string_view label,
              const BidsExportOptions& options) {
  if (Status s = ValidateSubjectLabel(label); !s) return s;
  const std::string& session_label = options.session;
  if (!session_label.empty()) {
    if (Status s = ValidateSessionLabel(session_label); !s) return s;
  }
  for (const std::string& author : options.authors) {
    if (Status s = ValidateAuthor(author); !s) return s;
  }
  const fs::path journal_path = JournalPath(dir, label, session_label);
  std::error_code ec;
  if (fs::symlink_status(journal_path, ec).type() == fs::file_type::not_found) {
    return Error{
        fmt::format("no journal for {} in {} ({} does not exist); "
                    "nothing to export",
                    SessionName(label, session_label), dir.string(),
                    journal_path.string())};
  }
  auto opened = db::OpenDb(journal_path, /*create=*/false);
  if (!opened) return opened.error();
  sqlite3* db = opened->get();
  if (auto version = db::CheckSchemaVersion(db, journal_path); !version) {
    return version.error();
  }
  if (Status s = db::Exec(db, "BEGIN", "cannot read", journal_path); !s)
    return s;
  ReadTransaction snapshot{db};
  Result<SessionInfo> session = db::ReadSession(db, journal_path);
  if (!session) return session.error();
  Result<std::vector<TrialRecord>> trials = db::ReadTrials(db, journal_path);
  if (!trials) return trials.error();
  Result<std::vector<db::TraceHeader>> headers =
      db::ReadTraceHeaders(db, journal_path);
  if (!headers) return headers.error();
  Result<SessionProgress> progress = db::ReadProgress(db, journal_path);
  if (!progress) return progress.error();
  for (const TrialRecord& t : *trials) {
    if (Status s = ValidateTrial(t); !s) {
      return Error{
          fmt::format("{}: {}", journal_path.string(), s.error().message)};
    }
  }

  // Blocks in order of first appearance, each with a distinct task label.
  std::vector<std::string> blocks;
  std::map<std::string, std::vector<const TrialRecord*>> block_trials;
  for (const TrialRecord& t : *trials) {
    auto& list = block_trials[t.block];
    if (list.empty()) blocks.push_back(t.block);
    list.push_back(&t);
  }
  std::map<std::string, std::string> task_labels;
  std::set<std::string> used_labels;
  for (const std::string& block : blocks) {
    const std::string base = TaskLabel(block);
    std::string task = base;
    for (int n = 2; used_labels.contains(task); ++n)
      task = fmt::format("{}{}", base, n);
    used_labels.insert(task);
    task_labels[block] = task;
  }

  // Files at the dataset root, only when absent.
  fs::create_directories(dir, ec);
  if (ec) {
    return Error{
        fmt::format("cannot create folder {}: {}", dir.string(), ec.message())};
  }
  RemoveStaleTempFiles(dir);
  OrderedJson description;
  description["Name"] = session->study;
  description["BIDSVersion"] = kBidsVersion;
  description["DatasetType"] = "raw";
  if (!options.authors.empty()) description["Authors"] = options.authors;
  description["GeneratedBy"] = OrderedJson::array(
      {{{"Name", "burrlab"}, {"Version", session->burrlab_version}}});
  if (Status s = WriteDatasetDescription(dir, description, options.authors);
      !s) {
    return s;
  }
  if (Status s = WriteIfAbsent(dir / ".bidsignore", "journal.sqlite*\n"); !s) {
    return s;
  }

  // Every file name of the session starts with `prefix`.
  const std::string prefix = SessionFilePrefix(label, session_label);
  const fs::path session_dir = SessionFolder(dir, label, session_label);
  const fs::path beh_dir = session_dir / "beh";
  RemoveStaleTempFiles(beh_dir);
  fs::create_directories(beh_dir, ec);
  if (ec) {
    return Error{fmt::format("cannot create folder {}: {}", beh_dir.string(),
                             ec.message())};
  }
  std::vector<std::string> scanned;  // files for the scans.tsv, in order
  for (const std::string& block : blocks) {
    const std::vector<const TrialRecord*>& list = block_trials[block];
    const std::string stem =
        fmt::format("{}_task-{}", prefix, task_labels.at(block));

    std::string tsv = Joined(BehColumns(), "\t") + "\n";
    for (const TrialRecord* t : list) {
      Result<std::vector<std::string>> row = BehRow(*t, *session);
      if (!row) return row.error();
      tsv += Joined(*row, "\t") + "\n";
    }
    if (Status s = ReplaceFile(beh_dir / (stem + "_beh.tsv"), tsv); !s)
      return s;
    if (Status s = ReplaceFile(beh_dir / (stem + "_beh.json"),
                               BehSidecar(block, list));
        !s) {
      return s;
    }

    scanned.push_back("beh/" + stem + "_beh.tsv");

    std::set<int> in_block;
    for (const TrialRecord* t : list) in_block.insert(t->trial_index);
    std::vector<TraceGroup> groups;
    for (const db::TraceHeader& h : *headers) {
      if (!in_block.contains(h.trace.trial_index)) continue;
      auto it =
          std::find_if(groups.begin(), groups.end(), [&](const TraceGroup& g) {
            return g.sampling_frequency_hz == h.trace.sampling_frequency_hz &&
                   g.columns == h.trace.columns;
          });
      if (it == groups.end()) {
        groups.push_back(TraceGroup{h.trace.sampling_frequency_hz,
                                    h.trace.columns,
                                    h.trace.start_time_s,
                                    {}});
        it = groups.end() - 1;
      }
      it->members.insert({h.trace.trial_index, h.trace.interval_index});
    }
    for (std::size_t k = 0; k < groups.size(); ++k) {
      const std::string physio_stem =
          groups.size() == 1
              ? stem + "_physio"
              : fmt::format("{}_recording-{}_physio", stem, k + 1);
      if (Status s =
              WritePhysio(db, journal_path, beh_dir / (physio_stem + ".tsv.gz"),
                          groups[k], list);
          !s) {
        return s;
      }
      if (Status s = ReplaceFile(beh_dir / (physio_stem + ".json"),
                                 PhysioSidecar(groups[k]));
          !s) {
        return s;
      }
      scanned.push_back("beh/" + physio_stem + ".tsv.gz");
    }
  }
  // The session's scans.tsv marks every file with the state of the session.
  RemoveStaleTempFiles(session_dir);
  std::string scans = Joined(ScansColumns(), "\t") + "\n";
  for (const std::string& file : scanned) {
    scans += fmt::format(
        "{}\t{}\t{}\t{}\n", file,
        !progress->complete
            ? std::string(kNa)
            : std::string(*progress->complete ? "complete" : "incomplete"),
        progress->trials, OrNa(progress->planned_trials));
  }
  if (Status s = ReplaceFile(session_dir / (prefix + "_scans.tsv"), scans);
      !s) {
    return s;
  }
  return ReplaceFile(session_dir / (prefix + "_scans.json"),
                     ScansSidecar(!session_label.empty()));
}

}  // namespace

const std::vector<std::string>& ScansColumns() {
  static const std::vector<std::string> kColumns = {
      "filename", "session_status", "session_trials", "session_planned_trials"};
  return kColumns;
}

const std::vector<std::string>& BehColumns() {
  static const std::vector<std::string> kColumns = {
      "trial_index",    "block",      "method",
      "task",           "trial_type", "practice",
      "stim_level",     "stim_unit",  "interval_materials",
      "correct_answer", "response",   "correct",
      "response_time",  "late",       "source",
      "staircase_id",   "reversal",   "step_size",
      "estimate",       "seed",       "extra"};
  return kColumns;
}

const std::vector<std::string>& PhysioLeadingColumns() {
  static const std::vector<std::string> kColumns = {"trial_index",
                                                    "interval_index", "time"};
  return kColumns;
}

std::string TaskLabel(std::string_view block_name) {
  std::string label;
  bool new_word = false;
  for (char c : block_name) {
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                       (c >= '0' && c <= '9');
    if (!alnum) {
      new_word = true;
      continue;
    }
    if (new_word && !label.empty() && c >= 'a' && c <= 'z') {
      c = static_cast<char>(c - 'a' + 'A');
    }
    new_word = false;
    label += c;
  }
  return label.empty() ? std::string("block") : label;
}

Status ValidateAuthor(std::string_view author) {
  if (author.find_first_not_of(' ') == std::string_view::npos) {
    return Error{"an author's name is empty; give one name per --author"};
  }
  if (!IsValidUtf8(author)) {
    return Error{fmt::format("author {} is not valid UTF-8", Quoted(author))};
  }
  for (std::size_t i = 0; i < author.size(); ++i) {
    const auto byte = static_cast<unsigned char>(author[i]);
    if (byte < 0x20 || byte == 0x7f) {
      return Error{fmt::format(
          "author {} has {} at position {}; a name is one line of text",
          Quoted(author), DescribeChar(author[i]), i + 1)};
    }
  }
  const auto commas = std::count(author.begin(), author.end(), ',');
  if (commas > 1) {
    return Error{fmt::format(
        "author {} has {} commas; give one name per --author (\"Surname, "
        "Given names\" at most: BIDS validators read more commas as several "
        "authors in one entry)",
        Quoted(author), commas)};
  }
  return {};
}

Status ExportBids(const fs::path& dir, std::string_view subject_label) {
  return ExportBids(dir, subject_label, BidsExportOptions{});
}

Status ExportBids(const fs::path& dir, std::string_view subject_label,
                  const BidsExportOptions& options) {
  try {
    return Export(dir, subject_label, options);
  } catch (const std::exception& e) {
    return Error{fmt::format("cannot export {}: internal error: {}",
                             SessionName(subject_label, options.session),
                             e.what())};
  }
}

}  // namespace burrlab::results_schema
