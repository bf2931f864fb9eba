// Station script parsing and checking.
#include "station/station_script.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>

#include "burrlab/stimuli/toml_fields.h"
#include "station/station_toml.h"

namespace burrlab::runner {
namespace {

using protocols::Diagnostic;

constexpr std::size_t kMaxWaypoints = 100'000;
constexpr std::size_t kMaxAnswers = 100'000;
constexpr std::size_t kMaxUnplugs = 1'000;
constexpr double kMaxTimeS = 3600.0;
constexpr double kMaxCoordinateMm = 1000.0;
constexpr std::string_view kScriptKeys[] = {"format",
                                            "path",
                                            "answers",
                                            "start_delay_s",
                                            "response_delay_s",
                                            "continue_delay_s",
                                            "end_feedback_after_s",
                                            "unplug"};
constexpr std::string_view kUnplugKeys[] = {"presentation", "interval",
                                            "after_s", "resume"};

// A number (integer or float) in [lo, hi], or a diagnostic naming `name`.
std::optional<double> Number(const toml::node& n, std::string_view name,
                             double lo, double hi, std::string_view unit,
                             std::vector<Diagnostic>* d) {
  const std::optional<double> v = n.value<double>();
  if (!v.has_value() || !(n.is_floating_point() || n.is_integer()) ||
      !std::isfinite(*v) || *v < lo || *v > hi) {
    d->push_back({At(n), fmt::format("{} must be a number{} from {} to {}",
                                     name, unit, lo, hi)});
    return std::nullopt;
  }
  return v;
}

void ParsePath(const toml::node& node, StationScript* script,
               std::vector<Diagnostic>* d) {
  const toml::array* points = node.as_array();
  if (points == nullptr || points->empty() || points->size() > kMaxWaypoints) {
    d->push_back({At(node), fmt::format("path must be an array of 1 to {} "
                                        "waypoints [t_s, x_mm, y_mm, z_mm]",
                                        kMaxWaypoints)});
    return;
  }
  double last_t_s = 0.0;
  for (std::size_t k = 0; k < points->size(); ++k) {
    const toml::node& p = *points->get(k);
    const toml::array* a = p.as_array();
    if (a == nullptr || a->size() != 4) {
      d->push_back({At(p), fmt::format("path[{}] must be [t_s, x_mm, y_mm, "
                                       "z_mm]",
                                       k)});
      continue;
    }
    Waypoint w;
    const std::optional<double> t = Number(
        *a->get(0), fmt::format("path[{}] t_s", k), 0.0, kMaxTimeS, " of s", d);
    bool ok = t.has_value();
    for (int axis = 0; axis < 3; ++axis) {
      const std::optional<double> c =
          Number(*a->get(static_cast<std::size_t>(axis) + 1),
                 fmt::format("path[{}] {}_mm", k, "xyz"[axis]),
                 -kMaxCoordinateMm, kMaxCoordinateMm, " of mm", d);
      if (c.has_value()) {
        w.position_mm[axis] = *c;
      } else {
        ok = false;
      }
    }
    if (!ok) continue;
    if (k > 0 && *t < last_t_s) {
      d->push_back({At(*a->get(0)),
                    fmt::format("path[{}] t_s = {} comes before the previous "
                                "waypoint's {} (times must not decrease)",
                                k, *t, last_t_s)});
      continue;
    }
    w.t_s = *t;
    last_t_s = *t;
    script->path.push_back(w);
  }
}

void ParseAnswers(const toml::node& node, StationScript* script,
                  std::vector<Diagnostic>* d) {
  const toml::array* answers = node.as_array();
  if (answers == nullptr || answers->size() > kMaxAnswers) {
    d->push_back({At(node), fmt::format("answers must be an array of at most "
                                        "{} keys, e.g. [\"1\", \"2\"]",
                                        kMaxAnswers)});
    return;
  }
  for (std::size_t k = 0; k < answers->size(); ++k) {
    const toml::node& a = *answers->get(k);
    const std::optional<std::string> key = a.value<std::string>();
    if (!a.is_string() || !key.has_value() || key->empty() ||
        key->size() > 64) {
      d->push_back({At(a), fmt::format("answers[{}] must be a key or answer "
                                       "of 1 to 64 characters",
                                       k)});
      continue;
    }
    script->answers.push_back(*key);
  }
}

void ParseUnplugs(const toml::node& node, StationScript* script,
                  std::vector<Diagnostic>* d) {
  const toml::array* unplugs = node.as_array();
  if (unplugs == nullptr || !unplugs->is_array_of_tables() ||
      unplugs->size() > kMaxUnplugs) {
    d->push_back({At(node), fmt::format("unplug must be [[unplug]] tables "
                                        "(at most {})",
                                        kMaxUnplugs)});
    return;
  }
  const stimuli::TomlFields fields = StationFields(d);
  for (const toml::node& n : *unplugs) {
    const toml::table& t = *n.as_table();
    fields.CheckKeys(t, "[[unplug]]", kUnplugKeys);
    ScriptedUnplug u;
    bool ok = true;
    for (auto [key, field] : {std::pair{"presentation", &u.presentation},
                              std::pair{"interval", &u.interval}}) {
      if (t.get(key) == nullptr) {
        fields.Fail(n, fmt::format("[[unplug]] needs {}", key));
        ok = false;
      } else if (auto v = fields.IntegerIn(t, key, key, 1, 1'000'000)) {
        *field = static_cast<int>(*v);
      } else {
        ok = false;
      }
    }
    if (t.get("after_s") != nullptr) {
      const std::optional<double> s = fields.Number(t, "after_s", "after_s");
      if (s.has_value() && fields.Range(t, "after_s", "after_s", *s, 0.0,
                                        kMaxTimeS, false, false)) {
        u.after_s = *s;
      } else {
        ok = false;
      }
    }
    if (t.get("resume") != nullptr) {
      if (auto v = fields.Boolean(t, "resume", "resume")) {
        u.resume = *v;
      } else {
        ok = false;
      }
    }
    if (ok) script->unplugs.push_back(u);
  }
}

}  // namespace

StationScriptParseOutcome ParseStationScript(std::string_view path,
                                             std::string_view text) {
  StationScriptParseOutcome outcome;
  std::vector<Diagnostic>& d = outcome.diagnostics;
  std::optional<toml::table> document = ReadStationToml(
      path, text, "station script", kStationScriptFormat, kScriptKeys, &d);
  if (!document.has_value()) return outcome;
  const toml::table& root = *document;
  StationScript script;
  if (const toml::node* n = root.get("path")) {
    ParsePath(*n, &script, &d);
  } else {
    d.push_back({{1, 1},
                 "missing key 'path' (the burr's waypoints in every interval, "
                 "e.g. path = [[0.0, 0.0, 0.0, 3.0], [0.5, 0.0, 0.0, 1.0]])"});
  }
  if (const toml::node* n = root.get("answers")) ParseAnswers(*n, &script, &d);
  const stimuli::TomlFields fields = StationFields(&d);
  for (auto [key, field] :
       {std::pair{"start_delay_s", &script.start_delay_s},
        std::pair{"response_delay_s", &script.response_delay_s},
        std::pair{"continue_delay_s", &script.continue_delay_s}}) {
    const std::optional<double> v = fields.Number(root, key, key);
    if (v.has_value() &&
        fields.Range(root, key, key, *v, 0.0, 60.0, false, false)) {
      *field = *v;
    }
  }
  constexpr std::string_view kEndFeedback = "end_feedback_after_s";
  const std::optional<double> end_feedback =
      fields.Number(root, kEndFeedback, kEndFeedback);
  if (end_feedback.has_value() &&
      fields.Range(root, kEndFeedback, kEndFeedback, *end_feedback, 0.0, 60.0,
                   false, false)) {
    script.end_feedback_after_s = end_feedback;
  }
  if (const toml::node* n = root.get("unplug")) ParseUnplugs(*n, &script, &d);
  if (d.empty()) outcome.script = std::move(script);
  return outcome;
}

}  // namespace burrlab::runner
