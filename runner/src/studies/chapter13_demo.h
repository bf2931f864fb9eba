// The chapter 13 demo (`burrlab demo`, cli/demo_command.h prints it): the
// dissertation's chapter 13 studies (§13.5.1, §13.5.2) re-run with simulated
// subjects. Simulated-observer models are fitted to the published PVC vs
// bone scores (probing 9.3 +- 0.4, drilling 9.6 +- 0.5 of 12, n = 20) by
// maximum likelihood and compared (kDemoVariants); 20 subjects of the best
// one's population run the PVC vs bone protocol, the best 12 of them run
// Pettigrew vs bone (as in the dissertation) and the best 5 the association
// design of §13.5.2 (which of simulated Pettigrew and PVC felt like the real
// Pettigrew sample, felt through its simulation; published 9.4 +- 0.4 of 10
// from 5 subjects who had run the first experiment), every study is analysed
// from its BIDS exports, and 200 virtual replications predict each result's
// mean and its chance of being significant. The table puts the
// dissertation's numbers beside burrlab's.
#ifndef BURRLAB_RUNNER_STUDIES_CHAPTER13_DEMO_H_
#define BURRLAB_RUNNER_STUDIES_CHAPTER13_DEMO_H_

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "studies/observer_fit.h"

namespace burrlab::runner {

// The observer models the demo compares: those whose renderings are the
// protocol's own (likelihood_varied, whose hand varies, would render every
// stimulus again at five levels of a subject's force).
inline constexpr std::string_view kDemoVariants[] = {
    "fixed", "differencing", "likelihood", "likelihood_alike"};

// The significance level of the predictions (P(p < kDemoAlpha)).
inline constexpr double kDemoAlpha = 0.05;
// The demo's results under DemoOptions::out_dir: one folder per study and the
// summary (demo.json, which also marks the folder as the demo's).
inline constexpr const char* kDemoPvcDir = "pvc_vs_bone";
inline constexpr const char* kDemoPettigrewDir = "pettigrew_vs_bone";
inline constexpr const char* kDemoAssociationDir = "reference_pettigrew";
inline constexpr const char* kDemoMarker = "demo.json";

struct DemoOptions {
  std::filesystem::path out_dir = "burrlab-demo";
  std::uint64_t seed = 1;
  int jobs = 2;
  int renderings = 8;  // simulator renderings per stimulus, for the fit and
                       // the virtual replications
  // The two simulated studies' sessions draw their intervals from those
  // renderings instead of rendering each afresh (faster; every subject then
  // feels one of the same few intervals of a stimulus).
  bool share_renderings = false;
  int virtual_subjects = 2000;       // per virtual study of the observer fits
                                     // (ObserverFitOptions)
  int runs = 200;                    // virtual replications for the prediction
  int subjects = 20;                 // PVC vs bone subjects (dissertation: 20)
  int best_subjects = 12;            // of them, who run Pettigrew vs bone (12)
  int association_subjects = 5;      // of them, who run §13.5.2 (5)
  std::ostream* progress = nullptr;  // progress bars (terminal only)
};

// One block of one study, side by side.
struct DemoRow {
  std::string study;  // "PVC vs bone", "Pettigrew vs bone", "Real Pettigrew"
  std::string block;  // "probe", "drill"
  int trials = 0;     // per subject
  // The dissertation's result; none where it gives no number.
  std::optional<double> paper_mean, paper_sem, paper_p;
  int paper_n = 0;
  std::string paper_finding;
  // One simulated study (burrlab's sessions, analysed from the exports).
  int subjects = 0;
  double mean = 0.0, sem = 0.0;
  double p = 1.0;  // one-sided test against chance
  // "t" (t-test of the subjects' proportions) or "binomial" (exact test of
  // the pooled answers, where every subject scored alike).
  std::string p_test = "t";
  // Virtual replications of the whole design.
  int runs = 0;
  double predicted_mean = 0.0;
  double predicted_sd = 0.0;  // between replications
  // The range holding 95 % of the replications' means (2.5 % and 97.5 %
  // quantiles, type 7): where one study's mean is predicted to fall.
  double predicted_low = 0.0, predicted_high = 0.0;
  double predicted_significant = 0.0;  // P(p < 0.05), t-test
  std::string verdict;                 // agreement with the dissertation
};

struct DemoReport {
  // The observer models fitted to the published PVC vs bone scores, best
  // (lowest AIC) first; the demo's subjects are the best's population.
  std::vector<VariantFit> variants;
  std::vector<ObserverFit> fits;  // the best's: probe, drill
  double weber_stiffness = 0.0, weber_removal = 0.0;
  double spread_stiffness = 0.0, spread_removal = 0.0;
  std::vector<std::string> best_subjects;         // labels, PVC study
  std::vector<std::string> association_subjects;  // labels, PVC study
  std::vector<DemoRow> rows;
  std::vector<std::string> figures;  // PNG paths
  int rendered = 0;                  // simulator intervals rendered
};

// Runs the demo: writes both studies' journals and exports, the figures and
// the summary (kDemoMarker) under options.out_dir; prints only progress bars
// (to options.progress).
Result<DemoReport> RunChapter13Demo(const DemoOptions& options);

// The summary as demo.json holds it (JSON, indented by 2, no final newline).
std::string DemoReportJsonText(const DemoReport& report,
                               const DemoOptions& options);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_CHAPTER13_DEMO_H_
