// The chapter 13 demo (see chapter13_demo.h): fit, simulate, analyse,
// compare.
#include "studies/chapter13_demo.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>

#include "burrlab/analysis/group_stats.h"
#include "burrlab/analysis/plot.h"
#include "burrlab/analysis/response_times.h"
#include "burrlab/analysis/scores.h"
#include "burrlab/protocols/protocol_file.h"
#include "burrlab/protocols/streams.h"
#include "burrlab/results_schema/bids_read.h"
#include "demo_protocols.h"
#include "studies/progress.h"
#include "studies/rendering_pool.h"
#include "studies/study.h"
#include "studies/virtual_study.h"

namespace burrlab::runner {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// §13.5.1: "The mean scores (out of 12) over all 20 subjects were ...
// Probing surface: 9.3 +- 0.4; Drilling material: 9.6 +- 0.5 ... (p=0.001)";
// "the best 12 subjects ... were incapable of differentiating" Pettigrew from
// bone (Fig. 13.2, no numbers given).
struct Published {
  const char* block;
  double mean;
  double sem;
};
constexpr Published kPvcPublished[] = {{"probe", 9.3, 0.4},
                                       {"drill", 9.6, 0.5}};
constexpr int kPublishedN = 20;
constexpr int kPublishedBestN = 12;
constexpr double kPublishedP = 0.001;
// §13.5.2: "five subjects each performed ten trials. The mean score (out of
// 10) over all 5 subjects was 9.4 +- 0.4 ... (p=0.0001)"; the subjects had
// taken part in the first experiment.
constexpr Published kAssociationPublished = {"association", 9.4, 0.4};
constexpr int kPublishedAssociationN = 5;
constexpr double kPublishedAssociationP = 0.0001;

constexpr const char* kPvcStudy = "PVC vs bone";
constexpr const char* kPettigrewStudy = "Pettigrew vs bone";
constexpr const char* kAssociationStudy = "Real Pettigrew";

// The demo's own folders may be replaced; anything else is never touched.
Status PrepareOutDir(const fs::path& dir) {
  std::error_code ec;
  const bool ours = fs::exists(dir / kDemoMarker, ec);
  for (const char* sub :
       {kDemoPvcDir, kDemoPettigrewDir, kDemoAssociationDir, "figures"}) {
    if (!fs::exists(dir / sub, ec)) continue;
    if (!ours) {
      return Error{fmt::format(
          "{} exists and was not written by burrlab demo (no {} beside it); "
          "choose another --out",
          (dir / sub).string(), kDemoMarker)};
    }
    fs::remove_all(dir / sub, ec);
    if (ec) {
      return Error{fmt::format("cannot replace {}: {}", (dir / sub).string(),
                               ec.message())};
    }
  }
  fs::create_directories(dir / "figures", ec);
  if (ec || !fs::is_directory(dir / "figures")) {
    return Error{fmt::format("cannot create folder {}: {}", dir.string(),
                             ec ? ec.message() : "not a folder")};
  }
  std::ofstream marker(dir / kDemoMarker);
  marker << "{\"status\": \"running\"}\n";
  if (!marker) {
    return Error{fmt::format("cannot write {}", (dir / kDemoMarker).string())};
  }
  return {};
}

Result<std::vector<analysis::BlockScores>> Analyse(const fs::path& dir) {
  Result<std::vector<results_schema::BehFile>> files =
      results_schema::ReadBidsDataset(dir);
  if (!files.ok()) return files.error();
  return analysis::ScoreBlocks(*files);
}

// Mean correct answers and the one-sided t-test p of one block's counts.
struct BlockStats {
  double mean = 0.0;
  double p = 1.0;
};
BlockStats StatsOf(const VirtualBlock& b) {
  std::vector<double> proportions;
  double sum = 0.0;
  for (std::size_t s = 0; s < b.correct.size(); ++s) {
    proportions.push_back(static_cast<double>(b.correct[s]) / b.trials[s]);
    sum += b.correct[s];
  }
  BlockStats stats;
  stats.mean = sum / static_cast<double>(b.correct.size());
  const analysis::ChanceLevel chance = analysis::ChanceOf(
      std::string(protocols::MethodName(b.method)), b.trial_type);
  if (!chance.p) return stats;
  if (Result<analysis::TTestResult> t =
          analysis::OneSampleTTest(proportions, *chance.p);
      t.ok()) {
    stats.p = t->p_greater;
  } else {
    stats.p = proportions[0] > *chance.p ? 0.0 : 1.0;  // all equal
  }
  return stats;
}

// The `best` subjects with the most correct answers over all blocks (ties:
// the earlier subject), in subject order.
std::vector<int> BestSubjects(const std::vector<int>& totals, int best) {
  std::vector<int> order(totals.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return totals[static_cast<std::size_t>(a)] >
           totals[static_cast<std::size_t>(b)];
  });
  order.resize(std::min(order.size(), static_cast<std::size_t>(best)));
  std::sort(order.begin(), order.end());
  return order;
}

struct Tally {
  std::vector<double> means;
  int significant = 0;
};

Json DemoReportJson(const DemoReport& r, const DemoOptions& o) {
  Json j;
  j["status"] = "done";
  j["seed"] = o.seed;
  j["renderings_per_stimulus"] = o.renderings;
  j["sessions_share_renderings"] = o.share_renderings;
  j["intervals_rendered"] = r.rendered;
  j["population"] = {{"weber_stiffness", r.weber_stiffness},
                     {"weber_removal", r.weber_removal},
                     {"spread_stiffness", r.spread_stiffness},
                     {"spread_removal", r.spread_removal}};
  j["observer_variant"] =
      r.variants.empty() ? "" : std::string(r.variants.front().variant.name);
  j["variants"] = Json::array();
  for (const VariantFit& v : r.variants) {
    j["variants"].push_back({{"variant", std::string(v.variant.name)},
                             {"parameters", v.parameters},
                             {"log_likelihood", v.log_likelihood},
                             {"aic", v.aic},
                             {"bic", v.bic},
                             {"delta_aic", v.delta_aic}});
  }
  j["fits"] = Json::array();
  for (const ObserverFit& f : r.fits) {
    j["fits"].push_back({{"block", f.block},
                         {"weber", f.weber},
                         {"weber_ci", {f.weber_low, f.weber_high}},
                         {"weber_spread", f.weber_spread},
                         {"spread_ci", {f.spread_low, f.spread_high}},
                         {"fitted_mean", f.fitted_mean},
                         {"fitted_sd", f.fitted_sd},
                         {"published_probability", f.published_probability},
                         {"notes", f.notes}});
  }
  j["best_subjects"] = r.best_subjects;
  j["association_subjects"] = r.association_subjects;
  j["rows"] = Json::array();
  for (const DemoRow& row : r.rows) {
    Json paper = {{"n", row.paper_n}, {"finding", row.paper_finding}};
    paper["mean"] = row.paper_mean ? Json(*row.paper_mean) : Json();
    paper["sem"] = row.paper_sem ? Json(*row.paper_sem) : Json();
    paper["p"] = row.paper_p ? Json(*row.paper_p) : Json();
    j["rows"].push_back(
        {{"study", row.study},
         {"block", row.block},
         {"trials", row.trials},
         {"dissertation", paper},
         {"simulated_study",
          {{"subjects", row.subjects},
           {"mean", row.mean},
           {"sem", row.sem},
           {"p_one_sided", row.p},
           {"p_test", row.p_test}}},
         {"predicted",
          {{"runs", row.runs},
           {"mean", row.predicted_mean},
           {"sd_between_studies", row.predicted_sd},
           {"range_95", {row.predicted_low, row.predicted_high}},
           {"p_significant", row.predicted_significant}}},
         {"verdict", row.verdict}});
  }
  j["figures"] = r.figures;
  return j;
}

// Mean proportions correct of the dissertation, the simulated study and the
// prediction, with SEM (SD between replications for the prediction) as
// vertical bars (the designs have 12 and 10 trials).
analysis::LinePlot ComparisonPlot(const DemoReport& r) {
  analysis::LinePlot plot;
  plot.title =
      "Mean proportion correct: dissertation, one burrlab study, burrlab "
      "prediction";
  plot.x_label = "study and task";
  plot.y_label = "proportion correct";
  plot.x_range = std::pair(0.5, static_cast<double>(r.rows.size()) + 0.5);
  analysis::Series paper{"dissertation (mean ± SEM)", {}, {}, false, true, 2};
  analysis::Series study{"burrlab study (mean ± SEM)", {}, {}, false, true, 0};
  analysis::Series predicted{
      "prediction (mean ± SD of replications)", {}, {}, false, true, 1};
  double trials = 1.0;
  const auto add = [&](analysis::Series& s, double x, double mid, double half) {
    s.x.push_back(x);
    s.y.push_back(mid / trials);
    s.y_low.push_back((mid - half) / trials);
    s.y_high.push_back((mid + half) / trials);
  };
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const DemoRow& row = r.rows[i];
    const double x = static_cast<double>(i) + 1.0;
    trials = std::max(1, row.trials);
    plot.x_tick_labels.emplace_back(
        x, fmt::format("{} {}", row.study.substr(0, row.study.find(" vs")),
                       row.block));
    if (row.paper_mean) {
      add(paper, x - 0.2, *row.paper_mean, row.paper_sem.value_or(0.0));
    }
    add(study, x, row.mean, row.sem);
    add(predicted, x + 0.2, row.predicted_mean, row.predicted_sd);
  }
  // Chance: half the answers (same-different with equal priors, 2AFC).
  plot.reference_lines.push_back({false, 0.5, "chance"});
  // The whole score range, so chance and a perfect score are in view.
  plot.reference_lines.push_back({false, 1.0, "all correct"});
  plot.series = {paper, study, predicted};
  return plot;
}

}  // namespace

std::string DemoReportJsonText(const DemoReport& report,
                               const DemoOptions& options) {
  return DemoReportJson(report, options).dump(2);
}

Result<DemoReport> RunChapter13Demo(const DemoOptions& options) {
  std::ostream* bar_stream = options.progress;
  std::ostringstream sink;
  std::ostream& progress = bar_stream != nullptr ? *bar_stream : sink;
  Result<protocols::LoadedProtocol> pvc =
      protocols::ParseLoadedProtocol(kDemoPvcVsBonePath, kDemoPvcVsBone);
  if (!pvc.ok()) return pvc.error();
  Result<protocols::LoadedProtocol> pettigrew = protocols::ParseLoadedProtocol(
      kDemoPettigrewVsBonePath, kDemoPettigrewVsBone);
  if (!pettigrew.ok()) return pettigrew.error();
  Result<protocols::LoadedProtocol> association =
      protocols::ParseLoadedProtocol(kDemoReferencePettigrewPath,
                                     kDemoReferencePettigrew);
  if (!association.ok()) return association.error();
  if (Status s = PrepareOutDir(options.out_dir); !s.ok()) return s.error();

  // 1. Render every stimulus of the three designs (shared by all that
  // follows).
  RenderingPool pool(options.renderings, options.seed);
  for (const protocols::LoadedProtocol* p :
       {&pvc.value(), &pettigrew.value(), &association.value()}) {
    ProgressBar bar(progress, 100);
    Result<int> n = PrerenderProtocol(
        p->protocol, pool, 2.0, options.jobs, 1, [&](int done, int total) {
          bar.Update(done * 100 / std::max(1, total),
                     fmt::format("rendering {} ({}/{})", p->path, done, total));
        });
    if (!n.ok()) return n.error();
  }
  CuePool cues(pool, 2.0);

  // 2. Fit the observer models to the published PVC vs bone scores by
  // maximum likelihood, and keep the best supported.
  DemoReport report;
  const protocols::ObserverParams protocol_observer =
      protocols::ObserverParamsFrom(pvc->protocol.observer);
  {
    std::vector<ObservedGroup> observed;
    for (const Published& published : kPvcPublished) {
      observed.push_back(
          {published.mean, published.sem, kPublishedN, published.block, 1});
    }
    std::vector<ObserverVariant> variants;
    for (std::string_view name : kDemoVariants) {
      Result<ObserverVariant> v = FindObserverVariant(name);
      if (!v.ok()) return v.error();
      variants.push_back(*v);
    }
    ObserverFitOptions fit_options;
    fit_options.virtual_subjects = options.virtual_subjects;
    fit_options.seed = options.seed;
    fit_options.base = protocol_observer;
    fit_options.jobs = options.jobs;
    ProgressBar bar(progress,
                    FitsToCompare(variants, static_cast<int>(observed.size())));
    Result<std::vector<VariantFit>> compared = CompareObserverVariants(
        pvc->protocol, observed, variants, fit_options, cues,
        [&](int done, std::string_view name) {
          bar.Update(done, fmt::format("fitted the {} observer to the PVC "
                                       "vs bone scores",
                                       name));
        });
    if (!compared.ok()) return compared.error();
    report.variants = std::move(*compared);
  }
  report.fits = report.variants.front().fits;
  const protocols::ObserverParams base = report.variants.front().observer;
  Result<VirtualStudyOptions> population =
      PopulationOf(report.fits, base, nullptr);
  if (!population.ok()) return population.error();
  report.weber_stiffness = population->observer.weber_stiffness;
  report.weber_removal = population->observer.weber_removal;
  report.spread_stiffness = population->spread_stiffness;
  report.spread_removal = population->spread_removal;

  // 3. One simulated study of each design, as a lab would run it.
  VirtualStudyOptions real = *population;
  real.seed = options.seed;
  SimulatedStudyOptions pvc_study;
  pvc_study.out_dir = options.out_dir / kDemoPvcDir;
  pvc_study.labels = SubjectLabels(options.subjects);
  for (int i = 0; i < options.subjects; ++i) {
    pvc_study.observers.push_back(SubjectObserver(real, i));
  }
  pvc_study.seed = options.seed;
  pvc_study.jobs = options.jobs;
  pvc_study.renderings = options.share_renderings ? &pool : nullptr;
  {
    ProgressBar bar(progress, options.subjects);
    pvc_study.progress = [&](int done, const std::string& label) {
      bar.Update(done, "PVC vs bone: sub-" + label);
    };
    const SimulatedStudyResult r = RunSimulatedStudy(pvc.value(), pvc_study);
    for (const std::string& f : r.failures) {
      if (!f.empty()) return Error{"PVC vs bone study: " + f};
    }
  }
  Result<std::vector<analysis::BlockScores>> pvc_scores =
      Analyse(pvc_study.out_dir);
  if (!pvc_scores.ok()) return pvc_scores.error();
  std::vector<int> totals(static_cast<std::size_t>(options.subjects), 0);
  for (const analysis::BlockScores& b : *pvc_scores) {
    for (std::size_t s = 0; s < b.subjects.size() && s < totals.size(); ++s) {
      totals[s] += b.subjects[s].correct;
    }
  }
  // A study the best `count` subjects of the PVC study run next (their labels
  // into `labels`), analysed from its exports.
  const auto follow_up = [&](const protocols::LoadedProtocol& protocol,
                             const char* dir, std::uint64_t seed_index,
                             int count, const std::string& name,
                             std::vector<std::string>* labels)
      -> Result<std::vector<analysis::BlockScores>> {
    SimulatedStudyOptions study;
    study.out_dir = options.out_dir / dir;
    study.seed = protocols::SeedFor(
        options.seed, protocols::StreamPurpose::kSubjectSeed, seed_index);
    study.jobs = options.jobs;
    study.renderings = options.share_renderings ? &pool : nullptr;
    for (int i : BestSubjects(totals, count)) {
      study.labels.push_back(pvc_study.labels[static_cast<std::size_t>(i)]);
      study.observers.push_back(
          pvc_study.observers[static_cast<std::size_t>(i)]);
    }
    *labels = study.labels;
    {
      ProgressBar bar(progress, static_cast<int>(study.labels.size()));
      study.progress = [&](int done, const std::string& label) {
        bar.Update(done, name + ": sub-" + label);
      };
      const SimulatedStudyResult r = RunSimulatedStudy(protocol, study);
      for (const std::string& f : r.failures) {
        if (!f.empty()) return Error{name + " study: " + f};
      }
    }
    return Analyse(study.out_dir);
  };
  Result<std::vector<analysis::BlockScores>> pettigrew_scores = follow_up(
      pettigrew.value(), kDemoPettigrewDir, 1ull << 42, options.best_subjects,
      "Pettigrew vs bone", &report.best_subjects);
  if (!pettigrew_scores.ok()) return pettigrew_scores.error();
  // §13.5.2 with subjects trained by the first experiment: its best 5.
  Result<std::vector<analysis::BlockScores>> association_scores =
      follow_up(association.value(), kDemoAssociationDir, 1ull << 45,
                options.association_subjects, "real vs simulated Pettigrew",
                &report.association_subjects);
  if (!association_scores.ok()) return association_scores.error();

  // 4. Virtual replications of the whole design: 20 subjects run PVC vs
  // bone, the best 12 of them Pettigrew vs bone and the best 5 the
  // association design.
  std::map<std::pair<std::string, std::string>, Tally> tallies;
  const auto tally = [&](const char* study,
                         const std::vector<VirtualBlock>& blocks) {
    for (const VirtualBlock& b : blocks) {
      const BlockStats st = StatsOf(b);
      Tally& t = tallies[{study, b.block}];
      t.means.push_back(st.mean);
      t.significant += st.p < kDemoAlpha ? 1 : 0;
    }
  };
  {
    ProgressBar bar(progress, options.runs);
    for (int r = 0; r < options.runs; ++r) {
      VirtualStudyOptions v = *population;
      v.subjects = options.subjects;
      v.seed = protocols::SeedFor(options.seed,
                                  protocols::StreamPurpose::kPopulation,
                                  1ull << 43, static_cast<std::uint64_t>(r));
      Result<std::vector<VirtualBlock>> first =
          RunVirtualStudy(pvc->protocol, v, cues);
      if (!first.ok()) return first.error();
      std::vector<int> sums(static_cast<std::size_t>(options.subjects), 0);
      for (const VirtualBlock& b : *first) {
        for (std::size_t s = 0; s < sums.size(); ++s) sums[s] += b.correct[s];
      }
      tally(kPvcStudy, *first);
      // The best `count` of this replication's subjects run `protocol`.
      const auto virtual_follow_up = [&](const protocols::Protocol& protocol,
                                         int count, std::uint64_t seed_index,
                                         const char* study) -> Status {
        VirtualStudyOptions w = *population;
        for (int i : BestSubjects(sums, count)) {
          w.subject_observers.push_back(SubjectObserver(v, i));
        }
        w.seed = protocols::SeedFor(options.seed,
                                    protocols::StreamPurpose::kPopulation,
                                    seed_index, static_cast<std::uint64_t>(r));
        Result<std::vector<VirtualBlock>> blocks =
            RunVirtualStudy(protocol, w, cues);
        if (!blocks.ok()) return blocks.error();
        tally(study, *blocks);
        return {};
      };
      if (Status s =
              virtual_follow_up(pettigrew->protocol, options.best_subjects,
                                1ull << 44, kPettigrewStudy);
          !s.ok()) {
        return s.error();
      }
      if (Status s = virtual_follow_up(association->protocol,
                                       options.association_subjects, 1ull << 45,
                                       kAssociationStudy);
          !s.ok()) {
        return s.error();
      }
      bar.Update(r + 1, fmt::format("predicting: replication {}", r + 1));
    }
  }

  // 5. The rows and the figures.
  const fs::path figures = options.out_dir / "figures";
  const auto add_rows = [&](const char* study, const char* dir,
                            const std::vector<analysis::BlockScores>& scores,
                            int paper_n) -> Status {
    for (const analysis::BlockScores& b : scores) {
      DemoRow row;
      row.study = study;
      row.block = b.block;
      row.trials = b.trials_per_subject.value_or(0);
      row.subjects = static_cast<int>(b.subjects.size());
      if (b.mean_score) {
        row.mean = b.mean_score->mean;
        row.sem = b.mean_score->sem;
      }
      if (b.t_test) {
        row.p = b.t_test->p_greater;
      } else if (b.binomial) {
        // No t-test when every subject scored alike (e.g. all perfect).
        row.p = b.binomial->p_greater;
        row.p_test = "binomial";
      }
      row.paper_n = paper_n;
      if (std::string(study) == kPvcStudy) {
        for (const Published& pub : kPvcPublished) {
          if (b.block != pub.block) continue;
          row.paper_mean = pub.mean;
          row.paper_sem = pub.sem;
          row.paper_p = kPublishedP;
          row.paper_finding = "significantly above chance";
        }
      } else if (std::string(study) == kAssociationStudy) {
        row.paper_mean = kAssociationPublished.mean;
        row.paper_sem = kAssociationPublished.sem;
        row.paper_p = kPublishedAssociationP;
        row.paper_finding = "significantly above chance";
      } else {
        row.paper_finding = "could not tell them apart";
      }
      const Tally& t = tallies[{study, b.block}];
      row.runs = static_cast<int>(t.means.size());
      if (Result<analysis::MeanSem> m = analysis::MeanAndSem(t.means); m.ok()) {
        row.predicted_mean = m->mean;
        row.predicted_sd = m->sd;
        std::vector<double> sorted = t.means;
        std::sort(sorted.begin(), sorted.end());
        row.predicted_low = analysis::QuantileType7(sorted, 0.025);
        row.predicted_high = analysis::QuantileType7(sorted, 0.975);
      }
      row.predicted_significant =
          row.runs > 0 ? static_cast<double>(t.significant) / row.runs : 0.0;
      if (row.paper_mean) {
        // The fitted population's expected score (a single study of 20 is
        // one draw around it, as the dissertation's was).
        const double off = row.predicted_mean - *row.paper_mean;
        row.verdict = std::abs(off) <= *row.paper_sem
                          ? "within its SEM"
                          : fmt::format("outside its SEM ({:+.2f})", off);
      } else {
        row.verdict = row.predicted_significant >= 0.5
                          ? "disagrees: predicts a difference"
                          : "agrees: no reliable difference";
      }
      report.rows.push_back(row);
      const fs::path png =
          figures / fmt::format("scores_{}_{}.png", dir, b.task_label);
      analysis::LinePlot plot = analysis::ScoreHistogram(b);
      plot.title =
          fmt::format("{}, {}: mean {:.1f} ± {:.1f} SEM of {}, p = {:.2g}",
                      study, b.block, row.mean, row.sem, row.trials, row.p);
      if (Status s = analysis::WritePlot(plot, png.string()); !s.ok()) {
        return s;
      }
      report.figures.push_back(png.string());
    }
    return {};
  };
  if (Status s = add_rows(kPvcStudy, kDemoPvcDir, *pvc_scores, kPublishedN);
      !s.ok()) {
    return s.error();
  }
  if (Status s = add_rows(kPettigrewStudy, kDemoPettigrewDir, *pettigrew_scores,
                          kPublishedBestN);
      !s.ok()) {
    return s.error();
  }
  if (Status s = add_rows(kAssociationStudy, kDemoAssociationDir,
                          *association_scores, kPublishedAssociationN);
      !s.ok()) {
    return s.error();
  }
  const fs::path comparison = figures / "comparison.png";
  if (Status s =
          analysis::WritePlot(ComparisonPlot(report), comparison.string());
      !s.ok()) {
    return s.error();
  }
  report.figures.push_back(comparison.string());
  report.rendered = pool.rendered();
  std::ofstream json(options.out_dir / kDemoMarker);
  json << DemoReportJsonText(report, options) << '\n';
  if (!json) {
    return Error{fmt::format("cannot write {}",
                             (options.out_dir / kDemoMarker).string())};
  }
  return report;
}

}  // namespace burrlab::runner
