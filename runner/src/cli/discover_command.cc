// `burrlab discover`: measured CSV -> verdict, effect, gap before and after,
// tests; DIR/report.json, DIR/report.md, DIR/fit.png, DIR/residuals.png.
#include "cli/discover_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <system_error>
#include <thread>
#include <utility>

#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/analysis/model_gap/discover_scenarios.h"
#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/analysis/model_gap/trace_data.h"
#include "burrlab/analysis/model_gap/trace_gap.h"
#include "burrlab/analysis/plot.h"
#include "burrlab/sim/descent.h"
#include "burrlab/sim/effects.h"
#include "burrlab/stimuli/materials.h"
#include "cli/calibrate_command.h"
#include "cli/flags.h"
#include "cli/json_number.h"
#include "studies/progress.h"

namespace burrlab::runner {
namespace {

using Json = nlohmann::ordered_json;

analysis::Series MakeSeries(std::string label, bool line, int colour) {
  analysis::Series s;
  s.label = std::move(label);
  s.line = line;
  s.markers = !line;
  s.colour = colour;
  return s;
}

sim::Effects EffectsOf(const analysis::ModelFit& fit) {
  sim::Effects effects;
  for (std::size_t k = 0; k < fit.effects.size(); ++k) {
    (void)sim::SetEffect(fit.effects[k], fit.effect_values[k], &effects);
  }
  return effects;
}

Json FitJson(const analysis::ModelFit& fit) {
  Json j;
  j["c_e"] = JsonNumber(fit.c_e_n_per_mm2);
  j["alpha"] = JsonNumber(fit.alpha_per_s);
  j["rmse_log_v"] = JsonNumber(fit.rmse_log_v);
  j["aicc"] = JsonNumber(fit.aicc);
  for (std::size_t k = 0; k < fit.effects.size(); ++k) {
    j[std::string(sim::FindEffect(fit.effects[k])->parameter)] =
        JsonNumber(fit.effect_values[k]);
  }
  return j;
}

Json ReportJson(const analysis::DiscoverReport& r) {
  Json j;
  j["verdict"] = analysis::VerdictName(r.verdict);
  j["velocity_definition"] =
      std::string(sim::VelocityDefinitionName(r.velocity_definition));
  j["effect"] = r.effects.empty() ? Json(nullptr) : Json(r.effects[0]);
  j["alias_set"] = r.alias_set;
  j["alias_sets"] = r.alias_sets;
  Json params = Json::object();
  for (std::size_t k = 0; k < r.augmented.effects.size(); ++k) {
    params[std::string(sim::FindEffect(r.augmented.effects[k])->parameter)] =
        JsonNumber(r.augmented.effect_values[k]);
  }
  j["effect_params"] = params;
  j["baseline"] = FitJson(r.baseline);
  j["augmented"] = FitJson(r.augmented);
  j["gap"] = {{"rmse_before", JsonNumber(r.baseline.rmse_log_v)},
              {"rmse_after", JsonNumber(r.augmented.rmse_log_v)},
              {"cv_rmse_before", JsonNumber(r.baseline.cv_rmse_log_v)},
              {"cv_rmse_after", JsonNumber(r.augmented.cv_rmse_log_v)}};
  const auto by_level = [](const std::vector<double>& values) {
    Json a = Json::array();
    for (double v : values) a.push_back(JsonNumber(v));
    return a;
  };
  j["gap"]["cv_rmse_by_level_before"] =
      by_level(r.baseline.cv_level_rmse_log_v);
  j["gap"]["cv_rmse_by_level_after"] =
      by_level(r.augmented.cv_level_rmse_log_v);
  Json tests;
  tests["lack_of_fit_p"] = JsonNumber(r.gap_before.lack_of_fit_p);
  tests["curvature_p"] = JsonNumber(r.gap_before.curvature_p);
  tests["runs_p"] = JsonNumber(r.gap_before.runs_p);
  tests["library_p"] = JsonNumber(r.gap_before.library_p);
  tests["gap_holm_p"] = JsonNumber(r.gap_before.holm_min_p);
  tests["lack_of_fit_p_after"] = JsonNumber(r.gap_after.lack_of_fit_p);
  tests["curvature_p_after"] = JsonNumber(r.gap_after.curvature_p);
  tests["runs_p_after"] = JsonNumber(r.gap_after.runs_p);
  tests["gap_holm_p_after"] = JsonNumber(r.gap_after.holm_min_p);
  Json scores = Json::object();
  if (!r.rounds.empty()) {
    for (const analysis::EffectAttribution& e : r.rounds[0]) {
      scores[e.id] = {{"score_p", JsonNumber(e.score_p)},
                      {"lr_p", JsonNumber(e.lr_p)},
                      {"lr_p_adjusted", JsonNumber(e.lr_p_adjusted)},
                      {"identifiability", JsonNumber(e.identifiability)},
                      {"variant", e.variant},
                      {"shape", e.shape},
                      {"shape_determined", e.shape_determined},
                      {"alike_shapes", e.alike_shapes}};
    }
  }
  tests["effects"] = scores;
  tests["lr_p"] = r.effects.empty() ? Json(nullptr) : JsonNumber(r.lr_p);
  tests["delta_aicc"] = r.effects.empty()
                            ? Json(nullptr)
                            : JsonNumber(r.augmented.aicc - r.baseline.aicc);
  tests["reference_p"] = JsonNumber(r.reference_p);
  tests["reference_effect_p"] = JsonNumber(r.reference_effect_p);
  if (r.trace_gap) {  // the trace-only effects (trace_gap.h)
    Json trace = Json::object();
    for (const analysis::TraceEffectTest& e : r.trace_gap->effects) {
      trace[e.id] = {{"value", JsonNumber(e.value)},
                     {"lr", JsonNumber(e.lr)},
                     {"lr_p", JsonNumber(e.p)},
                     {"lr_p_holm", JsonNumber(e.p_holm)},
                     {"rmse_force_n", JsonNumber(e.rmse_force_n)},
                     {"rmse_depth_mm", JsonNumber(e.rmse_depth_mm)}};
    }
    tests["trace_effects"] = trace;
    tests["trace_rmse_force_n"] = JsonNumber(r.trace_gap->rmse_force_n);
    tests["trace_rmse_depth_mm"] = JsonNumber(r.trace_gap->rmse_depth_mm);
  }
  j["tests"] = tests;
  return j;
}

std::string FormatP(double p) {
  return std::isfinite(p) ? fmt::format("{:.3g}", p) : std::string("n/a");
}

std::string ReportMarkdown(const analysis::DiscoverReport& r,
                           const std::string& measured_path,
                           const analysis::MeasuredData& data,
                           const std::string& reference_name) {
  std::string md = "# burrlab discover\n\n";
  md += fmt::format("Data: `{}`, {} runs at {} force levels.", measured_path,
                    data.runs.size(), data.force_levels);
  md += reference_name.empty()
            ? " No reference material.\n\n"
            : fmt::format(" Reference material: {}.\n\n", reference_name);
  md += fmt::format("**Verdict: {}**", analysis::VerdictName(r.verdict));
  if (!r.effects.empty()) {
    md += fmt::format(" — {}", r.effects[0]);
    for (std::size_t k = 1; k < r.effects.size(); ++k) {
      md += " + " + r.effects[k];
    }
  }
  md += "\n\n" + r.summary + "\n\n";
  for (std::size_t k = 0; k < r.alias_sets.size(); ++k) {
    if (r.alias_sets[k].size() < 2) continue;
    md += r.alias_sets.size() > 1
              ? fmt::format(
                    "Alias set of effect {} (cannot be told apart "
                    "with this design): ",
                    k + 1)
              : std::string(
                    "Alias set (cannot be told apart with this design): ");
    for (const std::string& id : r.alias_sets[k]) md += "`" + id + "` ";
    md += "\n\n";
  }
  md +=
      "## Fits\n\n| model | c_e (N/mm²) | α (1/s) | effect parameters | RMSE "
      "log v | held-out RMSE log v | AICc |\n|---|---|---|---|---|---|---|\n";
  const auto row = [&](const char* name, const analysis::ModelFit& f) {
    std::string params;
    for (std::size_t k = 0; k < f.effects.size(); ++k) {
      const sim::EffectSpec* spec = sim::FindEffect(f.effects[k]);
      params += fmt::format("{}{} = {:.4g} {}", params.empty() ? "" : "; ",
                            spec->parameter, f.effect_values[k], spec->unit);
    }
    md += fmt::format("| {} | {:.4g} | {:.4g} | {} | {:.4g} | {} | {:.4g} |\n",
                      name, f.c_e_n_per_mm2, f.alpha_per_s,
                      params.empty() ? "—" : params, f.rmse_log_v,
                      FormatP(f.cv_rmse_log_v), f.aicc);
  };
  row("base", r.baseline);
  row("augmented", r.augmented);
  md += fmt::format(
      "\n## Gap tests (Holm over the four)\n\n| test | before | after "
      "|\n|---|---|---|\n| lack of fit (pure error) | {} | {} |\n| curvature "
      "(x², x³ of log F, projected) | {} | {} |\n| runs of residual signs by "
      "F | {} | {} |\n| library (best effect's max-T adjusted LR) | {} | — "
      "|\n| smallest Holm-adjusted p | {} | {} |\n",
      FormatP(r.gap_before.lack_of_fit_p), FormatP(r.gap_after.lack_of_fit_p),
      FormatP(r.gap_before.curvature_p), FormatP(r.gap_after.curvature_p),
      FormatP(r.gap_before.runs_p), FormatP(r.gap_after.runs_p),
      FormatP(r.gap_before.library_p), FormatP(r.gap_before.holm_min_p),
      FormatP(r.gap_after.holm_min_p));
  for (std::size_t round = 0; round < r.rounds.size(); ++round) {
    md += fmt::format(
        "\n## Attribution, step {}\n\n| effect | identifiability ι | score "
        "z | score p | LR | LR p (χ̄²) | max-T adjusted | AICc | fitted "
        "parameter "
        "|\n|---|---|---|---|---|---|---|---|---|\n",
        round + 1);
    for (const analysis::EffectAttribution& e : r.rounds[round]) {
      md += fmt::format(
          "| {}{} | {:.3g}{} | {:.3g} | {} | {:.3g} | {} | {} | {} | {:.4g} "
          "|\n",
          e.id,
          e.shape.empty()
              ? std::string()
              : fmt::format(" ({}{})", e.shape,
                            e.shape_determined ? "" : "; shape undetermined"),
          e.identifiability, e.absorbed ? " (absorbed)" : "", e.score_z,
          FormatP(e.score_p), e.lr, FormatP(e.lr_p), FormatP(e.lr_p_adjusted),
          FormatP(e.aicc), e.value);
    }
  }
  if (r.trace_gap) {
    md += fmt::format(
        "\n## Trace-only effects ({} traced runs; lumped rig, c_e {:.4g} "
        "fitted to the traces)\n\nNull trace RMSE: {:.3g} N, {:.3g} mm.\n\n| "
        "effect | fitted parameter | LR | LR p (χ̄²) | Holm | RMSE force N | "
        "RMSE depth mm |\n|---|---|---|---|---|---|---|\n",
        r.trace_gap->runs, r.trace_gap->c_e_n_per_mm2,
        r.trace_gap->rmse_force_n, r.trace_gap->rmse_depth_mm);
    for (const analysis::TraceEffectTest& e : r.trace_gap->effects) {
      md += fmt::format(
          "| {} | {:.4g} {} | {:.3g} | {} | {} | {:.3g} | "
          "{:.3g} |\n",
          e.id, e.value, sim::FindEffect(e.id)->unit, e.lr, FormatP(e.p),
          FormatP(e.p_holm), e.rmse_force_n, e.rmse_depth_mm);
    }
  }
  if (!r.outlier_lines.empty()) {
    md += "\nLeft out as gross outliers (file lines):";
    for (int line : r.outlier_lines) md += fmt::format(" {}", line);
    md += "\n";
  }
  md +=
      "\n## Plots\n\n![data and "
      "models](fit.png)\n\n![residuals](residuals.png)\n";
  return md;
}

Status WritePlots(const analysis::DiscoverReport& r,
                  const analysis::MeasuredData& data, double radius_mm,
                  const std::filesystem::path& dir) {
  std::set<int> outliers(r.outlier_lines.begin(), r.outlier_lines.end());
  analysis::Series measured = MakeSeries("measured", false, 0);
  analysis::Series left_out = MakeSeries("left out (outlier)", false, 3);
  for (const analysis::MeasuredRun& run : data.runs) {
    analysis::Series& s = outliers.count(run.line) ? left_out : measured;
    s.x.push_back(run.force_n);
    s.y.push_back(run.velocity_mm_s);
  }
  double f_lo = data.runs[0].force_n, f_hi = f_lo;
  for (const analysis::MeasuredRun& run : data.runs) {
    f_lo = std::min(f_lo, run.force_n);
    f_hi = std::max(f_hi, run.force_n);
  }
  const auto curve = [&](const analysis::ModelFit& fit, std::string label,
                         int colour) {
    analysis::Series s = MakeSeries(std::move(label), true, colour);
    const sim::Effects effects = EffectsOf(fit);
    const bool initial =
        r.velocity_definition == sim::VelocityDefinition::kInitial;
    // The initial velocity's transient factor costs milliseconds a point.
    const int points = initial ? 60 : 200;
    for (int k = 0; k <= points; ++k) {
      const double f = f_lo + (f_hi - f_lo) * k / points;
      double transient = 1.0;
      if (initial) {
        analysis::DescentSurrogateInput in;
        in.force_n = f;
        in.c_e_n_per_mm2 = fit.c_e_n_per_mm2;
        in.alpha_per_s = fit.alpha_per_s;
        in.radius_mm = radius_mm;
        in.effects = effects;
        transient = analysis::InitialTransientFactor(in);
      }
      s.x.push_back(f);
      s.y.push_back(std::exp(analysis::ModelLogVelocity(
          f, fit.c_e_n_per_mm2, fit.alpha_per_s, radius_mm, effects,
          r.velocity_definition, transient)));
    }
    return s;
  };
  analysis::LinePlot fit_plot;
  fit_plot.title =
      fmt::format("{} penetration velocity: data, base and augmented",
                  sim::VelocityDefinitionName(r.velocity_definition));
  fit_plot.x_label = "force held (N)";
  fit_plot.y_label = "velocity (mm/s)";
  fit_plot.log_y = true;
  fit_plot.series = {measured, curve(r.baseline, "base model", 1)};
  if (!left_out.x.empty()) fit_plot.series.push_back(left_out);
  if (!r.augmented.effects.empty()) {
    std::string label = "augmented:";
    for (const std::string& id : r.augmented.effects) label += " " + id;
    fit_plot.series.push_back(curve(r.augmented, label, 2));
  }
  if (Status s = analysis::WritePlot(fit_plot, (dir / "fit.png").string());
      !s.ok()) {
    return s;
  }
  analysis::LinePlot res;
  res.title = "residuals of log v against force";
  res.x_label = "force held (N)";
  res.y_label = "log v measured - log v model";
  analysis::Series before = MakeSeries("base model", false, 1);
  analysis::Series after = MakeSeries("augmented", false, 2);
  std::size_t used = 0;
  for (const analysis::MeasuredRun& run : data.runs) {
    if (outliers.count(run.line)) continue;
    const double y = std::log(run.velocity_mm_s);
    before.x.push_back(run.force_n);
    before.y.push_back(y - r.baseline.fitted_log_v[used]);
    if (!r.augmented.effects.empty()) {
      after.x.push_back(run.force_n);
      after.y.push_back(y - r.augmented.fitted_log_v[used]);
    }
    ++used;
  }
  res.reference_lines.push_back({false, 0.0, "no residual"});
  res.series = {before};
  if (!after.x.empty()) res.series.push_back(after);
  return analysis::WritePlot(res, (dir / "residuals.png").string());
}

Status WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary);
  file << text;
  file.close();
  if (!file) return Error{fmt::format("cannot write {}", path.string())};
  return {};
}

}  // namespace

int RunDiscoverCommand(const Args& args, std::ostream& out, std::ostream& err) {
  if (!args.empty() && args[0] == "matrix") {
    return RunDiscoverMatrixCommand(Args(args.begin() + 1, args.end()), out,
                                    err);
  }
  CLI::App app{
      "Finds what the base burr model (c_e, alpha) misses in measured steady "
      "penetration velocities: fits the base model, tests for a gap (lack of "
      "fit against the replicates, residual structure against force), "
      "attributes it to a library effect (projected score tests, "
      "identifiability, alias sets, likelihood-ratio tests with Holm's "
      "correction), adds at most two effects one at a time and confirms them "
      "(boundary-aware likelihood ratio, AICc, leave-one-force-level-out "
      "cross-validation, residual tests). Writes DIR/report.json, "
      "DIR/report.md, DIR/fit.png and DIR/residuals.png. 'burrlab discover "
      "matrix' runs the hidden-effect scenario matrix (see its --help).",
      "burrlab discover"};
  std::string measured_path, out_dir, reference_name, traces_path;
  analysis::DiscoverOptions options;
  bool json = false;
  FlagSet flags(&app);
  flags
      .AddText("--measured",
               "measured data, CSV with force_n,velocity_mm_s per run",
               &measured_path)
      ->type_name("FILE.csv")
      ->required();
  flags
      .AddText("--out", "folder for the report (created; not overwritten)",
               &out_dir)
      ->type_name("DIR")
      ->required();
  flags.AddPositive("--radius-mm",
                    "burr radius R, mm (default: the file's burr_radius_mm)",
                    "mm", &options.radius_mm);
  flags
      .AddText("--reference",
               "reference material set (built-in name or file) for absorbed "
               "effects (default: the file's material column when it names "
               "a built-in set)",
               &reference_name)
      ->type_name("MATERIAL");
  flags
      .AddText("--traces",
               "time traces of the runs, CSV run,t_s,force_n,depth_mm (the "
               "run column names the measured runs): tests the trace-only "
               "effects load_cell_lag and arm_compliance",
               &traces_path)
      ->type_name("FILE.csv");
  int definition = -1;
  AddVelocityDefinitionFlag(&flags, &definition);
  flags.AddSwitch("--json", "print report.json to stdout as well", &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  Result<analysis::MeasuredData> data = ReadMeasuredWithRadius(
      measured_path, flags.Given("--radius-mm"), &options.radius_mm,
      VelocityDefinitionChoice(definition), &options.definition);
  if (!data.ok()) {  // multi-line: the data error quotes its line and a caret
    err << "burrlab: " << data.error().message << '\n';
    return 1;
  }
  if (!traces_path.empty()) {
    Result<analysis::TraceData> traces =
        analysis::ReadTracesOfRuns(traces_path, *data);
    if (!traces.ok()) {  // multi-line, as above
      err << "burrlab: " << traces.error().message << '\n';
      return 1;
    }
    options.traces = std::move(*traces);
  }
  // The reference material: the flag, else the material column when every
  // run names the same built-in set.
  if (!reference_name.empty()) {
    Result<stimuli::MaterialSet> set = stimuli::LoadMaterial(reference_name);
    if (!set.ok()) return Fail(err, "--reference: " + set.error().message);
    for (const std::string& note : set->notes) err << note << '\n';
    options.reference = set->material;
  } else if (!data->runs[0].material.empty()) {
    const std::string& name = data->runs[0].material;
    bool same = true;
    for (const analysis::MeasuredRun& run : data->runs) {
      same &= run.material == name;
    }
    for (const std::string& builtin : stimuli::BuiltinMaterialNames()) {
      if (same && builtin == name) {
        Result<stimuli::MaterialSet> set = stimuli::LoadBuiltinMaterial(name);
        if (set.ok()) {
          options.reference = set->material;
          reference_name = name;
        }
      }
    }
  }
  const std::filesystem::path dir(out_dir);
  std::error_code ec;
  if (std::filesystem::exists(dir / "report.json", ec)) {
    return Fail(err, fmt::format("{} already holds a report.json; choose "
                                 "another --out or remove it",
                                 out_dir));
  }
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    return Fail(err, fmt::format("cannot create --out folder {}: {}", out_dir,
                                 ec ? ec.message() : "not a folder"));
  }
  {
    const int steady_effects = static_cast<int>(
        std::count_if(sim::EffectLibrary().begin(), sim::EffectLibrary().end(),
                      [](const sim::EffectSpec& e) { return !e.trace_only; }));
    ProgressBar bar(err, 2 + steady_effects * options.max_effects);
    options.progress = [&bar](int done, int, std::string_view label) {
      bar.Update(done, label);
    };
    Result<analysis::DiscoverReport> report =
        analysis::Discover(*data, options);
    options.progress = nullptr;
    if (!report.ok()) return Fail(err, "discover: " + report.error().message);
    const Json j = ReportJson(*report);
    const std::string text = j.dump(2) + "\n";
    for (const Status& s :
         {WriteText(dir / "report.json", text),
          WriteText(dir / "report.md", ReportMarkdown(*report, measured_path,
                                                      *data, reference_name)),
          WritePlots(*report, *data, options.radius_mm, dir)}) {
      if (!s.ok()) return Fail(err, s.error().message);
    }
    if (json) {
      out << text;
    } else {
      out << fmt::format("verdict   {}\n",
                         analysis::VerdictName(report->verdict));
      if (!report->effects.empty()) {
        out << fmt::format("effect    {}\n", report->effects[0]);
      }
      out << fmt::format(
          "gap       rmse log v {:.4g} -> {:.4g}, held-out {} -> {}\n",
          report->baseline.rmse_log_v, report->augmented.rmse_log_v,
          FormatP(report->baseline.cv_rmse_log_v),
          FormatP(report->augmented.cv_rmse_log_v));
      out << report->summary << '\n';
      out << fmt::format("report    {}\n", (dir / "report.md").string());
    }
  }
  return 0;
}

int RunDiscoverMatrixCommand(const Args& args, std::ostream& out,
                             std::ostream& err) {
  CLI::App app{
      "The scenario matrix of the model-gap workflow: each library effect "
      "hidden at graded projected SNRs, a null control, porosity, a mid-force "
      "bump and 5 % gross outliers, on a material at loads 0.5-1.5 (6 levels x "
      "4 replicates, CV 10 %, R = 1 mm). Prints a Markdown table of hit rates "
      "(right id or an alias set holding it) and the null's false-discovery "
      "rate.",
      "burrlab discover matrix"};
  std::string material_name = "human_temporal_bone", snr_text = "2,3,4,5,6,8";
  int seeds = 20, null_seeds = 100;
  int jobs =
      static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  bool full_rig = false;
  FlagSet flags(&app);
  flags
      .AddText("--material", "built-in material set of the truth",
               &material_name)
      ->type_name("NAME");
  flags.AddText("--snr", "projected SNRs, comma-separated", &snr_text)
      ->type_name("S1,S2,...");
  flags.AddInteger("--seeds", "seeds per effect and SNR", 1, 100000, &seeds);
  flags.AddInteger("--null-seeds", "seeds of the null control", 1, 100000,
                   &null_seeds);
  flags.AddSwitch("--full-rig",
                  "truth from the full descent rig (slow: 5-60 s per force "
                  "level) instead of the continuum surrogate",
                  &full_rig);
  flags.AddInteger("--jobs",
                   "threads sharing each cell's seeds, and with --full-rig "
                   "the rig's force levels (default: the core count; the "
                   "table is the same for any number)",
                   1, 256, &jobs);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  std::vector<double> snrs;
  for (std::size_t start = 0; start <= snr_text.size();) {
    const std::size_t comma =
        std::min(snr_text.find(',', start), snr_text.size());
    try {
      std::size_t used = 0;
      const std::string item = snr_text.substr(start, comma - start);
      const double snr = std::stod(item, &used);
      if (used != item.size() || !(snr > 0.0) || !std::isfinite(snr)) {
        throw std::invalid_argument(item);
      }
      snrs.push_back(snr);
    } catch (const std::exception&) {
      return Fail(err, fmt::format("--snr must be positive numbers "
                                   "separated by commas, got '{}'",
                                   snr_text));
    }
    start = comma + 1;
  }
  Result<stimuli::MaterialSet> set =
      stimuli::LoadBuiltinMaterial(material_name);
  if (!set.ok()) return Fail(err, set.error().message);
  analysis::ScenarioDesign design;
  design.material_name = set->name;
  design.material = set->material;
  design.full_rig = full_rig;
  analysis::DiscoverOptions options;
  options.radius_mm = design.radius_mm;
  options.reference = design.material;
  const std::vector<std::string> ids = {
      "motor_power_limit",  "spindle_slowdown", "cutting_threshold",
      "viscous_resistance", "friction_erosion", "contact_exponent"};
  ProgressBar bar(err, static_cast<int>(ids.size() * snrs.size()) + 4);
  int done = 0;
  const auto run =
      [&](const sim::Effects& fx, const analysis::Distortion& distortion,
          const std::string& expected, int count,
          const std::string& label) -> Result<analysis::ScenarioOutcome> {
    bar.Update(done++, label);
    Result<std::vector<double>> truth =
        analysis::TruthVelocitiesMmS(design, fx, jobs);
    if (!truth.ok()) return truth.error();
    return analysis::RunScenario(design, *truth, distortion, expected, 1, count,
                                 options, jobs);
  };
  std::string table = "| effect |";
  std::string rule = "|---|";
  for (double snr : snrs) {
    table += fmt::format(" SNR {:g} |", snr);
    rule += "---|";
  }
  table += " held-out RMSE log v before → after (SNR " +
           fmt::format("{:g}", snrs.back()) + ") |\n" + rule + "---|\n";
  for (const std::string& id : ids) {
    table += "| `" + id + "` |";
    analysis::ScenarioOutcome last;
    for (double snr : snrs) {
      Result<sim::Effects> fx = analysis::EffectAtSnr(design, id, snr);
      if (!fx.ok()) {
        table += " n/a |";
        continue;
      }
      Result<analysis::ScenarioOutcome> o =
          run(*fx, {}, id, seeds, fmt::format("{} at SNR {:g}", id, snr));
      if (!o.ok()) return Fail(err, o.error().message);
      table +=
          fmt::format(" {:.2f} |", static_cast<double>(o->hits) / o->seeds);
      last = *o;
    }
    table += fmt::format(" {:.3f} → {:.3f} |\n", last.mean_cv_before,
                         last.mean_cv_after);
  }
  const auto count = [](const analysis::ScenarioOutcome& o,
                        analysis::Verdict verdict) {
    const auto it = o.verdicts.find(verdict);
    return it == o.verdicts.end() ? 0 : it->second;
  };
  Result<analysis::ScenarioOutcome> null =
      run({}, {}, "", null_seeds, "null control");
  if (!null.ok()) return Fail(err, null.error().message);
  sim::Effects porous;
  porous.porosity = 0.2;
  Result<analysis::ScenarioOutcome> absorbed =
      run(porous, {}, "porosity", seeds, "porosity 0.2");
  if (!absorbed.ok()) return Fail(err, absorbed.error().message);
  analysis::Distortion bump;
  bump.bump_log_v = 0.35;
  Result<analysis::ScenarioOutcome> outside =
      run({}, bump, "", seeds, "bump in log v");
  if (!outside.ok()) return Fail(err, outside.error().message);
  analysis::Distortion outliers;
  outliers.outlier_fraction = 0.05;
  Result<analysis::ScenarioOutcome> gross =
      run({}, outliers, "", seeds, "5 % outliers");
  if (!gross.ok()) return Fail(err, gross.error().message);
  // Names a control adds beyond the null's own chance shapes: seeds where
  // it names an effect and the null, on the same seed's noise, does not.
  table += fmt::format(
      "\n| control | seeds | none | named or ambiguous | named where the "
      "null's same seed is not | absorbed | unexplained |\n"
      "|---|---|---|---|---|---|---|\n");
  for (const auto& [name, outcome] :
       std::vector<std::pair<std::string, const analysis::ScenarioOutcome*>>{
           {"no effect (false-discovery rate = named or ambiguous)", &*null},
           {"porosity 0.2 (c_e x 0.64)", &*absorbed},
           {"bump of 0.35 in log v at mid force", &*outside},
           {"5 % gross outliers (x3 or /3), no effect", &*gross}}) {
    const analysis::ScenarioOutcome& o = *outcome;
    const bool is_null = outcome == &*null;
    table += fmt::format(
        "| {} | {} | {:.2f} | {:.2f} | {} | {:.2f} | {:.2f} |\n", name, o.seeds,
        static_cast<double>(count(o, analysis::Verdict::kNone)) / o.seeds,
        static_cast<double>(o.named_physical) / o.seeds,
        is_null ? std::string("—")
                : fmt::format("{:.2f}",
                              static_cast<double>(
                                  analysis::NamedBeyond(o, *null).size()) /
                                  o.seeds),
        static_cast<double>(count(o, analysis::Verdict::kAbsorbed)) / o.seeds,
        static_cast<double>(count(o, analysis::Verdict::kUnexplained)) /
            o.seeds);
  }
  out << fmt::format(
      "truth: {} ({}), loads {} of c_e R^2, {} replicates, CV {:g}, {} seeds "
      "per cell, {} null seeds\n\n",
      design.material_name, full_rig ? "full rig" : "surrogate",
      "0.5-1.5 (6 levels)", design.replicates, design.noise_cv, seeds,
      null_seeds);
  out << table;
  return 0;
}

}  // namespace burrlab::runner
