// The report's paragraph for people: what the discover workflow found and
// why, for each verdict and for the trace stage.
#include <fmt/format.h>

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/analysis/model_gap/trace_gap.h"
#include "burrlab/sim/effects.h"
#include "model_gap/discover_internal.h"

namespace burrlab::analysis::discover_internal {

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

std::string OutliersSentence(const DiscoverReport& report) {
  return report.outlier_lines.empty()
             ? std::string()
             : fmt::format(
                   " {} run(s) far outside their replicates were left "
                   "out as gross outliers.",
                   report.outlier_lines.size());
}

std::string AbsorbedSummary(const DiscoverReport& report,
                            const EffectAttribution& effect) {
  std::string summary = fmt::format(
      "Effect {} is absorbed by the base parameters: v(F) alone cannot "
      "show it (identifiability index {:.2g}), but the data reject the "
      "reference material (p = {:.3g}) while the reference with {} = "
      "{:.4g} fits as well as free c_e and alpha (p = {:.3g}); the fit "
      "absorbs it into c_e = {:.4g} and alpha = {:.4g}.{}",
      effect.id, effect.identifiability, report.reference_p, effect.id,
      report.augmented.effect_values[0], report.reference_effect_p,
      report.baseline.c_e_n_per_mm2, report.baseline.alpha_per_s,
      OutliersSentence(report));
  if (report.gap_before.detected) {
    summary += fmt::format(
        " The gap tests on the free fit fired (p = {:.3g}), but the "
        "reference with {} alone passes them, and it is the simpler "
        "model (1 free parameter against 3).",
        report.gap_before.holm_min_p, effect.id);
  }
  return summary;
}

std::string NoGapSummary(const DiscoverReport& report) {
  return fmt::format(
      "No discrepancy detected: the base model (c_e, alpha) fits v(F) "
      "within the replicates' scatter (smallest Holm-adjusted gap p = "
      "{:.3g}). This design would detect an RMS change of log v of about "
      "{:.3g} with probability 1/2.{}",
      report.gap_before.holm_min_p, report.detectable_rms_log_v,
      OutliersSentence(report));
}

// What the data say of the shape of step k's effect: "" for a family of one,
// " in its shape 'smooth droop'" when the data fix it, or " (shape
// undetermined: smooth droop, hard cap fit alike)".
std::string ShapeClause(const DiscoverReport& report, std::size_t k) {
  if (k >= report.rounds.size()) return "";
  for (const EffectAttribution& e : report.rounds[k]) {
    if (e.id != report.effects[k] || e.shape.empty()) continue;
    if (e.shape_determined) return fmt::format(" in its shape '{}'", e.shape);
    std::vector<std::string> shapes = {e.shape};
    shapes.insert(shapes.end(), e.alike_shapes.begin(), e.alike_shapes.end());
    return fmt::format(" (shape undetermined: {} fit alike)", Join(shapes));
  }
  return "";
}

std::string ExplainedSummary(const DiscoverReport& report) {
  std::string params;
  for (std::size_t k = 0; k < report.augmented.effects.size(); ++k) {
    const sim::EffectSpec* spec = sim::FindEffect(report.augmented.effects[k]);
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
                     "fitted contributions alike or AICc within 2); the "
                     "best, {}{}",
                     Join(set), report.effects[k], ShapeClause(report, k))
               : fmt::format("{}{} ({})", report.effects[k],
                             ShapeClause(report, k),
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
  return report.verdict == Verdict::kNamed
             ? fmt::format(
                   "The base model misses {}{}. {} ({}) closes the gap: "
                   "likelihood ratio p = {:.3g} (boundary-corrected), AICc "
                   "{:+.3g}, held-out RMSE of log v {:.3g} -> {:.3g}, and the "
                   "residual tests pass (Holm p = {:.3g}).{}",
                   found(0), second, adding, params, report.lr_p,
                   report.augmented.aicc - report.baseline.aicc,
                   report.baseline.cv_rmse_log_v,
                   report.augmented.cv_rmse_log_v, report.gap_after.holm_min_p,
                   OutliersSentence(report))
             : fmt::format(
                   "The base model misses {}{}. {} ({}), the best of {}, "
                   "closes the gap: AICc {:+.3g}, held-out RMSE of log v "
                   "{:.3g} -> {:.3g}. Force levels where their predictions "
                   "differ most would separate them.{}",
                   found(0), second, adding, params,
                   report.effects.size() > 1 ? "each set" : "the set",
                   report.augmented.aicc - report.baseline.aicc,
                   report.baseline.cv_rmse_log_v,
                   report.augmented.cv_rmse_log_v, OutliersSentence(report));
}

std::string UnexplainedSummary(const DiscoverReport& report,
                               const std::vector<std::string>& tried,
                               const std::string& failure) {
  return fmt::format(
      "The base model does not fit (smallest Holm-adjusted gap p = {:.3g}), "
      "and no effect of the library explains the gap{}: {}.{}",
      report.gap_before.holm_min_p,
      tried.empty() ? "" : fmt::format(" (tried: {})", Join(tried)),
      failure.empty()
          ? fmt::format("after {} the residual tests still fail ({})",
                        Join(report.effects), DescribeGap(report.gap_after))
          : failure,
      OutliersSentence(report));
}

std::string TraceGapNoneSentence(const TraceGapResult& gap) {
  double min_p = 1.0;
  for (const TraceEffectTest& e : gap.effects) {
    min_p = std::min(min_p, e.p_holm);
  }
  return fmt::format(
      " The traces ({} runs) show no trace-only effect (smallest "
      "Holm-adjusted p = {:.3g}).",
      gap.runs, min_p);
}

std::string TraceGapFinding(const TraceGapResult& gap,
                            const TraceEffectTest& named) {
  const sim::EffectSpec* spec = sim::FindEffect(named.id);
  return fmt::format(
      "The traces ({} runs) show {} ({}): {} = {:.4g} {}, likelihood ratio "
      "{:.3g}, Holm-adjusted p = {:.3g} (boundary-corrected), trace RMSE "
      "{:.3g} -> {:.3g} N and {:.3g} -> {:.3g} mm. Steady v(F) cannot see "
      "it.",
      gap.runs, named.id, spec->signature, spec->parameter, named.value,
      spec->unit, named.lr, named.p_holm, gap.rmse_force_n, named.rmse_force_n,
      gap.rmse_depth_mm, named.rmse_depth_mm);
}

}  // namespace burrlab::analysis::discover_internal
