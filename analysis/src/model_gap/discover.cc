// The model-gap workflow's stages: the outlier screen, the base fit, the gap
// tests, the reference check for an absorbed effect, attribution and
// augmentation one effect at a time with their confirmation, the verdict and
// its summary, then the trace stage.
#include "burrlab/analysis/model_gap/discover.h"

#include <fmt/format.h>

#include <Eigen/Dense>
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
#include "burrlab/sim/effects.h"
#include "model_gap/discover_internal.h"
#include "non_finite.h"

namespace burrlab::analysis {
namespace discover_internal {
namespace {

using detail::kInf;
using detail::kNaN;

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// The trace stage of Discover: tests the trace-only effects (trace_gap.h) on
// options.traces with the report's base fit and records the result in
// report->trace_gap. A significant effect is named when v(F) found nothing
// (verdict none -> named) and added after the v(F) effects when it found
// one; the summary says what the traces show either way.
Status AddTraceGap(const MeasuredData& data, const DiscoverOptions& options,
                   DiscoverReport* report) {
  if (!options.traces) return {};
  const std::vector<TraceRun> runs = PairTraces(*options.traces, data);
  if (runs.empty()) {
    return Error{"none of the traces belongs to a run of the measured data"};
  }
  TraceGapOptions o;
  o.c_e_n_per_mm2 = report->baseline.c_e_n_per_mm2;
  o.alpha_per_s = report->baseline.alpha_per_s;
  o.radius_mm = options.radius_mm;
  o.test_level = options.test_level;
  Result<TraceGapResult> gap = TestTraceEffects(runs, o);
  if (!gap.ok()) return Error{"traces: " + gap.error().message};
  report->trace_gap = *gap;
  if (gap->named.empty()) {
    double min_p = 1.0;
    for (const TraceEffectTest& e : gap->effects) {
      min_p = std::min(min_p, e.p_holm);
    }
    report->summary += fmt::format(
        " The traces ({} runs) show no trace-only effect (smallest "
        "Holm-adjusted p = {:.3g}).",
        gap->runs, min_p);
    return {};
  }
  const TraceEffectTest* named = nullptr;
  for (const TraceEffectTest& e : gap->effects) {
    if (e.id == gap->named) named = &e;
  }
  const sim::EffectSpec* spec = sim::FindEffect(named->id);
  const std::string finding = fmt::format(
      "The traces ({} runs) show {} ({}): {} = {:.4g} {}, likelihood ratio "
      "{:.3g}, Holm-adjusted p = {:.3g} (boundary-corrected), trace RMSE "
      "{:.3g} -> {:.3g} N and {:.3g} -> {:.3g} mm. Steady v(F) cannot see "
      "it.",
      gap->runs, named->id, spec->signature, spec->parameter, named->value,
      spec->unit, named->lr, named->p_holm, gap->rmse_force_n,
      named->rmse_force_n, gap->rmse_depth_mm, named->rmse_depth_mm);
  // The v(F) model is unchanged by a trace-only effect: the augmented fit
  // keeps its numbers and gains the parameter.
  const auto add = [&](ModelFit* fit) {
    fit->effects.push_back(named->id);
    fit->effect_values.push_back(named->value);
    fit->strengths.push_back(sim::StrengthOfParameter(*spec, named->value));
    ++fit->parameters;
  };
  if (report->verdict == "none") {
    report->verdict = "named";
    report->effects = {named->id};
    report->alias_set = {named->id};
    report->alias_sets = {report->alias_set};
    add(&report->augmented);
    report->summary = finding + " " + report->summary;
  } else if (report->verdict == "named" || report->verdict == "ambiguous") {
    report->effects.push_back(named->id);
    report->alias_sets.push_back({named->id});
    add(&report->augmented);
    report->summary += " " + finding;
  } else {
    report->summary += " " + finding;
  }
  return {};
}

// The workflow on v(F) alone (options.traces is not read).
Result<DiscoverReport> DiscoverFromVelocities(const MeasuredData& data,
                                              const DiscoverOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  const int n_all = static_cast<int>(data.runs.size());
  if (n_all <= kCalibrationParameters || data.force_levels < 2) {
    return Error{fmt::format(
        "discover needs more runs than parameters and at least 2 force "
        "levels, got {} runs at {} levels",
        n_all, data.force_levels)};
  }
  DiscoverReport report;
  const Runs all = MakeRuns(data, options.radius_mm);
  const std::vector<char> keep = ScreenOutliers(all, options.outlier_sigmas);
  for (int i = 0; i < all.size(); ++i) {
    if (!keep[i]) report.outlier_lines.push_back(all.line[i]);
  }
  const Runs runs = Subset(all, keep);
  const int n = runs.size();
  const double level = options.test_level;
  Workflow flow(runs, options);
  const int library = static_cast<int>(
      std::count_if(sim::EffectLibrary().begin(), sim::EffectLibrary().end(),
                    [](const sim::EffectSpec& e) { return !e.trace_only; }));
  flow.set_total_tasks(2 + library * std::max(1, options.max_effects));
  int done = 0;
  if (options.progress) options.progress(done++, 2, "base fit");

  // 1. The base model.
  Result<Point> base_point = flow.BaseFit({});
  if (!base_point.ok()) return base_point.error();
  Model base;
  base.point = *base_point;
  base.rss = Rss(runs, {}, base.point, {});
  report.baseline = flow.Describe(base);
  report.augmented = report.baseline;

  // 2. Is there a gap? The omnibus tests and the library's focused test
  // (the best effect's max-T adjusted likelihood ratio), Holm over the four.
  report.gap_before = flow.Gap(base);
  std::vector<Model> fits0;
  std::vector<Eigen::VectorXd> sigs0;
  report.rounds.push_back(flow.Attribute(base, &fits0, &sigs0, &done));
  report.gap_before.library_p = 1.0;
  for (const EffectAttribution& e : report.rounds[0]) {
    report.gap_before.library_p =
        std::min(report.gap_before.library_p, e.lr_p_adjusted);
  }
  CombineGapTests(&report.gap_before, level);
  report.gap_after = report.gap_before;
  {
    std::vector<double> residual(n);
    for (int i = 0; i < n; ++i) {
      residual[i] = runs.ln_v[i] - report.baseline.fitted_log_v[i];
    }
    double ss_pe = 0.0;
    int dof_pe = 0;
    PureError(runs, residual, &ss_pe, &dof_pe);
    const double sigma = dof_pe >= 1 && ss_pe > 0.0
                             ? std::sqrt(ss_pe / dof_pe)
                             : std::sqrt(base.rss / std::max(1, n - 2));
    report.detectable_rms_log_v = DetectableRms(runs, 2, sigma, level);
  }
  report.reference_p = kNaN;
  report.reference_effect_p = kNaN;
  const std::string outliers_text =
      report.outlier_lines.empty()
          ? std::string()
          : fmt::format(
                " {} run(s) far outside their replicates were left "
                "out as gross outliers.",
                report.outlier_lines.size());

  // Absorbed: with a reference material, the simplest account of the data
  // is tried first: the reference with one effect that v(F) cannot see
  // (porosity: c_e scaled), its strength the only free parameter. It wins
  // when the data reject the bare reference, but not the reference with the
  // effect, and the latter passes the omnibus gap tests: a chance gap of the
  // free fit does not outrank it.
  if (options.reference) {
    Point ref;
    ref.ln_c_e = std::log(options.reference->c_e_n_per_mm2);
    ref.ln_alpha = std::log(options.reference->alpha_per_s);
    const double rss_ref = Rss(runs, {}, ref, {});
    // The reference (0 free parameters) against the free base fit (2).
    const int dof = n - 2;
    report.reference_p =
        FUpper(((rss_ref - base.rss) / 2.0) / (base.rss / dof), 2, dof);
    double best_p = -1.0;
    const EffectAttribution* best = nullptr;
    for (const EffectAttribution& e : report.rounds[0]) {
      if (!e.absorbed) continue;
      const sim::EffectSpec* spec = sim::FindEffect(e.id);
      std::vector<ActiveEffect> active = {
          ScaleEffect(*spec, runs, options.reference->c_e_n_per_mm2,
                      options.reference->alpha_per_s)};
      // Reference + effect: only the strength is free (1 parameter).
      double lo = 0.0, hi = active[0].upper;
      const auto rss_at = [&](double u) {
        Point p = ref;
        p.u = {u};
        return Rss(runs, active, p, {});
      };
      const double u =
          boost::math::tools::brent_find_minima(rss_at, lo, hi, 40).first;
      double value = 0.0;
      value = rss_at(u);
      const double p_effect =
          FUpper(((value - base.rss) / 1.0) / (base.rss / dof), 1, dof);
      // The change the effect makes, as an RMS of log v.
      Point with = ref;
      with.u = {u};
      const std::vector<double> y1 = Predict(runs, active, with);
      const std::vector<double> y0 = Predict(runs, {}, ref);
      double change = 0.0;
      for (int i = 0; i < n; ++i) change += std::pow(y1[i] - y0[i], 2) / n;
      change = std::sqrt(change);
      if (change > std::log1p(options.absorbed_margin) && p_effect > best_p) {
        best_p = p_effect;
        best = &e;
        report.augmented = flow.Describe(Model{active, with, value});
        report.augmented.c_e_n_per_mm2 = options.reference->c_e_n_per_mm2;
        report.augmented.alpha_per_s = options.reference->alpha_per_s;
      }
    }
    // Reference + effect must also pass the omnibus gap tests itself.
    GapTests ref_gap;
    if (best != nullptr) {
      ref_gap = RunGapTests(runs, report.augmented.fitted_log_v,
                            Jacobian(runs, {}, base.point), level);
    }
    // ... at the share of the level the omnibus tests have in the gap
    // family, while the library's focused test finds no shape on the free
    // fit (a real shape effect on the reference material also moves c_e and
    // alpha, so that reference + porosity fits as well as the base).
    const bool no_shape =
        !(report.gap_before.library_p < (1.0 - kOmnibusShare) * level);
    if (best != nullptr && report.reference_p < level && best_p >= level &&
        ref_gap.holm_min_p >= kOmnibusShare * level && no_shape) {
      report.reference_effect_p = best_p;
      report.verdict = "absorbed";
      report.effects = {best->id};
      report.alias_set = {best->id};
      report.alias_sets = {report.alias_set};
      report.summary = fmt::format(
          "Effect {} is absorbed by the base parameters: v(F) alone cannot "
          "show it (identifiability index {:.2g}), but the data reject the "
          "reference material (p = {:.3g}) while the reference with {} = "
          "{:.4g} fits as well as free c_e and alpha (p = {:.3g}); the fit "
          "absorbs it into c_e = {:.4g} and alpha = {:.4g}.{}",
          best->id, best->identifiability, report.reference_p, best->id,
          report.augmented.effect_values[0], best_p,
          report.baseline.c_e_n_per_mm2, report.baseline.alpha_per_s,
          outliers_text);
      if (report.gap_before.detected) {
        report.summary += fmt::format(
            " The gap tests on the free fit fired (p = {:.3g}), but the "
            "reference with {} alone passes them, and it is the simpler "
            "model (1 free parameter against 3).",
            report.gap_before.holm_min_p, best->id);
      }
      return report;
    } else {
      report.augmented = report.baseline;
      if (best != nullptr) report.reference_effect_p = best_p;
    }
  }
  if (!report.gap_before.detected) {
    report.verdict = "none";
    report.summary = fmt::format(
        "No discrepancy detected: the base model (c_e, alpha) fits v(F) "
        "within the replicates' scatter (smallest Holm-adjusted gap p = "
        "{:.3g}). This design would detect an RMS change of log v of about "
        "{:.3g} with probability 1/2.{}",
        report.gap_before.holm_min_p, report.detectable_rms_log_v,
        outliers_text);
    return report;
  }

  // 3-4. Attribute and augment, one effect at a time.
  Model current = base;
  std::vector<std::string> tried;
  std::string failure;
  bool explained = false;
  // A step was taken on AICc alone (see below): the final model must then
  // lower the held-out error against the base model.
  bool held_out_deferred = false;
  for (int step = 0; step < options.max_effects; ++step) {
    // A model must leave the lack-of-fit test at least 3 degrees of freedom
    // (levels - parameters) to be checked at all.
    const int parameters = 3 + step;
    if (runs.levels - parameters < 3 && step > 0) {
      failure = fmt::format(
          "after {} the residual tests still fail ({}), and {} force levels "
          "leave too few degrees of freedom to check a model with a further "
          "effect",
          Join(report.effects), DescribeGap(report.gap_after), runs.levels);
      break;
    }
    std::vector<Model> fits;
    std::vector<Eigen::VectorXd> sigs;
    if (step == 0) {
      fits = fits0;
      sigs = sigs0;
    } else {
      report.rounds.push_back(flow.Attribute(current, &fits, &sigs, &done));
    }
    const std::vector<EffectAttribution> round = report.rounds.back();
    // Candidates: significant after the max-T correction, best AICc first.
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
    if (candidates.empty()) {
      failure = step == 0
                    ? "no effect's likelihood-ratio test is significant after "
                      "the family-wise (max-T) correction"
                    : fmt::format(
                          "after {} the residual tests still fail ({}) and no "
                          "further effect is significant",
                          Join(report.effects), DescribeGap(report.gap_after));
      break;
    }
    // The best candidate that passes the confirmation; the runners-up
    // within 2 of its AICc (which the data cannot rank) are tried in turn.
    // Preferred: the first that lowers AICc and the held-out error and whose
    // residual tests pass; then the first that lowers both (the next step
    // looks for a further effect); then, when a further effect can still be
    // checked, the first that lowers AICc and leaves the residual tests
    // failing: with two effects in the data one alone may not predict a
    // held-out end level better, so the held-out error is then required of
    // the final model against the base model instead.
    ModelFit before = step == 0 ? report.baseline : report.augmented;
    const bool further_step_possible =
        step + 1 < options.max_effects && runs.levels - (parameters + 1) >= 3;
    struct Pick {
      std::size_t k = 0;
      ModelFit fit;
      GapTests gap;
    };
    std::optional<Pick> clean, open_gap, provisional;
    for (std::size_t c = 0; c < candidates.size() && !clean; ++c) {
      const std::size_t k = candidates[c];
      if (c > 0 && round[k].aicc - round[candidates[0]].aicc >= 2.0) break;
      Pick pick{k, flow.Describe(fits[k]), {}};
      tried.push_back(round[k].id);
      const double delta_aicc = pick.fit.aicc - before.aicc;
      if (!(delta_aicc < 0.0)) {
        failure = fmt::format("adding {} does not lower AICc ({:+.3g})",
                              round[k].id, delta_aicc);
        continue;
      }
      pick.gap = flow.Gap(fits[k]);
      // NaN passes.
      const bool held_out_drops =
          !(pick.fit.cv_rmse_log_v >= before.cv_rmse_log_v);
      if (!held_out_drops) {
        failure = fmt::format(
            "adding {} does not lower the held-out error ({:.4g} -> {:.4g})",
            round[k].id, before.cv_rmse_log_v, pick.fit.cv_rmse_log_v);
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
    const std::optional<Pick>& chosen = clean      ? clean
                                        : open_gap ? open_gap
                                                   : provisional;
    if (!chosen) break;
    if (!clean && !open_gap) held_out_deferred = true;
    const std::size_t best = chosen->k;
    const ModelFit after = chosen->fit;
    const GapTests after_gap = chosen->gap;
    failure.clear();
    const Model& augmented = fits[best];
    report.lr_p = round[best].lr_p;
    report.delta_aicc = after.aicc - before.aicc;
    report.delta_aicc_runner_up =
        candidates.size() > 1
            ? round[candidates[1]].aicc - round[candidates[0]].aicc
            : kNaN;
    {
      // Alias set: effects the design cannot separate from the best, given
      // the effects already added. Their local signatures may be nearly
      // parallel, or their fitted contributions (augmented minus current
      // predictions, projected off the current Jacobian: for a capped effect
      // such as the power limit the local signature sits at the top force
      // only) are.
      std::vector<std::string> alias = {round[best].id};
      const std::vector<double> y_now =
          Predict(runs, current.active, current.point);
      const Eigen::MatrixXd basis =
          ColumnBasis(Jacobian(runs, current.active, current.point));
      const auto contribution = [&](std::size_t k) {
        const std::vector<double> y =
            Predict(runs, fits[k].active, fits[k].point);
        Eigen::VectorXd d(n);
        for (int i = 0; i < n; ++i) {
          d(i) = std::isfinite(y[i]) ? y[i] - y_now[i] : 0.0;
        }
        return Eigen::VectorXd(Project(basis, d));
      };
      const Eigen::VectorXd c_best = contribution(best);
      // Separation: what a test between the best and effect j could see.
      // The other effect, fitted (with its own c_e and alpha, and the
      // effects already added) to a model's noise-free predictions, leaves a
      // remainder; over the noise variance it is the noncentrality of a
      // test between the two on this design were the best the truth; below
      // options.alias_separation the design would not tell them apart.
      // (The reverse, the best fitted to j's model, was tried: it did not
      // change the second set of the two-effect test's seed 6.)
      double sigma2 = 0.0;
      {
        std::vector<double> residual(n);
        for (int i = 0; i < n; ++i) residual[i] = runs.ln_v[i] - y_now[i];
        double ss_pe = 0.0;
        int dof_pe = 0;
        PureError(runs, residual, &ss_pe, &dof_pe);
        sigma2 = dof_pe >= 2 && ss_pe > 0.0
                     ? ss_pe / dof_pe
                     : fits[best].rss / std::max(1, n - 3);
      }
      // The current model (base plus the effects already added) refitted to
      // `target`'s predictions, then with `spec` added: the remainder over
      // sigma^2.
      struct Pseudo {
        Runs runs;
        std::optional<Model> current;
      };
      const auto make_pseudo = [&](const Model& target) {
        Pseudo ps{runs, std::nullopt};
        ps.runs.ln_v = target.active.empty()
                           ? y_now
                           : Predict(runs, target.active, target.point);
        const Workflow flow_t(ps.runs, options);
        const Result<Point> b = flow_t.BaseFit({});
        if (b.ok()) {
          ps.current = current.active.empty()
                           ? Model{{}, *b, Rss(ps.runs, {}, *b, {})}
                           : flow_t.FitAugmented(current.active, *b, {});
        }
        return ps;
      };
      const auto remainder = [&](const Pseudo& ps,
                                 const sim::EffectSpec& spec) {
        if (!ps.current || !(sigma2 > 0.0)) return kInf;
        const Workflow flow_t(ps.runs, options);
        std::vector<ActiveEffect> active = ps.current->active;
        active.push_back(ScaleEffect(spec, ps.runs,
                                     std::exp(ps.current->point.ln_c_e),
                                     std::exp(ps.current->point.ln_alpha)));
        const Model m = flow_t.FitAugmented(active, ps.current->point, {});
        return std::min(m.rss, ps.current->rss) / sigma2;
      };
      const Pseudo as_best = make_pseudo(fits[best]);
      const auto separation = [&](std::size_t j) {
        return remainder(as_best, *fits[j].active.back().spec);
      };
      for (std::size_t j = 0; j < round.size(); ++j) {
        if (j == best || round[j].absorbed) continue;
        if (separation(j) < options.alias_separation) {
          alias.push_back(round[j].id);
          continue;
        }
        if (std::find(candidates.begin(), candidates.end(), j) ==
            candidates.end()) {
          continue;
        }
        const double denom = sigs[best].norm() * sigs[j].norm();
        const Eigen::VectorXd c_j = contribution(j);
        const double fitted_denom = c_best.norm() * c_j.norm();
        const double cosine = std::max(
            denom > 0.0 ? std::abs(sigs[best].dot(sigs[j])) / denom : 0.0,
            fitted_denom > 0.0 ? std::abs(c_best.dot(c_j)) / fitted_denom
                               : 0.0);
        if (cosine > options.alias_cosine ||
            round[j].aicc - round[best].aicc < 2.0) {
          alias.push_back(round[j].id);
        }
      }
      if (step == 0) report.alias_set = alias;
      report.alias_sets.push_back(std::move(alias));
    }
    current = augmented;
    report.effects.push_back(round[best].id);
    report.augmented = after;
    report.gap_after = after_gap;
    if (!report.gap_after.detected) {
      explained = true;
      break;
    }
  }
  if (explained && held_out_deferred &&
      report.augmented.cv_rmse_log_v >= report.baseline.cv_rmse_log_v) {
    explained = false;
    failure = fmt::format(
        "adding {} does not lower the held-out error ({:.4g} -> {:.4g})",
        Join(report.effects), report.baseline.cv_rmse_log_v,
        report.augmented.cv_rmse_log_v);
  }
  if (explained) {
    bool ambiguous = false;
    for (const auto& set : report.alias_sets) ambiguous |= set.size() > 1;
    report.verdict = ambiguous ? "ambiguous" : "named";
    std::string params;
    for (std::size_t k = 0; k < report.augmented.effects.size(); ++k) {
      const sim::EffectSpec* spec =
          sim::FindEffect(report.augmented.effects[k]);
      params += fmt::format("{}{} = {:.4g} {}", params.empty() ? "" : ", ",
                            spec->parameter, report.augmented.effect_values[k],
                            spec->unit);
    }
    // What step k found: the effect with its signature, or the set the
    // design cannot tell apart.
    const auto found = [&](std::size_t k) {
      const std::vector<std::string>& set = report.alias_sets[k];
      return set.size() > 1
                 ? fmt::format(
                       "an effect of the set {{{}}}, which this design cannot "
                       "tell apart (projected signatures nearly parallel, "
                       "fitted contributions alike or AICc within 2)",
                       Join(set))
                 : fmt::format("{} ({})", report.effects[k],
                               sim::FindEffect(report.effects[k])->signature);
    };
    // A second effect, when one was needed after the first.
    const std::string second =
        report.effects.size() > 1
            ? fmt::format(" and, once it is added, {}", found(1))
            : std::string();
    const std::string adding =
        report.effects.size() > 1
            ? fmt::format("Adding {} and {}", report.effects[0],
                          report.effects[1])
            : std::string("Adding it");
    report.summary =
        report.verdict == "named"
            ? fmt::format(
                  "The base model misses {}{}. {} ({}) closes the gap: "
                  "likelihood ratio p = {:.3g} (boundary-corrected), AICc "
                  "{:+.3g}, held-out RMSE of log v {:.3g} -> {:.3g}, and the "
                  "residual tests pass (Holm p = {:.3g}).{}",
                  found(0), second, adding, params, report.lr_p,
                  report.augmented.aicc - report.baseline.aicc,
                  report.baseline.cv_rmse_log_v, report.augmented.cv_rmse_log_v,
                  report.gap_after.holm_min_p, outliers_text)
            : fmt::format(
                  "The base model misses {}{}. {} ({}), the best of {}, "
                  "closes the gap: AICc {:+.3g}, held-out RMSE of log v "
                  "{:.3g} -> {:.3g}. Force levels where their predictions "
                  "differ most would separate them.{}",
                  found(0), second, adding, params,
                  report.effects.size() > 1 ? "each set" : "the set",
                  report.augmented.aicc - report.baseline.aicc,
                  report.baseline.cv_rmse_log_v, report.augmented.cv_rmse_log_v,
                  outliers_text);
    return report;
  }
  // Something outside the library (or not confirmed): no forced name.
  report.verdict = "unexplained";
  report.summary = fmt::format(
      "The base model does not fit (smallest Holm-adjusted gap p = {:.3g}), "
      "and no effect of the library explains the gap{}: {}.{}",
      report.gap_before.holm_min_p,
      tried.empty() ? "" : fmt::format(" (tried: {})", Join(tried)),
      failure.empty()
          ? fmt::format("after {} the residual tests still fail ({})",
                        Join(report.effects), DescribeGap(report.gap_after))
          : failure,
      outliers_text);
  report.effects.clear();
  report.alias_set.clear();
  report.alias_sets.clear();
  report.augmented = report.baseline;
  report.gap_after = report.gap_before;
  return report;
}

}  // namespace
}  // namespace discover_internal

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

Result<DiscoverReport> Discover(const MeasuredData& data,
                                const DiscoverOptions& options) {
  // v(F) cannot see load_cell_lag or arm_compliance: the workflow runs on
  // v(F) alone, then its base fit feeds the trace-gap test.
  Result<DiscoverReport> report =
      discover_internal::DiscoverFromVelocities(data, options);
  if (!report.ok() || !options.traces) return report;
  if (Status s = discover_internal::AddTraceGap(data, options, &*report);
      !s.ok()) {
    return s.error();
  }
  return report;
}

}  // namespace burrlab::analysis
