// Threshold estimators per method, recomputed from the exported trials.
#include "burrlab/analysis/thresholds.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "burrlab/analysis/group_stats.h"

namespace burrlab::analysis {
namespace {

using results_schema::BehFile;
using results_schema::TrialRecord;
using Json = nlohmann::json;

Json Extra(const TrialRecord& t) {
  Json j = Json::parse(t.extra, nullptr, false);
  return j.is_object() ? j : Json::object();
}

std::optional<double> NumberIn(const Json& j, const char* key) {
  if (!j.contains(key) || !j[key].is_number()) return std::nullopt;
  return j[key].get<double>();
}

// Sample SD of `values` (n - 1), none below 2 values.
std::optional<double> Spread(const std::vector<double>& values) {
  Result<MeanSem> m = MeanAndSem(values);
  if (!m.ok()) return std::nullopt;
  return m->sd;
}

// A staircase's step domain: how levels are averaged (Levitt 1971 averages
// in the units the steps are taken in).
struct Domain {
  std::string name;  // "linear", "log10" or "db"
  double To(double level) const {
    if (name == "log10") return std::log10(level);
    if (name == "db") return 20.0 * std::log10(level);
    return level;
  }
  double From(double value) const {
    if (name == "log10") return std::pow(10.0, value);
    if (name == "db") return std::pow(10.0, value / 20.0);
    return value;
  }
  std::string Unit(const std::string& stim_unit) const {
    if (name == "log10") return "log10";
    if (name == "db") return "dB";
    return stim_unit;
  }
};

ThresholdEstimate Base(const std::string& subject,
                       const std::vector<const TrialRecord*>& trials) {
  ThresholdEstimate e;
  e.subject = subject;
  e.block = trials.front()->block;
  e.method = trials.front()->method;
  e.task = trials.front()->task;
  e.stim_unit = trials.front()->stim_unit;
  e.spread_unit = e.stim_unit;
  return e;
}

ThresholdEstimate Staircase(const std::string& subject, int id,
                            const std::vector<const TrialRecord*>& trials,
                            const ThresholdOptions& options) {
  ThresholdEstimate e = Base(subject, trials);
  e.staircase_id = id;
  const Json last = Extra(*trials.back());
  Domain domain{last.contains("step_scale") && last["step_scale"].is_string()
                    ? last["step_scale"].get<std::string>()
                    : "linear"};
  if (domain.name != "linear" && domain.name != "log10" &&
      domain.name != "db") {
    domain.name = "linear";
  }
  int k = options.reversals;
  if (k == 0) {
    const std::optional<double> recorded =
        NumberIn(last, "threshold_reversals");
    k = recorded.has_value() ? static_cast<int>(*recorded) : 6;
    if (!recorded.has_value()) {
      e.note = "the trials do not record threshold_reversals; used 6";
    }
  }
  std::vector<double> reversals;
  for (const TrialRecord* t : trials) {
    if (t->reversal.value_or(false) && t->stim_level.has_value()) {
      reversals.push_back(domain.To(*t->stim_level));
    }
  }
  e.estimator =
      fmt::format("mean of the last {} reversals ({} scale)", k, domain.name);
  e.spread_unit = domain.Unit(e.stim_unit);
  if (static_cast<int>(reversals.size()) < k) {
    e.n = static_cast<int>(reversals.size());
    e.note = fmt::format(
        "only {} reversals in {} trials; {} are needed (fewer with "
        "--reversals)",
        reversals.size(), trials.size(), k);
    return e;
  }
  const std::vector<double> used(reversals.end() - k, reversals.end());
  e.n = k;
  e.value = domain.From(Mean(used));
  e.spread = Spread(used);
  return e;
}

ThresholdEstimate Quest(const std::string& subject,
                        const std::vector<const TrialRecord*>& trials) {
  ThresholdEstimate e = Base(subject, trials);
  e.estimator = "QUEST posterior mean";
  e.spread_unit = "log10";
  e.n = static_cast<int>(trials.size());
  const Json last = Extra(*trials.back());
  const std::optional<double> mean = NumberIn(last, "posterior_mean_log10");
  if (!mean.has_value()) {
    e.note = "the last trial records no posterior_mean_log10";
    return e;
  }
  e.value = std::pow(10.0, *mean);
  e.spread = NumberIn(last, "posterior_sd_log10");
  return e;
}

ThresholdEstimate Limits(const std::string& subject,
                         const std::vector<const TrialRecord*>& trials) {
  ThresholdEstimate e = Base(subject, trials);
  e.estimator = "mean of the series' transition levels";
  std::vector<double> transitions, ascending, descending;
  int series = 0;
  // The current series' first level and answer, and its second level (the
  // direction: ascending series step up); NaN until seen.
  constexpr double kUnseen = std::numeric_limits<double>::quiet_NaN();
  double first_level = kUnseen, second_level = kUnseen;
  int seen = 0;  // trials of the current series so far
  std::string first_answer;
  for (const TrialRecord* t : trials) {
    const Json extra = Extra(*t);
    if (seen == 0) {
      first_level = t->stim_level.value_or(kUnseen);
      first_answer = t->response;
    } else if (seen == 1) {
      second_level = t->stim_level.value_or(kUnseen);
    }
    ++seen;
    if (!extra.value("ends_series", false)) continue;
    ++series;
    const std::optional<double> level = NumberIn(extra, "transition_level");
    if (level.has_value()) transitions.push_back(*level);
    if (std::isfinite(first_level) && std::isfinite(second_level) &&
        second_level != first_level) {
      const bool up = second_level > first_level;
      if (level.has_value()) (up ? ascending : descending).push_back(*level);
      // An ascending series stops at "yes", a descending one at "no".
      if (first_answer == (up ? "yes" : "no")) ++e.started_on_stopping_answer;
    }
    seen = 0;
    first_level = second_level = kUnseen;
  }
  if (!ascending.empty()) e.ascending_mean = Mean(ascending);
  if (!descending.empty()) e.descending_mean = Mean(descending);
  e.ascending_n = static_cast<int>(ascending.size());
  e.descending_n = static_cast<int>(descending.size());
  e.n = static_cast<int>(transitions.size());
  if (transitions.empty()) {
    e.note = fmt::format(
        "none of the {} finished series changed its answer (each ran into "
        "the floor or ceiling)",
        series);
    return e;
  }
  std::vector<std::string> notes;
  if (e.n < series) {
    notes.push_back(
        fmt::format("{} of {} series had no transition", series - e.n, series));
  }
  notes.push_back(fmt::format(
      "ascending {}, descending {}",
      e.ascending_mean
          ? fmt::format("{:.4g} (n = {})", *e.ascending_mean, e.ascending_n)
          : std::string("n/a"),
      e.descending_mean
          ? fmt::format("{:.4g} (n = {})", *e.descending_mean, e.descending_n)
          : std::string("n/a")));
  if (e.started_on_stopping_answer > 0) {
    notes.push_back(fmt::format(
        "warning: {} of {} series started on their stopping answer (an "
        "ascending series on \"yes\", a descending one on \"no\"): their "
        "start was already past the threshold, so start them farther out",
        e.started_on_stopping_answer, series));
  }
  e.note = fmt::format("{}", fmt::join(notes, "; "));
  e.value = Mean(transitions);
  e.spread = Spread(transitions);
  return e;
}

ThresholdEstimate Adjustment(const std::string& subject,
                             const std::vector<const TrialRecord*>& trials) {
  ThresholdEstimate e = Base(subject, trials);
  e.estimator = "mean adjusted level";
  std::vector<double> finals;
  for (const TrialRecord* t : trials) {
    if (const std::optional<double> level =
            NumberIn(Extra(*t), "final_level")) {
      finals.push_back(*level);
    } else if (t->stim_level.has_value()) {
      finals.push_back(*t->stim_level);
    }
  }
  e.n = static_cast<int>(finals.size());
  if (finals.empty()) {
    e.note = "no adjustment was finished";
    return e;
  }
  e.value = Mean(finals);
  e.spread = Spread(finals);
  return e;
}

ThresholdEstimate ConstantStimuli(const std::string& subject,
                                  const std::vector<const TrialRecord*>& trials,
                                  const ThresholdOptions& options) {
  ThresholdEstimate e = Base(subject, trials);
  const bool yes_no = trials.front()->trial_type != "2afc";
  std::map<double, DataBlock> pooled;
  for (const TrialRecord* t : trials) {
    if (!t->stim_level.has_value()) continue;
    DataBlock& b = pooled[*t->stim_level];
    b.level = *t->stim_level;
    ++b.n_total;
    b.n_correct += yes_no ? (t->response == "yes" ? 1 : 0)
                          : (t->correct.value_or(false) ? 1 : 0);
  }
  std::vector<DataBlock> data;
  for (const auto& [level, block] : pooled) data.push_back(block);
  // A ratio axis is fitted in log10(level) and its threshold and interval
  // transformed back: ratios are perceived on a log scale (Weber's law), the
  // fitted function is then symmetric where the observer's noise is, and no
  // bound can be a ratio <= 0 (Kingdom & Prins 2016, ch. 4).
  // The Weibull is left on the ratio itself: it is already a log-scale
  // model (a Gumbel in log x).
  const bool log_fit =
      e.stim_unit == "ratio" && options.sigmoid != Sigmoid::kWeibull &&
      std::all_of(data.begin(), data.end(),
                  [](const DataBlock& b) { return b.level > 0.0; });
  if (log_fit) {
    for (DataBlock& b : data) b.level = std::log10(b.level);
    e.fit_scale = "log10";
  }
  const auto back = [&](double x) { return log_fit ? std::pow(10.0, x) : x; };
  PsychometricOptions o;
  o.sigmoid = options.sigmoid;
  o.n_intervals = yes_no ? 1 : 2;
  o.cuts = {options.cut};
  o.conf = {0.025, 0.975};
  o.bootstrap_samples = options.bootstrap_samples;
  o.seed = options.seed;
  e.estimator =
      fmt::format("{} fit{} ({}), threshold F^-1({})", SigmoidName(o.sigmoid),
                  log_fit ? " in log10(level)" : "", yes_no ? "yes/no" : "2AFC",
                  options.cut);
  e.n = static_cast<int>(trials.size());
  if (Status s = ValidateData(data, o.sigmoid); !s.ok()) {
    e.note = "no fit: " + s.error().message;
    return e;
  }
  Result<PsychometricAnalysis> a = AnalyzePsychometric(data, o);
  if (!a.ok()) {
    e.note = "no fit: " + a.error().message;
    return e;
  }
  e.fit = a->fit;
  const BootstrapEstimate& t = a->thresholds[0];
  e.value = back(t.value);
  // The BCa interval; the percentile interval when BCa has neither bound
  // (e.g. the Fisher information is singular at the fit).
  const bool percentile = !std::isfinite(t.bca[0]) && !std::isfinite(t.bca[1]);
  if (percentile) e.ci_method = "percentile";
  const std::vector<double>& bounds = percentile ? t.percentile : t.bca;
  if (std::isfinite(bounds[0])) e.ci_low = back(bounds[0]);
  if (std::isfinite(bounds[1])) e.ci_high = back(bounds[1]);
  const std::vector<bool>& limited =
      percentile ? t.percentile_at_search_limit : t.bca_at_search_limit;
  e.ci_low_at_search_limit = !limited.empty() && limited[0];
  e.ci_high_at_search_limit = limited.size() > 1 && limited[1];
  if (std::isfinite(a->deviance_p)) e.deviance_p = a->deviance_p;
  // The fit's own warnings and those about the threshold's bounds; the
  // slope's interval is not reported here, nor its warnings.
  std::vector<std::string> skip;
  for (const BootstrapEstimate& b : a->slopes) {
    skip.insert(skip.end(), b.warnings.begin(), b.warnings.end());
  }
  std::string notes;
  for (const std::string& w : a->warnings) {
    if (std::find(skip.begin(), skip.end(), w) != skip.end()) continue;
    notes += (notes.empty() ? "" : "; ") + w;
  }
  if (!a->fit.converged) {
    notes = "the fit did not converge" + (notes.empty() ? "" : "; " + notes);
  }
  e.note = notes;
  return e;
}

}  // namespace

Result<std::vector<ThresholdEstimate>> EstimateThresholds(
    std::span<const BehFile> files, const ThresholdOptions& options) {
  if (options.reversals < 0) {
    return Error{
        fmt::format("reversals must be 0 (the protocol's) or more, "
                    "got {}",
                    options.reversals)};
  }
  if (!(options.cut > 0.0 && options.cut < 1.0)) {
    return Error{fmt::format("cut must be in (0, 1), got {}", options.cut)};
  }
  if (options.bootstrap_samples < 0) {
    return Error{fmt::format("bootstrap samples must be 0 or more, got {}",
                             options.bootstrap_samples)};
  }
  std::vector<ThresholdEstimate> out;
  for (const BehFile& file : files) {
    const std::size_t first_of_file = out.size();
    // Trials per block in order, then per staircase.
    std::vector<std::string> blocks;
    std::map<std::string, std::vector<const TrialRecord*>> by_block;
    for (const TrialRecord& t : file.table.trials) {
      if (t.practice) continue;  // familiarization: never estimated
      auto& list = by_block[t.block];
      if (list.empty()) blocks.push_back(t.block);
      list.push_back(&t);
    }
    for (const std::string& block : blocks) {
      const std::vector<const TrialRecord*>& trials = by_block[block];
      const std::string& method = trials.front()->method;
      if (method == "staircase") {
        std::map<int, std::vector<const TrialRecord*>> tracks;
        for (const TrialRecord* t : trials) {
          tracks[t->staircase_id.value_or(0)].push_back(t);
        }
        for (const auto& [id, track] : tracks) {
          out.push_back(Staircase(file.subject, id, track, options));
        }
      } else if (method == "quest") {
        out.push_back(Quest(file.subject, trials));
      } else if (method == "limits") {
        out.push_back(Limits(file.subject, trials));
      } else if (method == "adjustment") {
        out.push_back(Adjustment(file.subject, trials));
      } else if (method == "constant_stimuli") {
        out.push_back(ConstantStimuli(file.subject, trials, options));
      }
    }
    for (std::size_t k = first_of_file; k < out.size(); ++k) {
      out[k].session = file.session;
    }
  }
  if (out.empty()) {
    return Error{
        "no block has a threshold (staircase, quest, limits, adjustment or "
        "constant_stimuli); same-different and two-interval blocks are "
        "scored with burrlab analyze scores"};
  }
  return out;
}

namespace {

// The two-sided 95 % Student t interval of a mean: mean -+ t(0.975, n - 1) sem.
std::pair<double, double> TInterval95(const MeanSem& m) {
  const boost::math::students_t_distribution<double> t(m.n - 1);
  const double half = boost::math::quantile(t, 0.975) * m.sem;
  return {m.mean - half, m.mean + half};
}

}  // namespace

std::vector<GroupThreshold> GroupThresholds(
    std::span<const ThresholdEstimate> estimates) {
  std::vector<GroupThreshold> groups;
  for (const ThresholdEstimate& e : estimates) {
    auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) {
      return g.session == e.session && g.block == e.block &&
             g.staircase_id == e.staircase_id;
    });
    if (it == groups.end()) {
      GroupThreshold g;
      g.session = e.session;
      g.block = e.block;
      g.staircase_id = e.staircase_id;
      g.method = e.method;
      g.estimator = e.estimator;
      g.stim_unit = e.stim_unit;
      // Ratios, or levels averaged in a log step domain.
      g.geometric = e.stim_unit == "ratio" || e.spread_unit == "log10" ||
                    e.spread_unit == "dB";
      groups.push_back(std::move(g));
      it = groups.end() - 1;
    }
    if (e.value && std::isfinite(*e.value)) {
      it->subjects.push_back(e.subject);
      it->values.push_back(*e.value);
      if (e.ci_low_at_search_limit || e.ci_high_at_search_limit) {
        it->unbounded.push_back(e.subject);
      }
    } else {
      it->without_value.emplace_back(e.subject, e.note);
    }
  }
  for (GroupThreshold& g : groups) {
    g.n = static_cast<int>(g.values.size());
    if (g.n == 0) continue;
    g.mean = Mean(g.values);
    if (g.geometric) {
      g.geometric = std::all_of(g.values.begin(), g.values.end(),
                                [](double v) { return v > 0.0; });
    }
    std::vector<double> logs;
    if (g.geometric) {
      for (double v : g.values) logs.push_back(std::log(v));
      g.geometric_mean = std::exp(Mean(logs));
    }
    if (g.n < 2) continue;
    // Boost.Math reports domain errors by throwing; with n >= 2 finite
    // values none is expected, and none may leave the library.
    try {
      const MeanSem m = *MeanAndSem(g.values);
      g.sd = m.sd;
      g.sem = m.sem;
      std::tie(g.ci_low, g.ci_high) = TInterval95(m);
      if (g.geometric) {
        const MeanSem l = *MeanAndSem(logs);
        g.geometric_sd_factor = std::exp(l.sd);
        g.geometric_sem_factor = std::exp(l.sem);
        const auto [low, high] = TInterval95(l);
        g.geometric_ci_low = std::exp(low);
        g.geometric_ci_high = std::exp(high);
      }
    } catch (const std::exception&) {
      g.ci_low = g.ci_high = g.geometric_ci_low = g.geometric_ci_high =
          GroupThreshold::kNone;
    }
  }
  return groups;
}

LinePlot GroupThresholdPlot(const GroupThreshold& group,
                            std::span<const ThresholdEstimate> estimates) {
  constexpr double kNone = GroupThreshold::kNone;
  LinePlot plot;
  plot.title = fmt::format(
      "{}{}{}: threshold per subject and the group", group.block,
      group.staircase_id ? fmt::format(" staircase {}", *group.staircase_id)
                         : std::string(),
      group.session.empty() ? std::string() : ", ses-" + group.session);
  plot.x_label = "subject";
  plot.y_label = group.stim_unit.empty()
                     ? std::string("threshold")
                     : fmt::format("threshold ({})", group.stim_unit);
  plot.log_y = group.geometric;
  Series bounded{"subject, 95 % interval", {}, {}, false, true, 0};
  Series unbounded{
      "subject, interval at a search limit", {}, {}, false, true, 3};
  Series spread{"subject ± SD of its values", {}, {}, false, true, 2};
  Series plain{"subject", {}, {}, false, true, 4};
  double x = 0.0;
  for (const ThresholdEstimate& e : estimates) {
    if (e.session != group.session || e.block != group.block ||
        e.staircase_id != group.staircase_id || !e.value ||
        !std::isfinite(*e.value)) {
      continue;
    }
    x += 1.0;
    plot.x_tick_labels.emplace_back(x, "sub-" + e.subject);
    const bool limited = e.ci_low_at_search_limit || e.ci_high_at_search_limit;
    const bool has_ci = e.ci_low && e.ci_high;
    const bool has_sd = e.spread && e.spread_unit == e.stim_unit;
    Series& s = limited  ? unbounded
                : has_ci ? bounded
                : has_sd ? spread
                         : plain;
    s.x.push_back(x);
    s.y.push_back(*e.value);
    double low = kNone, high = kNone;
    if (!limited && has_ci) {
      low = *e.ci_low;
      high = *e.ci_high;
    } else if (!limited && has_sd) {
      low = *e.value - *e.spread;
      high = *e.value + *e.spread;
    }
    s.y_low.push_back(low);
    s.y_high.push_back(high);
  }
  x += 1.0;
  plot.x_tick_labels.emplace_back(x, "group");
  const bool geometric = group.geometric && std::isfinite(group.geometric_mean);
  Series mean{geometric ? "group geometric mean, 95 % t interval"
                        : "group mean, 95 % t interval",
              {x},
              {geometric ? group.geometric_mean : group.mean},
              false,
              true,
              1};
  mean.y_low = {geometric ? group.geometric_ci_low : group.ci_low};
  mean.y_high = {geometric ? group.geometric_ci_high : group.ci_high};
  mean.marker_px = {11.0};
  plot.x_range = std::pair(0.4, x + 0.6);
  if (group.stim_unit == "ratio") {
    plot.reference_lines.push_back({false, 1.0, "the standard (ratio 1)"});
  }
  for (Series* s : {&bounded, &spread, &plain, &unbounded}) {
    if (!s->x.empty()) plot.series.push_back(std::move(*s));
  }
  if (std::isfinite(mean.y[0])) plot.series.push_back(std::move(mean));
  return plot;
}

}  // namespace burrlab::analysis
