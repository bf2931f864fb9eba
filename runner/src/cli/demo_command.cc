// `burrlab demo` (see demo_command.h): runs the chapter 13 demo and prints
// its report.
#include "cli/demo_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <thread>

#include "cli/flags.h"

namespace burrlab::runner {

void PrintDemoReport(const DemoReport& r, const DemoOptions& o,
                     std::ostream& out) {
  out << "Chapter 13 of the dissertation (§13.5.1, §13.5.2), re-run with "
         "simulated subjects\n\n";
  out << "Observer models fitted to the published PVC vs bone scores by "
         "maximum likelihood (analyze fit-observers --compare-variants; ln "
         "L: log probability of both published results):\n";
  out << fmt::format("  {:<18} {:>2} {:>9} {:>8} {:>8} {:>7}\n", "variant", "k",
                     "ln L", "AIC", "BIC", "dAIC");
  for (const VariantFit& v : r.variants) {
    out << fmt::format("  {:<18} {:>2} {:>9.3f} {:>8.2f} {:>8.2f} {:>7.2f}\n",
                       v.variant.name, v.parameters, v.log_likelihood, v.aic,
                       v.bic, v.delta_aic);
  }
  out << fmt::format(
      "The demo's subjects are the best's population ({}, rule {}):\n",
      r.variants.empty() ? "" : r.variants.front().variant.name,
      r.variants.empty()
          ? ""
          : protocols::SameDifferentRuleName(r.variants.front().observer.rule));
  for (const ObserverFit& f : r.fits) {
    out << fmt::format(
        "  {:<6} {} cue: Weber {:.3g} [{:.3g}, {:.3g}], spread {:.3g} "
        "[{:.3g}, {:.3g}] (SD of ln W; 95 % profile intervals); fitted mean "
        "{:.2f}, SD {:.2f}; P(the published result) {:.3g}\n",
        f.block, f.task == protocols::Task::kProbe ? "stiffness" : "removal",
        f.weber, f.weber_low, f.weber_high, f.weber_spread, f.spread_low,
        f.spread_high, f.fitted_mean, f.fitted_sd, f.published_probability);
    for (const std::string& note : f.notes) {
      out << "         note: " << note << '\n';
    }
  }
  out << fmt::format(
      "\n{} simulated subjects ran PVC vs bone; the best {} of them (sub-{}) "
      "ran Pettigrew vs bone, and the best {} (sub-{}) said which of "
      "simulated Pettigrew and PVC felt like the real Pettigrew sample (felt "
      "through its simulation), as in the dissertation.\n",
      o.subjects, r.best_subjects.size(), fmt::join(r.best_subjects, ", sub-"),
      r.association_subjects.size(),
      fmt::join(r.association_subjects, ", sub-"));
  out << fmt::format(
      "Scores are correct answers, of 12 (10 for Real Pettigrew). Expected: "
      "{} virtual replications of the whole design (mean, the range "
      "holding 95 % of their means, and how often p < {}); one study: the "
      "simulated study above, "
      "analysed from its exports (mean +- SEM; p: one-sided t-test against "
      "chance, half the trials, or the exact binomial test of the pooled "
      "answers where every subject scored alike). Agreement compares the "
      "expected score with "
      "the dissertation's mean +- SEM, or the chance of a significant result "
      "with its finding.\n\n",
      r.rows.empty() ? 0 : r.rows[0].runs, kDemoAlpha);
  out << fmt::format("{:<28}  {:<26}  {:<31}  {:<39}  {}\n", "study, block",
                     "dissertation", "burrlab, expected", "burrlab, one study",
                     "agreement");
  for (const DemoRow& row : r.rows) {
    const std::string paper =
        row.paper_mean
            ? fmt::format("{:.1f} +- {:.1f}, p={} (n {})", *row.paper_mean,
                          *row.paper_sem, *row.paper_p, row.paper_n)
            : fmt::format("not different (n {})", row.paper_n);
    const std::string study =
        fmt::format("{:.2f} +- {:.2f}, p={:.2g}{} (n {})", row.mean, row.sem,
                    row.p, row.p_test == "t" ? "" : " binomial", row.subjects);
    const std::string predicted = fmt::format(
        "{:.2f} [{:.2f}, {:.2f}], P(sig) {:.2f}", row.predicted_mean,
        row.predicted_low, row.predicted_high, row.predicted_significant);
    out << fmt::format("{:<28}  {:<26}  {:<31}  {:<39}  {}\n",
                       row.study + ", " + row.block, paper, predicted, study,
                       row.verdict);
  }
  out << fmt::format(
      "\nFigures: {}\nResults (journals, BIDS exports): {}, {}, {}; summary: "
      "{}\n",
      fmt::join(r.figures, ", "), (o.out_dir / kDemoPvcDir).string(),
      (o.out_dir / kDemoPettigrewDir).string(),
      (o.out_dir / kDemoAssociationDir).string(),
      (o.out_dir / kDemoMarker).string());
  out << fmt::format(
      "({} simulator intervals rendered for the fit and the replications, {} "
      "per stimulus; {}; re-analyse with 'burrlab analyze scores {}')\n",
      r.rendered, o.renderings,
      o.share_renderings ? "the sessions shared them"
                         : "every session rendered its own intervals",
      (o.out_dir / kDemoPvcDir).string());
}

int RunDemoCommand(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Re-run the dissertation's chapter 13 studies (§13.5.1, §13.5.2) with "
      "simulated subjects: fit an observer population to the published PVC "
      "vs bone scores, run 20 simulated subjects through PVC vs bone, the "
      "best 12 through Pettigrew vs bone and the best 5 through the "
      "association with the real Pettigrew sample (journals and BIDS "
      "exports), analyse them, predict the Pettigrew and association results "
      "from virtual replications, and print the results beside the "
      "dissertation's, with score histograms.",
      "burrlab demo"};
  DemoOptions options;
  std::string out_dir = options.out_dir.string();
  bool json = false;
  options.jobs =
      static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  FlagSet flags(&app);
  flags
      .AddText("--out",
               "results folder (default burrlab-demo; the demo's own earlier "
               "results there are replaced)",
               &out_dir)
      ->type_name("DIR");
  flags.AddUnsigned("--seed", "seed (default 1)", &options.seed);
  flags.AddInteger("--jobs", "parallel sessions (default: the core count)", 1,
                   256, &options.jobs);
  flags.AddInteger("--renderings",
                   "simulator renderings per stimulus for the fit and the "
                   "virtual replications (default 8)",
                   1, 1000, &options.renderings);
  flags.AddSwitch("--share-renderings",
                  "the simulated studies' sessions draw their intervals from "
                  "those renderings instead of rendering each afresh (faster; "
                  "every subject then feels one of the same few intervals of "
                  "a stimulus)",
                  &options.share_renderings);
  flags.AddInteger("--runs",
                   "virtual replications for the prediction (default 200)", 1,
                   100000, &options.runs);
  flags.AddInteger("--virtual-subjects",
                   "subjects per virtual study of the observer fits (default "
                   "2000)",
                   2, 1000000, &options.virtual_subjects);
  flags.AddSwitch("--json", "print the summary (demo.json) as JSON", &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  options.out_dir = out_dir;
  options.progress = &err;
  Result<DemoReport> report = RunChapter13Demo(options);
  if (!report.ok()) return Fail(err, "demo: " + report.error().message);
  if (json) {
    out << DemoReportJsonText(*report, options) << '\n';
  } else {
    PrintDemoReport(*report, options, out);
  }
  return 0;
}

}  // namespace burrlab::runner
