// The "burrlab-protocol/1" parser and validator: every problem is collected
// with its position, named by key path ("blocks[2].step_down", blocks counted
// from 1) and described with the accepted values.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "burrlab/base/printable.h"
#include "burrlab/base/spelling.h"
#include "burrlab/protocols/protocol.h"
#include "burrlab/stimuli/materials.h"
#include "burrlab/stimuli/toml_fields.h"
#include "burrlab/stimuli/toml_guard.h"

namespace burrlab::protocols {
namespace {

using Keys = stimuli::TomlKeys;
using stimuli::EchoText;
using stimuli::JoinKeys;
using stimuli::TomlTypeName;

// Nesting limit before toml++ parses (see stimuli/toml_guard.h); a protocol
// with long level lists has a few hundred '.' in numbers.
constexpr std::size_t kMaxDots = 4096;
constexpr int kMaxTrialsPerBlock = 10000;
constexpr std::size_t kMaxScheduleEntries = 100;

constexpr std::string_view kRootKeys[] = {
    "format",         "study",     "recording", "observer",
    "counterbalance", "materials", "axes",      "blocks"};
constexpr std::string_view kStudyKeys[] = {
    "name", "description", "instructions", "breaks_between_blocks"};
constexpr std::string_view kRecordingKeys[] = {"trace_hz"};
constexpr std::string_view kObserverKeys[] = {
    "weber_stiffness",     "weber_removal", "lapse",
    "criterion",           "rule",          "bias",
    "probe_force_n",       "drill_force_n", "exploration",
    "force_spread",        "speed_spread",  "subject_force_spread",
    "subject_speed_spread"};
constexpr std::string_view kCounterbalanceKeys[] = {"scheme"};
// The spelling of each material parameter, in MaterialParameter order (the
// order of sim::Material), shared with material files.
constexpr auto& kSpellings = stimuli::kMaterialParameterSpellings;
constexpr std::string_view kMaterialKeys[] = {
    "builtin",         "display_name",    "description",     kSpellings[0].key,
    kSpellings[1].key, kSpellings[2].key, kSpellings[3].key, kSpellings[4].key};
constexpr std::string_view kParameterKeys[] = {
    kSpellings[0].key, kSpellings[1].key, kSpellings[2].key, kSpellings[3].key,
    kSpellings[4].key};
static_assert(std::size(kSpellings) == 5 &&
              kSpellings[static_cast<int>(MaterialParameter::kCE)].field ==
                  &sim::Material::c_e_n_per_mm2 &&
              kSpellings[static_cast<int>(MaterialParameter::kAlpha)].field ==
                  &sim::Material::alpha_per_s &&
              kSpellings[static_cast<int>(MaterialParameter::kCMu)].field ==
                  &sim::Material::c_mu_n_per_mm2 &&
              kSpellings[static_cast<int>(MaterialParameter::kMu)].field ==
                  &sim::Material::mu &&
              kSpellings[static_cast<int>(MaterialParameter::kCI)].field ==
                  &sim::Material::c_i_n_s_per_mm3);
constexpr std::string_view kAxisKeys[] = {"kind", "parameter", "reference",
                                          "from", "to"};
constexpr std::string_view kCommonBlockKeys[] = {"name",
                                                 "method",
                                                 "task",
                                                 "instructions",
                                                 "question",
                                                 "interval_s",
                                                 "practice",
                                                 "feedback",
                                                 "isi_s",
                                                 "iti_s",
                                                 "response_deadline_s",
                                                 "break_every"};
// Longest gap (isi_s, iti_s) and response deadline, s: as an interval.
constexpr double kMaxGapS = 600.0;
constexpr std::string_view kSameDifferentKeys[] = {"a", "b", "trials"};
constexpr std::string_view kTwoIntervalKeys[] = {
    "design", "standard", "comparison",         "a",
    "b",      "matching", "reference_material", "reference_description",
    "trials"};
constexpr std::string_view kAxisMethodKeys[] = {"axis", "standard_level"};
constexpr std::string_view kConstantKeys[] = {"levels", "repetitions", "order",
                                              "response"};
constexpr std::string_view kLimitsKeys[] = {
    "step",  "ascending_start", "descending_start", "start_jitter_steps",
    "floor", "ceiling",         "series",           "first_direction"};
constexpr std::string_view kAdjustmentKeys[] = {
    "start_level", "start_jitter_steps", "step",       "step_scale", "floor",
    "ceiling",     "max_steps",          "repetitions"};
constexpr std::string_view kStaircaseKeys[] = {
    "n_down",     "n_up",          "step_down",    "step_up",
    "step_scale", "step_schedule", "start_level",  "floor",
    "ceiling",    "max_trials",    "max_reversals"};
constexpr std::string_view kStaircaseBlockKeys[] = {"threshold_reversals",
                                                    "response", "staircases"};
constexpr std::string_view kScheduleKeys[] = {"after_reversals", "step_down",
                                              "step_up"};
constexpr std::string_view kQuestBlockKeys[] = {"trials", "response", "quest",
                                                "floor", "ceiling"};
constexpr std::string_view kQuestKeys[] = {"tGuess", "tGuessSd", "pThreshold",
                                           "beta",   "delta",    "gamma",
                                           "grain",  "range"};
constexpr std::string_view kMethods[] = {
    "same_different", "two_interval", "constant_stimuli",
    "limits",         "adjustment",   "staircase",
    "quest"};

// At most kMaxListed ids joined by ", ", then how many there are in all: a
// message names a few of the declared ids, not all of a hostile file's.
std::string JoinDeclared(Keys ids) {
  constexpr std::size_t kMaxListed = 20;
  if (ids.size() <= kMaxListed) return JoinKeys(ids);
  return fmt::format("{}, ... ({} in all)", JoinKeys(ids.first(kMaxListed)),
                     ids.size());
}

SourceLocation Where(const toml::node& node) {
  const toml::source_position p = node.source().begin;
  return {static_cast<int>(p.line), static_cast<int>(p.column)};
}

class Parser {
 public:
  explicit Parser(std::string_view path) : path_(path) {}
  // fields_ reports through this parser: no copies.
  Parser(const Parser&) = delete;
  Parser& operator=(const Parser&) = delete;

  ParseOutcome Parse(const toml::table& root);
  std::vector<Diagnostic>& diagnostics() { return diagnostics_; }

 private:
  void Fail(SourceLocation where, std::string message) {
    diagnostics_.push_back({where, std::move(message)});
  }
  void Fail(const toml::node& node, std::string message) {
    Fail(Where(node), std::move(message));
  }

  // The shared field readers (burrlab/stimuli/toml_fields.h), reporting
  // through Fail.
  void CheckKeys(const toml::table& table, const std::string& name,
                 Keys allowed, Keys elsewhere = {},
                 std::string_view elsewhere_message = {}) {
    fields_.CheckKeys(table, name, allowed, elsewhere, elsewhere_message);
  }
  const toml::table* Table(const toml::table& parent, std::string_view key,
                           const std::string& name) {
    return fields_.Table(parent, key, name);
  }
  std::optional<std::string> String(const toml::table& t, std::string_view key,
                                    const std::string& name) {
    return fields_.String(t, key, name);
  }
  std::optional<double> Number(const toml::table& t, std::string_view key,
                               const std::string& name) {
    return fields_.Number(t, key, name);
  }
  std::optional<std::int64_t> Integer(const toml::table& t,
                                      std::string_view key,
                                      const std::string& name) {
    return fields_.Integer(t, key, name);
  }
  std::optional<int> Choice(const toml::table& t, std::string_view key,
                            const std::string& name, Keys choices) {
    return fields_.Choice(t, key, name, choices);
  }
  std::optional<bool> Boolean(const toml::table& t, std::string_view key,
                              const std::string& name) {
    return fields_.Boolean(t, key, name);
  }
  bool Range(const toml::table& t, std::string_view key,
             const std::string& name, double value, double lo, double hi,
             bool lo_open, bool hi_open) {
    return fields_.Range(t, key, name, value, lo, hi, lo_open, hi_open);
  }

  void ParseStudy(const toml::table& root, Protocol& p);
  void ParseRecording(const toml::table& root, Protocol& p);
  void ParseObserver(const toml::table& root, Protocol& p);
  void ParseCounterbalance(const toml::table& root, Protocol& p);
  void ParseMaterials(const toml::table& root, Protocol& p);
  void ParseAxes(const toml::table& root, Protocol& p);
  void ParseBlocks(const toml::table& root, Protocol& p);
  void ParseBlock(const toml::table& t, int index, const Protocol& p, Block& b);
  // The table of a [materials.<id>] or [axes.<id>] entry, or null after
  // reporting a bad id or a value that is not a table.
  const toml::table* EntryTable(const std::string& id, const toml::node& node,
                                std::string_view kind, const std::string& name);
  // An axis's parameter, by its key or (with a note) its old spelling; the
  // index into kSpellings.
  std::optional<int> AxisParameter(const toml::table& t,
                                   const std::string& name);
  // A material id that must be declared.
  std::optional<std::string> MaterialRef(const toml::table& t,
                                         std::string_view key,
                                         const std::string& name,
                                         const Protocol& p, bool required);
  // A level that must lie in the axis's domain.
  void CheckLevel(const toml::table& t, std::string_view key,
                  const std::string& name, const Axis* axis, double level);
  void ParseStaircase(const toml::table& t, const std::string& name,
                      StaircaseOptions& o, const Axis* axis);
  void ParseIntervals(const toml::table& t, const std::string& name,
                      std::size_t count, Block& b);
  // practice, feedback, isi_s, iti_s, response_deadline_s and break_every
  // (after the method's keys: feedback depends on the design).
  void ParsePacing(const toml::table& t, const std::string& name, Block& b);
  // Fills b.reach for a block parsed without errors: the materials it names
  // and, on its axis, its standard and the ends of the levels it can reach.
  // `staircases` holds each staircase's table.
  void Reach(const toml::table& t, const std::string& name, const Protocol& p,
             const Axis* axis, std::span<const toml::table* const> staircases,
             Block& b);
  // Adds a level the block can reach to b.reach, or reports why its material
  // cannot be presented (`what` names it, `fix` ends the message).
  void ReachLevel(const Protocol& p, const Axis& axis, double level,
                  std::string what, SourceLocation where, std::string_view fix,
                  Block& b);

  // The declared material or axis with this id, or null (a lookup in the
  // index, so that many references to many ids stay linear).
  const ProtocolMaterial* FindMaterial(const Protocol& p,
                                       std::string_view id) const;
  const Axis* FindAxis(const Protocol& p, std::string_view id) const;
  // Rebuilds the indices after p.materials or p.axes changed.
  void Index(const Protocol& p);
  // "Did you mean" among `ids`, while the budget of comparisons lasts.
  std::string_view Suggest(std::string_view typed, Keys ids);

  std::string path_;
  std::vector<Diagnostic> diagnostics_;
  std::vector<Diagnostic> notes_;
  stimuli::TomlFields fields_{[this](toml::source_position p, std::string m) {
    Fail(SourceLocation{static_cast<int>(p.line), static_cast<int>(p.column)},
         std::move(m));
  }};
  std::set<std::string> broken_materials_;  // declared, but with errors
  std::set<std::string> broken_axes_;       // declared, but with errors
  std::map<std::string, std::size_t, std::less<>> material_index_;
  std::map<std::string, std::size_t, std::less<>> axis_index_;
  std::vector<std::string_view> material_ids_;  // in p.materials' order
  std::vector<std::string_view> axis_ids_;      // in p.axes' order
  // Candidate comparisons left for suggestions among declared ids: a file
  // with thousands of bad references to thousands of ids gets suggestions
  // for the first ones and stays linear in its size.
  std::size_t suggestion_budget_ = 1'000'000;
};

void Parser::Index(const Protocol& p) {
  material_index_.clear();
  material_ids_.clear();
  for (std::size_t i = 0; i < p.materials.size(); ++i) {
    material_index_.emplace(p.materials[i].id, i);
    material_ids_.push_back(p.materials[i].id);
  }
  axis_index_.clear();
  axis_ids_.clear();
  for (std::size_t i = 0; i < p.axes.size(); ++i) {
    axis_index_.emplace(p.axes[i].id, i);
    axis_ids_.push_back(p.axes[i].id);
  }
}

const ProtocolMaterial* Parser::FindMaterial(const Protocol& p,
                                             std::string_view id) const {
  const auto it = material_index_.find(id);
  return it == material_index_.end() ? nullptr : &p.materials[it->second];
}

const Axis* Parser::FindAxis(const Protocol& p, std::string_view id) const {
  const auto it = axis_index_.find(id);
  return it == axis_index_.end() ? nullptr : &p.axes[it->second];
}

std::string_view Parser::Suggest(std::string_view typed, Keys ids) {
  if (ids.size() > suggestion_budget_) return {};
  suggestion_budget_ -= ids.size();
  return DidYouMean(typed, ids);
}

void Parser::ParseStudy(const toml::table& root, Protocol& p) {
  const toml::table* study = Table(root, "study", "study");
  if (study == nullptr) {
    if (root.get("study") == nullptr) {
      Fail(SourceLocation{1, 1},
           "the protocol needs a [study] table with a name");
    }
    return;
  }
  CheckKeys(*study, "[study]", {std::begin(kStudyKeys), std::end(kStudyKeys)});
  if (auto name = String(*study, "name", "study.name")) {
    if (name->empty()) {
      Fail(*study->get("name"), "study.name must not be empty");
    }
    p.study_name = *name;
  } else if (study->get("name") == nullptr) {
    Fail(*study, "[study] needs \"name\"");
  }
  p.description =
      String(*study, "description", "study.description").value_or("");
  p.instructions =
      String(*study, "instructions", "study.instructions").value_or("");
  p.breaks_between_blocks =
      Boolean(*study, "breaks_between_blocks", "study.breaks_between_blocks")
          .value_or(false);
}

void Parser::ParseRecording(const toml::table& root, Protocol& p) {
  const toml::table* t = Table(root, "recording", "recording");
  if (t == nullptr) return;
  CheckKeys(*t, "[recording]",
            {std::begin(kRecordingKeys), std::end(kRecordingKeys)});
  if (auto hz = Integer(*t, "trace_hz", "recording.trace_hz")) {
    if (*hz < 1 || *hz > 1000 || 1000 % *hz != 0) {
      Fail(*t->get("trace_hz"),
           fmt::format("recording.trace_hz must divide 1000 (1, 2, 4, 5, 8, "
                       "10, ..., 500, 1000), got {}",
                       *hz));
    } else {
      p.trace_hz = static_cast<int>(*hz);
    }
  }
}

void Parser::ParseObserver(const toml::table& root, Protocol& p) {
  const toml::table* t = Table(root, "observer", "observer");
  if (t == nullptr) return;
  CheckKeys(*t, "[observer]",
            {std::begin(kObserverKeys), std::end(kObserverKeys)});
  struct Field {
    std::string_view key;
    double* value;
    double lo, hi;
    bool lo_open, hi_open;
  };
  ObserverDefaults& o = p.observer;
  // The preset first: the spreads given one by one override it.
  constexpr std::string_view kExplorations[] = {"fixed", "varied"};
  if (auto e =
          Choice(*t, "exploration", "observer.exploration", kExplorations)) {
    o.exploration = *e == 1 ? kVariedExploration : ExplorationSpreads{};
  }
  const Field fields[] = {
      {"weber_stiffness", &o.weber_stiffness, 0, 5, true, false},
      {"weber_removal", &o.weber_removal, 0, 5, true, false},
      {"lapse", &o.lapse, 0, 0.5, false, true},
      {"criterion", &o.criterion, 0, 100, false, false},
      {"bias", &o.bias, -5, 5, false, false},
      {"probe_force_n", &o.probe_force_n, 0, 20, true, false},
      {"drill_force_n", &o.drill_force_n, 0, 20, true, false},
      {"force_spread", &o.exploration.force, 0, 1, false, false},
      {"speed_spread", &o.exploration.speed, 0, 1, false, false},
      {"subject_force_spread", &o.exploration.subject_force, 0, 1, false,
       false},
      {"subject_speed_spread", &o.exploration.subject_speed, 0, 1, false,
       false},
  };
  for (const Field& f : fields) {
    const std::string name = fmt::format("observer.{}", f.key);
    if (auto v = Number(*t, f.key, name)) {
      if (Range(*t, f.key, name, *v, f.lo, f.hi, f.lo_open, f.hi_open)) {
        *f.value = *v;
      }
    }
  }
  if (auto r = Choice(*t, "rule", "observer.rule", kSameDifferentRuleNames)) {
    o.rule = static_cast<SameDifferentRule>(*r);
  }
}

void Parser::ParseCounterbalance(const toml::table& root, Protocol& p) {
  const toml::table* t = Table(root, "counterbalance", "counterbalance");
  if (t == nullptr) return;
  CheckKeys(*t, "[counterbalance]",
            {std::begin(kCounterbalanceKeys), std::end(kCounterbalanceKeys)});
  constexpr std::string_view kSchemes[] = {"none", "latin_square", "reverse"};
  if (auto c = Choice(*t, "scheme", "counterbalance.scheme", kSchemes)) {
    p.counterbalance = static_cast<Counterbalance>(*c);
  }
}

bool ValidId(std::string_view id) {
  if (id.empty() || id.size() > 64) return false;
  if (!((id[0] >= 'a' && id[0] <= 'z') || (id[0] >= 'A' && id[0] <= 'Z'))) {
    return false;
  }
  return std::all_of(id.begin(), id.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
           (c >= '0' && c <= '9') || c == '_';
  });
}

const toml::table* Parser::EntryTable(const std::string& id,
                                      const toml::node& node,
                                      std::string_view kind,
                                      const std::string& name) {
  if (!ValidId(id)) {
    Fail(node, fmt::format("{} id \"{}\" must start with a letter and hold "
                           "only letters, digits and '_' (at most 64)",
                           kind, EchoText(id)));
    return nullptr;
  }
  if (!node.is_table()) {
    Fail(node,
         fmt::format("{} must be a table, got {}", name, TomlTypeName(node)));
    return nullptr;
  }
  return node.as_table();
}

void Parser::ParseMaterials(const toml::table& root, Protocol& p) {
  const toml::table* materials = Table(root, "materials", "materials");
  if (materials == nullptr) return;
  // The simulator's rule (sim::Material::Validate), as material files have
  // it: c_e > 0 (a material with no elastic force cannot be felt), the others
  // >= 0 (no erosion, no friction, no impact damping).
  for (const auto& [key, node] : *materials) {
    const std::string id(key.str());
    const std::string name = fmt::format("materials.{}", EchoText(id));
    const toml::table* entry = EntryTable(id, node, "material", name);
    if (entry == nullptr) {
      broken_materials_.insert(id);
      continue;
    }
    const toml::table& t = *entry;
    CheckKeys(t, "[" + name + "]",
              {std::begin(kMaterialKeys), std::end(kMaterialKeys)});
    ProtocolMaterial m;
    m.id = id;
    m.where = Where(t);
    bool ok = true;
    if (auto builtin = String(t, "builtin", name + ".builtin")) {
      Result<stimuli::MaterialSet> set = stimuli::LoadBuiltinMaterial(*builtin);
      if (!set.ok()) {
        Fail(*t.get("builtin"),
             fmt::format("{}.builtin: {}", name, set.error().message));
        ok = false;
      } else {
        m.builtin = *builtin;
        m.set = set.value();
      }
    } else if (t.get("builtin") != nullptr) {
      ok = false;
    } else {
      m.set.name = id;
      m.set.display_name = id;
      m.set.source = fmt::format("protocol {}", path_);
      std::vector<std::string_view> missing;
      for (const stimuli::MaterialParameterSpelling& param : kSpellings) {
        if (t.get(param.key) == nullptr) missing.push_back(param.key);
      }
      if (!missing.empty()) {
        Fail(t, fmt::format("[{}] needs \"builtin\" or all of c_e_n_per_mm2, "
                            "alpha_per_s, c_mu_n_per_mm2, mu, "
                            "c_i_n_s_per_mm3 (missing {})",
                            name, JoinKeys(missing)));
        ok = false;
      }
    }
    for (const stimuli::MaterialParameterSpelling& param : kSpellings) {
      const std::string field = fmt::format("{}.{}", name, param.key);
      // c_e > 0 (a material with no elastic force cannot be felt), the
      // others >= 0, as sim::Material::Validate and material files have it.
      const bool zero_ok = param.field != &sim::Material::c_e_n_per_mm2;
      if (auto v = Number(t, param.key, field)) {
        if (Range(t, param.key, field, *v, 0.0, 1e6, !zero_ok, false)) {
          m.set.material.*param.field = *v;
        } else {
          ok = false;
        }
      } else if (t.get(param.key) != nullptr) {
        ok = false;
      }
    }
    if (auto display = String(t, "display_name", name + ".display_name")) {
      m.set.display_name = *display;
    }
    if (auto description = String(t, "description", name + ".description")) {
      m.set.description = *description;
    }
    if (ok) {
      p.materials.push_back(std::move(m));
    } else {
      broken_materials_.insert(id);  // reported once, not at every use
    }
  }
}

std::optional<std::string> Parser::MaterialRef(const toml::table& t,
                                               std::string_view key,
                                               const std::string& name,
                                               const Protocol& p,
                                               bool required) {
  std::optional<std::string> id = String(t, key, name);
  if (!id.has_value()) {
    if (required && t.get(key) == nullptr) {
      Fail(t, fmt::format("{} needs \"{}\" (a material id from [materials])",
                          name.substr(0, name.rfind('.')), key));
    }
    return std::nullopt;
  }
  if (FindMaterial(p, *id) != nullptr) return id;
  if (broken_materials_.contains(*id)) return std::nullopt;
  const Keys ids = material_ids_;
  const std::string_view hint = Suggest(*id, ids);
  Fail(*t.get(key),
       fmt::format("{}: unknown material \"{}\"{}", name, EchoText(*id),
                   !hint.empty() ? fmt::format(" (did you mean \"{}\"?)", hint)
                   : ids.empty()
                       ? std::string(" (no [materials] declared)")
                       : fmt::format(" (declared: {})", JoinDeclared(ids))));
  return std::nullopt;
}

std::optional<int> Parser::AxisParameter(const toml::table& t,
                                         const std::string& name) {
  const toml::node* node = t.get("parameter");
  if (node != nullptr && node->is_string()) {
    const std::string_view value = node->as_string()->get();
    for (std::size_t i = 0; i < std::size(kSpellings); ++i) {
      if (kSpellings[i].old_key.empty() || value != kSpellings[i].old_key) {
        continue;
      }
      notes_.push_back(
          {Where(*node),
           fmt::format("{}.parameter \"{}\" is the old spelling of \"{}\" "
                       "(read in {}); rename it, a later format will refuse "
                       "the old spelling",
                       name, value, kSpellings[i].key, kSpellings[i].unit),
           Severity::kNote});
      return static_cast<int>(i);
    }
  }
  return Choice(t, "parameter", name + ".parameter", kParameterKeys);
}

void Parser::ParseAxes(const toml::table& root, Protocol& p) {
  const toml::table* axes = Table(root, "axes", "axes");
  if (axes == nullptr) return;
  constexpr std::string_view kKinds[] = {"ratio", "increment", "value",
                                         "log_interpolation"};
  for (const auto& [key, node] : *axes) {
    const std::string id(key.str());
    const std::string name = fmt::format("axes.{}", EchoText(id));
    const toml::table* entry = EntryTable(id, node, "axis", name);
    if (entry == nullptr) {
      broken_axes_.insert(id);
      continue;
    }
    const toml::table& t = *entry;
    CheckKeys(t, "[" + name + "]",
              {std::begin(kAxisKeys), std::end(kAxisKeys)});
    Axis axis;
    axis.id = id;
    axis.where = Where(t);
    std::optional<int> kind = Choice(t, "kind", name + ".kind", kKinds);
    if (!kind.has_value()) {
      if (t.get("kind") == nullptr) {
        Fail(t, fmt::format("[{}] needs \"kind\" (one of {})", name,
                            JoinKeys(kKinds)));
      }
      continue;
    }
    axis.kind = static_cast<AxisKind>(*kind);
    bool ok = true;
    if (axis.kind == AxisKind::kLogInterpolation) {
      if (t.get("parameter") != nullptr) {
        Fail(*t.get("parameter"),
             fmt::format("{}.parameter does not apply to kind "
                         "log_interpolation (it moves every parameter)",
                         name));
        ok = false;
      }
      auto from = MaterialRef(t, "from", name + ".from", p, true);
      auto to = MaterialRef(t, "to", name + ".to", p, true);
      if (!from || !to) {
        ok = false;
      } else {
        axis.from = *from;
        axis.to = *to;
        for (const std::string& m : {*from, *to}) {
          for (const stimuli::MaterialParameterSpelling& spelling :
               kSpellings) {
            const std::string_view parameter_key = spelling.key;
            if (FindMaterial(p, m)->set.material.*spelling.field <= 0.0) {
              Fail(t, fmt::format("{}: material \"{}\" has {} = 0; a log "
                                  "interpolation needs every parameter > 0",
                                  name, m, parameter_key));
              ok = false;
              break;
            }
          }
        }
      }
    } else {
      std::optional<int> parameter = AxisParameter(t, name);
      if (!parameter.has_value()) {
        if (t.get("parameter") == nullptr) {
          Fail(t, fmt::format("[{}] needs \"parameter\" (one of {})", name,
                              JoinKeys(kParameterKeys)));
        }
        ok = false;
      } else {
        axis.parameter = static_cast<MaterialParameter>(*parameter);
      }
      auto reference =
          MaterialRef(t, "reference", name + ".reference", p, true);
      if (!reference) {
        ok = false;
      } else {
        axis.reference = *reference;
        // A ratio or an increment scales the reference's value: of 0, every
        // level would be the same material.
        if (parameter.has_value() && (axis.kind == AxisKind::kRatio ||
                                      axis.kind == AxisKind::kIncrement)) {
          const double base = GetParameter(
              FindMaterial(p, *reference)->set.material, axis.parameter);
          if (base <= 0.0) {
            Fail(t,
                 fmt::format(
                     "{}: material \"{}\" has {} = 0; a {} axis "
                     "scales it, so every level would give 0 (use "
                     "kind = \"value\")",
                     name, *reference,
                     kParameterKeys[static_cast<std::size_t>(axis.parameter)],
                     AxisKindName(axis.kind)));
            ok = false;
          }
        }
      }
      for (std::string_view k : {"from", "to"}) {
        if (t.get(k) != nullptr) {
          Fail(*t.get(k), fmt::format("{}.{} applies only to kind "
                                      "log_interpolation",
                                      name, k));
          ok = false;
        }
      }
    }
    if (ok) {
      p.axes.push_back(axis);
    } else {
      broken_axes_.insert(id);
    }
  }
}

void Parser::CheckLevel(const toml::table& t, std::string_view key,
                        const std::string& name, const Axis* axis,
                        double level) {
  if (axis == nullptr) return;
  switch (axis->kind) {
    case AxisKind::kRatio:
    case AxisKind::kValue:
      if (level <= 0.0) {
        Fail(*t.get(key),
             fmt::format("{} = {} is outside the domain of axis \"{}\" ({}: "
                         "levels > 0)",
                         name, level, axis->id, AxisKindName(axis->kind)));
      }
      break;
    case AxisKind::kIncrement:
      if (level <= -1.0) {
        Fail(*t.get(key),
             fmt::format("{} = {} is outside the domain of axis \"{}\" "
                         "(increment: levels > -1)",
                         name, level, axis->id));
      }
      break;
    case AxisKind::kLogInterpolation:
      if (level < 0.0 || level > 1.0) {
        Fail(*t.get(key),
             fmt::format("{} = {} is outside the domain of axis \"{}\" "
                         "(log_interpolation: levels in [0, 1])",
                         name, level, axis->id));
      }
      break;
  }
}

void Parser::ParseIntervals(const toml::table& t, const std::string& name,
                            std::size_t count, Block& b) {
  const bool reference = b.method == Method::kTwoInterval &&
                         b.design == TwoIntervalDesign::kReference;
  const toml::node* node = t.get("interval_s");
  if (node == nullptr) {
    b.interval_s.assign(count, 10.0);
    if (reference && b.reference_material.empty()) b.interval_s[0] = 0.0;
    return;
  }
  const std::string key = name + ".interval_s";
  std::vector<std::pair<double, const toml::node*>> values;
  if (node->is_number()) {
    values.assign(count, {node->value<double>().value_or(0.0), node});
  } else if (const toml::array* a = node->as_array()) {
    if (a->size() != count) {
      Fail(*node, fmt::format("{} must hold {} durations (one per interval "
                              "of this method), got {}",
                              key, count, a->size()));
      return;
    }
    for (const toml::node& v : *a) {
      if (!v.is_number()) {
        Fail(v,
             fmt::format("{} must hold numbers, got {}", key, TomlTypeName(v)));
        return;
      }
      values.push_back({v.value<double>().value_or(0.0), &v});
    }
  } else {
    Fail(*node, fmt::format("{} must be a number or an array of numbers, got "
                            "{}",
                            key, TomlTypeName(*node)));
    return;
  }
  b.interval_s.clear();
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double v = values[i].first;
    const bool real_reference =
        reference && i == 0 && b.reference_material.empty();
    if (real_reference && v == 0.0) {
      b.interval_s.push_back(0.0);
      continue;
    }
    if (!(std::isfinite(v) && v >= 0.1 && v <= 600.0)) {
      Fail(*values[i].second,
           fmt::format("{} durations must be in [0.1, 600] s{}, got {}", key,
                       real_reference ? " (or 0: subject-paced)" : "", v));
      return;
    }
    b.interval_s.push_back(v);
  }
}

void Parser::ParsePacing(const toml::table& t, const std::string& name,
                         Block& b) {
  b.practice = Boolean(t, "practice", name + ".practice").value_or(false);
  // Feedback needs a correct answer that is more than the answer itself.
  const std::string no_feedback = NoFeedbackReason(b);
  if (std::optional<bool> f = Boolean(t, "feedback", name + ".feedback")) {
    if (*f && !no_feedback.empty()) {
      Fail(*t.get("feedback"),
           fmt::format("{}.feedback cannot be true: {}", name, no_feedback));
    } else {
      b.feedback = *f;
    }
  } else {
    b.feedback = b.practice && no_feedback.empty();
  }
  struct Gap {
    std::string_view key;
    double* value;
  };
  for (const Gap& g : {Gap{"isi_s", &b.isi_s}, Gap{"iti_s", &b.iti_s}}) {
    const std::string field = fmt::format("{}.{}", name, g.key);
    if (std::optional<double> v = Number(t, g.key, field)) {
      if (Range(t, g.key, field, *v, 0.0, kMaxGapS, false, false)) {
        *g.value = *v;
      }
    }
  }
  const std::string deadline = name + ".response_deadline_s";
  if (std::optional<double> v = Number(t, "response_deadline_s", deadline)) {
    if (Range(t, "response_deadline_s", deadline, *v, 0.0, kMaxGapS, true,
              false)) {
      b.response_deadline_s = *v;
    }
  }
  const std::string every = name + ".break_every";
  if (std::optional<std::int64_t> v = Integer(t, "break_every", every)) {
    if (Range(t, "break_every", every, static_cast<double>(*v), 1,
              kMaxTrialsPerBlock, false, false)) {
      b.break_every = static_cast<int>(*v);
    }
  }
}

void Parser::ParseStaircase(const toml::table& t, const std::string& name,
                            StaircaseOptions& o, const Axis* axis) {
  auto integer = [&](std::string_view key, int* out, int lo, int hi) {
    const std::string field = fmt::format("{}.{}", name, key);
    if (auto v = Integer(t, key, field)) {
      if (Range(t, key, field, static_cast<double>(*v), lo, hi, false, false)) {
        *out = static_cast<int>(*v);
      }
    }
  };
  auto number = [&](std::string_view key, double* out, bool positive) {
    const std::string field = fmt::format("{}.{}", name, key);
    if (auto v = Number(t, key, field)) {
      if (positive && *v <= 0.0) {
        Fail(*t.get(key),
             fmt::format("{} must be positive, got {}", field, *v));
        return;
      }
      *out = *v;
    }
  };
  integer("n_down", &o.n_down, 1, 10);
  integer("n_up", &o.n_up, 1, 10);
  number("step_down", &o.step_down, true);
  number("step_up", &o.step_up, true);
  constexpr std::string_view kScales[] = {"linear", "log10", "db"};
  if (auto s = Choice(t, "step_scale", name + ".step_scale", kScales)) {
    o.step_scale = static_cast<StepScale>(*s);
  }
  if (auto v = Number(t, "start_level", name + ".start_level")) {
    o.start_level = *v;
    CheckLevel(t, "start_level", name + ".start_level", axis, *v);
  }
  if (auto v = Number(t, "floor", name + ".floor")) {
    o.floor_level = *v;
    CheckLevel(t, "floor", name + ".floor", axis, *v);
  }
  if (auto v = Number(t, "ceiling", name + ".ceiling")) {
    o.ceiling_level = *v;
    CheckLevel(t, "ceiling", name + ".ceiling", axis, *v);
  }
  integer("max_trials", &o.max_trials, 0, kMaxTrialsPerBlock);
  integer("max_reversals", &o.max_reversals, 0, 1000);
  if (const toml::node* node = t.get("step_schedule")) {
    const toml::array* a = node->as_array();
    if (a == nullptr || !a->is_array_of_tables()) {
      Fail(*node, fmt::format("{}.step_schedule must be an array of tables "
                              "{{after_reversals, step_down, step_up}}, got {}",
                              name, TomlTypeName(*node)));
    } else if (a->size() > kMaxScheduleEntries) {
      // Every interleaved staircase copies the block's schedule: bounded, so
      // that copies stay linear in the file.
      Fail(*node, fmt::format("{}.step_schedule holds {} entries; at most {}",
                              name, a->size(), kMaxScheduleEntries));
    } else {
      o.step_schedule.clear();
      for (std::size_t i = 0; i < a->size(); ++i) {
        const toml::table& e = *a->get(i)->as_table();
        const std::string en = fmt::format("{}.step_schedule[{}]", name, i + 1);
        CheckKeys(e, en, {std::begin(kScheduleKeys), std::end(kScheduleKeys)});
        StepChange c;
        bool ok = true;
        for (std::string_view k : kScheduleKeys) {
          if (e.get(k) == nullptr) {
            Fail(e, fmt::format("{} needs \"{}\"", en, k));
            ok = false;
          }
        }
        if (auto v = Integer(e, "after_reversals", en + ".after_reversals")) {
          c.after_reversals =
              static_cast<int>(std::clamp<std::int64_t>(*v, -1, 100000));
        }
        if (auto v = Number(e, "step_down", en + ".step_down"))
          c.step_down = *v;
        if (auto v = Number(e, "step_up", en + ".step_up")) c.step_up = *v;
        if (ok) o.step_schedule.push_back(c);
      }
    }
  }
}

void Parser::ParseBlock(const toml::table& t, int index, const Protocol& p,
                        Block& b) {
  const std::string name = fmt::format("blocks[{}]", index);
  b.where = Where(t);
  b.name = fmt::format("block{}", index);
  if (auto n = String(t, "name", name + ".name")) {
    if (n->empty()) {
      Fail(*t.get("name"), name + ".name must not be empty");
    } else {
      b.name = *n;
    }
  }
  std::optional<int> method = Choice(t, "method", name + ".method", kMethods);
  if (!method.has_value()) {
    if (t.get("method") == nullptr) {
      Fail(t, fmt::format("{} needs \"method\" (one of {})", name,
                          JoinKeys(kMethods)));
    }
    return;
  }
  b.method = static_cast<Method>(*method);
  constexpr std::string_view kTasks[] = {"probe", "drill"};
  if (auto task = Choice(t, "task", name + ".task", kTasks)) {
    b.task = static_cast<Task>(*task);
  } else if (t.get("task") == nullptr) {
    Fail(t, fmt::format("{} needs \"task\" (probe or drill)", name));
  }
  b.instructions =
      String(t, "instructions", name + ".instructions").value_or("");
  b.question = String(t, "question", name + ".question").value_or("");

  // Keys of this method and of all others (for "does not apply").
  std::vector<std::string_view> allowed(std::begin(kCommonBlockKeys),
                                        std::end(kCommonBlockKeys));
  std::vector<std::string_view> every;
  auto add = [](std::vector<std::string_view>& to, Keys keys) {
    for (std::string_view k : keys) {
      if (std::find(to.begin(), to.end(), k) == to.end()) to.push_back(k);
    }
  };
  for (Keys k : {Keys(kSameDifferentKeys), Keys(kTwoIntervalKeys),
                 Keys(kAxisMethodKeys), Keys(kConstantKeys), Keys(kLimitsKeys),
                 Keys(kAdjustmentKeys), Keys(kStaircaseKeys),
                 Keys(kStaircaseBlockKeys), Keys(kQuestBlockKeys)}) {
    add(every, k);
  }
  const bool axis_method =
      b.method != Method::kSameDifferent && b.method != Method::kTwoInterval;
  if (axis_method) add(allowed, kAxisMethodKeys);
  switch (b.method) {
    case Method::kSameDifferent:
      add(allowed, kSameDifferentKeys);
      break;
    case Method::kTwoInterval:
      add(allowed, kTwoIntervalKeys);
      break;
    case Method::kConstantStimuli:
      add(allowed, kConstantKeys);
      break;
    case Method::kLimits:
      add(allowed, kLimitsKeys);
      break;
    case Method::kAdjustment:
      add(allowed, kAdjustmentKeys);
      break;
    case Method::kStaircase:
      add(allowed, kStaircaseKeys);
      add(allowed, kStaircaseBlockKeys);
      break;
    case Method::kQuest:
      add(allowed, kQuestBlockKeys);
      break;
  }
  std::vector<std::string_view> elsewhere;
  for (std::string_view k : every) {
    if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
      elsewhere.push_back(k);
    }
  }
  CheckKeys(t, name, allowed, elsewhere,
            fmt::format("does not apply to method {}", MethodName(b.method)));

  const Axis* axis = nullptr;
  if (axis_method) {
    if (auto id = String(t, "axis", name + ".axis")) {
      axis = FindAxis(p, *id);
      if (axis == nullptr && !broken_axes_.contains(*id)) {
        const Keys ids = axis_ids_;
        const std::string_view hint = Suggest(*id, ids);
        Fail(*t.get("axis"),
             fmt::format(
                 "{}.axis: unknown axis \"{}\"{}", name, EchoText(*id),
                 !hint.empty() ? fmt::format(" (did you mean \"{}\"?)", hint)
                 : ids.empty()
                     ? std::string(" (no [axes] declared)")
                     : fmt::format(" (declared: {})", JoinDeclared(ids))));
      } else {
        b.axis = *id;
      }
    } else if (t.get("axis") == nullptr) {
      Fail(t, fmt::format("{} needs \"axis\" (an axis id from [axes])", name));
    }
    if (auto s = Number(t, "standard_level", name + ".standard_level")) {
      b.standard_level = *s;
      CheckLevel(t, "standard_level", name + ".standard_level", axis, *s);
    } else if (axis != nullptr) {
      if (axis->kind == AxisKind::kRatio) {
        b.standard_level = 1.0;
      } else if (axis->kind == AxisKind::kIncrement) {
        b.standard_level = 0.0;
      } else if (t.get("standard_level") == nullptr) {
        Fail(t, fmt::format("{} needs \"standard_level\" (axis \"{}\" is {}, "
                            "which has no natural standard)",
                            name, axis->id, AxisKindName(axis->kind)));
      }
    }
  }
  auto trials = [&](int fallback) -> int {
    if (auto v = Integer(t, "trials", name + ".trials")) {
      if (Range(t, "trials", name + ".trials", static_cast<double>(*v), 1,
                kMaxTrialsPerBlock, false, false)) {
        return static_cast<int>(*v);
      }
      return -1;
    }
    return fallback;
  };
  auto report = [&](const Status& s, std::string_view key) {
    if (s.ok()) return;
    const toml::node* node = key.empty() ? nullptr : t.get(key);
    Fail(node != nullptr ? Where(*node) : Where(t),
         fmt::format("{}: {}", name, s.error().message));
  };

  std::size_t n_intervals = 2;
  std::vector<const toml::table*> staircase_tables;
  const std::size_t errors_before = diagnostics_.size();
  switch (b.method) {
    case Method::kSameDifferent: {
      auto a = MaterialRef(t, "a", name + ".a", p, true);
      auto bm = MaterialRef(t, "b", name + ".b", p, true);
      if (a && bm) {
        b.material_a = *a;
        b.material_b = *bm;
        if (*a == *bm) {
          Fail(*t.get("b"), fmt::format("{}: a and b are both \"{}\"; a "
                                        "same-different block needs two "
                                        "materials",
                                        name, *a));
        }
      }
      const int n = trials(12);
      if (n > 0) {
        b.same_different.n_trials = n;
        if (n % 4 != 0) {
          Fail(*t.get("trials"),
               fmt::format("{}.trials = {} cannot be balanced over AA, AB, "
                           "BA and BB (same-different needs a multiple of 4)",
                           name, n));
        }
      }
      break;
    }
    case Method::kTwoInterval: {
      constexpr std::string_view kDesigns[] = {"2afc", "reference"};
      if (auto d = Choice(t, "design", name + ".design", kDesigns)) {
        b.design = static_cast<TwoIntervalDesign>(*d);
      }
      const bool reference = b.design == TwoIntervalDesign::kReference;
      for (std::string_view k :
           reference ? std::vector<std::string_view>{"standard", "comparison"}
                     : std::vector<std::string_view>{"a", "b", "matching",
                                                     "reference_material",
                                                     "reference_description"}) {
        if (t.get(k) != nullptr) {
          Fail(*t.get(k), fmt::format("key \"{}\" does not apply to design {}",
                                      k, reference ? "reference" : "2afc"));
        }
      }
      if (reference) {
        n_intervals = 3;
        auto a = MaterialRef(t, "a", name + ".a", p, true);
        auto bm = MaterialRef(t, "b", name + ".b", p, true);
        if (a && bm) {
          b.material_a = *a;
          b.material_b = *bm;
        }
        constexpr std::string_view kAb[] = {"a", "b"};
        if (auto m = Choice(t, "matching", name + ".matching", kAb)) {
          b.reference.matching_material = static_cast<MaterialLabel>(*m);
        }
        if (t.get("reference_material") != nullptr) {
          if (auto r = MaterialRef(t, "reference_material",
                                   name + ".reference_material", p, false)) {
            b.reference_material = *r;
          }
        }
        b.reference_description =
            String(t, "reference_description", name + ".reference_description")
                .value_or("");
        if (t.get("reference_material") == nullptr &&
            b.reference_description.empty() &&
            t.get("reference_description") == nullptr) {
          Fail(t, fmt::format("{} needs \"reference_description\" (what the "
                              "real sample is) or \"reference_material\" (a "
                              "simulated reference)",
                              name));
        }
        const int n = trials(10);
        if (n > 0) {
          b.reference.n_trials = n;
          if (n % 2 != 0) {
            Fail(*t.get("trials"),
                 fmt::format("{}.trials = {} cannot be balanced over "
                             "intervals 2 and 3 (the reference design needs "
                             "an even number)",
                             name, n));
          }
        }
      } else {
        auto s = MaterialRef(t, "standard", name + ".standard", p, true);
        auto c = MaterialRef(t, "comparison", name + ".comparison", p, true);
        if (s && c) {
          b.material_a = *s;
          b.material_b = *c;
        }
        const int n = trials(12);
        if (n > 0) {
          b.two_interval.n_trials = n;
          if (n % 2 != 0) {
            Fail(*t.get("trials"),
                 fmt::format("{}.trials = {} cannot be balanced over "
                             "intervals 1 and 2 (2afc needs an even number)",
                             name, n));
          }
        }
      }
      break;
    }
    case Method::kConstantStimuli: {
      ConstantStimuliOptions& o = b.constant_stimuli;
      if (const toml::node* node = t.get("levels")) {
        const toml::array* a = node->as_array();
        if (a == nullptr) {
          Fail(*node, fmt::format("{}.levels must be an array of numbers, got "
                                  "{}",
                                  name, TomlTypeName(*node)));
        } else {
          bool ok = true;
          for (const toml::node& v : *a) {
            if (!v.is_number()) {
              Fail(v, fmt::format("{}.levels must hold numbers, got {}", name,
                                  TomlTypeName(v)));
              ok = false;
              break;
            }
            o.levels.push_back(v.value<double>().value_or(0.0));
          }
          std::set<double> distinct(o.levels.begin(), o.levels.end());
          if (ok && distinct.size() < 2) {
            Fail(*node, fmt::format("{}.levels needs at least 2 distinct "
                                    "levels, got {}",
                                    name, distinct.size()));
          }
          for (double level : o.levels) {
            CheckLevel(t, "levels", name + ".levels", axis, level);
          }
        }
      } else {
        Fail(t, fmt::format("{} needs \"levels\" (the stimulus levels)", name));
      }
      if (auto r = Integer(t, "repetitions", name + ".repetitions")) {
        if (Range(t, "repetitions", name + ".repetitions",
                  static_cast<double>(*r), 1, 1000, false, false)) {
          o.repetitions = static_cast<int>(*r);
        }
      }
      constexpr std::string_view kOrders[] = {"full", "blocked"};
      if (auto c = Choice(t, "order", name + ".order", kOrders)) {
        o.order = static_cast<TrialOrder>(*c);
      }
      constexpr std::string_view kModes[] = {"yesno", "2afc"};
      if (auto c = Choice(t, "response", name + ".response", kModes)) {
        o.response = static_cast<ResponseMode>(*c);
      }
      n_intervals = o.response == ResponseMode::kYesNo ? 1 : 2;
      if (o.levels.size() >= 2) report(o.Validate(), "levels");
      break;
    }
    case Method::kLimits: {
      LimitsOptions& o = b.limits;
      struct F {
        std::string_view key;
        double* value;
      };
      for (F f : {F{"step", &o.step}, F{"ascending_start", &o.ascending_start},
                  F{"descending_start", &o.descending_start},
                  F{"floor", &o.floor_level}, F{"ceiling", &o.ceiling_level}}) {
        if (auto v = Number(t, f.key, fmt::format("{}.{}", name, f.key))) {
          *f.value = *v;
          if (f.key != "step") {
            CheckLevel(t, f.key, fmt::format("{}.{}", name, f.key), axis, *v);
          }
        }
      }
      if (auto v =
              Integer(t, "start_jitter_steps", name + ".start_jitter_steps")) {
        o.start_jitter_steps =
            static_cast<int>(std::clamp<std::int64_t>(*v, -1, 100000));
      }
      if (auto v = Integer(t, "series", name + ".series")) {
        o.n_series = static_cast<int>(std::clamp<std::int64_t>(*v, -1, 100000));
      }
      constexpr std::string_view kDirections[] = {"ascending", "descending"};
      if (auto c = Choice(t, "first_direction", name + ".first_direction",
                          kDirections)) {
        o.first_direction = static_cast<SeriesDirection>(*c);
      }
      report(o.Validate(), "");
      break;
    }
    case Method::kAdjustment: {
      AdjustmentOptions& o = b.adjustment;
      if (auto v = Number(t, "start_level", name + ".start_level")) {
        o.start_level = *v;
        CheckLevel(t, "start_level", name + ".start_level", axis, *v);
      } else if (t.get("start_level") == nullptr) {
        Fail(t, fmt::format("{} needs \"start_level\"", name));
      }
      if (auto v = Number(t, "step", name + ".step")) o.step = *v;
      if (auto v = Number(t, "floor", name + ".floor")) {
        o.floor_level = *v;
        CheckLevel(t, "floor", name + ".floor", axis, *v);
      }
      if (auto v = Number(t, "ceiling", name + ".ceiling")) {
        o.ceiling_level = *v;
        CheckLevel(t, "ceiling", name + ".ceiling", axis, *v);
      }
      constexpr std::string_view kScales[] = {"linear", "log10", "db"};
      if (auto s = Choice(t, "step_scale", name + ".step_scale", kScales)) {
        o.step_scale = static_cast<StepScale>(*s);
      }
      if (auto v =
              Integer(t, "start_jitter_steps", name + ".start_jitter_steps")) {
        o.start_jitter_steps =
            static_cast<int>(std::clamp<std::int64_t>(*v, -1, 100000));
      }
      if (auto v = Integer(t, "max_steps", name + ".max_steps")) {
        o.max_steps =
            static_cast<int>(std::clamp<std::int64_t>(*v, -1, 1000000));
      }
      if (auto v = Integer(t, "repetitions", name + ".repetitions")) {
        if (Range(t, "repetitions", name + ".repetitions",
                  static_cast<double>(*v), 1, 1000, false, false)) {
          b.adjustment_repetitions = static_cast<int>(*v);
        }
      }
      report(o.Validate(), "");
      break;
    }
    case Method::kStaircase: {
      StaircaseOptions base;
      ParseStaircase(t, name, base, axis);
      if (auto v = Integer(t, "threshold_reversals",
                           name + ".threshold_reversals")) {
        if (Range(t, "threshold_reversals", name + ".threshold_reversals",
                  static_cast<double>(*v), 1, 1000, false, false)) {
          b.threshold_reversals = static_cast<int>(*v);
        }
      }
      constexpr std::string_view kModes[] = {"2afc", "yesno"};
      if (auto c = Choice(t, "response", name + ".response", kModes)) {
        b.adaptive_response = static_cast<AdaptiveResponse>(*c);
      }
      std::vector<std::pair<StaircaseOptions, const toml::table*>> list;
      if (const toml::node* node = t.get("staircases")) {
        const toml::array* a = node->as_array();
        if (a == nullptr || !a->is_array_of_tables() || a->empty()) {
          Fail(*node, fmt::format("{}.staircases must be a non-empty array of "
                                  "tables ([[blocks.staircases]])",
                                  name));
        } else {
          for (std::size_t i = 0; i < a->size(); ++i) {
            const toml::table& e = *a->get(i)->as_table();
            const std::string en =
                fmt::format("{}.staircases[{}]", name, i + 1);
            CheckKeys(e, en,
                      {std::begin(kStaircaseKeys), std::end(kStaircaseKeys)});
            StaircaseOptions o = base;
            ParseStaircase(e, en, o, axis);
            list.push_back({o, &e});
          }
        }
      } else {
        list.push_back({base, &t});
      }
      for (std::size_t i = 0; i < list.size(); ++i) {
        const auto& [o, table] = list[i];
        const std::string en =
            t.get("staircases") != nullptr
                ? fmt::format("{}.staircases[{}]", name, i + 1)
                : name;
        if (t.get("max_trials") == nullptr &&
            table->get("max_trials") == nullptr) {
          // Documented as required: the trial count sets the session's
          // length and how many reversals the estimate can use, so it is the
          // author's choice, not a silent default.
          Fail(Where(*table),
               table == &t
                   ? fmt::format("{} needs \"max_trials\" (1 to {}): the "
                                 "staircase stops after that many trials, or "
                                 "sooner at max_reversals",
                                 en, kMaxTrialsPerBlock)
                   : fmt::format("{} needs \"max_trials\" (1 to {}), here or "
                                 "in {}: the staircase stops after that many "
                                 "trials, or sooner at max_reversals",
                                 en, kMaxTrialsPerBlock, name));
          continue;
        }
        if (o.max_trials == 0) {
          const toml::node* at = table->get("max_trials");
          Fail(at != nullptr ? Where(*at) : Where(*table),
               fmt::format("{}: the staircase can never stop: give max_trials "
                           "(1 to {}); a reversal limit alone never ends when "
                           "the subject is always right at the floor",
                           en, kMaxTrialsPerBlock));
          continue;
        }
        if (o.max_reversals > 0 && b.threshold_reversals > o.max_reversals) {
          Fail(t.get("threshold_reversals") != nullptr
                   ? Where(*t.get("threshold_reversals"))
                   : Where(*table),
               fmt::format("{}: threshold_reversals = {} exceeds "
                           "max_reversals = {}, so no threshold could be "
                           "computed",
                           en, b.threshold_reversals, o.max_reversals));
        }
        if (Status s = o.Validate(); !s.ok()) {
          Fail(Where(*table), fmt::format("{}: {}", en, s.error().message));
          continue;
        }
        b.staircases.push_back(o);
        staircase_tables.push_back(table);
      }
      n_intervals = b.adaptive_response == AdaptiveResponse::kYesNo ? 1 : 2;
      break;
    }
    case Method::kQuest: {
      const int n = trials(40);
      if (n > 0) b.quest_trials = n;
      if (auto v = Number(t, "floor", name + ".floor")) {
        b.quest_floor_level = *v;
        CheckLevel(t, "floor", name + ".floor", axis, *v);
      }
      if (auto v = Number(t, "ceiling", name + ".ceiling")) {
        b.quest_ceiling_level = *v;
        CheckLevel(t, "ceiling", name + ".ceiling", axis, *v);
        if (!(b.quest_floor_level < *v)) {
          Fail(*t.get("ceiling"),
               fmt::format("{}.ceiling = {} must be above floor = {}", name, *v,
                           b.quest_floor_level));
        }
      }
      constexpr std::string_view kModes[] = {"2afc", "yesno"};
      if (auto c = Choice(t, "response", name + ".response", kModes)) {
        b.adaptive_response = static_cast<AdaptiveResponse>(*c);
      }
      if (const toml::table* q = Table(t, "quest", name + ".quest")) {
        const std::string qn = name + ".quest";
        CheckKeys(*q, qn, {std::begin(kQuestKeys), std::end(kQuestKeys)});
        QuestOptions& o = b.quest;
        struct F {
          std::string_view key;
          double* value;
        };
        for (F f : {F{"tGuess", &o.t_guess}, F{"tGuessSd", &o.t_guess_sd},
                    F{"pThreshold", &o.p_threshold}, F{"beta", &o.beta},
                    F{"delta", &o.delta}, F{"gamma", &o.gamma},
                    F{"grain", &o.grain}, F{"range", &o.range}}) {
          if (auto v = Number(*q, f.key, fmt::format("{}.{}", qn, f.key))) {
            *f.value = *v;
          }
        }
        // Building the track checks more than Validate (the psychometric
        // table must hold pThreshold): what run would refuse is refused here.
        if (Result<Quest> built = Quest::Create(o); !built.ok()) {
          // The library names fields in snake_case; protocol files use
          // QuestCreate's names.
          std::string message = built.error().message;
          if (message.starts_with("quest: ")) message.erase(0, 7);
          const toml::node* at = q;
          constexpr std::pair<std::string_view, std::string_view> kNames[] = {
              {"t_guess_sd", "tGuessSd"},
              {"t_guess", "tGuess"},
              {"p_threshold", "pThreshold"},
              {"beta", "beta"},
              {"delta", "delta"},
              {"gamma", "gamma"},
              {"grain", "grain"},
              {"range", "range"}};
          bool named = false;
          for (const auto& [snake, ptb] : kNames) {
            if (message.starts_with(std::string(snake) + " ")) {
              message.replace(0, snake.size(), ptb);
              if (const toml::node* key = q->get(ptb)) at = key;
              named = true;
              break;
            }
          }
          Fail(*at, fmt::format("{}{}{}", qn, named ? "." : ": ", message));
        }
      } else if (t.get("quest") == nullptr) {
        Fail(t, fmt::format("{} needs a [blocks.quest] table with at least "
                            "tGuess and tGuessSd (log10 units)",
                            name));
      }
      n_intervals = b.adaptive_response == AdaptiveResponse::kYesNo ? 1 : 2;
      break;
    }
  }
  ParseIntervals(t, name, n_intervals, b);
  ParsePacing(t, name, b);
  if (diagnostics_.size() == errors_before) {
    Reach(t, name, p, axis, staircase_tables, b);
  }
}

void Parser::ReachLevel(const Protocol& p, const Axis& axis, double level,
                        std::string what, SourceLocation where,
                        std::string_view fix, Block& b) {
  Result<stimuli::MaterialSet> set = MaterialAtLevel(p, axis, level);
  if (!set.ok()) {
    Fail(where, fmt::format("{}: {}{}", what, set.error().message, fix));
    return;
  }
  b.reach.push_back({std::move(what), where, level, std::move(set.value())});
}

void Parser::Reach(const toml::table& t, const std::string& name,
                   const Protocol& p, const Axis* axis,
                   std::span<const toml::table* const> staircases, Block& b) {
  auto at = [](const toml::table& table, std::string_view key) {
    const toml::node* node = table.get(key);
    return node != nullptr ? Where(*node) : Where(table);
  };
  // A material the block names under `key`.
  auto material = [&](std::string_view key, const std::string& id) {
    if (const ProtocolMaterial* m = FindMaterial(p, id)) {
      b.reach.push_back({fmt::format("{}.{} = \"{}\"", name, key, id),
                         at(t, key), std::nullopt, m->set});
    }
  };
  if (b.method == Method::kSameDifferent) {
    material("a", b.material_a);
    material("b", b.material_b);
    return;
  }
  if (b.method == Method::kTwoInterval) {
    const bool reference = b.design == TwoIntervalDesign::kReference;
    material(reference ? "a" : "standard", b.material_a);
    material(reference ? "b" : "comparison", b.material_b);
    if (!b.reference_material.empty()) {
      material("reference_material", b.reference_material);
    }
    return;
  }
  if (axis == nullptr) return;
  ReachLevel(
      p, *axis, b.standard_level,
      t.get("standard_level") != nullptr
          ? fmt::format("{}.standard_level = {}", name, b.standard_level)
          : fmt::format("{}: the standard (level {})", name, b.standard_level),
      at(t, "standard_level"), "", b);
  // One end of a track's levels: the bound (floor when `down`, else ceiling)
  // from `table` (named `table_name`) where it stops the track before its
  // steps do, else the level `stepped` its steps reach (`steps` says how).
  auto track_end = [&](bool down, double bound, const toml::table& table,
                       const std::string& table_name, double stepped,
                       const std::string& steps) {
    const std::string_view key = down ? "floor" : "ceiling";
    if (std::isfinite(bound) && (down ? bound >= stepped : bound <= stepped)) {
      const toml::table& from = table.get(key) != nullptr ? table : t;
      const std::string& from_name =
          table.get(key) != nullptr ? table_name : name;
      ReachLevel(p, *axis, bound,
                 fmt::format("{}.{} = {}", from_name, key, bound),
                 at(from, key), "", b);
      return;
    }
    ReachLevel(p, *axis, stepped,
               fmt::format(
                   "{}: {}{} reach level {:.6g}", table_name,
                   std::isfinite(bound) ? "" : fmt::format("with no {}, ", key),
                   steps, stepped),
               Where(table),
               std::isfinite(bound)
                   ? fmt::format("; {} {}", down ? "raise" : "lower", key)
                   : fmt::format("; set {}", key),
               b);
  };
  switch (b.method) {
    case Method::kConstantStimuli: {
      // The lowest and highest levels, at their place in the array.
      const toml::array& levels = *t.get("levels")->as_array();
      std::size_t lo = 0, hi = 0;
      for (std::size_t i = 1; i < b.constant_stimuli.levels.size(); ++i) {
        const double v = b.constant_stimuli.levels[i];
        if (v < b.constant_stimuli.levels[lo]) lo = i;
        if (v > b.constant_stimuli.levels[hi]) hi = i;
      }
      for (std::size_t i : {lo, hi}) {
        const double v = b.constant_stimuli.levels[i];
        ReachLevel(p, *axis, v, fmt::format("{}.levels: level {}", name, v),
                   Where(*levels.get(i)), "", b);
      }
      break;
    }
    case Method::kLimits: {
      // Series walk on to the floor and the ceiling (given or default).
      const LimitsOptions& o = b.limits;
      for (const auto& [key, level] :
           {std::pair<std::string_view, double>{"floor", o.floor_level},
            std::pair<std::string_view, double>{"ceiling", o.ceiling_level}}) {
        ReachLevel(p, *axis, level,
                   t.get(key) != nullptr
                       ? fmt::format("{}.{} = {}", name, key, level)
                       : fmt::format("{}: with no {}, series go on to level "
                                     "{} (the default {})",
                                     name, key, level, key),
                   at(t, key),
                   t.get(key) != nullptr ? "" : fmt::format("; set {}", key),
                   b);
      }
      break;
    }
    case Method::kAdjustment: {
      // The jittered start, then max_steps presses the same way.
      const AdjustmentOptions& o = b.adjustment;
      const double steps =
          static_cast<double>(o.start_jitter_steps) + o.max_steps;
      for (const bool down : {true, false}) {
        track_end(down, down ? o.floor_level : o.ceiling_level, t, name,
                  ApplyStep(o.start_level, (down ? -steps : steps) * o.step,
                            o.step_scale),
                  fmt::format("{} steps of {} {} from start_level {}", steps,
                              o.step, down ? "down" : "up", o.start_level));
      }
      break;
    }
    case Method::kStaircase: {
      // A move down needs n_down trials and one up n_up, so max_trials trials
      // make at most max_trials / n_down moves down, each at most the
      // largest down step of the schedule (and the same up).
      for (std::size_t i = 0; i < b.staircases.size(); ++i) {
        const StaircaseOptions& o = b.staircases[i];
        const toml::table& table = *staircases[i];
        const std::string table_name =
            &table == &t ? name : fmt::format("{}.staircases[{}]", name, i + 1);
        double step_down = o.step_down, step_up = o.step_up;
        for (const StepChange& c : o.step_schedule) {
          step_down = std::max(step_down, c.step_down);
          step_up = std::max(step_up, c.step_up);
        }
        const int moves_down = o.max_trials / o.n_down;
        const int moves_up = o.max_trials / o.n_up;
        track_end(
            true, o.floor_level, table, table_name,
            ApplyStep(o.start_level, -moves_down * step_down, o.step_scale),
            fmt::format("{} steps of {} down from start_level {}", moves_down,
                        step_down, o.start_level));
        track_end(false, o.ceiling_level, table, table_name,
                  ApplyStep(o.start_level, moves_up * step_up, o.step_scale),
                  fmt::format("{} steps of {} up from start_level {}", moves_up,
                              step_up, o.start_level));
      }
      break;
    }
    case Method::kQuest: {
      // Placements lie on the posterior's grid, tGuess +- range/2 (log10
      // units), presented clamped to the axis's domain, floor and ceiling.
      Result<Quest> quest = Quest::Create(b.quest);
      if (!quest.ok()) break;
      const toml::table& q = *t.get("quest")->as_table();
      const auto [domain_lo, domain_hi] = AxisDomain(p, *axis);
      const bool floored = b.quest_floor_level >= domain_lo;
      const bool ceiled = b.quest_ceiling_level <= domain_hi;
      const double lo = floored ? b.quest_floor_level : domain_lo;
      const double hi =
          std::max(lo, ceiled ? b.quest_ceiling_level : domain_hi);
      for (const bool down : {true, false}) {
        const double x = down ? quest->intensity_min() : quest->intensity_max();
        const double raw = std::pow(10.0, x);
        if (raw < lo || raw > hi) {
          const bool below = raw < lo;
          const bool key = below ? floored : ceiled;
          const std::string_view bound = below ? "floor" : "ceiling";
          const double level = below ? lo : hi;
          ReachLevel(
              p, *axis, level,
              key ? fmt::format("{}.{} = {}", name, bound, level)
                  : fmt::format("{}.quest: placements {} level {:.6g} (the {} "
                                "of axis \"{}\"'s domain) are presented there",
                                name, below ? "below" : "above", level,
                                below ? "lower end" : "upper end", axis->id),
              key ? at(t, bound) : Where(q), "", b);
        } else {
          ReachLevel(p, *axis, raw,
                     fmt::format("{}.quest: placements reach level {:.6g} "
                                 "(tGuess {} range/2 = {:.6g} in log10 units)",
                                 name, raw, down ? "-" : "+", x),
                     Where(q), "", b);
        }
      }
      break;
    }
    default:
      break;
  }
}

void Parser::ParseBlocks(const toml::table& root, Protocol& p) {
  const toml::node* node = root.get("blocks");
  if (node == nullptr) {
    Fail(SourceLocation{1, 1},
         "the protocol needs at least one [[blocks]] table");
    return;
  }
  const toml::array* blocks = node->as_array();
  if (blocks == nullptr || !blocks->is_array_of_tables() || blocks->empty()) {
    Fail(*node, fmt::format("blocks must be an array of tables ([[blocks]]), "
                            "got {}",
                            TomlTypeName(*node)));
    return;
  }
  std::map<std::string, int> names;
  for (std::size_t i = 0; i < blocks->size(); ++i) {
    const toml::table& t = *blocks->get(i)->as_table();
    Block b;
    const std::size_t before = diagnostics_.size();
    ParseBlock(t, static_cast<int>(i) + 1, p, b);
    if (auto [it, inserted] = names.emplace(b.name, static_cast<int>(i) + 1);
        !inserted) {
      const toml::node* at = t.get("name");
      Fail(at != nullptr ? Where(*at) : Where(t),
           fmt::format("blocks[{}]: name \"{}\" is already used by blocks[{}]",
                       i + 1, EchoText(b.name), it->second));
    }
    if (diagnostics_.size() == before) p.blocks.push_back(std::move(b));
  }
}

ParseOutcome Parser::Parse(const toml::table& root) {
  Protocol p;
  CheckKeys(root, "the protocol", {std::begin(kRootKeys), std::end(kRootKeys)});
  if (const toml::node* f = root.get("format")) {
    if (!f->is_string() || f->as_string()->get() != kProtocolFormat) {
      Fail(*f, fmt::format(
                   "format must be \"{}\", got {}", kProtocolFormat,
                   f->is_string()
                       ? fmt::format("\"{}\"", EchoText(f->as_string()->get()))
                       : std::string(TomlTypeName(*f))));
    }
  } else {
    Fail(SourceLocation{1, 1},
         fmt::format("the protocol must start with format = \"{}\"",
                     kProtocolFormat));
  }
  p.format = std::string(kProtocolFormat);
  ParseStudy(root, p);
  ParseRecording(root, p);
  ParseObserver(root, p);
  ParseCounterbalance(root, p);
  ParseMaterials(root, p);
  Index(p);
  ParseAxes(root, p);
  // toml++ keeps table keys sorted; the model keeps file order.
  auto by_position = [](const auto& a, const auto& b) {
    return std::pair(a.where.line, a.where.column) <
           std::pair(b.where.line, b.where.column);
  };
  std::stable_sort(p.materials.begin(), p.materials.end(), by_position);
  std::stable_sort(p.axes.begin(), p.axes.end(), by_position);
  Index(p);
  ParseBlocks(root, p);
  ParseOutcome outcome;
  std::stable_sort(diagnostics_.begin(), diagnostics_.end(),
                   [](const Diagnostic& a, const Diagnostic& b) {
                     return std::pair(a.where.line, a.where.column) <
                            std::pair(b.where.line, b.where.column);
                   });
  outcome.diagnostics = std::move(diagnostics_);
  std::stable_sort(notes_.begin(), notes_.end(),
                   [](const Diagnostic& a, const Diagnostic& b) {
                     return std::pair(a.where.line, a.where.column) <
                            std::pair(b.where.line, b.where.column);
                   });
  outcome.notes = std::move(notes_);
  if (outcome.diagnostics.empty()) outcome.protocol = std::move(p);
  return outcome;
}

}  // namespace

ParseOutcome ParseProtocol(std::string_view path, std::string_view text) {
  ParseOutcome outcome;
  if (text.size() > kMaxProtocolBytes) {
    outcome.diagnostics.push_back(
        {{},
         fmt::format("the file is {} bytes; protocol files are limited "
                     "to {} bytes",
                     text.size(), kMaxProtocolBytes)});
    return outcome;
  }
  std::variant<toml::table, stimuli::TomlFailure> root =
      stimuli::ParseTomlDocument(
          path, text, kMaxDots,
          fmt::format("more than {} '.' outside strings and comments; nesting "
                      "this deep is refused",
                      kMaxDots));
  if (const auto* failure = std::get_if<stimuli::TomlFailure>(&root)) {
    SourceLocation where;  // none: the file only
    if (failure->where.has_value()) {
      where = {static_cast<int>(failure->where->line),
               static_cast<int>(failure->where->column)};
    }
    outcome.diagnostics.push_back({where, failure->message});
    return outcome;
  }
  try {
    return Parser(path).Parse(std::get<toml::table>(root));
  } catch (const std::exception& error) {
    outcome.diagnostics.push_back(
        {{}, fmt::format("cannot parse: {}", error.what())});
  }
  return outcome;
}

}  // namespace burrlab::protocols
