// `burrlab analyze scores|rt|thresholds|kinematics DIR`: read the study's BIDS
// exports (results_schema/bids_read.h), analyse them (analysis/) and print a
// table or JSON, with PNG figures on request.
#include "cli/analyze_results_commands.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <boost/math/distributions/binomial.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include "burrlab/analysis/group_stats.h"
#include "burrlab/analysis/kinematics.h"
#include "burrlab/analysis/participant_groups.h"
#include "burrlab/analysis/response_times.h"
#include "burrlab/analysis/scores.h"
#include "burrlab/analysis/thresholds.h"
#include "burrlab/protocols/protocol_file.h"
#include "burrlab/results_schema/bids_read.h"
#include "burrlab/results_schema/dataset_layout.h"
#include "cli/flags.h"
#include "cli/json_number.h"
#include "studies/fit_recovery.h"
#include "studies/observer_fit.h"
#include "studies/progress.h"
#include "studies/session.h"
#include "studies/virtual_study.h"

namespace burrlab::runner {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

Json Optional(const std::optional<double>& value) {
  return value.has_value() ? JsonNumber(*value) : Json(nullptr);
}

// " --session S" for a labelled session, else nothing.
std::string SessionFlag(const std::string& session) {
  return session.empty() ? std::string() : " --session " + session;
}

// The study's exports, or one error line. First warns on `err` of every
// subject whose journal holds trials its exports do not, so no subject is
// left out silently, then of every other subject whose session stopped
// before its end (one warning per subject).
Result<std::vector<results_schema::BehFile>> ReadResults(const std::string& dir,
                                                         std::ostream& err) {
  Result<std::vector<results_schema::BehFile>> files =
      results_schema::ReadBidsDataset(dir);
  const std::vector<results_schema::BehFile> none;
  const std::vector<results_schema::UnexportedTrials> unexported =
      results_schema::FindUnexportedTrials(dir, files.ok() ? *files : none);
  for (const results_schema::UnexportedTrials& u : unexported) {
    err << fmt::format(
        "burrlab: warning: {}'s journal holds {} trials but its exports "
        "only {}, and analyses read the exports; `burrlab run PROTOCOL "
        "--subject {}{} --out {} --resume` exports them (and finishes the "
        "session if it can)\n",
        results_schema::SessionName(u.subject, u.session),
        u.journal_trials < 0 ? std::string("unreadable")
                             : std::to_string(u.journal_trials),
        u.exported_trials, u.subject, SessionFlag(u.session), dir);
  }
  for (const results_schema::IncompleteSession& s :
       results_schema::FindIncompleteSessions(dir)) {
    const bool warned =
        std::any_of(unexported.begin(), unexported.end(),
                    [&](const results_schema::UnexportedTrials& u) {
                      return u.subject == s.subject && u.session == s.session;
                    });
    if (!warned) err << IncompleteSessionWarning(s, dir);
  }
  if (!files.ok()) return files.error();
  return std::move(files.value());
}

}  // namespace

std::string IncompleteSessionWarning(
    const results_schema::IncompleteSession& session, const std::string& dir) {
  return fmt::format(
      "burrlab: warning: {4}'s session is incomplete: it stopped after "
      "{1}{2} trials; its {1} trials are analysed, and `burrlab run PROTOCOL "
      "--subject {0}{5} --out {3} --resume` finishes it\n",
      session.subject, session.trials,
      session.planned_trials
          ? fmt::format(" of {} planned", *session.planned_trials)
          : std::string(),
      dir, results_schema::SessionName(session.subject, session.session),
      SessionFlag(session.session));
}

namespace {

// The figure formats of --format, and the flag itself (default png).
const std::vector<std::string> kFigureFormats = {"png", "pdf", "svg"};
void AddFigureFormat(FlagSet& flags, int* format) {
  flags.AddChoice("--format",
                  "figure format of --plots: png, pdf or svg (default png)",
                  kFigureFormats, format);
}
std::string FigureExtension(int format) {
  return "." + kFigureFormats[static_cast<std::size_t>(format)];
}

// Creates the figure folder; an error names it.
Status MakePlotDir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    return Error{fmt::format("cannot create folder {}: {}", dir,
                             ec ? ec.message() : "not a folder")};
  }
  return {};
}

std::string P(double p) { return fmt::format("{:.3g}", p); }

// "left out 4 practice trials, never scored: practice (4)": the practice
// trials per block, never `what` (familiarization, §13.5.1).
std::string PracticeLine(const std::vector<analysis::PracticeLeftOut>& practice,
                         std::string_view what) {
  int n = 0;
  std::string which;
  for (const analysis::PracticeLeftOut& p : practice) {
    n += p.trials;
    which +=
        fmt::format("{}{} ({})", which.empty() ? "" : ", ", p.block, p.trials);
  }
  return fmt::format("left out {} practice trial{}, never {}: {}", n,
                     n == 1 ? "" : "s", what, which);
}

Json RatesJson(const analysis::SameDifferentRates& r) {
  return {{"hits", r.hits},
          {"different_trials", r.different_trials},
          {"false_alarms", r.false_alarms},
          {"same_trials", r.same_trials},
          {"hit_rate", JsonNumber(r.hit_rate)},
          {"false_alarm_rate", JsonNumber(r.false_alarm_rate)},
          {"corrected", r.corrected},
          {"dprime_differencing", Optional(r.dprime_differencing)},
          {"dprime_independent_observation",
           Optional(r.dprime_independent_observation)},
          {"note", r.note}};
}

constexpr const char* kResponseTimeText =
    "response_time in s from the response prompt; n: trials with a time; "
    "missing: trials without one (n/a, e.g. answers typed into a pipe), "
    "skipped; median, q1, q3: median and quartiles of the n times by R's "
    "quantile type 7 (its default); iqr = q3 - q1; condition: the trial_type, "
    "or the stimulus level in constant-stimuli blocks; all: every trial";

Json ResponseTimesJson(const std::vector<analysis::ResponseTimeSummary>& rt) {
  Json j = {{"definition", kResponseTimeText}, {"conditions", Json::array()}};
  for (const analysis::ResponseTimeSummary& s : rt) {
    j["conditions"].push_back({{"condition", s.condition},
                               {"n", s.n},
                               {"missing", s.missing},
                               {"median_s", Optional(s.median_s)},
                               {"q1_s", Optional(s.q1_s)},
                               {"q3_s", Optional(s.q3_s)},
                               {"iqr_s", Optional(s.iqr_s)}});
  }
  return j;
}

// "0.842 [0.610, 1.200]" (median [Q1, Q3]), or "n/a" without times.
std::string MedianQuartilesText(const analysis::ResponseTimeSummary& s) {
  if (!s.median_s) return "n/a";
  return fmt::format("{:.3f} [{:.3f}, {:.3f}]", *s.median_s, *s.q1_s, *s.q3_s);
}

Json ScoresJson(const analysis::BlockScores& b, const std::string& plot) {
  Json j;
  j["block"] = b.block;
  j["task_label"] = b.task_label;
  j["method"] = b.method;
  j["task"] = b.task;
  j["chance"] = Optional(b.chance);
  j["trials_per_subject"] =
      b.trials_per_subject ? Json(*b.trials_per_subject) : Json(nullptr);
  j["subjects"] = Json::array();
  for (const analysis::SubjectScore& s : b.subjects) {
    Json sj = {{"subject", s.subject},
               {"correct", s.correct},
               {"trials", s.trials},
               {"proportion", s.proportion},
               {"late_answers", s.late_answers}};
    if (s.rates) sj["rates"] = RatesJson(*s.rates);
    j["subjects"].push_back(sj);
  }
  const auto mean_sem = [](const std::optional<analysis::MeanSem>& m) {
    return m ? Json{{"mean", m->mean},
                    {"sem", m->sem},
                    {"sd", m->sd},
                    {"n", m->n}}
             : Json(nullptr);
  };
  j["score"] = mean_sem(b.mean_score);
  j["proportion"] = mean_sem(b.mean_proportion);
  j["t_test"] = b.t_test ? Json{{"test",
                                 "one-sample t-test of proportions "
                                 "correct against chance"},
                                {"t", b.t_test->t},
                                {"df", b.t_test->df},
                                {"p_two_sided", b.t_test->p_two_sided},
                                {"p_greater", b.t_test->p_greater}}
                         : Json(nullptr);
  j["binomial"] = b.binomial
                      ? Json{{"test",
                              "exact binomial test of pooled answers against "
                              "chance"},
                             {"successes", b.binomial->successes},
                             {"trials", b.binomial->trials},
                             {"p_two_sided", b.binomial->p_two_sided},
                             {"p_greater", b.binomial->p_greater},
                             {"ci", {b.binomial->ci_low, b.binomial->ci_high}}}
                      : Json(nullptr);
  j["pooled_rates"] =
      b.pooled_rates ? RatesJson(*b.pooled_rates) : Json(nullptr);
  j["response_times"] = ResponseTimesJson(b.response_times);
  j["answers_with_deadline"] = b.answers_with_deadline;
  j["late_answers"] = b.late_answers;
  j["no_test_reason"] = b.no_test_reason;
  j["warnings"] = b.warnings;
  j["histogram"] = plot.empty() ? Json(nullptr) : Json(plot);
  return j;
}

std::string DPrimeText(const analysis::SameDifferentRates& r) {
  const auto d = [](const std::optional<double>& v) {
    return v ? fmt::format("{:.3f}", *v) : std::string("n/a");
  };
  // `*` marks each rate of 0 or 1 that d' used corrected (the key below the
  // block says so).
  const auto mark = [](int k, int n) { return k == 0 || k == n ? "*" : ""; };
  return fmt::format("H {:.3f}{} F {:.3f}{}  d' {} (differencing) {} (IO)",
                     r.hit_rate, mark(r.hits, r.different_trials),
                     r.false_alarm_rate, mark(r.false_alarms, r.same_trials),
                     d(r.dprime_differencing),
                     d(r.dprime_independent_observation));
}

void PrintScores(std::ostream& out, const analysis::BlockScores& b,
                 const std::string& plot) {
  out << fmt::format("block {} ({}, {}): {} subjects{}\n", b.block, b.method,
                     b.task, b.subjects.size(),
                     b.trials_per_subject ? fmt::format(", {} trials each",
                                                        *b.trials_per_subject)
                                          : std::string());
  if (b.mean_score) {
    out << fmt::format("  score      {:.2f} +- {:.2f} (mean +- SEM) of {}\n",
                       b.mean_score->mean, b.mean_score->sem,
                       *b.trials_per_subject);
  }
  if (b.mean_proportion) {
    out << fmt::format("  correct    {:.1f} +- {:.1f} %\n",
                       100.0 * b.mean_proportion->mean,
                       100.0 * b.mean_proportion->sem);
  }
  if (b.t_test) {
    out << fmt::format(
        "  t-test     t({}) = {:.3f} against chance {}: p = {} one-sided "
        "(above chance), {} two-sided\n",
        b.t_test->df, b.t_test->t, *b.chance, P(b.t_test->p_greater),
        P(b.t_test->p_two_sided));
  }
  if (b.binomial) {
    out << fmt::format(
        "  binomial   {} of {} correct: p = {} one-sided, {} two-sided\n",
        b.binomial->successes, b.binomial->trials, P(b.binomial->p_greater),
        P(b.binomial->p_two_sided));
  }
  if (!b.chance) out << "  no test    " << b.no_test_reason << '\n';
  if (b.pooled_rates) {
    out << "  pooled     " << DPrimeText(*b.pooled_rates) << '\n';
  }
  if (b.answers_with_deadline > 0) {
    out << fmt::format(
        "  late       {} of {} answers after the response deadline (kept and "
        "scored)\n",
        b.late_answers, b.answers_with_deadline);
  }
  for (const analysis::SubjectScore& s : b.subjects) {
    out << fmt::format(
        "  sub-{:<8} {:>3} of {:<3}{}{}\n", s.subject, s.correct, s.trials,
        b.answers_with_deadline > 0 ? fmt::format("  {} late", s.late_answers)
                                    : std::string(),
        s.rates ? "  " + DPrimeText(*s.rates) : std::string());
  }
  if (!b.response_times.empty()) {
    out << "  response time, s: median [Q1, Q3] (R quantile type 7), IQR = "
           "Q3 - Q1, n timed trials, n/a trials without a time (skipped)\n";
    for (const analysis::ResponseTimeSummary& r : b.response_times) {
      out << fmt::format(
          "    {:<12} {:<24} IQR {:<7} n {:<5} n/a {}\n", r.condition,
          MedianQuartilesText(r),
          r.iqr_s ? fmt::format("{:.3f}", *r.iqr_s) : std::string("n/a"), r.n,
          r.missing);
    }
  }
  bool any_corrected = b.pooled_rates && b.pooled_rates->corrected;
  for (const analysis::SubjectScore& s : b.subjects) {
    any_corrected = any_corrected || (s.rates && s.rates->corrected);
  }
  if (any_corrected) {
    out << "  *          a rate of 0 or 1: d' used 1/(2N) or 1 - 1/(2N) "
           "instead (Macmillan & Kaplan 1985), N its trials\n";
  }
  for (const std::string& w : b.warnings) out << "  warning    " << w << '\n';
  if (!plot.empty()) out << "  histogram  " << plot << '\n';
}

int RunScores(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Scores per block of a study's results (the --out folder of burrlab "
      "run or study): each subject's correct answers, mean +- SEM, a "
      "one-sample t-test of the proportions correct against chance (one- "
      "and two-sided), an exact binomial test of the pooled answers, and for "
      "same-different blocks hit and false-alarm rates with d' "
      "(differencing and independent-observation models; rates of 0 or 1 "
      "moved to 1/(2N), marked *), response times per condition "
      "(median and quartiles, R quantile type 7; trials without a time are "
      "skipped and counted). Practice trials are left out (the output "
      "says how many); answers after a block's response deadline are counted "
      "per block and scored.",
      "burrlab analyze scores"};
  std::string dir, plots;
  bool json = false;
  int format = 0;
  FlagSet flags(&app);
  app.add_option("DIR", dir, "results folder")->required();
  flags.AddSwitch("--json", "print the results as JSON", &json);
  flags.AddText("--plots", "write a score histogram per block here", &plots)
      ->type_name("DIR");
  AddFigureFormat(flags, &format);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  Result<std::vector<results_schema::BehFile>> files = ReadResults(dir, err);
  if (!files.ok()) return Fail(err, files.error().message);
  const std::vector<analysis::PracticeLeftOut> practice =
      analysis::PracticeTrials(*files);
  Result<std::vector<analysis::BlockScores>> blocks =
      analysis::ScoreBlocks(*files);
  if (!blocks.ok())
    return Fail(err, "analyze scores: " + blocks.error().message);
  std::vector<std::string> plot_paths(blocks->size());
  if (flags.Given("--plots")) {
    if (Status s = MakePlotDir(plots); !s.ok())
      return Fail(err, s.error().message);
    for (std::size_t i = 0; i < blocks->size(); ++i) {
      plot_paths[i] =
          (fs::path(plots) / fmt::format("scores_{}{}", (*blocks)[i].task_label,
                                         FigureExtension(format)))
              .string();
      if (Status s = analysis::WritePlot(analysis::ScoreHistogram((*blocks)[i]),
                                         plot_paths[i]);
          !s.ok()) {
        return Fail(err, s.error().message);
      }
    }
  }
  if (json) {
    Json j;
    j["results"] = dir;
    j["practice_left_out"] = Json::array();
    for (const analysis::PracticeLeftOut& p : practice) {
      j["practice_left_out"].push_back(
          {{"block", p.block}, {"trials", p.trials}});
    }
    j["blocks"] = Json::array();
    for (std::size_t i = 0; i < blocks->size(); ++i) {
      j["blocks"].push_back(ScoresJson((*blocks)[i], plot_paths[i]));
    }
    out << j.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    return 0;
  }
  if (!practice.empty()) out << PracticeLine(practice, "scored") << "\n\n";
  for (std::size_t i = 0; i < blocks->size(); ++i) {
    if (i > 0) out << '\n';
    PrintScores(out, (*blocks)[i], plot_paths[i]);
  }
  return 0;
}

// Writes each {path, text} to a new file; an error names the file, and no
// file is written when one of them exists already.
Status WriteNewFiles(
    const std::vector<std::pair<std::string, std::string>>& files) {
  for (const auto& [path, text] : files) {
    std::error_code ec;
    if (fs::exists(path, ec)) {
      return Error{
          fmt::format("{} already exists; choose another --tsv or "
                      "remove it",
                      path)};
    }
  }
  for (const auto& [path, text] : files) {
    std::ofstream file(path, std::ios::binary);
    file << text;
    file.close();
    if (!file) return Error{fmt::format("cannot write {}", path)};
  }
  return {};
}

int RunResponseTimes(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Response times per subject, block and condition of a study's results "
      "(the response_time column of the _beh.tsv files): the median, the "
      "quartiles Q1 and Q3 (R's quantile type 7, its default) and IQR = Q3 - "
      "Q1 of the trials with a time, and how many trials had none (n/a, e.g. "
      "answers typed into a pipe: skipped and counted). A condition is the "
      "trial_type, or the stimulus level in constant-stimuli blocks; 'all' is "
      "every trial of the block.",
      "burrlab analyze rt"};
  std::string dir, tsv;
  bool json = false;
  FlagSet flags(&app);
  app.add_option("DIR", dir, "results folder")->required();
  flags.AddSwitch("--json", "print the results as JSON", &json);
  flags
      .AddText("--tsv",
               "also write the table as tab-separated values (n/a for none) "
               "to FILE.tsv, its columns described in FILE.json beside it; "
               "existing files are not overwritten",
               &tsv)
      ->type_name("FILE.tsv");
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  if (flags.Given("--tsv") && !tsv.ends_with(".tsv")) {
    return Fail(err, fmt::format("--tsv {}: the file name must end in .tsv "
                                 "(its column descriptions go to the .json "
                                 "beside it)",
                                 tsv));
  }
  Result<std::vector<results_schema::BehFile>> files = ReadResults(dir, err);
  if (!files.ok()) return Fail(err, files.error().message);
  const std::vector<analysis::SubjectBlockResponseTimes> rt =
      analysis::ResponseTimesBySubject(*files);
  const auto value = [](const std::optional<double>& v) {
    return v ? fmt::format("{}", *v) : std::string("n/a");
  };
  if (flags.Given("--tsv")) {
    std::string text =
        "participant_id\tblock\tmethod\tcondition\tn\tmissing\tmedian_s\t"
        "q1_s\tq3_s\tiqr_s\n";
    for (const analysis::SubjectBlockResponseTimes& b : rt) {
      for (const analysis::ResponseTimeSummary& r : b.summaries) {
        text += fmt::format("sub-{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\n",
                            b.subject, b.block, b.method, r.condition, r.n,
                            r.missing, value(r.median_s), value(r.q1_s),
                            value(r.q3_s), value(r.iqr_s));
      }
    }
    Json sidecar;
    sidecar["participant_id"] = {{"Description", "the subject, sub-<label>"}};
    sidecar["block"] = {{"Description", "block name from the protocol"}};
    sidecar["method"] = {{"Description", "the block's psychophysical method"}};
    sidecar["condition"] = {
        {"Description",
         "the trials summarised: all (every trial of the block), a "
         "trial_type, or 'level X' (constant-stimuli blocks, stim_level X)"}};
    sidecar["n"] = {{"Description", "trials with a response time"}};
    sidecar["missing"] = {
        {"Description",
         "trials without a response time (n/a in the _beh.tsv, e.g. answers "
         "typed into a pipe), left out of the quartiles"}};
    const auto quartile = [](const char* what) {
      return Json{{"Description",
                   fmt::format("{} of the n response times, R quantile type 7 "
                               "(its default); n/a when n = 0",
                               what)},
                  {"Units", "s"}};
    };
    sidecar["median_s"] = quartile("median");
    sidecar["q1_s"] = quartile("first quartile");
    sidecar["q3_s"] = quartile("third quartile");
    sidecar["iqr_s"] = {{"Description", "inter-quartile range, q3_s - q1_s"},
                        {"Units", "s"}};
    const std::string json_path = tsv.substr(0, tsv.size() - 4) + ".json";
    if (Status s =
            WriteNewFiles({{tsv, text}, {json_path, sidecar.dump(2) + "\n"}});
        !s.ok()) {
      return Fail(err, s.error().message);
    }
  }
  if (json) {
    Json j;
    j["results"] = dir;
    j["definition"] = kResponseTimeText;
    j["tsv"] = tsv.empty() ? Json(nullptr) : Json(tsv);
    j["response_times"] = Json::array();
    for (const analysis::SubjectBlockResponseTimes& b : rt) {
      Json one = ResponseTimesJson(b.summaries);
      j["response_times"].push_back({{"subject", b.subject},
                                     {"block", b.block},
                                     {"method", b.method},
                                     {"conditions", one["conditions"]}});
    }
    out << j.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    return 0;
  }
  out << fmt::format(
      "{:<12} {:<12} {:<12} {:>5} {:>5} {:>9} {:>8} {:>8} "
      "{:>8}\n",
      "subject", "block", "condition", "n", "n/a", "median s", "Q1 s", "Q3 s",
      "IQR s");
  const auto fixed = [](const std::optional<double>& v) {
    return v ? fmt::format("{:.3f}", *v) : std::string("n/a");
  };
  for (const analysis::SubjectBlockResponseTimes& b : rt) {
    for (const analysis::ResponseTimeSummary& r : b.summaries) {
      out << fmt::format(
          "{:<12} {:<12} {:<12} {:>5} {:>5} {:>9} {:>8} {:>8} {:>8}\n",
          "sub-" + b.subject, b.block, r.condition, r.n, r.missing,
          fixed(r.median_s), fixed(r.q1_s), fixed(r.q3_s), fixed(r.iqr_s));
    }
  }
  out << "n: trials with a response time; n/a: trials without one (e.g. "
         "answers typed into a pipe), skipped; median, Q1, Q3: median and "
         "quartiles of the n times, R quantile type 7; IQR = Q3 - Q1; "
         "condition: the trial_type, or the stimulus level in "
         "constant-stimuli blocks; all: every trial of the block.\n";
  if (!tsv.empty()) {
    out << fmt::format("wrote {} (columns described in {})\n", tsv,
                       tsv.substr(0, tsv.size() - 4) + ".json");
  }
  return 0;
}

// A number of a group summary; NaN (not computed) is null.
Json GroupNumber(double x) {
  return std::isfinite(x) ? Json(x) : Json(nullptr);
}

Json GroupThresholdJson(const analysis::GroupThreshold& g) {
  Json j;
  if (!g.session.empty()) j["session"] = g.session;
  j.update(Json{
      {"block", g.block},
      {"staircase_id", g.staircase_id ? Json(*g.staircase_id) : Json(nullptr)},
      {"method", g.method},
      {"estimator", g.estimator},
      {"unit", g.stim_unit},
      {"n", g.n},
      {"subjects", g.subjects},
      {"values", g.values},
      {"unbounded", g.unbounded},
      {"mean", GroupNumber(g.mean)},
      {"sd", GroupNumber(g.sd)},
      {"sem", GroupNumber(g.sem)},
      {"ci", Json{GroupNumber(g.ci_low), GroupNumber(g.ci_high)}}});
  j["without_value"] = Json::array();
  for (const auto& [subject, note] : g.without_value) {
    j["without_value"].push_back(Json{{"subject", subject}, {"note", note}});
  }
  j["geometric"] =
      g.geometric ? Json{{"mean", GroupNumber(g.geometric_mean)},
                         {"sd_factor", GroupNumber(g.geometric_sd_factor)},
                         {"sem_factor", GroupNumber(g.geometric_sem_factor)},
                         {"ci", Json{GroupNumber(g.geometric_ci_low),
                                     GroupNumber(g.geometric_ci_high)}}}
                  : Json(nullptr);
  return j;
}

// The group lines of `analyze thresholds`, and a key to their symbols.
void PrintGroupThresholds(std::ostream& out,
                          const std::vector<analysis::GroupThreshold>& groups,
                          const std::vector<std::string>& figures) {
  if (groups.empty()) return;
  bool any_spread = false, any_geometric = false;
  out << '\n';
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const analysis::GroupThreshold& g = groups[i];
    const std::string what = fmt::format(
        "group {}{}{}",
        g.session.empty() ? std::string() : "ses-" + g.session + " ", g.block,
        g.staircase_id ? fmt::format(" staircase {}", *g.staircase_id)
                       : std::string());
    if (g.n == 0) {
      out << what << ": no subject has a threshold\n";
    } else if (g.n == 1) {
      out << fmt::format("{}: {:.4g} {}, 1 subject (sub-{}): no spread\n", what,
                         g.mean, g.stim_unit, g.subjects.front());
    } else {
      std::string line = fmt::format(
          "{}: mean {:.4g} {} ± {:.3g} SEM [{:.4g}, {:.4g}] 95 % CI, SD "
          "{:.3g}",
          what, g.mean, g.stim_unit, g.sem, g.ci_low, g.ci_high, g.sd);
      any_spread = true;
      if (g.geometric) {
        any_geometric = true;
        line += fmt::format(
            "; geometric mean {:.4g} {} ×/÷ {:.4g} [{:.4g}, {:.4g}] 95 % CI, "
            "SD factor {:.4g}",
            g.geometric_mean, g.stim_unit, g.geometric_sem_factor,
            g.geometric_ci_low, g.geometric_ci_high, g.geometric_sd_factor);
      }
      out << line << fmt::format("; n = {} subjects\n", g.n);
    }
    if (g.n > 0) {
      std::vector<std::string> names;
      for (const std::string& s : g.subjects) names.push_back("sub-" + s);
      out << fmt::format("  subjects: {}\n", fmt::join(names, ", "));
    }
    if (!g.unbounded.empty()) {
      std::vector<std::string> names;
      for (const std::string& s : g.unbounded) names.push_back("sub-" + s);
      out << fmt::format(
          "  included, but their data do not bound their threshold (an "
          "interval bound is a search limit): {}\n",
          fmt::join(names, ", "));
    }
    for (const auto& [subject, note] : g.without_value) {
      out << fmt::format("  left out, no threshold: sub-{}{}\n", subject,
                         note.empty() ? std::string() : " (" + note + ")");
    }
    if (!figures[i].empty()) out << "  figure " << figures[i] << '\n';
  }
  if (!any_spread) return;
  out << "group: ± SEM is the standard error of the subjects' mean; 95 % CI "
         "a Student t interval with n - 1 degrees of freedom";
  if (any_geometric) {
    out << "; the geometric mean is the mean of the log thresholds "
           "transformed back, ×/÷ f its standard error as a factor (the mean "
           "times or divided by f), its CI the t interval of the logs "
           "transformed back";
  }
  out << ".\n";
}

int RunThresholds(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Thresholds per subject and block of a study's results, by each "
      "method's estimator: staircases the mean of the last k reversals in "
      "the step scale (k from the protocol, or --reversals), QUEST the "
      "posterior mean (spread: posterior SD, log10 units), limits the mean "
      "transition level, adjustment the mean adjusted level, constant "
      "stimuli a maximum-likelihood psychometric fit with a 95 % BCa "
      "bootstrap interval.",
      "burrlab analyze thresholds"};
  std::string dir, plots;
  analysis::ThresholdOptions options;
  int sigmoid = 0, format = 0;
  bool json = false;
  FlagSet flags(&app);
  app.add_option("DIR", dir, "results folder")->required();
  flags.AddInteger("--reversals",
                   "staircases: reversals averaged (default: the protocol's "
                   "threshold_reversals)",
                   1, 10000, &options.reversals);
  flags.AddChoice("--sigmoid",
                  "constant stimuli: the shape F (default logistic)",
                  {"logistic", "cumnorm", "weibull", "gumbel"}, &sigmoid);
  flags.AddPositive("--cut",
                    "constant stimuli: threshold at F = cut (default 0.5)", "",
                    &options.cut, 0.999999);
  flags.AddInteger("--bootstrap",
                   "constant stimuli: bootstrap samples (default 999)", 0,
                   1000000, &options.bootstrap_samples);
  flags.AddUnsigned("--seed", "bootstrap seed (default 1)", &options.seed);
  flags.AddSwitch("--json", "print the results as JSON", &json);
  flags
      .AddText("--plots",
               "write each group's figure (its subjects' thresholds with "
               "their intervals, and the group mean) here",
               &plots)
      ->type_name("DIR");
  AddFigureFormat(flags, &format);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  options.sigmoid = *analysis::SigmoidFromName(
      std::vector<std::string>{"logistic", "cumnorm", "weibull",
                               "gumbel"}[static_cast<std::size_t>(sigmoid)]);
  Result<std::vector<results_schema::BehFile>> files = ReadResults(dir, err);
  if (!files.ok()) return Fail(err, files.error().message);
  Result<std::vector<analysis::ThresholdEstimate>> estimates =
      analysis::EstimateThresholds(*files, options);
  if (!estimates.ok()) {
    return Fail(err, "analyze thresholds: " + estimates.error().message);
  }
  const std::vector<analysis::PracticeLeftOut> practice =
      analysis::PracticeTrials(*files);
  const std::vector<analysis::GroupThreshold> groups =
      analysis::GroupThresholds(*estimates);
  // One figure per group with a subject: thresholds_BLOCK[_staircase-N]
  // [_ses-S].EXT.
  std::vector<std::string> figures(groups.size());
  if (flags.Given("--plots")) {
    if (Status s = MakePlotDir(plots); !s.ok()) {
      return Fail(err, s.error().message);
    }
    for (std::size_t i = 0; i < groups.size(); ++i) {
      const analysis::GroupThreshold& g = groups[i];
      if (g.n == 0) continue;
      figures[i] =
          (fs::path(plots) /
           fmt::format("thresholds_{}{}{}{}", g.block,
                       g.staircase_id
                           ? fmt::format("_staircase-{}", *g.staircase_id)
                           : std::string(),
                       g.session.empty() ? std::string() : "_ses-" + g.session,
                       FigureExtension(format)))
              .string();
      if (Status s = analysis::WritePlot(
              analysis::GroupThresholdPlot(g, *estimates), figures[i]);
          !s.ok()) {
        return Fail(err, s.error().message);
      }
    }
  }
  if (json) {
    Json j;
    j["results"] = dir;
    j["group"] = Json::array();
    for (std::size_t i = 0; i < groups.size(); ++i) {
      Json g = GroupThresholdJson(groups[i]);
      g["plot"] = figures[i].empty() ? Json(nullptr) : Json(figures[i]);
      j["group"].push_back(g);
    }
    j["practice_left_out"] = Json::array();
    for (const analysis::PracticeLeftOut& p : practice) {
      j["practice_left_out"].push_back(
          Json{{"block", p.block}, {"trials", p.trials}});
    }
    j["thresholds"] = Json::array();
    for (const analysis::ThresholdEstimate& e : *estimates) {
      Json t = {{"subject", e.subject}};
      if (!e.session.empty()) t["session"] = e.session;
      t.update(Json{
          {"block", e.block},
          {"method", e.method},
          {"task", e.task},
          {"staircase_id",
           e.staircase_id ? Json(*e.staircase_id) : Json(nullptr)},
          {"estimator", e.estimator},
          {"value", Optional(e.value)},
          {"unit", e.stim_unit},
          {"spread", Optional(e.spread)},
          {"spread_unit", e.spread_unit},
          {"n", e.n},
          {"ci", e.fit ? Json{e.ci_low_at_search_limit ? Json(nullptr)
                                                       : Optional(e.ci_low),
                              e.ci_high_at_search_limit ? Json(nullptr)
                                                        : Optional(e.ci_high)}
                       : Json(nullptr)},
          {"ci_method", e.fit ? Json(e.ci_method) : Json(nullptr)},
          {"ci_at_search_limit",
           e.fit ? Json{e.ci_low_at_search_limit, e.ci_high_at_search_limit}
                 : Json(nullptr)},
          {"note", e.note}});
      if (e.method == "limits") {
        t["ascending"] = {{"mean", Optional(e.ascending_mean)},
                          {"n", e.ascending_n}};
        t["descending"] = {{"mean", Optional(e.descending_mean)},
                           {"n", e.descending_n}};
        t["started_on_stopping_answer"] = e.started_on_stopping_answer;
      }
      if (e.fit) {
        t["fit"] = {{"x_scale", e.fit_scale},
                    {"alpha", e.fit->params.alpha},
                    {"beta", e.fit->params.beta},
                    {"gamma", e.fit->params.gamma},
                    {"lambda", e.fit->params.lambda},
                    {"deviance", e.fit->deviance},
                    {"deviance_p", Optional(e.deviance_p)},
                    {"converged", e.fit->converged}};
      }
      j["thresholds"].push_back(t);
    }
    out << j.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    return 0;
  }
  for (const analysis::ThresholdEstimate& e : *estimates) {
    const std::string who = fmt::format(
        "{} {}{}", results_schema::SessionName(e.subject, e.session), e.block,
        e.staircase_id ? fmt::format(" staircase {}", *e.staircase_id)
                       : std::string());
    std::string value = "n/a";
    if (e.value) {
      value = fmt::format("{:.4g} {}", *e.value, e.stim_unit);
      if (e.ci_low && e.ci_high) {
        // A bound at the fit's search range is no number of the data's.
        const auto bound = [](double x, bool at_limit) {
          return at_limit ? std::string("search limit")
                          : fmt::format("{:.4g}", x);
        };
        value += fmt::format(" [{}, {}] 95 % CI{}",
                             bound(*e.ci_low, e.ci_low_at_search_limit),
                             bound(*e.ci_high, e.ci_high_at_search_limit),
                             e.ci_method == "BCa" ? "" : " (percentile)");
      } else if (e.spread) {
        value += fmt::format(" (SD {:.3g} {})", *e.spread, e.spread_unit);
      }
    }
    out << fmt::format("{}: {}  - {}, n = {}{}\n", who, value, e.estimator, e.n,
                       e.note.empty() ? "" : "; " + e.note);
  }
  PrintGroupThresholds(out, groups, figures);
  if (!practice.empty()) out << PracticeLine(practice, "estimated") << '\n';
  return 0;
}

Json HistogramJson(const analysis::Histogram& h) {
  return {{"low", h.low},
          {"width", h.width},
          {"counts", h.counts},
          {"outside", h.outside}};
}

Json KinematicsJson(const analysis::KinematicsSummary& k,
                    const std::pair<std::string, std::string>& plots) {
  Json j = {{"subject", k.subject}};
  if (!k.session.empty()) j["session"] = k.session;
  if (!k.block.empty()) j["block"] = k.block;
  j.update({{"task", k.task},
            {"intervals", k.intervals},
            {"samples", k.samples},
            {"duration_s", k.duration_s},
            {"force_measure", k.force_measure},
            {"mean_force_n", k.mean_force_n},
            {"sd_force_n", k.sd_force_n},
            {"max_force_n", k.max_force_n},
            {"contact_fraction", k.contact_fraction},
            {"speed_measure", k.speed_measure},
            {"mean_speed_mm_s", k.mean_speed_mm_s},
            {"removed_mm3", Optional(k.removed_mm3)},
            {"removal_rate_mm3_per_s", Optional(k.removal_rate_mm3_per_s)},
            {"force_histogram_n", HistogramJson(k.force)},
            {"speed_histogram_mm_s", HistogramJson(k.speed)},
            {"plots", plots.first.empty() ? Json(nullptr)
                                          : Json{plots.first, plots.second}}});
  return j;
}

// The subjects' summaries of one block (and session) and their measures.
struct KinematicsGroup {
  std::string session, block, task, material;
  std::vector<std::string> subjects;
  // mean_force_n, contact_fraction, mean_speed_mm_s, removal_rate_mm3_per_s
  // (subjects without removed_mm3 left out of the last).
  std::vector<std::pair<std::string, std::vector<double>>> measures;
};

std::vector<KinematicsGroup> KinematicsGroups(
    const std::vector<analysis::KinematicsSummary>& blocks) {
  std::vector<KinematicsGroup> groups;
  for (const analysis::KinematicsSummary& k : blocks) {
    auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) {
      return g.session == k.session && g.block == k.block &&
             g.material == k.material;
    });
    if (it == groups.end()) {
      KinematicsGroup g{k.session, k.block, k.task, k.material, {}, {}};
      for (const char* name : {"mean_force_n", "contact_fraction",
                               "mean_speed_mm_s", "removal_rate_mm3_per_s"}) {
        g.measures.emplace_back(name, std::vector<double>());
      }
      groups.push_back(std::move(g));
      it = groups.end() - 1;
    }
    it->subjects.push_back(k.subject);
    it->measures[0].second.push_back(k.mean_force_n);
    it->measures[1].second.push_back(k.contact_fraction);
    it->measures[2].second.push_back(k.mean_speed_mm_s);
    if (k.removal_rate_mm3_per_s) {
      it->measures[3].second.push_back(*k.removal_rate_mm3_per_s);
    }
  }
  return groups;
}

// "1.23 ± 0.05" (mean ± SEM), "1.23" for one value, "n/a" for none.
std::string MeanSemText(const std::vector<double>& values, double scale,
                        int digits) {
  if (values.empty()) return "n/a";
  Result<analysis::MeanSem> m = analysis::MeanAndSem(values);
  const double mean = scale * analysis::Mean(values);
  return m.ok() ? fmt::format("{:.{}f} ± {:.{}f}", mean, digits, scale * m->sem,
                              digits)
                : fmt::format("{:.{}f}", mean, digits);
}

// The group's lines of `analyze kinematics`: per block (and per block and
// material felt), the subjects' mean force, contact share, speed and removal
// rate, mean ± SEM.
void PrintKinematicsGroups(std::ostream& out,
                           const analysis::KinematicsReport& report) {
  out << "group per block and per material felt, mean ± SEM over subjects:\n";
  std::vector<KinematicsGroup> groups = KinematicsGroups(report.blocks);
  for (KinematicsGroup& g : KinematicsGroups(report.materials)) {
    groups.push_back(std::move(g));
  }
  for (const KinematicsGroup& g : groups) {
    out << fmt::format(
        "  {:<14} {:>3} subjects  force {} N  contact {} %  speed {} mm/s  "
        "removal {} mm3/s\n",
        (g.session.empty() ? "" : "ses-" + g.session + " ") + g.block +
            (g.material.empty() ? "" : ":" + g.material),
        g.subjects.size(), MeanSemText(g.measures[0].second, 1.0, 3),
        MeanSemText(g.measures[1].second, 100.0, 1),
        MeanSemText(g.measures[2].second, 1.0, 3),
        MeanSemText(g.measures[3].second, 1.0, 4));
  }
}

// Writes the force and speed histograms of `k` as STEM_force.EXT and
// STEM_speed.EXT (EXT: ".png", ".pdf" or ".svg"); the two paths, or an error
// naming the file.
Result<std::pair<std::string, std::string>> WriteKinematicsPlots(
    const analysis::KinematicsSummary& k, const std::string& stem,
    const std::string& extension) {
  std::pair<std::string, std::string> paths = {stem + "_force" + extension,
                                               stem + "_speed" + extension};
  if (Status s =
          analysis::WritePlot(analysis::ForceHistogramPlot(k), paths.first);
      !s.ok()) {
    return s.error();
  }
  if (Status s =
          analysis::WritePlot(analysis::SpeedHistogramPlot(k), paths.second);
      !s.ok()) {
    return s.error();
  }
  return paths;
}

constexpr const char* kWelchText =
    "Welch's two-sample t-test (variances not assumed equal; R t.test(x, "
    "y)): t = (mean x - mean y) / sqrt(var x / n x + var y / n y), df by "
    "Welch-Satterthwaite, two-sided p";
constexpr const char* kMannWhitneyText =
    "Mann-Whitney U test (Wilcoxon rank-sum; R wilcox.test(x, y)): W = U of "
    "x, the rank sum of x minus n x (n x + 1) / 2; two-sided p, exact when "
    "both groups have fewer than 50 subjects and no values tie, else the "
    "normal approximation with continuity correction";

Json ComparisonJson(const analysis::KinematicsGroupComparison& c,
                    const std::string& path) {
  Json j;
  j["file"] = path;
  j["column"] = c.column;
  j["x"] = c.groups[0];
  j["y"] = c.groups[1];
  j["subjects"] = {{c.groups[0], c.subjects[0]}, {c.groups[1], c.subjects[1]}};
  j["left_out"] = c.left_out;
  j["welch_test"] = kWelchText;
  j["mann_whitney_test"] = kMannWhitneyText;
  j["comparisons"] = Json::array();
  for (const analysis::KinematicsComparison& m : c.comparisons) {
    Json r;
    r["block"] = m.block.empty() ? Json(nullptr) : Json(m.block);
    r["measure"] = m.measure;
    r["values"] = {{c.groups[0], m.values[0]}, {c.groups[1], m.values[1]}};
    r["welch"] = m.welch ? Json{{"mean_x", m.welch->mean_x},
                                {"mean_y", m.welch->mean_y},
                                {"t", m.welch->t},
                                {"df", m.welch->df},
                                {"p_two_sided", m.welch->p_two_sided}}
                         : Json(nullptr);
    r["welch_note"] = m.welch_note;
    r["mann_whitney"] = m.mann_whitney
                            ? Json{{"w", m.mann_whitney->w},
                                   {"p_two_sided", m.mann_whitney->p_two_sided},
                                   {"exact", m.mann_whitney->exact},
                                   {"method", m.mann_whitney->method}}
                            : Json(nullptr);
    r["mann_whitney_note"] = m.mann_whitney_note;
    j["comparisons"].push_back(r);
  }
  return j;
}

void PrintComparison(std::ostream& out,
                     const analysis::KinematicsGroupComparison& c,
                     const std::string& path) {
  const auto members = [](const std::vector<std::string>& labels) {
    std::string text;
    for (const std::string& l : labels) {
      text += (text.empty() ? "sub-" : ", sub-") + l;
    }
    return text.empty() ? std::string("none") : text;
  };
  out << fmt::format(
      "\ngroups ({}, column {}): x = {} ({}), y = {} ({}){}\n", path, c.column,
      c.groups[0], members(c.subjects[0]), c.groups[1], members(c.subjects[1]),
      c.left_out.empty()
          ? std::string()
          : fmt::format("; left out (n/a): {}", members(c.left_out)));
  out << fmt::format(
      "{:<10} {:<22} {:>6} {:>6} {:>10} {:>10} {:>8} {:>7} "
      "{:>9} {:>7} {:>9}\n",
      "block", "measure", "n x", "n y", "mean x", "mean y", "t", "df", "p (t)",
      "W", "p (W)");
  std::vector<std::string> notes;
  for (const analysis::KinematicsComparison& m : c.comparisons) {
    const std::string block = m.block.empty() ? "(all)" : m.block;
    const auto mean = [](const std::vector<double>& v) {
      if (v.empty()) return std::string("n/a");
      double sum = 0.0;
      for (double x : v) sum += x;
      return fmt::format("{:.4g}", sum / static_cast<double>(v.size()));
    };
    std::string t = "n/a", df = "n/a", pt = "n/a", w = "n/a", pw = "n/a";
    if (m.welch) {
      t = fmt::format("{:.3f}", m.welch->t);
      df = fmt::format("{:.2f}", m.welch->df);
      pt = P(m.welch->p_two_sided);
    } else {
      notes.push_back(
          fmt::format("{} {}: no t: {}", block, m.measure, m.welch_note));
    }
    if (m.mann_whitney) {
      w = fmt::format("{:g}", m.mann_whitney->w);
      pw = (m.mann_whitney->exact ? "" : "~") + P(m.mann_whitney->p_two_sided);
    } else {
      notes.push_back(fmt::format("{} {}: no W: {}", block, m.measure,
                                  m.mann_whitney_note));
    }
    out << fmt::format(
        "{:<10} {:<22} {:>6} {:>6} {:>10} {:>10} {:>8} {:>7} {:>9} {:>7} "
        "{:>9}\n",
        block, m.measure, m.values[0].size(), m.values[1].size(),
        mean(m.values[0]), mean(m.values[1]), t, df, pt, w, pw);
  }
  out << fmt::format(
      "Each subject's summary is one value; n: subjects per group. t, df, p "
      "(t): {}. W, p (W): {}; ~ marks the approximation. n/a: not tested "
      "(see below). (all): the subjects' summaries over all blocks.\n",
      kWelchText, kMannWhitneyText);
  for (const std::string& note : notes) out << "note: " << note << '\n';
}

int RunKinematics(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Kinematics of a study's recorded intervals (dissertation ch. 12, Fig. "
      "12.4-12.6): per subject and block, and per subject over all its "
      "blocks, histograms of the felt force |F| and of the burr speed "
      "|dp/dt| over common ranges, the mean force and the material removal "
      "rate (removed volume per traced second). Station traces give 3-D "
      "position and force; simulated intervals move the burr along z only "
      "and record the vertical force_n. With --groups, each per-subject "
      "measure is compared between two groups (e.g. experts and trainees, "
      "as §12.3) by Welch's t-test and the Mann-Whitney U test.",
      "burrlab analyze kinematics"};
  std::string dir, plots;
  analysis::KinematicsOptions options;
  bool json = false;
  int format = 0;
  FlagSet flags(&app);
  app.add_option("DIR", dir, "results folder")->required();
  flags.AddInteger("--bins", "histogram bins (default 30)", 1, 10000,
                   &options.bins);
  flags.AddSwitch("--json", "print the results as JSON", &json);
  flags
      .AddText("--plots",
               "write force and speed histograms per subject and block, and "
               "per subject over all its blocks, here",
               &plots)
      ->type_name("DIR");
  AddFigureFormat(flags, &format);
  std::string groups_path, group_column = "group";
  flags
      .AddText("--groups",
               "compare two groups of subjects (e.g. experts and trainees) "
               "named in this participants.tsv: tab-separated, a header row "
               "with participant_id (sub-<label>) and the group column; n/a "
               "leaves a subject out",
               &groups_path)
      ->type_name("FILE");
  flags
      .AddText("--group-column",
               "the --groups file's column naming each subject's group "
               "(default group)",
               &group_column)
      ->type_name("NAME");
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  if (flags.Given("--group-column") && !flags.Given("--groups")) {
    return Fail(err, "--group-column goes with --groups FILE");
  }
  if (group_column.empty()) {
    return Fail(err, "--group-column must name a column, got ''");
  }
  std::optional<analysis::ParticipantGroups> groups;
  if (flags.Given("--groups")) {
    Result<analysis::ParticipantGroups> g =
        analysis::ReadParticipantGroups(groups_path, group_column);
    if (!g.ok()) {  // may be multi-line: the line and a caret
      err << "burrlab: --groups: " << g.error().message << '\n';
      return 1;
    }
    groups = std::move(*g);
  }
  Result<std::vector<results_schema::BehFile>> files = ReadResults(dir, err);
  if (!files.ok()) return Fail(err, files.error().message);
  Result<analysis::KinematicsReport> report =
      analysis::SummarizeKinematics(*files, options);
  if (!report.ok()) {
    return Fail(err, "analyze kinematics: " + report.error().message);
  }
  std::optional<analysis::KinematicsGroupComparison> comparison;
  if (groups) {
    Result<analysis::KinematicsGroupComparison> c =
        analysis::CompareKinematicsGroups(*report, *groups);
    if (!c.ok()) {
      return Fail(
          err, fmt::format("--groups {}: {}", groups_path, c.error().message));
    }
    comparison = std::move(*c);
  }
  using PlotPaths = std::vector<std::pair<std::string, std::string>>;
  PlotPaths block_plots(report->blocks.size()),
      subject_plots(report->subjects.size());
  std::vector<std::string> group_plots;
  if (flags.Given("--plots")) {
    if (Status s = MakePlotDir(plots); !s.ok())
      return Fail(err, s.error().message);
    for (auto [summaries, paths] :
         {std::pair{&report->blocks, &block_plots},
          std::pair{&report->subjects, &subject_plots}}) {
      for (std::size_t i = 0; i < summaries->size(); ++i) {
        const analysis::KinematicsSummary& k = (*summaries)[i];
        const std::string stem =
            (fs::path(plots) /
             (k.block.empty() ? fmt::format("sub-{}", k.subject)
                              : fmt::format("{}_{}",
                                            results_schema::SessionFilePrefix(
                                                k.subject, k.session),
                                            k.block)))
                .string();
        Result<std::pair<std::string, std::string>> written =
            WriteKinematicsPlots(k, stem, FigureExtension(format));
        if (!written.ok()) return Fail(err, written.error().message);
        (*paths)[i] = *written;
      }
    }
    // The group's histograms per block (and session), and per block and
    // material felt: group_[ses-S_]BLOCK[_MATERIAL]_force and _speed.
    using Key = std::tuple<std::string, std::string, std::string>;
    std::vector<Key> keys;
    for (const auto* summaries : {&report->blocks, &report->materials}) {
      for (const analysis::KinematicsSummary& k : *summaries) {
        const Key key{k.session, k.block, k.material};
        if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
          keys.push_back(key);
        }
      }
    }
    for (const auto& [session, block, material] : keys) {
      std::vector<analysis::KinematicsSummary> members;
      for (const auto* summaries : {&report->blocks, &report->materials}) {
        for (const analysis::KinematicsSummary& k : *summaries) {
          if (k.session == session && k.block == block &&
              k.material == material) {
            members.push_back(k);
          }
        }
      }
      const std::string stem =
          (fs::path(plots) /
           fmt::format("group_{}{}{}",
                       session.empty() ? "" : "ses-" + session + "_", block,
                       material.empty() ? "" : "_" + material))
              .string();
      for (const auto& [suffix, plot] :
           {std::pair{"_force", analysis::GroupForceHistogramPlot(members)},
            std::pair{"_speed", analysis::GroupSpeedHistogramPlot(members)}}) {
        const std::string path = stem + suffix + FigureExtension(format);
        if (Status s = analysis::WritePlot(plot, path); !s.ok()) {
          return Fail(err, s.error().message);
        }
        group_plots.push_back(path);
      }
    }
  }
  if (json) {
    Json j;
    j["group_plots"] = group_plots;
    j["results"] = dir;
    j["kinematics"] = Json::array();
    for (std::size_t i = 0; i < report->blocks.size(); ++i) {
      j["kinematics"].push_back(
          KinematicsJson(report->blocks[i], block_plots[i]));
    }
    j["subjects"] = Json::array();
    for (std::size_t i = 0; i < report->subjects.size(); ++i) {
      j["subjects"].push_back(
          KinematicsJson(report->subjects[i], subject_plots[i]));
    }
    j["materials"] = Json::array();
    for (const analysis::KinematicsSummary& k : report->materials) {
      Json one = KinematicsJson(k, {});
      one["material"] = k.material;
      j["materials"].push_back(one);
    }
    j["group_comparison"] =
        comparison ? ComparisonJson(*comparison, groups_path) : Json(nullptr);
    j["group"] = Json::array();
    std::vector<KinematicsGroup> summaries = KinematicsGroups(report->blocks);
    for (KinematicsGroup& g : KinematicsGroups(report->materials)) {
      summaries.push_back(std::move(g));
    }
    for (const KinematicsGroup& g : summaries) {
      Json one = {
          {"block", g.block}, {"task", g.task}, {"subjects", g.subjects}};
      one["material"] = g.material.empty() ? Json(nullptr) : Json(g.material);
      if (!g.session.empty()) one["session"] = g.session;
      for (const auto& [name, values] : g.measures) {
        Result<analysis::MeanSem> m = analysis::MeanAndSem(values);
        one[name] = {{"n", values.size()},
                     {"mean", values.empty() ? Json(nullptr)
                                             : Json(analysis::Mean(values))},
                     {"sem", m.ok() ? Json(m->sem) : Json(nullptr)}};
      }
      j["group"].push_back(one);
    }
    out << j.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    return 0;
  }
  out << fmt::format("{:<12} {:<10} {:>11} {:>8} {:>12} {:>10} {:>12} {:>16}\n",
                     "subject", "block", "task", "time s", "mean force N",
                     "contact %", "speed mm/s", "removal mm3/s");
  for (const auto* summaries :
       {&report->blocks, &report->materials, &report->subjects}) {
    for (const analysis::KinematicsSummary& k : *summaries) {
      out << fmt::format(
          "{:<12} {:<10} {:>11} {:>8.1f} {:>12.3f} {:>10.1f} {:>12.3f} "
          "{:>16}\n",
          results_schema::SessionName(k.subject, k.session),
          k.block.empty()      ? "(all)"
          : k.material.empty() ? k.block
                               : k.block + ":" + k.material,
          k.task, k.duration_s, k.mean_force_n, 100.0 * k.contact_fraction,
          k.mean_speed_mm_s,
          k.removal_rate_mm3_per_s
              ? fmt::format("{:.4g}", *k.removal_rate_mm3_per_s)
              : std::string("n/a"));
    }
  }
  PrintKinematicsGroups(out, *report);
  std::string force_measures, speed_measures;
  for (const analysis::KinematicsSummary& k : report->subjects) {
    if (force_measures.find(k.force_measure) == std::string::npos) {
      force_measures += (force_measures.empty() ? "" : "; ") + k.force_measure;
    }
    if (speed_measures.find(k.speed_measure) == std::string::npos) {
      speed_measures += (speed_measures.empty() ? "" : "; ") + k.speed_measure;
    }
  }
  out << fmt::format(
      "(all): the subject's blocks together; BLOCK:MATERIAL: the block's "
      "intervals of that material. force: {}. speed: {}, between "
      "consecutive samples of one interval. contact: samples with force above "
      "0.01 N. removal: removed_mm3 per traced second (n/a: the traces have "
      "no removed_mm3).\n",
      force_measures, speed_measures);
  if (comparison) PrintComparison(out, *comparison, groups_path);
  if (flags.Given("--plots")) {
    out << "plots in " << plots << " (the group's per block: "
        << fmt::format("{}", fmt::join(group_plots, ", ")) << ")\n";
  }
  return 0;
}

// One block's power as JSON: P(significant) per test with its 95 %
// Clopper-Pearson interval over the studies.
Json PowerJson(const BlockPower& t) {
  const auto interval = [&](int k) {
    Result<analysis::BinomialTestResult> b =
        analysis::ExactBinomialTest(k, t.runs, 0.5);
    return Json{b->ci_low, b->ci_high};
  };
  Result<analysis::MeanSem> m = analysis::MeanAndSem(t.mean_scores);
  Result<analysis::MeanSem> c = analysis::MeanAndSem(t.mean_counts);
  Json b = {{"block", t.block},
            {"method", t.method},
            {"chance", Optional(t.chance.p)},
            {"mean_proportion_correct",
             m.ok() ? Json(m->mean) : Json(t.mean_scores[0])},
            {"mean_score", c.ok() ? Json(c->mean) : Json(t.mean_counts[0])},
            {"sd_between_studies", m.ok() ? Json(m->sd) : Json(nullptr)},
            {"score_sd_between_studies", c.ok() ? Json(c->sd) : Json(nullptr)}};
  if (t.chance.p) {
    b["power_t_test"] = {{"p", static_cast<double>(t.t_significant) / t.runs},
                         {"ci", interval(t.t_significant)}};
    b["power_binomial"] = {
        {"p", static_cast<double>(t.binomial_significant) / t.runs},
        {"ci", interval(t.binomial_significant)}};
  } else {
    b["no_test_reason"] = t.chance.reason;
  }
  return b;
}

int RunPower(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Power of a protocol: runs R simulated studies of N simulated subjects "
      "whose perceptual noise is the Weber fraction W (both cues), and "
      "reports per scored block the probability of a significant result "
      "(one-sided t-test of proportions correct and exact binomial test of "
      "pooled answers, each against chance at --alpha) with its 95 % "
      "Clopper-Pearson interval. Cues come from a pool of simulator "
      "renderings per stimulus (--cue-samples each); see "
      "analysis/README.md.",
      "burrlab analyze power"};
  std::string protocol_path;
  double weber = 0.0, weber_spread = 0.0, alpha = 0.05, lapse = -1.0;
  int subjects = 0, runs = 0, cue_samples = 8;
  std::uint64_t seed = 1;
  bool json = false;
  FlagSet flags(&app);
  flags.AddText("--protocol", "the protocol file", &protocol_path)
      ->type_name("FILE")
      ->required();
  flags
      .AddPositive("--weber", "Weber fraction of both cues (sigma of ln cue)",
                   "", &weber)
      ->required();
  flags
      .AddInteger("--subjects", "simulated subjects per study", 2, 100000,
                  &subjects)
      ->required();
  flags.AddInteger("--runs", "simulated studies", 1, 1000000, &runs)
      ->required();
  flags.AddUnsigned("--seed", "seed (default 1)", &seed);
  flags.AddPositive("--alpha", "significance level (default 0.05)", "", &alpha,
                    0.5);
  flags.AddNonNegative("--weber-spread",
                       "SD of ln(Weber) across subjects (default 0)", "",
                       &weber_spread);
  flags.AddNonNegative("--lapse", "lapse rate (default: the protocol's)", "",
                       &lapse);
  flags.AddInteger("--cue-samples",
                   "simulator renderings per stimulus in the cue pool "
                   "(default 8)",
                   1, 1000, &cue_samples);
  flags.AddSwitch("--json", "print the results as JSON", &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  if (flags.Given("--lapse") && !(lapse < 1.0)) {
    return Fail(err, fmt::format("--lapse must be below 1, got '{}'", lapse));
  }
  Result<protocols::LoadedProtocol> loaded =
      protocols::LoadProtocol(protocol_path);
  if (!loaded.ok()) return ReportLoadError(err, loaded.error());
  err << loaded->notes;
  VirtualStudyOptions options;
  options.subjects = subjects;
  options.spread_stiffness = weber_spread;
  options.spread_removal = weber_spread;
  options.observer = protocols::ObserverParamsFrom(loaded->protocol.observer);
  options.observer.weber_stiffness = weber;
  options.observer.weber_removal = weber;
  if (flags.Given("--lapse")) options.observer.lapse = lapse;
  if (Status s = options.observer.Validate(); !s.ok()) {
    return Fail(err, "analyze power: " + s.error().message);
  }
  CuePool pool(cue_samples, 2.0, seed);
  ProgressBar bar(err, runs);
  Result<std::vector<BlockPower>> powers = EstimatePower(
      loaded->protocol, options, seed, runs, alpha, pool,
      [&](int done) { bar.Update(done, fmt::format("study {}", done)); });
  if (!powers.ok())
    return Fail(err, "analyze power: " + powers.error().message);
  const std::vector<BlockPower>& tallies = *powers;
  Json j;
  j["protocol"] = protocol_path;
  j["weber"] = weber;
  j["weber_spread"] = weber_spread;
  j["lapse"] = options.observer.lapse;
  j["subjects"] = subjects;
  j["runs"] = runs;
  j["alpha"] = alpha;
  j["seed"] = seed;
  j["cue_samples"] = cue_samples;
  j["intervals_rendered"] = pool.rendered();
  j["blocks"] = Json::array();
  for (const BlockPower& t : tallies) j["blocks"].push_back(PowerJson(t));
  if (json) {
    out << j.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    return 0;
  }
  out << fmt::format(
      "{} studies of {} simulated subjects, Weber {}{}, lapse {}, alpha {} "
      "({} intervals rendered for the cue pool)\n",
      runs, subjects, weber,
      weber_spread > 0.0 ? fmt::format(" (spread {} in ln)", weber_spread)
                         : std::string(),
      options.observer.lapse, alpha, pool.rendered());
  for (const Json& b : j["blocks"]) {
    out << fmt::format("block {} ({}): mean {:.1f} % correct",
                       b["block"].get<std::string>(),
                       b["method"].get<std::string>(),
                       100.0 * b["mean_proportion_correct"].get<double>());
    if (b.contains("power_t_test")) {
      out << fmt::format(
          "; P(significant) t-test {:.3f} [{:.3f}, {:.3f}], binomial {:.3f} "
          "[{:.3f}, {:.3f}]\n",
          b["power_t_test"]["p"].get<double>(),
          b["power_t_test"]["ci"][0].get<double>(),
          b["power_t_test"]["ci"][1].get<double>(),
          b["power_binomial"]["p"].get<double>(),
          b["power_binomial"]["ci"][0].get<double>(),
          b["power_binomial"]["ci"][1].get<double>());
    } else {
      out << "; not tested: " << b["no_test_reason"].get<std::string>() << '\n';
    }
  }
  return 0;
}

int RunFitObservers(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Fit a simulated-observer population to published group results: for "
      "each observed block, the Weber fraction W of the block's cue "
      "(stiffness when probing, removal rate when drilling) and its spread "
      "across subjects (SD of ln W) that make the published mean +- SEM most "
      "likely, by maximum likelihood over virtual studies of the protocol "
      "(the exact probability that n simulated subjects report those rounded "
      "numbers), with 95 % profile-likelihood intervals for both. Give "
      "--observed once per block (block=NAME,mean=M,sem=S,n=N); --observer "
      "chooses the observer model fitted (its decision rule, bias and "
      "exploration). With --predict, simulate another protocol with that "
      "population and report its predicted scores and power.",
      "burrlab analyze fit-observers"};
  std::string protocol_path, predict_path, block, observer, variant_name;
  std::vector<std::string> observed_texts;
  ObserverFitOptions options;
  double lapse = 0.0, alpha = 0.05;
  int cue_samples = 8, runs = 200, predict_subjects = 0;
  bool no_spread = false, json = false, compare_variants = false,
       moments = false;
  FlagSet flags(&app);
  flags
      .AddText("--protocol", "the protocol the observed results come from",
               &protocol_path)
      ->type_name("FILE")
      ->required();
  app.add_option("--observed", observed_texts,
                 "a group result, [block=NAME,]mean=M,sem=S,n=N, or each "
                 "subject's score, [block=NAME,]scores=S1/S2/... (once per "
                 "block)")
      ->type_name("[block=NAME,]mean=M,sem=S,n=N")
      ->allow_extra_args(false)
      ->required();
  flags.AddText("--block",
                "the block scored, with one --observed (default: the first "
                "scored one)",
                &block);
  flags.AddInteger("--virtual-subjects",
                   "subjects per virtual study (default 2000; fewer are "
                   "faster and make the fit noisier)",
                   2, 1000000, &options.virtual_subjects);
  flags.AddUnsigned("--seed", "seed (default 1)", &options.seed);
  int jobs = 0;
  flags.AddInteger("--jobs",
                   "fits at once, one per block and variant (default: the "
                   "core count; the results do not depend on it)",
                   1, 256, &jobs);
  flags.AddSwitch("--no-spread", "all subjects alike (fit W only)", &no_spread);
  flags.AddSwitch("--moments",
                  "match the mean and SD only (faster, no likelihood "
                  "maximised; W's interval from mean +- 1.96 SEM)",
                  &moments);
  flags
      .AddText("--observer",
               "the observer model fitted, simulated[:key=value,...] over "
               "the protocol's [observer], as run --observer takes it (e.g. "
               "simulated:rule=likelihood,exploration=varied); its Weber "
               "fractions are what is fitted",
               &observer)
      ->type_name("SPEC");
  flags
      .AddText("--variant",
               "a named observer model (fixed, differencing, likelihood, "
               "likelihood_varied, likelihood_alike, likelihood_lapse): its "
               "rule, exploration, whether W spreads across subjects and "
               "whether a lapse shared by the blocks is fitted, over "
               "--observer",
               &variant_name)
      ->type_name("NAME");
  flags.AddSwitch("--compare-variants",
                  "fit every named observer model and compare them by how "
                  "likely each makes the observed results (AIC, BIC); "
                  "--predict then uses the best",
                  &compare_variants);
  flags.AddNonNegative("--lapse", "lapse rate (default: the protocol's)", "",
                       &lapse);
  flags.AddInteger("--cue-samples",
                   "simulator renderings per stimulus (default 8)", 1, 1000,
                   &cue_samples);
  flags
      .AddText("--predict", "a protocol to predict with the fitted population",
               &predict_path)
      ->type_name("FILE");
  flags.AddInteger("--predict-subjects",
                   "subjects per predicted study (default: the observed n)", 2,
                   100000, &predict_subjects);
  flags.AddInteger("--runs", "predicted studies (default 200)", 1, 1000000,
                   &runs);
  int recovery = 0;
  flags.AddInteger(
      "--recovery",
      "check the intervals: simulate N published results of the observed n "
      "subjects from the fitted population, fit each back the same way and "
      "count how often each 95 % interval holds the truth (N fits per block)",
      1, 100000, &recovery);
  flags.AddPositive("--alpha", "significance level (default 0.05)", "", &alpha,
                    0.5);
  flags.AddSwitch("--json", "print the results as JSON", &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  options.jobs =
      jobs > 0
          ? jobs
          : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<ObservedGroup> observed;
  for (const std::string& text : observed_texts) {
    Result<ObservedGroup> g = ParseObservedGroup(text);
    if (!g.ok()) return Fail(err, g.error().message);
    observed.push_back(*g);
  }
  if (!block.empty()) {
    if (observed.size() > 1) {
      return Fail(err,
                  "--block goes with one --observed; with several, name each "
                  "one's block inside it (block=NAME,mean=...)");
    }
    if (!observed[0].block.empty() && observed[0].block != block) {
      return Fail(err, fmt::format("--block {} but --observed names block {}",
                                   block, observed[0].block));
    }
    observed[0].block = block;
  }
  if (observed.size() > 1) {
    for (std::size_t i = 0; i < observed.size(); ++i) {
      if (observed[i].block.empty()) {
        return Fail(err, fmt::format("--observed {} needs block=NAME when "
                                     "--observed is given more than once",
                                     observed_texts[i]));
      }
    }
  }
  if (flags.Given("--lapse") && !(lapse < 0.5)) {
    return Fail(err, fmt::format("--lapse must be below 0.5, got '{}'", lapse));
  }
  Result<protocols::LoadedProtocol> loaded =
      protocols::LoadProtocol(protocol_path);
  if (!loaded.ok()) return ReportLoadError(err, loaded.error());
  err << loaded->notes;
  options.fit_spread = !no_spread;
  options.maximum_likelihood = !moments;
  options.base = protocols::ObserverParamsFrom(loaded->protocol.observer);
  if (!observer.empty()) {
    Result<protocols::ObserverParams> spec =
        protocols::ParseObserverSpec(observer, options.base);
    if (!spec.ok()) {
      return Fail(err, "analyze fit-observers: " + spec.error().message);
    }
    options.base = *spec;
  }
  if (flags.Given("--lapse")) options.base.lapse = lapse;
  if (!variant_name.empty() && compare_variants) {
    return Fail(err, "--variant and --compare-variants exclude each other");
  }
  CuePool pool(cue_samples, 2.0, options.seed);
  // The JSON of the fit of block `g`.
  const auto fit_json = [](const ObservedGroup& g, const ObserverFit& fit) {
    Json f;
    f["block"] = fit.block;
    f["cue"] = fit.task == protocols::Task::kProbe ? "stiffness" : "removal";
    f["trials_per_subject"] = fit.trials_per_subject;
    f["observed"] = {
        {"mean", g.mean}, {"sem", g.sem}, {"n", g.n}, {"sd", fit.observed_sd}};
    if (!g.scores.empty()) f["observed"]["scores"] = g.scores;
    f["weber"] = fit.weber;
    f["weber_ci"] = {fit.weber_low, fit.weber_high};
    f["weber_spread"] = fit.weber_spread;
    f["spread_ci"] = {fit.spread_low, fit.spread_high};
    f["method"] = fit.maximum_likelihood ? "maximum likelihood" : "moments";
    f["log_likelihood"] = fit.log_likelihood;
    f["fitted"] = {{"mean", fit.fitted_mean}, {"sd", fit.fitted_sd}};
    f["published_probability"] = fit.published_probability;
    f["virtual_studies"] = fit.virtual_studies;
    f["notes"] = fit.notes;
    return f;
  };
  Json comparison = Json::array();
  std::vector<ObserverFit> fits;
  // The chosen variant fits a lapse shared by the blocks: its interval and
  // notes.
  bool lapse_fitted = false;
  std::array<double, 2> lapse_ci{};
  std::vector<std::string> lapse_notes;
  Json fits_json = Json::array();
  if (!variant_name.empty() || compare_variants) {
    std::vector<ObserverVariant> variants;
    if (compare_variants) {
      variants.assign(std::begin(kObserverVariants),
                      std::end(kObserverVariants));
    } else {
      Result<ObserverVariant> v = FindObserverVariant(variant_name);
      if (!v.ok()) return Fail(err, "--variant: " + v.error().message);
      variants.push_back(*v);
    }
    const int total =
        FitsToCompare(variants, static_cast<int>(observed.size()));
    ProgressBar bar(err, total);
    Result<std::vector<VariantFit>> compared = CompareObserverVariants(
        loaded->protocol, observed, variants, options, pool,
        [&](int done, std::string_view name) {
          bar.Update(done, fmt::format("fitted {}", name));
        });
    if (!compared.ok()) {
      return Fail(err, "analyze fit-observers: " + compared.error().message);
    }
    bar.Update(total, "variants fitted");
    for (const VariantFit& v : *compared) {
      Json c = {{"variant", std::string(v.variant.name)},
                {"parameters", v.parameters},
                {"log_likelihood", v.log_likelihood},
                {"aic", v.aic},
                {"bic", v.bic},
                {"delta_aic", v.delta_aic}};
      if (v.variant.lapse) {
        c["lapse"] = v.observer.lapse;
        c["lapse_ci"] = {v.lapse_low, v.lapse_high};
        c["lapse_profile"] = Json::array();
        for (const auto& [rate, ll] : v.lapse_profile) {
          c["lapse_profile"].push_back(
              {{"lapse", rate}, {"log_likelihood", ll}});
        }
        c["notes"] = v.notes;
      }
      comparison.push_back(c);
    }
    const VariantFit& best = compared->front();
    options.base = best.observer;
    options.fit_spread = best.fit_spread;
    fits = best.fits;
    if (best.variant.lapse) {
      lapse_fitted = true;
      lapse_ci = {best.lapse_low, best.lapse_high};
      lapse_notes = best.notes;
    }
  } else {
    Result<std::vector<ObserverFit>> fitted =
        FitObserverGroups(loaded->protocol, observed, options, pool);
    if (!fitted.ok()) {
      return Fail(err, "analyze fit-observers: " + fitted.error().message);
    }
    fits = std::move(*fitted);
  }
  for (std::size_t i = 0; i < fits.size(); ++i) {
    fits_json.push_back(fit_json(observed[i], fits[i]));
  }
  if (recovery > 0) {
    // The range of k (studies whose interval holds the truth) a 95 % interval
    // gives in 95 % of such checks: the smallest k where Binomial(N, 0.95)'s
    // CDF reaches 0.025, and where it reaches 0.975.
    const boost::math::binomial_distribution<double> chance(recovery, 0.95);
    int chance_low = -1, chance_high = -1;
    for (int k = 0; k <= recovery && chance_high < 0; ++k) {
      const double cdf = boost::math::cdf(chance, k);
      if (chance_low < 0 && cdf >= 0.025) chance_low = k;
      if (cdf >= 0.975) chance_high = k;
    }
    for (std::size_t i = 0; i < fits.size(); ++i) {
      RecoveryOptions r;
      r.studies = recovery;
      r.seed = options.seed;
      r.renderings = cue_samples;
      ProgressBar bar(err, recovery);
      Result<Recovery> checked = CheckRecovery(
          loaded->protocol, observed[i], fits[i], options, pool, r,
          [&](int done) {
            bar.Update(done, fmt::format("recovery of block {}: study {}",
                                         fits[i].block, done));
          });
      if (!checked.ok()) {
        return Fail(err, "analyze fit-observers: " + checked.error().message);
      }
      fits_json[i]["recovery"] = {{"studies", checked->studies},
                                  {"weber_covered", checked->weber_covered},
                                  {"spread_covered", checked->spread_covered},
                                  {"both_covered", checked->both_covered},
                                  {"weber_at_limit", checked->weber_at_limit},
                                  {"spread_at_limit", checked->spread_at_limit},
                                  {"chance_95", {chance_low, chance_high}}};
    }
  }
  Json j;
  j["protocol"] = protocol_path;
  j["lapse"] = options.base.lapse;
  if (lapse_fitted) {
    j["lapse_ci"] = lapse_ci;
    j["lapse_notes"] = lapse_notes;
  }
  const protocols::Exploration& e = options.base.exploration;
  j["observer"] = {
      {"rule",
       std::string(protocols::SameDifferentRuleName(options.base.rule))},
      {"bias", options.base.bias},
      {"criterion", options.base.criterion},
      {"force_spread", e.force_spread},
      {"speed_spread", e.speed_spread},
      {"subject_force_spread", e.subject_force_spread},
      {"subject_speed_spread", e.subject_speed_spread}};
  j["virtual_subjects"] = options.virtual_subjects;
  j["fits"] = fits_json;
  if (!comparison.empty()) j["variants"] = comparison;
  std::vector<std::string> population_notes;
  Result<VirtualStudyOptions> population =
      PopulationOf(fits, options.base, &population_notes);
  if (!population.ok()) {
    return Fail(err, "analyze fit-observers: " + population.error().message);
  }
  j["population"] = {{"weber_stiffness", population->observer.weber_stiffness},
                     {"weber_removal", population->observer.weber_removal},
                     {"spread_stiffness", population->spread_stiffness},
                     {"spread_removal", population->spread_removal},
                     {"notes", population_notes}};
  if (!predict_path.empty()) {
    Result<protocols::LoadedProtocol> other =
        protocols::LoadProtocol(predict_path);
    if (!other.ok()) return ReportLoadError(err, other.error());
    err << other->notes;
    VirtualStudyOptions v = *population;
    v.subjects = predict_subjects > 0 ? predict_subjects : observed[0].n;
    CuePool other_pool(cue_samples, 2.0, options.seed);
    ProgressBar bar(err, runs);
    Result<std::vector<BlockPower>> powers = EstimatePower(
        other->protocol, v, options.seed, runs, alpha, other_pool,
        [&](int done) { bar.Update(done, fmt::format("study {}", done)); });
    if (!powers.ok()) {
      return Fail(
          err, "analyze fit-observers: --predict: " + powers.error().message);
    }
    j["prediction"] = {{"protocol", predict_path},
                       {"subjects", v.subjects},
                       {"runs", runs},
                       {"alpha", alpha},
                       {"blocks", Json::array()}};
    for (const BlockPower& p : *powers) {
      j["prediction"]["blocks"].push_back(PowerJson(p));
    }
  }
  if (json) {
    out << j.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    return 0;
  }
  if (j.contains("variants") && j["variants"].size() > 1) {
    Json sorted = j["variants"];
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const Json& a, const Json& b) {
                       return a["aic"].get<double>() < b["aic"].get<double>();
                     });
    out << "observer variants (each fitted to the observed means and SDs; "
           "ln L: log probability of the observed results at that fit):\n";
    out << fmt::format("  {:<18} {:>2} {:>9} {:>8} {:>8} {:>7}\n", "variant",
                       "k", "ln L", "AIC", "BIC", "dAIC");
    for (const Json& v : sorted) {
      out << fmt::format(
          "  {:<18} {:>2} {:>9.3f} {:>8.2f} {:>8.2f} {:>7.2f}\n",
          v["variant"].get<std::string>(), v["parameters"].get<int>(),
          v["log_likelihood"].get<double>(), v["aic"].get<double>(),
          v["bic"].get<double>(), v["delta_aic"].get<double>());
    }
    for (const Json& v : sorted) {
      if (!v.contains("lapse")) continue;
      out << fmt::format(
          "  {}: lapse {:.3g} [{:.3g}, {:.3g}] shared by the blocks (95 % "
          "profile interval)\n",
          v["variant"].get<std::string>(), v["lapse"].get<double>(),
          v["lapse_ci"][0].get<double>(), v["lapse_ci"][1].get<double>());
      for (const Json& note : v["notes"]) {
        out << "    note: " << note.get<std::string>() << '\n';
      }
    }
    out << fmt::format("best: {} (below)\n",
                       sorted.front()["variant"].get<std::string>());
  }
  out << fmt::format(
      "observer rule {}{}, exploration {}\n",
      protocols::SameDifferentRuleName(options.base.rule),
      options.base.rule == protocols::SameDifferentRule::kFixed
          ? fmt::format(" (criterion {})", options.base.criterion)
          : fmt::format(" (bias {})", options.base.bias),
      e.Varies() || e.subject_force_spread > 0.0 || e.subject_speed_spread > 0.0
          ? fmt::format("varied (SD of ln force {} between intervals and {} "
                        "between subjects, of ln speed {} and {})",
                        e.force_spread, e.subject_force_spread, e.speed_spread,
                        e.subject_speed_spread)
          : std::string("fixed"));
  for (const std::string& note : lapse_notes)
    out << "note     " << note << '\n';
  for (const Json& f : j["fits"]) {
    const bool scores = f["observed"].contains("scores");
    const double mean = f["observed"]["mean"].get<double>(),
                 sem = f["observed"]["sem"].get<double>();
    out << fmt::format(
        "block {} ({} trials, {} cue): observed {} (n {}, SD {:.3g})\n",
        f["block"].get<std::string>(), f["trials_per_subject"].get<int>(),
        f["cue"].get<std::string>(),
        scores ? fmt::format("{:.2f} +- {:.2f}, each subject's score given",
                             mean, sem)
               : fmt::format("{} +- {}", mean, sem),
        f["observed"]["n"].get<int>(), f["observed"]["sd"].get<double>());
    out << fmt::format(
        "fitted   Weber {:.3g} [{:.3g}, {:.3g}], spread {:.3g} [{:.3g}, "
        "{:.3g}] (SD of ln W; 95 % {} intervals), lapse {}\n",
        f["weber"].get<double>(), f["weber_ci"][0].get<double>(),
        f["weber_ci"][1].get<double>(), f["weber_spread"].get<double>(),
        f["spread_ci"][0].get<double>(), f["spread_ci"][1].get<double>(),
        f["method"].get<std::string>() == "moments" ? "moment"
                                                    : "profile-likelihood",
        lapse_fitted
            ? fmt::format("{:.3g} [{:.3g}, {:.3g}] (fitted, shared by the "
                          "blocks)",
                          options.base.lapse, lapse_ci[0], lapse_ci[1])
            : fmt::format("{}", options.base.lapse));
    out << fmt::format(
        "         population mean {:.2f}, SD {:.2f} ({} virtual subjects, {} "
        "virtual studies); {} = {:.3g}\n",
        f["fitted"]["mean"].get<double>(), f["fitted"]["sd"].get<double>(),
        options.virtual_subjects, f["virtual_studies"].get<int>(),
        scores ? fmt::format("P(these {} scores, in this order)",
                             f["observed"]["n"].get<int>())
               : fmt::format("P({} subjects report {} +- {})",
                             f["observed"]["n"].get<int>(),
                             f["observed"]["mean"].get<double>(),
                             f["observed"]["sem"].get<double>()),
        f["published_probability"].get<double>());
    if (f.contains("recovery")) {
      const Json& r = f["recovery"];
      out << fmt::format(
          "recovery {} published results simulated from this fit and fitted "
          "back: W's interval held the truth in {}, the spread's in {}, both "
          "in {} (a 95 % interval: {} to {} by chance); intervals at a search "
          "limit: W {}, spread {}\n",
          r["studies"].get<int>(), r["weber_covered"].get<int>(),
          r["spread_covered"].get<int>(), r["both_covered"].get<int>(),
          r["chance_95"][0].get<int>(), r["chance_95"][1].get<int>(),
          r["weber_at_limit"].get<int>(), r["spread_at_limit"].get<int>());
    }
    for (const Json& note : f["notes"]) {
      out << "note     " << note.get<std::string>() << '\n';
    }
  }
  for (const std::string& note : population_notes) {
    out << "note     " << note << '\n';
  }
  if (j.contains("prediction")) {
    out << fmt::format("predicted {} ({} subjects, {} studies):\n",
                       predict_path, j["prediction"]["subjects"].get<int>(),
                       runs);
    for (const Json& b : j["prediction"]["blocks"]) {
      out << fmt::format(
          "  block {}: mean score {:.2f} (SD {:.2f} between studies)",
          b["block"].get<std::string>(), b["mean_score"].get<double>(),
          b["score_sd_between_studies"].is_null()
              ? 0.0
              : b["score_sd_between_studies"].get<double>());
      if (b.contains("power_t_test")) {
        out << fmt::format(
            "; P(significant) t-test {:.3f} [{:.3f}, {:.3f}], binomial "
            "{:.3f}\n",
            b["power_t_test"]["p"].get<double>(),
            b["power_t_test"]["ci"][0].get<double>(),
            b["power_t_test"]["ci"][1].get<double>(),
            b["power_binomial"]["p"].get<double>());
      } else {
        out << '\n';
      }
    }
  }
  return 0;
}

}  // namespace

int RunScoresCommand(const Args& args, std::ostream& out, std::ostream& err) {
  return RunScores(args, out, err);
}
int RunResponseTimesCommand(const Args& args, std::ostream& out,
                            std::ostream& err) {
  return RunResponseTimes(args, out, err);
}
int RunThresholdsCommand(const Args& args, std::ostream& out,
                         std::ostream& err) {
  return RunThresholds(args, out, err);
}
int RunKinematicsCommand(const Args& args, std::ostream& out,
                         std::ostream& err) {
  return RunKinematics(args, out, err);
}
int RunPowerCommand(const Args& args, std::ostream& out, std::ostream& err) {
  return RunPower(args, out, err);
}
int RunFitObserversCommand(const Args& args, std::ostream& out,
                           std::ostream& err) {
  return RunFitObservers(args, out, err);
}

}  // namespace burrlab::runner
