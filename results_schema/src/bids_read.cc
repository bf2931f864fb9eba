// Reading the BIDS-style exports back: _beh.tsv tables, dataset discovery,
// _physio sidecars and streamed .tsv.gz rows.
#include "burrlab/results_schema/bids_read.h"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "burrlab/base/file_text.h"
#include "burrlab/results_schema/bids_export.h"
#include "burrlab/results_schema/dataset_layout.h"
#include "burrlab/results_schema/journal.h"
#include "journal_db.h"
#include "text.h"

namespace burrlab::results_schema {
namespace {

namespace fs = std::filesystem;

// Splits a line at tabs, keeping the 0-based byte offset of each cell.
struct Cell {
  std::string_view text;
  std::size_t offset = 0;
};
std::vector<Cell> SplitTabs(std::string_view line) {
  std::vector<Cell> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t tab = line.find('\t', start);
    cells.push_back({line.substr(start, tab - start), start});
    if (tab == std::string_view::npos) break;
    start = tab + 1;
  }
  return cells;
}

std::optional<double> ParseDouble(std::string_view text) {
  double value = 0.0;
  const auto [end, ec] =
      std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() ||
      !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

template <typename Int>
std::optional<Int> ParseInt(std::string_view text) {
  Int value = 0;
  const auto [end, ec] =
      std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty()) {
    return std::nullopt;
  }
  return value;
}

// "sub-<label>[_ses-<session>]_task-<task>[_recording-<k>]_<suffix>" ->
// (label, session, task, k).
struct BidsName {
  std::string subject, session, task, recording;
};
std::optional<BidsName> ParseBidsName(std::string_view name,
                                      std::string_view suffix) {
  if (!name.starts_with("sub-") || !name.ends_with(suffix)) return std::nullopt;
  name.remove_suffix(suffix.size());
  name.remove_prefix(4);
  const std::size_t task = name.find("_task-");
  if (task == std::string_view::npos || task == 0) return std::nullopt;
  BidsName out;
  out.subject = std::string(name.substr(0, task));
  if (const std::size_t ses = out.subject.find("_ses-");
      ses != std::string::npos) {
    out.session = out.subject.substr(ses + 5);
    out.subject.resize(ses);
    if (!ValidateSessionLabel(out.session)) return std::nullopt;
  }
  std::string_view rest = name.substr(task + 6);
  const std::size_t recording = rest.find("_recording-");
  if (recording != std::string_view::npos) {
    out.recording = std::string(rest.substr(recording + 11));
    rest = rest.substr(0, recording);
  }
  out.task = std::string(rest);
  if (out.task.empty() || !ValidateSubjectLabel(out.subject)) {
    return std::nullopt;
  }
  return out;
}

}  // namespace

Result<BehTable> ParseBehTsv(std::string_view path, std::string_view text) {
  const auto fail = [&](int line, std::size_t column, const std::string& what) {
    return Error{line > 0 ? fmt::format("{}:{}:{}: error: {}", path, line,
                                        column + 1, what)
                          : fmt::format("{}: error: {}", path, what)};
  };
  const std::vector<std::string_view> lines = TextLines(text);
  if (lines.empty() || lines[0].empty()) {
    return fail(0, 0,
                "the file is empty; expected a _beh.tsv with the header "
                "trial_index\tblock\t...");
  }
  const std::vector<Cell> header = SplitTabs(lines[0]);
  std::map<std::string, std::size_t, std::less<>> index;
  for (std::size_t k = 0; k < header.size(); ++k) {
    index.emplace(std::string(header[k].text), k);
  }
  // BehColumns() position -> file column (kAbsent: an optional column the
  // file does not have).
  constexpr std::size_t kAbsent = static_cast<std::size_t>(-1);
  std::vector<std::size_t> at;
  for (const std::string& name : BehColumns()) {
    const auto it = index.find(name);
    if (it == index.end() &&
        (name == "source" || name == "practice" || name == "late")) {
      at.push_back(kAbsent);  // exports written before it existed
      continue;
    }
    if (it == index.end()) {
      return fail(1, 0,
                  fmt::format("the header has no column '{}' (a burrlab "
                              "_beh.tsv has {})",
                              name, fmt::join(BehColumns(), ", ")));
    }
    at.push_back(it->second);
  }
  enum Col {
    kTrialIndex,
    kBlock,
    kMethod,
    kTask,
    kTrialType,
    kPractice,
    kStimLevel,
    kStimUnit,
    kMaterials,
    kCorrectAnswer,
    kResponse,
    kCorrect,
    kResponseTime,
    kLate,
    kSource,
    kStaircaseId,
    kReversal,
    kStepSize,
    kEstimate,
    kSeed,
    kExtra
  };
  BehTable table;
  bool have_seed = false;
  for (std::size_t n = 1; n < lines.size(); ++n) {
    if (lines[n].empty()) continue;
    const int line = static_cast<int>(n) + 1;
    const std::vector<Cell> cells = SplitTabs(lines[n]);
    if (cells.size() != header.size()) {
      return fail(line, 0,
                  fmt::format("{} cells, but the header has {} columns",
                              cells.size(), header.size()));
    }
    const auto cell = [&](Col c) -> const Cell& { return cells[at[c]]; };
    const auto bad = [&](Col c, std::string_view rule) {
      return fail(
          line, cell(c).offset,
          fmt::format("{} {} {}", BehColumns()[c], Quoted(cell(c).text), rule));
    };
    const auto text_of = [&](Col c) {
      return cell(c).text == kNa ? std::string() : std::string(cell(c).text);
    };
    const auto number = [&](Col c, std::optional<double>* out) -> bool {
      if (cell(c).text == kNa) return true;
      *out = ParseDouble(cell(c).text);
      return out->has_value();
    };
    const auto flag = [&](Col c, std::optional<bool>* out) -> bool {
      if (cell(c).text == kNa) return true;
      if (cell(c).text != "0" && cell(c).text != "1") return false;
      *out = cell(c).text == "1";
      return true;
    };
    TrialRecord t;
    const std::optional<int> index_value =
        ParseInt<int>(cell(kTrialIndex).text);
    if (!index_value || *index_value < 0) {
      return bad(kTrialIndex, "is not a whole number of at least 0");
    }
    t.trial_index = *index_value;
    t.block = std::string(cell(kBlock).text);
    t.method = std::string(cell(kMethod).text);
    t.task = std::string(cell(kTask).text);
    if (!IsKnownTask(t.task)) return bad(kTask, "is not 'probe' or 'drill'");
    t.trial_type = text_of(kTrialType);
    if (!number(kStimLevel, &t.stim_level)) {
      return bad(kStimLevel, "is not a finite number or n/a");
    }
    t.stim_unit = text_of(kStimUnit);
    if (cell(kMaterials).text != kNa) {
      std::string_view m = cell(kMaterials).text;
      for (std::size_t s = 0;;) {
        const std::size_t plus = m.find('+', s);
        t.interval_materials.emplace_back(m.substr(s, plus - s));
        if (plus == std::string_view::npos) break;
        s = plus + 1;
      }
    }
    t.correct_answer = text_of(kCorrectAnswer);
    t.response = text_of(kResponse);
    if (!flag(kCorrect, &t.correct)) return bad(kCorrect, "is not 1, 0 or n/a");
    if (at[kSource] != kAbsent) t.source = text_of(kSource);
    if (at[kPractice] != kAbsent) {
      if (cell(kPractice).text != "0" && cell(kPractice).text != "1") {
        return bad(kPractice, "is not 1 or 0");
      }
      t.practice = cell(kPractice).text == "1";
    }
    if (at[kLate] != kAbsent && !flag(kLate, &t.late)) {
      return bad(kLate, "is not 1, 0 or n/a");
    }
    if (!number(kResponseTime, &t.response_time_s) ||
        (t.response_time_s && *t.response_time_s < 0.0)) {
      return bad(kResponseTime, "is not a time of at least 0 s or n/a");
    }
    if (cell(kStaircaseId).text != kNa) {
      t.staircase_id = ParseInt<int>(cell(kStaircaseId).text);
      if (!t.staircase_id || *t.staircase_id < 0) {
        return bad(kStaircaseId, "is not a whole number of at least 0 or n/a");
      }
    }
    if (!flag(kReversal, &t.reversal)) {
      return bad(kReversal, "is not 1, 0 or n/a");
    }
    if (!number(kStepSize, &t.step_size)) {
      return bad(kStepSize, "is not a finite number or n/a");
    }
    if (!number(kEstimate, &t.estimate)) {
      return bad(kEstimate, "is not a finite number or n/a");
    }
    // "seed-N", or the bare N of exports before the seed became text.
    const std::optional<std::uint64_t> seed = ParseSeedText(cell(kSeed).text);
    if (!seed) {
      return bad(kSeed,
                 "is not seed-N (or N) with N a whole number from 0 to "
                 "18446744073709551615");
    }
    if (have_seed && *seed != table.seed) {
      return bad(kSeed, fmt::format("differs from the seed {} of the rows "
                                    "above (one file holds one session)",
                                    table.seed));
    }
    table.seed = *seed;
    have_seed = true;
    if (cell(kExtra).text != kNa) {
      const auto extra =
          nlohmann::json::parse(cell(kExtra).text, nullptr, false);
      if (extra.is_discarded() || !extra.is_object()) {
        return bad(kExtra, "is not a JSON object or n/a");
      }
      t.extra = std::string(cell(kExtra).text);
    }
    if (!table.trials.empty() &&
        t.trial_index <= table.trials.back().trial_index) {
      return bad(kTrialIndex,
                 fmt::format("does not follow trial {} (rows are in trial "
                             "order)",
                             table.trials.back().trial_index));
    }
    table.trials.push_back(std::move(t));
  }
  if (table.trials.empty()) {
    return fail(0, 0, "the file has a header but no trials");
  }
  return table;
}

Result<PhysioFile> ParsePhysioSidecar(const fs::path& json_path,
                                      std::string_view text) {
  const auto j = nlohmann::json::parse(text, nullptr, false);
  const auto fail = [&](const std::string& what) {
    return Error{fmt::format("{}: error: {}", json_path.string(), what)};
  };
  if (j.is_discarded() || !j.is_object()) return fail("not a JSON object");
  PhysioFile f;
  const std::string name = json_path.filename().string();
  if (!name.ends_with("_physio.json")) {
    return fail("a physio sidecar's name ends in _physio.json");
  }
  f.data_path =
      json_path.parent_path() / (name.substr(0, name.size() - 5) + ".tsv.gz");
  if (!j.contains("SamplingFrequency") || !j["SamplingFrequency"].is_number() ||
      !(j["SamplingFrequency"].get<double>() > 0.0)) {
    return fail("SamplingFrequency must be a number above 0");
  }
  f.sampling_frequency_hz = j["SamplingFrequency"].get<double>();
  if (j.contains("StartTime") && j["StartTime"].is_number()) {
    f.start_time_s = j["StartTime"].get<double>();
  }
  if (!j.contains("Columns") || !j["Columns"].is_array() ||
      j["Columns"].empty()) {
    return fail("Columns must be a non-empty array of names");
  }
  for (const auto& c : j["Columns"]) {
    if (!c.is_string())
      return fail("Columns must be a non-empty array of names");
    f.columns.push_back(c.get<std::string>());
  }
  return f;
}

Result<PhysioFile> ReadPhysioSidecar(const fs::path& json_path) {
  Result<std::string> text = ReadTextFile(json_path.string(), 16u << 20);
  if (!text) return text.error();
  return ParsePhysioSidecar(json_path, *text);
}

namespace {

// The rows of a _physio.tsv fed in pieces (as zlib inflates them, or all at
// once): lines end in LF (a CR before it is dropped), blank lines are
// skipped, each other line gives one value per column to `row`.
class PhysioRowReader {
 public:
  PhysioRowReader(std::string_view path, std::span<const std::string> columns,
                  const std::function<bool(std::span<const double>)>& row)
      : path_(path), columns_(columns), row_(row), values_(columns.size()) {}

  // Parses the complete lines of `bytes`, keeping a last partial line for
  // the next call. Sets *stopped when `row` asked to stop.
  Status Feed(std::string_view bytes, bool* stopped) {
    while (!bytes.empty() && !*stopped) {
      const std::size_t newline = bytes.find('\n');
      const std::string_view piece = bytes.substr(0, newline);
      if (line_.size() + piece.size() > kMaxPhysioLineBytes) {
        return Error{fmt::format(
            "{}:{}:1: error: the line is longer than {} bytes (a physio row "
            "has one number per column)",
            path_, line_number_ + 1, kMaxPhysioLineBytes)};
      }
      line_ += piece;
      if (newline == std::string_view::npos) break;
      bytes.remove_prefix(newline + 1);
      if (Status s = EndLine(stopped); !s) return s;
    }
    return {};
  }

  // Parses a last line without a line break.
  Status Finish(bool* stopped) {
    if (line_.empty() || *stopped) return {};
    return EndLine(stopped);
  }

 private:
  Status EndLine(bool* stopped) {
    ++line_number_;
    if (!line_.empty() && line_.back() == '\r') line_.pop_back();
    if (line_.empty()) return {};
    std::size_t k = 0, start = 0;
    while (true) {
      const std::size_t tab = line_.find('\t', start);
      const std::string_view cell =
          std::string_view(line_).substr(start, tab - start);
      if (k >= values_.size()) break;
      if (cell == kNa) {
        values_[k] = std::numeric_limits<double>::quiet_NaN();
      } else if (const std::optional<double> v = ParseDouble(cell)) {
        values_[k] = *v;
      } else {
        return Error{fmt::format(
            "{}:{}:{}: error: {} {} is not a number or n/a", path_,
            line_number_, start + 1, Quoted(columns_[k]), Quoted(cell))};
      }
      ++k;
      if (tab == std::string::npos) break;
      start = tab + 1;
    }
    const std::size_t cells =
        static_cast<std::size_t>(std::count(line_.begin(), line_.end(), '\t')) +
        1;
    if (cells != values_.size()) {
      return Error{fmt::format(
          "{}:{}:1: error: {} cells, but the sidecar names {} columns", path_,
          line_number_, cells, values_.size())};
    }
    line_.clear();
    if (!row_(values_)) *stopped = true;
    return {};
  }

  std::string_view path_;
  std::span<const std::string> columns_;
  const std::function<bool(std::span<const double>)>& row_;
  std::vector<double> values_;
  std::string line_;  // the line read so far
  int line_number_ = 0;
};

}  // namespace

Status ForEachPhysioRowOfText(
    std::string_view path, std::span<const std::string> columns,
    std::string_view text,
    const std::function<bool(std::span<const double>)>& row) {
  PhysioRowReader reader(path, columns, row);
  bool stopped = false;
  if (Status s = reader.Feed(text, &stopped); !s) return s;
  return reader.Finish(&stopped);
}

Status ForEachPhysioRow(
    const PhysioFile& file,
    const std::function<bool(std::span<const double>)>& row) {
  errno = 0;
  std::unique_ptr<gzFile_s, int (*)(gzFile)> gz(
      gzopen(file.data_path.c_str(), "rb"), &gzclose);
  if (gz == nullptr) {
    return Error{fmt::format("cannot read {}: {}", file.data_path.string(),
                             std::strerror(errno != 0 ? errno : ENOMEM))};
  }
  const std::string path = file.data_path.string();
  PhysioRowReader reader(path, file.columns, row);
  bool stopped = false;
  std::vector<char> buffer(1 << 16);
  while (!stopped) {
    const int n =
        gzread(gz.get(), buffer.data(), static_cast<unsigned>(buffer.size()));
    if (n <= 0) break;
    const std::string_view chunk(buffer.data(), static_cast<std::size_t>(n));
    if (Status s = reader.Feed(chunk, &stopped); !s) return s;
  }
  if (stopped) return {};
  int errnum = 0;
  const char* message = gzerror(gz.get(), &errnum);
  if (errnum != Z_OK && errnum != Z_STREAM_END) {
    return Error{
        fmt::format("cannot read {}: {}", path,
                    errnum == Z_ERRNO ? std::strerror(errno) : message)};
  }
  return reader.Finish(&stopped);
}

namespace {

// The session folders of DIR that hold a journal, sorted by subject, then
// session.
std::vector<SessionFolderEntry> SessionsWithJournals(const fs::path& dir) {
  std::vector<SessionFolderEntry> sessions;
  for (SessionFolderEntry& entry : ListSessionFolders(dir)) {
    std::error_code ec;
    if (fs::is_regular_file(JournalPath(dir, entry.subject, entry.session),
                            ec)) {
      sessions.push_back(std::move(entry));
    }
  }
  return sessions;
}

}  // namespace

std::vector<UnexportedTrials> FindUnexportedTrials(
    const fs::path& dir, const std::vector<BehFile>& files) {
  std::map<std::pair<std::string, std::string>, int> exported;
  for (const BehFile& f : files) {
    exported[{f.subject, f.session}] += static_cast<int>(f.table.trials.size());
  }
  std::vector<UnexportedTrials> found;
  for (const SessionFolderEntry& s : SessionsWithJournals(dir)) {
    const fs::path journal = JournalPath(dir, s.subject, s.session);
    int trials = -1;
    if (auto db = db::OpenDb(journal, /*create=*/false)) {
      if (auto count = db::CountTrials(db->get(), journal)) trials = *count;
    }
    const auto it = exported.find({s.subject, s.session});
    const int in_exports = it != exported.end() ? it->second : 0;
    if (trials < 0 || trials > in_exports) {
      found.push_back({s.subject, trials, in_exports, s.session});
    }
  }
  return found;
}

std::vector<IncompleteSession> FindIncompleteSessions(const fs::path& dir) {
  std::vector<IncompleteSession> found;
  for (const SessionFolderEntry& s : SessionsWithJournals(dir)) {
    Result<SessionProgress> progress =
        ReadSessionProgress(dir, s.subject, s.session);
    if (!progress || progress->complete != false) continue;
    found.push_back(
        {s.subject, progress->trials, progress->planned_trials, s.session});
  }
  return found;
}

Result<std::vector<BehFile>> ReadBidsDataset(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    return Error{fmt::format("cannot read {}: not a folder", dir.string())};
  }
  std::vector<BehFile> files;
  // An unreadable folder is an error (ListSessionFolders passes over it).
  const fs::directory_iterator listing(dir, ec);
  if (ec)
    return Error{fmt::format("cannot read {}: {}", dir.string(), ec.message())};
  for (const SessionFolderEntry& folder : ListSessionFolders(dir)) {
    const fs::path beh = folder.folder / "beh";
    if (!fs::is_directory(beh, ec)) continue;
    std::vector<fs::path> entries;
    for (const fs::directory_entry& e : fs::directory_iterator(beh, ec)) {
      entries.push_back(e.path());
    }
    std::sort(entries.begin(), entries.end());
    std::vector<BehFile> mine;
    for (const fs::path& path : entries) {
      const std::optional<BidsName> name =
          ParseBidsName(path.filename().string(), "_beh.tsv");
      if (!name || !name->recording.empty() ||
          name->subject != folder.subject || name->session != folder.session) {
        continue;
      }
      Result<std::string> text = ReadTextFile(path.string(), kMaxBehBytes);
      if (!text) return text.error();
      Result<BehTable> table = ParseBehTsv(path.string(), *text);
      if (!table) return table.error();
      BehFile f;
      f.subject = name->subject;
      f.session = name->session;
      f.task = name->task;
      f.path = path;
      f.table = std::move(table.value());
      for (const fs::path& other : entries) {
        const std::optional<BidsName> p =
            ParseBidsName(other.filename().string(), "_physio.json");
        if (!p || p->subject != f.subject || p->session != f.session ||
            p->task != f.task) {
          continue;
        }
        Result<PhysioFile> physio = ReadPhysioSidecar(other);
        if (!physio) return physio.error();
        f.physio.push_back(std::move(physio.value()));
      }
      mine.push_back(std::move(f));
    }
    std::sort(mine.begin(), mine.end(), [](const BehFile& a, const BehFile& b) {
      return a.table.trials.front().trial_index <
             b.table.trials.front().trial_index;
    });
    for (BehFile& f : mine) files.push_back(std::move(f));
  }
  if (files.empty()) {
    return Error{fmt::format(
        "{} holds no burrlab results (no sub-*/beh/sub-*_task-*_beh.tsv); "
        "give the --out folder of 'burrlab run' or 'burrlab study'",
        dir.string())};
  }
  return files;
}

}  // namespace burrlab::results_schema
