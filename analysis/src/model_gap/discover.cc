// Discover and its stages, in the order it runs them: the outlier screen, the
// base fit, the gap tests, the reference check for an absorbed effect,
// attribution and augmentation one effect at a time with their confirmation,
// the verdict, then the trace stage. The fits, the tests and the attribution
// they call are in discover_model_fit.cc, discover_gap_tests.cc and
// discover_attribution.cc, the report's text in discover_summary.cc.
#include "burrlab/analysis/model_gap/discover.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/math/tools/minima.hpp>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/analysis/model_gap/trace_gap.h"
#include "burrlab/base/result.h"
#include "burrlab/sim/effects.h"
#include "model_gap/discover_internal.h"
#include "non_finite.h"

namespace burrlab::analysis {
namespace discover_internal {
namespace {

using detail::kInf;
using detail::kNaN;

// Refits of the base model with the initial velocity's transient factors
// refreshed, at most, and the change of their logs that ends them.
constexpr int kTransientRounds = 4;
constexpr double kTransientTolerance = 1e-3;

// Data the base fit and the gap tests cannot use: no more runs than
// parameters, or a single force level.
Status CheckDesign(const MeasuredData& data) {
  const int n_all = static_cast<int>(data.runs.size());
  if (n_all <= kCalibrationParameters || data.force_levels < 2) {
    return Error{fmt::format(
        "discover needs more runs than parameters and at least 2 force "
        "levels, got {} runs at {} levels",
        n_all, data.force_levels)};
  }
  return {};
}

// The runs the fits use: all of `data` but its gross outliers, whose file
// lines go to report->outlier_lines.
Runs LeaveOutGrossOutliers(const MeasuredData& data,
                           const DiscoverOptions& options,
                           DiscoverReport* report) {
  const Runs all = MakeRuns(data, options.radius_mm, options.definition);
  const std::vector<char> keep = ScreenOutliers(all, options.outlier_sigmas);
  for (int i = 0; i < all.size(); ++i) {
    if (!keep[i]) report->outlier_lines.push_back(all.line[i]);
  }
  return Subset(all, keep);
}

// The progress count's total: the base fit and every v(F) effect family of
// the library in each attribution round.
int ProgressTasks(const DiscoverOptions& options) {
  const int library = static_cast<int>(
      std::count_if(sim::EffectLibrary().begin(), sim::EffectLibrary().end(),
                    [](const sim::EffectSpec& e) {
                      return !e.trace_only && e.Family() == e.id;
                    }));
  return 2 + library * std::max(1, options.max_effects);
}

// The held-out levels `after` predicts better than `before`, and how many
// both predict (0 when either has no per-level errors).
std::pair<int, int> LevelsBetter(const ModelFit& after,
                                 const ModelFit& before) {
  const std::vector<double>& a = after.cv_level_rmse_log_v;
  const std::vector<double>& b = before.cv_level_rmse_log_v;
  if (a.size() != b.size()) return {0, 0};
  int better = 0;
  for (std::size_t i = 0; i < a.size(); ++i) better += a[i] < b[i];
  return {better, static_cast<int>(a.size())};
}

std::string HeldOutFailure(const std::string& added, const ModelFit& before,
                           const ModelFit& after) {
  const auto [better, levels] = LevelsBetter(after, before);
  return fmt::format(
      "adding {} does not lower the held-out error ({:.4g} -> {:.4g}; better "
      "at {} of {} held-out force levels)",
      added, before.cv_rmse_log_v, after.cv_rmse_log_v, better, levels);
}

// Effects significant after the max-T correction, best AICc first.
std::vector<std::size_t> SignificantEffects(
    const std::vector<EffectAttribution>& round, double level) {
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < round.size(); ++i) {
    if (!round[i].absorbed && round[i].lr_p_adjusted < level) {
      candidates.push_back(i);
    }
  }
  std::sort(candidates.begin(), candidates.end(),
            [&](std::size_t a, std::size_t b) {
              return round[a].aicc < round[b].aicc;
            });
  return candidates;
}

// A candidate effect's augmented model, described and tested.
struct Pick {
  std::size_t k = 0;  // index into the round
  ModelFit fit;
  GapTests gap;
};

// The candidate a step adds, if any. `held_out_deferred`: it was taken on
// AICc alone, so the final model must lower the held-out error against the
// base model.
struct StepChoice {
  std::optional<Pick> pick;
  bool held_out_deferred = false;
};

// What the forward steps came to: whether the augmented model explains the
// gap, the effects tried and, when it does not, why.
struct StepwiseOutcome {
  bool explained = false;
  std::vector<std::string> tried;
  std::string failure;
};

// The stages of Discover on one data set. The object holds what they pass
// on: the runs the fits use, the fits and tests on them, the base model, the
// first attribution round, the progress count and the report.
class DiscoverStages {
 public:
  // Screens the gross outliers.
  DiscoverStages(const MeasuredData& data, const DiscoverOptions& options);
  DiscoverStages(const DiscoverStages&) = delete;
  DiscoverStages& operator=(const DiscoverStages&) = delete;

  // 1. The base model (c_e, alpha).
  Status FitBaseModel();
  // 2. Is there a gap? The omnibus tests and the library's focused test (the
  // best effect's max-T adjusted likelihood ratio), combined.
  void TestForGap();
  // 3. With a reference material: the reference with an effect v(F) cannot
  // see explains the data (verdict absorbed).
  bool AbsorbedByReference();
  bool GapDetected() const { return report_.gap_before.detected; }
  // Verdict none.
  void ReportNoGap();
  // 4-5. Attribute and augment one effect at a time, then the verdict:
  // named, ambiguous or unexplained.
  void AttributeAndAugment();
  // 6. The trace stage: tests the trace-only effects (trace_gap.h) on
  // options.traces with the report's base fit and records the result in the
  // report's trace_gap. A significant effect is named when v(F) found nothing
  // (verdict none -> named) and added after the v(F) effects when it found
  // one; the summary says what the traces show either way.
  Status AddTraceGap(const MeasuredData& data);

  DiscoverReport TakeReport() { return std::move(report_); }

 private:
  StepwiseOutcome AddEffectsStepwise();
  StepChoice ChooseEffect(const AttributionRound& round,
                          const std::vector<std::size_t>& candidates,
                          const ModelFit& before, bool further_step_possible,
                          StepwiseOutcome* outcome) const;
  void ReportExplained();
  void ReportUnexplained(const StepwiseOutcome& outcome);

  const DiscoverOptions& options_;
  DiscoverReport report_;
  Runs runs_;      // gross outliers left out
  Workflow flow_;  // on runs_
  Model base_;     // the base fit
  // The base model as the effects' fits see it: with the initial velocity's
  // transient factors held at the base fit, (c_e, alpha) refitted. Where the
  // factors settled this is the base fit; where they did not, the effects'
  // fits (which hold the factors) must be compared with it, not with the fit
  // that computed them at every point, or the stale factors alone give every
  // effect a likelihood ratio at its null strength.
  Model null_;
  ModelFit null_fit_;
  AttributionRound first_round_;  // against null_
  int progress_done_ = 0;
};

DiscoverStages::DiscoverStages(const MeasuredData& data,
                               const DiscoverOptions& options)
    : options_(options),
      runs_(LeaveOutGrossOutliers(data, options, &report_)),
      flow_(runs_, options) {
  flow_.set_total_tasks(ProgressTasks(options));
  report_.velocity_definition = options.definition;
}

Status DiscoverStages::FitBaseModel() {
  if (options_.progress) options_.progress(progress_done_++, 2, "base fit");
  Result<Point> base_point = flow_.BaseFit({});
  if (!base_point.ok()) return base_point.error();
  // The initial velocity's transient factors, held at the base fit: refit
  // until they stop moving. Where the refits cycle instead (near full
  // immersion), fit with the factors computed at every point, from the
  // round that fitted best with its own factors.
  bool settled = runs_.definition != sim::VelocityDefinition::kInitial;
  Point best = *base_point;
  double best_rss = kInf;
  for (int round = 0; round < kTransientRounds && !settled; ++round) {
    settled = RefreshTransient(&runs_, {}, *base_point) < kTransientTolerance;
    const double own = Rss(runs_, {}, *base_point, {});
    if (own < best_rss) {
      best_rss = own;
      best = *base_point;
    }
    if (settled) break;
    base_point = flow_.BaseFit({});
    if (!base_point.ok()) return base_point.error();
  }
  if (settled) {
    base_.point = *base_point;
    base_.rss = Rss(runs_, {}, base_.point, {});
  } else {
    base_.point = FitBaseWithOwnTransient(&runs_, best, &base_.rss);
  }
  report_.baseline = flow_.Describe(base_);
  report_.augmented = report_.baseline;
  null_ = base_;
  null_fit_ = report_.baseline;
  if (!settled) {
    const Result<Point> held = flow_.BaseFit({});
    if (held.ok()) {
      const double rss = Rss(runs_, {}, *held, {});
      if (rss < base_.rss) {
        null_ = Model{{}, *held, rss};
        null_fit_ = flow_.Describe(null_);
      }
    }
  }
  return {};
}

void DiscoverStages::TestForGap() {
  const int n = runs_.size();
  const double level = options_.test_level;
  report_.gap_before = flow_.Gap(base_);
  first_round_ = flow_.Attribute(null_, &progress_done_);
  report_.rounds.push_back(first_round_.effects);
  report_.gap_before.library_p = 1.0;
  for (const EffectAttribution& e : report_.rounds[0]) {
    report_.gap_before.library_p =
        std::min(report_.gap_before.library_p, e.lr_p_adjusted);
  }
  CombineGapTests(&report_.gap_before, level);
  report_.gap_after = report_.gap_before;
  std::vector<double> residual(n);
  for (int i = 0; i < n; ++i) {
    residual[i] = runs_.ln_v[i] - report_.baseline.fitted_log_v[i];
  }
  double ss_pe = 0.0;
  int dof_pe = 0;
  PureError(runs_, residual, &ss_pe, &dof_pe);
  const double sigma = dof_pe >= 1 && ss_pe > 0.0
                           ? std::sqrt(ss_pe / dof_pe)
                           : std::sqrt(base_.rss / std::max(1, n - 2));
  report_.detectable_rms_log_v = DetectableRms(runs_, 2, sigma, level);
}

// The simplest account of the data is tried first: the reference with one
// effect that v(F) cannot see (porosity: c_e scaled), its strength the only
// free parameter. It wins when the data reject the bare reference, but not
// the reference with the effect, and the latter passes the omnibus gap tests:
// a chance gap of the free fit does not outrank it.
bool DiscoverStages::AbsorbedByReference() {
  report_.reference_p = kNaN;
  report_.reference_effect_p = kNaN;
  if (!options_.reference) return false;
  const int n = runs_.size();
  const double level = options_.test_level;
  Point ref;
  ref.ln_c_e = std::log(options_.reference->c_e_n_per_mm2);
  ref.ln_alpha = std::log(options_.reference->alpha_per_s);
  const double rss_ref = Rss(runs_, {}, ref, {});
  // The reference (0 free parameters) against the free base fit (2).
  const int dof = n - 2;
  report_.reference_p =
      FUpper(((rss_ref - base_.rss) / 2.0) / (base_.rss / dof), 2, dof);
  double best_p = -1.0;
  const EffectAttribution* best = nullptr;
  for (const EffectAttribution& e : report_.rounds[0]) {
    if (!e.absorbed) continue;
    const sim::EffectSpec* spec =
        sim::FindEffect(e.variant.empty() ? e.id : e.variant);
    std::vector<ActiveEffect> active = {
        ScaleEffect(*spec, runs_, options_.reference->c_e_n_per_mm2,
                    options_.reference->alpha_per_s)};
    // Reference + effect: only the strength is free (1 parameter).
    double lo = 0.0, hi = active[0].upper;
    const auto rss_at = [&](double u) {
      Point p = ref;
      p.u = {u};
      return Rss(runs_, active, p, {});
    };
    const double u =
        boost::math::tools::brent_find_minima(rss_at, lo, hi, 40).first;
    double value = 0.0;
    value = rss_at(u);
    const double p_effect =
        FUpper(((value - base_.rss) / 1.0) / (base_.rss / dof), 1, dof);
    // The change the effect makes, as an RMS of log v.
    Point with = ref;
    with.u = {u};
    const std::vector<double> y1 = Predict(runs_, active, with);
    const std::vector<double> y0 = Predict(runs_, {}, ref);
    double change = 0.0;
    for (int i = 0; i < n; ++i) change += std::pow(y1[i] - y0[i], 2) / n;
    change = std::sqrt(change);
    if (change > std::log1p(options_.absorbed_margin) && p_effect > best_p) {
      best_p = p_effect;
      best = &e;
      report_.augmented = flow_.Describe(Model{active, with, value});
      report_.augmented.c_e_n_per_mm2 = options_.reference->c_e_n_per_mm2;
      report_.augmented.alpha_per_s = options_.reference->alpha_per_s;
    }
  }
  // Reference + effect must also pass the omnibus gap tests itself.
  GapTests ref_gap;
  if (best != nullptr) {
    ref_gap = RunGapTests(runs_, report_.augmented.fitted_log_v,
                          Jacobian(runs_, {}, base_.point), level);
  }
  // ... at the share of the level the omnibus tests have in the gap family,
  // while the library's focused test finds no shape on the free fit (a real
  // shape effect on the reference material also moves c_e and alpha, so that
  // reference + porosity fits as well as the base).
  const bool no_shape =
      !(report_.gap_before.library_p < (1.0 - kOmnibusShare) * level);
  if (best != nullptr && report_.reference_p < level && best_p >= level &&
      ref_gap.holm_min_p >= kOmnibusShare * level && no_shape) {
    report_.reference_effect_p = best_p;
    report_.verdict = Verdict::kAbsorbed;
    report_.effects = {best->id};
    report_.alias_set = {best->id};
    report_.alias_sets = {report_.alias_set};
    report_.summary = AbsorbedSummary(report_, *best);
    return true;
  }
  report_.augmented = report_.baseline;
  if (best != nullptr) report_.reference_effect_p = best_p;
  return false;
}

void DiscoverStages::ReportNoGap() {
  report_.verdict = Verdict::kNone;
  report_.summary = NoGapSummary(report_);
}

void DiscoverStages::AttributeAndAugment() {
  const StepwiseOutcome outcome = AddEffectsStepwise();
  if (outcome.explained) {
    ReportExplained();
  } else {
    ReportUnexplained(outcome);
  }
}

StepwiseOutcome DiscoverStages::AddEffectsStepwise() {
  const double level = options_.test_level;
  StepwiseOutcome outcome;
  Model current = null_;
  // A step was taken on AICc alone (see ChooseEffect): the final model must
  // then lower the held-out error against the base model.
  bool held_out_deferred = false;
  for (int step = 0; step < options_.max_effects; ++step) {
    // A model must leave the lack-of-fit test at least 3 degrees of freedom
    // (levels - parameters) to be checked at all.
    const int parameters = 3 + step;
    if (runs_.levels - parameters < 3 && step > 0) {
      outcome.failure = fmt::format(
          "after {} the residual tests still fail ({}), and {} force levels "
          "leave too few degrees of freedom to check a model with a further "
          "effect",
          Join(report_.effects), DescribeGap(report_.gap_after), runs_.levels);
      break;
    }
    AttributionRound round;
    if (step == 0) {
      round = first_round_;
    } else {
      round = flow_.Attribute(current, &progress_done_);
      report_.rounds.push_back(round.effects);
    }
    const std::vector<std::size_t> candidates =
        SignificantEffects(round.effects, level);
    if (candidates.empty()) {
      outcome.failure =
          step == 0
              ? "no effect's likelihood-ratio test is significant after "
                "the family-wise (max-T) correction"
              : fmt::format(
                    "after {} the residual tests still fail ({}) and no "
                    "further effect is significant",
                    Join(report_.effects), DescribeGap(report_.gap_after));
      break;
    }
    const ModelFit before = step == 0 ? null_fit_ : report_.augmented;
    const bool further_step_possible =
        step + 1 < options_.max_effects && runs_.levels - (parameters + 1) >= 3;
    const StepChoice choice = ChooseEffect(round, candidates, before,
                                           further_step_possible, &outcome);
    if (!choice.pick) break;
    if (choice.held_out_deferred) held_out_deferred = true;
    const std::size_t best = choice.pick->k;
    outcome.failure.clear();
    report_.lr_p = round.effects[best].lr_p;
    report_.delta_aicc = choice.pick->fit.aicc - before.aicc;
    report_.delta_aicc_runner_up = candidates.size() > 1
                                       ? round.effects[candidates[1]].aicc -
                                             round.effects[candidates[0]].aicc
                                       : kNaN;
    std::vector<std::string> alias =
        AliasSet(flow_, current, round, best, candidates);
    if (step == 0) report_.alias_set = alias;
    report_.alias_sets.push_back(std::move(alias));
    current = round.fits[best];
    report_.effects.push_back(round.effects[best].id);
    report_.augmented = choice.pick->fit;
    report_.gap_after = choice.pick->gap;
    if (!report_.gap_after.detected) {
      outcome.explained = true;
      break;
    }
  }
  if (outcome.explained && held_out_deferred &&
      !PredictsHeldOutBetter(report_.augmented, null_fit_)) {
    outcome.explained = false;
    outcome.failure =
        HeldOutFailure(Join(report_.effects), null_fit_, report_.augmented);
  }
  return outcome;
}

// The best candidate that passes the confirmation; the runners-up within 2
// of its AICc (which the data cannot rank) are tried in turn. Preferred: the
// first that lowers AICc and the held-out error and whose residual tests
// pass; then the first that lowers both (the next step looks for a further
// effect); then, when a further effect can still be checked, the first that
// lowers AICc and leaves the residual tests failing: with two effects in the
// data one alone may not predict a held-out end level better, so the
// held-out error is then required of the final model against the base model
// instead. Each candidate tried goes to outcome->tried, and the reason the
// last one was turned down to outcome->failure.
StepChoice DiscoverStages::ChooseEffect(
    const AttributionRound& round, const std::vector<std::size_t>& candidates,
    const ModelFit& before, bool further_step_possible,
    StepwiseOutcome* outcome) const {
  std::optional<Pick> clean, open_gap, provisional;
  for (std::size_t c = 0; c < candidates.size() && !clean; ++c) {
    const std::size_t k = candidates[c];
    if (c > 0 &&
        round.effects[k].aicc - round.effects[candidates[0]].aicc >= 2.0) {
      break;
    }
    Pick pick{k, flow_.Describe(round.fits[k]), {}};
    outcome->tried.push_back(round.effects[k].id);
    const double delta_aicc = pick.fit.aicc - before.aicc;
    if (!(delta_aicc < 0.0)) {
      outcome->failure = fmt::format("adding {} does not lower AICc ({:+.3g})",
                                     round.effects[k].id, delta_aicc);
      continue;
    }
    pick.gap = flow_.Gap(round.fits[k]);
    if (!PredictsHeldOutBetter(pick.fit, before)) {
      outcome->failure = HeldOutFailure(round.effects[k].id, before, pick.fit);
      if (further_step_possible && pick.gap.detected && !provisional) {
        provisional = pick;
      }
      continue;
    }
    if (pick.gap.detected) {
      if (!open_gap) open_gap = pick;
      continue;
    }
    clean = pick;
  }
  if (clean) return {clean, false};
  if (open_gap) return {open_gap, false};
  return {provisional, provisional.has_value()};
}

void DiscoverStages::ReportExplained() {
  bool ambiguous = false;
  for (const auto& set : report_.alias_sets) ambiguous |= set.size() > 1;
  report_.verdict = ambiguous ? Verdict::kAmbiguous : Verdict::kNamed;
  report_.summary = ExplainedSummary(report_);
}

// Something outside the library (or not confirmed): no forced name.
void DiscoverStages::ReportUnexplained(const StepwiseOutcome& outcome) {
  report_.verdict = Verdict::kUnexplained;
  report_.summary = UnexplainedSummary(report_, outcome.tried, outcome.failure);
  report_.effects.clear();
  report_.alias_set.clear();
  report_.alias_sets.clear();
  report_.augmented = report_.baseline;
  report_.gap_after = report_.gap_before;
}

Status DiscoverStages::AddTraceGap(const MeasuredData& data) {
  if (!options_.traces) return {};
  const std::vector<TraceRun> runs = PairTraces(*options_.traces, data);
  if (runs.empty()) {
    return Error{"none of the traces belongs to a run of the measured data"};
  }
  TraceGapOptions o;
  o.c_e_n_per_mm2 = report_.baseline.c_e_n_per_mm2;
  o.alpha_per_s = report_.baseline.alpha_per_s;
  o.radius_mm = options_.radius_mm;
  o.test_level = options_.test_level;
  Result<TraceGapResult> gap = TestTraceEffects(runs, o);
  if (!gap.ok()) return Error{"traces: " + gap.error().message};
  report_.trace_gap = *gap;
  if (gap->named.empty()) {
    report_.summary += TraceGapNoneSentence(*gap);
    return {};
  }
  const TraceEffectTest* named = nullptr;
  for (const TraceEffectTest& e : gap->effects) {
    if (e.id == gap->named) named = &e;
  }
  const sim::EffectSpec* spec = sim::FindEffect(named->id);
  const std::string finding = TraceGapFinding(*gap, *named);
  // The v(F) model is unchanged by a trace-only effect: the augmented fit
  // keeps its numbers and gains the parameter.
  const auto add = [&](ModelFit* fit) {
    fit->effects.push_back(named->id);
    fit->effect_values.push_back(named->value);
    fit->strengths.push_back(sim::StrengthOfParameter(*spec, named->value));
    ++fit->parameters;
  };
  if (report_.verdict == Verdict::kNone) {
    report_.verdict = Verdict::kNamed;
    report_.effects = {named->id};
    report_.alias_set = {named->id};
    report_.alias_sets = {report_.alias_set};
    add(&report_.augmented);
    report_.summary = finding + " " + report_.summary;
  } else if (report_.verdict == Verdict::kNamed ||
             report_.verdict == Verdict::kAmbiguous) {
    report_.effects.push_back(named->id);
    report_.alias_sets.push_back({named->id});
    add(&report_.augmented);
    report_.summary += " " + finding;
  } else {
    report_.summary += " " + finding;
  }
  return {};
}

}  // namespace
}  // namespace discover_internal

bool PredictsHeldOutBetter(const ModelFit& after, const ModelFit& before) {
  if (!(after.cv_rmse_log_v >= before.cv_rmse_log_v)) return true;
  const auto [better, levels] = discover_internal::LevelsBetter(after, before);
  return 2 * better > levels;
}

Status DiscoverOptions::Validate() const {
  if (!std::isfinite(radius_mm) || radius_mm <= 0.0) {
    return Error{fmt::format(
        "radius_mm must be a positive finite number of mm, got {}", radius_mm)};
  }
  if (!(test_level > 0.0 && test_level < 0.5)) {
    return Error{
        fmt::format("test_level must lie in (0, 0.5), got {}", test_level)};
  }
  if (max_effects < 0 || max_effects > 2) {
    return Error{
        fmt::format("max_effects must lie in [0, 2], got {}", max_effects)};
  }
  if (!(alias_separation >= 0.0 && std::isfinite(alias_separation))) {
    return Error{
        fmt::format("alias_separation must be a finite number >= 0, got {}",
                    alias_separation)};
  }
  if (!(alias_cosine > 0.0 && alias_cosine < 1.0)) {
    return Error{
        fmt::format("alias_cosine must lie in (0, 1), got {}", alias_cosine)};
  }
  if (!(absorbed_index >= 0.0 && absorbed_index < 1.0)) {
    return Error{fmt::format("absorbed_index must lie in [0, 1), got {}",
                             absorbed_index)};
  }
  if (!(outlier_sigmas > 2.0)) {
    return Error{
        fmt::format("outlier_sigmas must exceed 2, got {}", outlier_sigmas)};
  }
  if (!(absorbed_margin >= 0.0 && std::isfinite(absorbed_margin))) {
    return Error{fmt::format("absorbed_margin must be finite and >= 0, got {}",
                             absorbed_margin)};
  }
  if (reference) {
    if (Status s = reference->Validate(); !s.ok()) return s;
  }
  return {};
}

std::string_view VerdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kNone:
      return "none";
    case Verdict::kNamed:
      return "named";
    case Verdict::kAmbiguous:
      return "ambiguous";
    case Verdict::kUnexplained:
      return "unexplained";
    case Verdict::kAbsorbed:
      return "absorbed";
  }
  return "none";
}

Result<DiscoverReport> Discover(const MeasuredData& data,
                                const DiscoverOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  if (Status s = discover_internal::CheckDesign(data); !s.ok()) {
    return s.error();
  }
  // A file that names its velocities must name the ones the model predicts
  // (the command line checks this first, with the file's path).
  if (Status s =
          CheckVelocityDefinition("measured data", data, options.definition);
      !s.ok()) {
    return s.error();
  }
  discover_internal::DiscoverStages stages(data, options);
  if (Status s = stages.FitBaseModel(); !s.ok()) return s.error();
  stages.TestForGap();
  if (!stages.AbsorbedByReference()) {
    if (stages.GapDetected()) {
      stages.AttributeAndAugment();
    } else {
      stages.ReportNoGap();
    }
  }
  // v(F) cannot see load_cell_lag or arm_compliance: their test runs on the
  // traces with the base fit of v(F).
  if (Status s = stages.AddTraceGap(data); !s.ok()) return s.error();
  return stages.TakeReport();
}

}  // namespace burrlab::analysis
