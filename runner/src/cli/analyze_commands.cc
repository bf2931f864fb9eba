// `burrlab analyze fit` (maximum-likelihood psychometric fit, parametric
// bootstrap, plot) and `burrlab analyze dprime` (signal-detection d').
// Exit codes (analysis/README.md): 0 done; 1 bad flags or data, nothing
// printed on stdout; 2 the fit did not converge (results printed, flagged).
#include "cli/analyze_commands.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/analysis/condition_comparison.h"
#include "burrlab/analysis/psychometric.h"
#include "burrlab/analysis/psychometric_data.h"
#include "burrlab/analysis/psychometric_plot.h"
#include "burrlab/analysis/sdt.h"
#include "burrlab/base/file_text.h"
#include "cli/analyze_results_commands.h"
#include "cli/flags.h"
#include "cli/json_number.h"
#include "studies/progress.h"

namespace burrlab::runner {
namespace {

using analysis::PsychometricOptions;
using Json = nlohmann::ordered_json;

// Exit code when the results are printed but the fit did not converge.
constexpr int kNotConverged = 2;

// "2afc" -> 2, "yesno" -> 1, "nafc:N" -> N (2..100).
Result<int> ParseTask(const std::string& text) {
  if (text == "2afc") return 2;
  if (text == "yesno") return 1;
  if (text.starts_with("nafc:")) {
    Result<std::int64_t> n =
        ParseInteger("--task nafc:N", text.substr(5), 2, 100);
    if (n.ok()) return static_cast<int>(*n);
  }
  return Error{fmt::format(
      "--task must be '2afc', 'yesno' or 'nafc:N' with N from 2 to 100, got "
      "'{}'",
      text)};
}

// "0.2,0.5,0.8": each in (0, 1).
Result<std::vector<double>> ParseCuts(const std::string& text) {
  std::vector<double> cuts;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string word = text.substr(start, comma - start);
    Result<double> cut = ParseNumber("--cuts", word);
    if (!cut.ok() || !(*cut > 0.0 && *cut < 1.0)) {
      return Error{fmt::format(
          "--cuts must be numbers in (0, 1) separated by commas, got '{}'",
          text)};
    }
    cuts.push_back(*cut);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cuts;
}

std::string TaskName(int n_intervals) {
  return n_intervals == 1 ? "yesno" : fmt::format("{}afc", n_intervals);
}

// One BootstrapEstimate's bounds as an object keyed by conf ("0.023": ...);
// a bound at the fit's search range is "search limit", not a number.
Json Bounds(const PsychometricOptions& options,
            const std::vector<double>& bounds,
            const std::vector<bool>& at_search_limit) {
  Json object = Json::object();
  for (std::size_t k = 0; k < options.conf.size(); ++k) {
    object[fmt::format("{}", options.conf[k])] =
        k < at_search_limit.size() && at_search_limit[k]
            ? Json("search limit")
            : JsonNumber(bounds[k]);
  }
  return object;
}

Json AnalysisJson(const analysis::PsychometricAnalysis& a,
                  const std::string& path,
                  const analysis::PsychometricDataFile& file) {
  const PsychometricOptions& o = a.options;
  Json j;
  j["alpha"] = JsonNumber(a.fit.params.alpha);
  j["beta"] = JsonNumber(a.fit.params.beta);
  j["gamma"] = JsonNumber(a.fit.params.gamma);
  j["lambda"] = JsonNumber(a.fit.params.lambda);
  j["log_likelihood"] = JsonNumber(a.fit.log_likelihood);
  j["deviance"] = JsonNumber(a.fit.deviance);
  j["deviance_p"] = JsonNumber(a.deviance_p);
  j["converged"] = a.fit.converged;
  j["thresholds"] = Json::array();
  for (const analysis::BootstrapEstimate& t : a.thresholds) {
    j["thresholds"].push_back(
        {{"cut", t.cut},
         {"value", JsonNumber(t.value)},
         {"ci", Bounds(o, t.bca, t.bca_at_search_limit)},
         {"ci_percentile",
          Bounds(o, t.percentile, t.percentile_at_search_limit)}});
  }
  j["slopes"] = Json::array();
  for (const analysis::BootstrapEstimate& s : a.slopes) {
    j["slopes"].push_back({{"cut", s.cut}, {"value", JsonNumber(s.value)}});
  }
  j["sigmoid"] = analysis::SigmoidName(o.sigmoid);
  j["task"] = TaskName(o.n_intervals);
  j["lambda_max"] = o.lambda_max;
  j["gamma_max"] = o.n_intervals == 1 ? Json(o.gamma_max) : Json(nullptr);
  j["bootstrap_samples"] = a.bootstrap_samples;
  j["bootstrap_not_converged"] = a.bootstrap_not_converged;
  j["seed"] = o.seed;
  const char* const names[4] = {"alpha", "beta", "gamma", "lambda"};
  j["at_bound"] = Json::object();
  for (std::size_t k = 0; k < 4; ++k) {
    const analysis::Bound b = a.fit.at_bound[k];
    j["at_bound"][names[k]] =
        b == analysis::Bound::kNone
            ? Json(nullptr)
            : Json(b == analysis::Bound::kLower ? "lower" : "upper");
  }
  j["warnings"] = a.warnings;
  j["data"] = {
      {"file", path},
      {"format", file.format == analysis::PsychometricDataFile::Format::kCounts
                     ? "counts"
                     : "trials"},
      {"levels", file.blocks.size()},
      {"rows", file.rows},
      {"skipped_rows", file.skipped_rows},
      {"practice_rows_left_out", file.practice_rows}};
  return j;
}

// The x axis' name: the _beh.tsv's stim_unit when it has one.
std::string LevelLabel(const analysis::PsychometricDataFile& file) {
  return file.stim_unit.empty()
             ? std::string("stimulus level")
             : fmt::format("stimulus level ({})", file.stim_unit);
}

Json ConditionFitJson(const analysis::ConditionFit& fit,
                      const std::vector<std::string>& names) {
  Json j = {{"model", analysis::ConditionModelName(fit.model)},
            {"log_likelihood", JsonNumber(fit.log_likelihood)},
            {"deviance", JsonNumber(fit.deviance)},
            {"free_parameters", fit.free_parameters},
            {"converged", fit.converged}};
  j["conditions"] = Json::array();
  for (std::size_t k = 0; k < names.size(); ++k) {
    const analysis::PsychometricParams& p = fit.params[k];
    j["conditions"].push_back({{"name", names[k]},
                               {"alpha", JsonNumber(p.alpha)},
                               {"beta", JsonNumber(p.beta)},
                               {"gamma", JsonNumber(p.gamma)},
                               {"lambda", JsonNumber(p.lambda)}});
  }
  return j;
}

// `analyze fit --by COLUMN`: each condition's own fit with its intervals,
// the joint fits with shared and separate thresholds and slopes, and the
// likelihood-ratio tests between them.
int RunFitByCondition(const analysis::PsychometricDataFile& file,
                      const std::string& text, const std::string& data_path,
                      const std::string& by, PsychometricOptions options,
                      const std::string& plot_path, bool json,
                      std::ostream& out, std::ostream& err) {
  if (file.conditions.size() < 2) {
    return Fail(err, fmt::format("--by {}: the data have {} condition{}{}; "
                                 "comparing needs at least 2",
                                 by, file.conditions.size(),
                                 file.conditions.size() == 1 ? "" : "s",
                                 file.conditions.size() == 1
                                     ? " ('" + file.conditions[0].name + "')"
                                     : std::string()));
  }
  std::vector<analysis::ConditionData> conditions;
  std::vector<std::vector<analysis::DataBlock>> blocks;
  std::vector<std::string> names;
  for (const analysis::PsychometricDataFile::Condition& c : file.conditions) {
    std::size_t bad = 0;
    if (Status s = analysis::ValidateData(c.blocks, options.sigmoid, &bad);
        !s.ok()) {
      const bool has_line = bad < c.lines.size();
      std::string message = s.error().message;
      if (has_line && message.starts_with("block ")) {
        message = message.substr(message.find(": ") + 2);
      }
      err << analysis::FormatDataDiagnostic(
                 data_path, text, has_line ? c.lines[bad] : 0, 1,
                 fmt::format(
                     "{} '{}': {}{}", by, c.name,
                     file.format ==
                             analysis::PsychometricDataFile::Format::kTrials
                         ? "after pooling the trials by level, "
                         : "",
                     message))
          << '\n';
      return 1;
    }
    conditions.push_back({c.name, c.blocks});
    blocks.push_back(c.blocks);
    names.push_back(c.name);
  }
  const int samples = options.bootstrap_samples;
  const int total = samples * static_cast<int>(conditions.size() + 2);
  std::vector<analysis::PsychometricAnalysis> analyses;
  Result<analysis::ConditionComparison> comparison = [&] {
    ProgressBar bar(err, total);
    int offset = 0;
    options.progress = [&](int done, int) {
      const int step = std::max(total / 100, 1);
      if ((offset + done) % step == 0 || offset + done == total) {
        bar.Update(offset + done, "bootstrap refits");
      }
    };
    for (const analysis::ConditionData& c : conditions) {
      Result<analysis::PsychometricAnalysis> a =
          analysis::AnalyzePsychometric(c.blocks, options);
      if (!a.ok()) {
        return Result<analysis::ConditionComparison>(
            Error{fmt::format("{} '{}': {}", by, c.name, a.error().message)});
      }
      analyses.push_back(*a);
      offset += samples;
    }
    // The comparison's progress counts per test: after the first test's
    // last data set, the second starts from 1 again.
    int last = 0;
    options.progress = [&](int done, int) {
      if (done < last) offset += samples;
      last = done;
      const int step = std::max(total / 100, 1);
      if ((offset + done) % step == 0 || offset + done == total) {
        bar.Update(offset + done, "likelihood-ratio bootstrap");
      }
    };
    return analysis::CompareConditions(conditions, options);
  }();
  if (!comparison.ok()) {
    return Fail(err, "analyze fit: " + comparison.error().message);
  }
  const analysis::ConditionComparison& c = *comparison;
  for (std::size_t k = 0; k < analyses.size(); ++k) {
    for (const std::string& w : analyses[k].warnings) {
      err << fmt::format("burrlab: warning: {} '{}': {}\n", by, names[k], w);
    }
  }
  for (const std::string& w : c.warnings) {
    err << "burrlab: warning: " << w << '\n';
  }
  std::vector<std::string> legend;
  for (const std::string& name : names) legend.push_back(by + " " + name);
  if (!plot_path.empty()) {
    if (Status s =
            analysis::WritePlot(analysis::MakeConditionsPlot(
                                    blocks, analyses, legend, LevelLabel(file)),
                                plot_path);
        !s.ok()) {
      return Fail(err, s.error().message);
    }
  }
  bool converged = true;
  for (const analysis::PsychometricAnalysis& a : analyses) {
    converged = converged && a.fit.converged;
  }
  for (const analysis::ConditionFit& fit : c.fits) {
    converged = converged && fit.converged;
  }
  const std::string lapse =
      options.lambda_max > 0.0
          ? fmt::format("one lapse rate for all conditions, in [0, {}]",
                        options.lambda_max)
          : std::string("no lapses (lambda = 0)");
  if (json) {
    Json j;
    j["by"] = by;
    j["conditions"] = Json::array();
    for (std::size_t k = 0; k < analyses.size(); ++k) {
      Json one = AnalysisJson(analyses[k], data_path, file);
      one.erase("data");
      one["name"] = names[k];
      one["levels"] = blocks[k].size();
      j["conditions"].push_back(one);
    }
    j["models"] = Json::array();
    for (const analysis::ConditionFit& fit : c.fits) {
      j["models"].push_back(ConditionFitJson(fit, names));
    }
    j["lapse"] = lapse;
    j["tests"] = Json::array();
    for (const analysis::LikelihoodRatioTest& t : c.tests) {
      j["tests"].push_back({{"question", t.question},
                            {"lesser", analysis::ConditionModelName(t.lesser)},
                            {"fuller", analysis::ConditionModelName(t.fuller)},
                            {"lr", JsonNumber(t.lr)},
                            {"df", t.df},
                            {"p_chi_square", JsonNumber(t.p_chi_square)},
                            {"p_bootstrap", JsonNumber(t.p_bootstrap)},
                            {"bootstrap_samples", t.bootstrap_samples},
                            {"bootstrap_failures", t.bootstrap_failures}});
    }
    j["warnings"] = c.warnings;
    j["plot"] = plot_path.empty() ? Json(nullptr) : Json(plot_path);
    out << j.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    return converged ? 0 : kNotConverged;
  }
  out << fmt::format("data       {} ({} conditions by {}: {})\n", data_path,
                     names.size(), by, fmt::join(names, ", "));
  for (std::size_t k = 0; k < analyses.size(); ++k) {
    out << fmt::format("\n{} {}\n", by, names[k]);
    out << analyses[k].FullReport(/*with_warnings=*/false);
  }
  out << fmt::format("\nmodels     all conditions fitted at once, {}\n", lapse);
  for (const analysis::ConditionFit& fit : c.fits) {
    out << fmt::format(
        "  {:<13} log L {:<12.6g} {} parameters, deviance {:.4g}"
        "{}\n",
        analysis::ConditionModelName(fit.model), fit.log_likelihood,
        fit.free_parameters, fit.deviance,
        fit.converged ? "" : " (not converged)");
  }
  out << "tests      likelihood ratio LR = 2 (log L fuller - log L lesser); "
         "p by chi-square (Wilks) and by parametric bootstrap from the lesser "
         "fit\n";
  for (const analysis::LikelihoodRatioTest& t : c.tests) {
    out << fmt::format(
        "  {} ({} vs {}): LR {:.4g}, df {}, p {:.4g} chi-square, p {} "
        "bootstrap{}\n",
        t.question, analysis::ConditionModelName(t.lesser),
        analysis::ConditionModelName(t.fuller), t.lr, t.df, t.p_chi_square,
        std::isfinite(t.p_bootstrap) ? fmt::format("{:.4g}", t.p_bootstrap)
                                     : std::string("n/a"),
        std::isfinite(t.p_bootstrap)
            ? fmt::format(" ({} data sets)", t.bootstrap_samples)
            : std::string(" (--bootstrap 0)"));
  }
  if (!plot_path.empty()) out << "plot       " << plot_path << '\n';
  return converged ? 0 : kNotConverged;
}

int RunFit(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Maximum-likelihood fit of psi = gamma + (1 - gamma - lambda) F(x; "
      "alpha, beta) as psignifit 2.5.6 fits it, with thresholds F^-1(cut), "
      "slopes dF/dx there, parametric-bootstrap BCa and percentile "
      "intervals, and the deviance with its bootstrap p-value. DATA is a "
      "CSV/TSV with the header level,n_correct,n_total, or a burrlab "
      "_beh.tsv (stim_level and correct); rows at one level are pooled. Exit "
      "code 2: the fit did not converge (results still printed).",
      "burrlab analyze fit"};
  PsychometricOptions options;
  std::string data_path, task_text, plot_path, by, cuts_text = "0.2,0.5,0.8";
  int sigmoid = 0;
  bool json = false;
  FlagSet flags(&app);
  flags
      .AddText("--data", "the data file (CSV/TSV counts or a _beh.tsv)",
               &data_path)
      ->type_name("FILE")
      ->required();
  flags
      .AddText("--task",
               "2afc, yesno (gamma free in [0, --gamma-max]) or nafc:N "
               "(gamma = 1/N)",
               &task_text)
      ->type_name("2afc|yesno|nafc:N")
      ->required();
  flags
      .AddChoice("--sigmoid", "the shape F (psignifit 2.5.6 parameterisation)",
                 {"logistic", "cumnorm", "weibull", "gumbel"}, &sigmoid)
      ->required();
  flags.AddInteger(
      "--bootstrap",
      fmt::format("refitted bootstrap data sets, 0 for none (default {})",
                  options.bootstrap_samples),
      0, 1000000, &options.bootstrap_samples);
  flags.AddUnsigned(
      "--seed", fmt::format("bootstrap random seed (default {})", options.seed),
      &options.seed);
  flags
      .AddText("--cuts",
               "cuts of F for thresholds and slopes (default 0.2,0.5,0.8)",
               &cuts_text)
      ->type_name("C1,C2,...");
  flags.AddNonNegative("--lambda-max",
                       fmt::format("lapse rate range [0, L] (default {}; 0 "
                                   "fixes lambda at 0)",
                                   options.lambda_max),
                       "", &options.lambda_max);
  flags.AddNonNegative(
      "--gamma-max",
      fmt::format("yes/no guess rate range [0, G] (default {})",
                  options.gamma_max),
      "", &options.gamma_max);
  flags.AddInteger("--max-evaluations",
                   fmt::format("likelihood evaluations per optimiser start "
                               "(default {}); fewer than needed: exit code 2",
                               options.max_evaluations),
                   1, 10000000, &options.max_evaluations);
  flags
      .AddText("--by",
               "fit each value of this column as a condition, with shared "
               "and separate thresholds and slopes, and compare them by "
               "likelihood ratios (chi-square and bootstrap p)",
               &by)
      ->type_name("COLUMN");
  flags.AddSwitch("--json", "print the results as JSON", &json);
  flags
      .AddText("--plot",
               "write the data, the fit and the threshold intervals as PNG",
               &plot_path)
      ->type_name("FILE.png");
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  Result<int> task = ParseTask(task_text);
  if (!task.ok()) return Fail(err, task.error().message);
  options.n_intervals = *task;
  options.sigmoid = *analysis::SigmoidFromName(
      std::vector<std::string>{"logistic", "cumnorm", "weibull",
                               "gumbel"}[static_cast<std::size_t>(sigmoid)]);
  Result<std::vector<double>> cuts = ParseCuts(cuts_text);
  if (!cuts.ok()) return Fail(err, cuts.error().message);
  options.cuts = *cuts;
  if (!(options.lambda_max < 1.0)) {
    return Fail(err, fmt::format("--lambda-max must be below 1, got '{}'",
                                 options.lambda_max));
  }
  if (flags.Given("--gamma-max") && options.n_intervals != 1) {
    return Fail(err,
                "--gamma-max applies to --task yesno only (n-AFC fixes gamma "
                "at 1/N)");
  }
  if (!(options.gamma_max < 1.0)) {
    return Fail(err, fmt::format("--gamma-max must be below 1, got '{}'",
                                 options.gamma_max));
  }
  if (flags.Given("--plot") && plot_path.empty()) {
    return Fail(err, "--plot needs a file name, got ''");
  }
  if (Status s = options.Validate(); !s.ok()) {
    return Fail(err, "analyze fit: " + s.error().message);
  }

  // A subject's _beh.tsv in a results folder (DIR/sub-<id>/beh/ or
  // DIR/sub-<id>/ses-<session>/beh/): warn when its session stopped before
  // its end.
  const std::filesystem::path data(data_path);
  std::filesystem::path session_dir = data.parent_path().parent_path();
  std::string session;
  if (const std::string name = session_dir.filename();
      name.starts_with("ses-")) {
    session = name.substr(4);
    session_dir = session_dir.parent_path();
  }
  const std::string subject_dir = session_dir.filename();
  if (data.parent_path().filename() == "beh" &&
      subject_dir.starts_with("sub-")) {
    const std::filesystem::path dir = session_dir.parent_path();
    for (const results_schema::IncompleteSession& s :
         results_schema::FindIncompleteSessions(dir.empty() ? "." : dir)) {
      if ("sub-" + s.subject == subject_dir && s.session == session) {
        err << IncompleteSessionWarning(s, dir.empty() ? "." : dir.string());
      }
    }
  }
  if (std::filesystem::is_directory(data_path)) {
    // A study's results: each subject is fitted by `analyze thresholds`.
    return Fail(
        err, fmt::format("--data {0} is a folder; 'burrlab analyze thresholds "
                         "{0}' fits every subject's constant-stimuli blocks "
                         "and reports the group, and --data takes one file "
                         "(e.g. a subject's _beh.tsv under {0}/sub-*/beh/)",
                         data_path));
  }
  Result<std::string> text = ReadTextFile(data_path);
  if (!text.ok()) return Fail(err, text.error().message);
  Result<analysis::PsychometricDataFile> file =
      analysis::ParsePsychometricData(data_path, *text, by);
  if (!file.ok()) {
    err << file.error().message << '\n';
    return 1;
  }
  if (!by.empty()) {
    return RunFitByCondition(*file, *text, data_path, by, options, plot_path,
                             json, out, err);
  }
  std::size_t bad = 0;
  if (Status s = analysis::ValidateData(file->blocks, options.sigmoid, &bad);
      !s.ok()) {
    const bool has_line =
        file->format == analysis::PsychometricDataFile::Format::kCounts &&
        bad < file->lines.size();
    std::string message = s.error().message;
    if (has_line && message.starts_with("block ")) {
      message = message.substr(message.find(": ") + 2);  // the line says it
    }
    err << analysis::FormatDataDiagnostic(
               data_path, *text, has_line ? file->lines[bad] : 0, 1,
               file->format == analysis::PsychometricDataFile::Format::kTrials
                   ? "after pooling the trials by level, " + message
                   : message)
        << '\n';
    return 1;
  }
  Result<analysis::PsychometricAnalysis> result = [&] {
    // Bootstrap progress on a terminal, redrawn once per percent.
    ProgressBar bar(err, options.bootstrap_samples);
    options.progress = [&bar](int done, int total) {
      const int step = std::max(total / 100, 1);
      if (done % step == 0 || done == total)
        bar.Update(done, "bootstrap refits");
    };
    return analysis::AnalyzePsychometric(file->blocks, options);
  }();
  if (!result.ok()) return Fail(err, "analyze fit: " + result.error().message);
  const analysis::PsychometricAnalysis& a = *result;
  if (!plot_path.empty()) {
    if (Status s = analysis::WritePlot(
            analysis::MakePsychometricPlot(file->blocks, a, LevelLabel(*file)),
            plot_path);
        !s.ok()) {
      return Fail(err, s.error().message);
    }
  }
  for (const std::string& warning : a.warnings) {
    err << "burrlab: warning: " << warning << '\n';
  }
  if (json) {
    out << AnalysisJson(a, data_path, *file)
               .dump(2, ' ', false, Json::error_handler_t::replace)
        << '\n';
  } else {
    out << fmt::format(
        "data       {} ({} levels{}{})\n", data_path, file->blocks.size(),
        file->skipped_rows > 0
            ? fmt::format(", {} rows with n/a skipped", file->skipped_rows)
            : std::string(),
        file->practice_rows > 0
            ? fmt::format(", {} practice trials left out (never fitted)",
                          file->practice_rows)
            : std::string());
    if (file->rows > file->blocks.size()) {
      out << fmt::format("pooled     {} rows into {} levels\n", file->rows,
                         file->blocks.size());
    }
    out << a.FullReport(/*with_warnings=*/false);  // they went to stderr
    if (!plot_path.empty()) out << "plot       " << plot_path << '\n';
  }
  return a.fit.converged ? 0 : kNotConverged;
}

int RunDPrime(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Signal-detection sensitivity d' (Macmillan & Creelman; R psyphy "
      "conventions): yes/no z(H) - z(F); 2AFC sqrt(2) z(Pc); n-AFC by "
      "dprime.mAFC; same-different by the differencing or the "
      "independent-observation model.",
      "burrlab analyze dprime"};
  std::string design;
  int model = 0;
  double hit = 0.0, fa = 0.0, pc = 0.0;
  bool json = false;
  FlagSet flags(&app);
  flags.AddText("--design", "yesno, 2afc, nafc:N or same-different", &design)
      ->type_name("yesno|2afc|nafc:N|same-different")
      ->required();
  flags.AddChoice("--model", "same-different model (default differencing)",
                  {"differencing", "independent-observation"}, &model);
  flags.AddPositive("--hit", "hit rate H in (0, 1)", "", &hit);
  flags.AddPositive("--fa", "false-alarm rate F in (0, 1)", "", &fa);
  flags.AddPositive("--pc", "proportion correct in (0, 1) (2afc, nafc:N)", "",
                    &pc);
  flags.AddSwitch("--json", "print {\"dprime\": ...} and the inputs as JSON",
                  &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  const bool rates = flags.Given("--hit") || flags.Given("--fa");
  int alternatives = 0;
  if (design == "2afc") {
    alternatives = 2;
  } else if (design.starts_with("nafc:")) {
    Result<int> task = ParseTask(design);
    if (!task.ok()) {
      return Fail(err, fmt::format("--design nafc:N needs N from 2 to 100, "
                                   "got '{}'",
                                   design));
    }
    alternatives = *task;
  } else if (design != "yesno" && design != "same-different") {
    return Fail(err, fmt::format("--design must be 'yesno', '2afc', 'nafc:N' "
                                 "or 'same-different', got '{}'",
                                 design));
  }
  if (flags.Given("--model") && design != "same-different") {
    return Fail(err, "--model applies to --design same-different only");
  }
  Result<double> d = Error{};
  if (alternatives > 0) {
    if (rates || !flags.Given("--pc")) {
      return Fail(err, fmt::format("--design {} takes --pc P (not --hit/--fa)",
                                   design));
    }
    d = analysis::DPrimeMAfc(pc, alternatives);
  } else {
    if (flags.Given("--pc") || !flags.Given("--hit") || !flags.Given("--fa")) {
      return Fail(err, fmt::format("--design {} takes --hit H and --fa F (not "
                                   "--pc)",
                                   design));
    }
    d = design == "yesno"
            ? analysis::DPrimeYesNo(hit, fa)
            : analysis::DPrimeSameDifferent(
                  hit, fa,
                  model == 0
                      ? analysis::SameDifferentModel::kDifferencing
                      : analysis::SameDifferentModel::kIndependentObservation);
  }
  if (!d.ok()) return Fail(err, "analyze dprime: " + d.error().message);
  const std::string model_name =
      model == 0 ? "differencing" : "independent-observation";
  if (json) {
    Json j;
    j["dprime"] = *d;
    j["design"] = design;
    if (design == "same-different") j["model"] = model_name;
    if (alternatives > 0) {
      j["pc"] = pc;
    } else {
      j["hit"] = hit;
      j["fa"] = fa;
    }
    out << j.dump(2) << '\n';
    return 0;
  }
  out << fmt::format(
      "d' = {:.6g} ({}{}; {})\n", *d, design,
      design == "same-different" ? ", " + model_name + " model" : "",
      alternatives > 0 ? fmt::format("Pc {}", pc)
                       : fmt::format("H {}, F {}", hit, fa));
  return 0;
}

int RunAnalyzeHelp(const Args& args, std::ostream& out, std::ostream& err);

constexpr Command kAnalyzeCommands[] = {
    {"fit",
     "psychometric fit (psignifit 2.5.6 conventions) with bootstrap "
     "intervals, from counts or a _beh.tsv",
     RunFit},
    {"dprime", "d' for yes/no, 2AFC/n-AFC and same-different designs",
     RunDPrime},
    {"scores",
     "scores per block of a study's results: mean +- SEM, t and binomial "
     "tests against chance, same-different d', response times, histograms",
     RunScoresCommand},
    {"rt",
     "response times per subject, block and condition: median, quartiles, "
     "missing times counted",
     RunResponseTimesCommand},
    {"thresholds",
     "thresholds per subject and block: staircase reversals, QUEST, limits, "
     "adjustment, constant-stimuli fits",
     RunThresholdsCommand},
    {"kinematics",
     "force and speed histograms, mean force and removal rate of the traces; "
     "two groups compared",
     RunKinematicsCommand},
    {"power",
     "probability of a significant result from simulated studies of a "
     "protocol",
     RunPowerCommand},
    {"fit-observers",
     "fit a simulated-observer population to a group result and predict "
     "another protocol",
     RunFitObserversCommand},
    {"help", "list the commands; 'help COMMAND' shows the flags of one",
     RunAnalyzeHelp},
};

int RunAnalyzeHelp(const Args& args, std::ostream& out, std::ostream& err) {
  return RunHelp("burrlab analyze", kAnalyzeCommands, args, out, err);
}

}  // namespace

int RunAnalyzeCommand(const Args& args, std::ostream& out, std::ostream& err) {
  return Dispatch("burrlab analyze", kAnalyzeCommands, args, out, err);
}

}  // namespace burrlab::runner
