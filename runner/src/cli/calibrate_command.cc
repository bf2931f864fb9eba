// `burrlab calibrate`: measured CSV -> c_e, alpha, intervals, identifiability.
#include "cli/calibrate_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "burrlab/analysis/model_gap/calibration.h"
#include "burrlab/analysis/model_gap/measured_data.h"
#include "cli/flags.h"

namespace burrlab::runner {
namespace {

nlohmann::ordered_json IntervalJson(
    const std::optional<analysis::Interval>& ci) {
  return ci ? nlohmann::ordered_json::array({(*ci)[0], (*ci)[1]})
            : nlohmann::ordered_json(nullptr);
}

std::string IntervalText(const std::optional<analysis::Interval>& ci) {
  return ci ? fmt::format("[{:.4g}, {:.4g}]", (*ci)[0], (*ci)[1])
            : std::string("not identifiable");
}

}  // namespace

void AddVelocityDefinitionFlag(FlagSet* flags, int* choice) {
  *choice = -1;
  flags->AddChoice(
      "--velocity-definition",
      fmt::format("what the measured velocities are (default: the file's "
                  "velocity_definition column, else {}): {}",
                  sim::VelocityDefinitionName(sim::kDefaultVelocityDefinition),
                  sim::VelocityDefinitionHelp()),
      {"initial", "settled"}, choice);
}

std::optional<sim::VelocityDefinition> VelocityDefinitionChoice(int choice) {
  if (choice < 0) return std::nullopt;
  return choice == 0 ? sim::VelocityDefinition::kInitial
                     : sim::VelocityDefinition::kSettled;
}

Result<analysis::MeasuredData> ReadMeasuredWithRadius(
    const std::string& path, bool radius_given, double* radius_mm,
    std::optional<sim::VelocityDefinition> flag_definition,
    sim::VelocityDefinition* definition) {
  Result<analysis::MeasuredData> read = analysis::ReadMeasuredData(path);
  if (!read.ok()) return read.error();
  const analysis::MeasuredData& data = *read;
  if (flag_definition) {
    if (Status s =
            analysis::CheckVelocityDefinition(path, data, *flag_definition);
        !s.ok()) {
      return Error{fmt::format(
          "{}; --velocity-definition {} asked for the latter (leave the flag "
          "out to fit the file's own kind)",
          s.error().message, sim::VelocityDefinitionName(*flag_definition))};
    }
    *definition = *flag_definition;
  } else {
    *definition =
        data.velocity_definition.value_or(sim::kDefaultVelocityDefinition);
  }
  if (radius_given) {
    if (data.burr_radius_mm && *data.burr_radius_mm != *radius_mm) {
      return Error{
          fmt::format("--radius-mm {} differs from burr_radius_mm {} in {}",
                      *radius_mm, *data.burr_radius_mm, path)};
    }
  } else if (data.burr_radius_mm) {
    *radius_mm = *data.burr_radius_mm;
  } else {
    return Error{fmt::format(
        "no burr radius: give --radius-mm R or a burr_radius_mm column in {}",
        path)};
  }
  return read;
}

int RunCalibrateCommand(const Args& args, std::ostream& out,
                        std::ostream& err) {
  CLI::App app{
      "Fits the elastic constant c_e (N/mm^2) and the erosion constant alpha "
      "(1/s) to measured steady penetration velocities of a constant-force "
      "descent (dissertation §8.6-8.7): least squares on log v through a "
      "steady-state surrogate of the virtual rig, identifiability checked by "
      "the SVD of the Jacobian and the profile likelihood, profile-likelihood "
      "intervals. The data format is in analysis/README.md.",
      "burrlab calibrate"};
  std::string measured_path;
  analysis::CalibrationOptions options;
  bool json = false;
  FlagSet flags(&app);
  flags
      .AddText("--measured",
               "measured data, CSV with force_n,velocity_mm_s per run",
               &measured_path)
      ->type_name("FILE.csv")
      ->required();
  flags.AddPositive("--radius-mm",
                    "burr radius R, mm (default: the file's burr_radius_mm)",
                    "mm", &options.radius_mm);
  int definition = -1;
  AddVelocityDefinitionFlag(&flags, &definition);
  flags.AddSwitch("--json", "print the results as JSON", &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  Result<analysis::MeasuredData> data = ReadMeasuredWithRadius(
      measured_path, flags.Given("--radius-mm"), &options.radius_mm,
      VelocityDefinitionChoice(definition), &options.definition);
  if (!data.ok()) {  // multi-line: the data error quotes its line and a caret
    err << "burrlab: " << data.error().message << '\n';
    return 1;
  }
  Result<analysis::CalibrationSummary> fit =
      analysis::Calibrate(*data, options);
  if (!fit.ok()) return Fail(err, "calibrate: " + fit.error().message);
  const analysis::CalibrationSummary& r = *fit;
  if (json) {
    nlohmann::ordered_json j;
    j["c_e"] = r.c_e_n_per_mm2;
    j["alpha"] = r.alpha_per_s;
    j["ci"] = {{"c_e", IntervalJson(r.c_e_ci)},
               {"alpha", IntervalJson(r.alpha_ci)}};
    j["identifiable"] = {
        {"both", r.identifiable},
        {"sentence", r.identifiability},
        {"combination",
         {{"expression", analysis::CombinationName(r.combination_exponent)},
          {"exponent", r.combination_exponent},
          {"value", r.combination_value},
          {"ci", IntervalJson(r.combination_ci)}}}};
    if (r.second_minimum) {
      const analysis::SecondMinimum& m = *r.second_minimum;
      j["second_minimum"] = {{"c_e", m.c_e_n_per_mm2},
                             {"alpha", m.alpha_per_s},
                             {"rss_log_v", m.rss_log_v},
                             {"ci_c_e", IntervalJson(m.c_e_ci)}};
    } else {
      j["second_minimum"] = nullptr;
    }
    j["rss_log_v"] = r.rss_log_v;
    j["rmse_log_v"] = r.rmse_log_v;
    j["sigma_log_v"] = r.sigma_log_v;
    j["jacobian_singular_values"] = r.singular_values;
    j["condition_number"] = r.condition_number;
    j["confidence"] = options.confidence;
    j["radius_mm"] = options.radius_mm;
    j["velocity_definition"] = sim::VelocityDefinitionName(options.definition);
    j["runs"] = r.runs;
    j["force_levels"] = r.force_levels;
    j["units"] = {{"c_e", "N/mm^2"}, {"alpha", "1/s"}};
    out << j.dump(2) << '\n';
    return 0;
  }
  out << fmt::format(
      "data             {} runs at {} force levels, R = {} mm, {} velocity\n",
      r.runs, r.force_levels, options.radius_mm,
      sim::VelocityDefinitionName(options.definition));
  out << fmt::format("c_e              {:.4g} N/mm^2  95 % {}\n",
                     r.c_e_n_per_mm2, IntervalText(r.c_e_ci));
  out << fmt::format("alpha            {:.4g} 1/s     95 % {}\n", r.alpha_per_s,
                     IntervalText(r.alpha_ci));
  out << fmt::format("rmse log v       {:.4g}\n", r.rmse_log_v);
  out << fmt::format("identifiability  {}\n", r.identifiability);
  if (r.second_minimum) {
    const analysis::SecondMinimum& m = *r.second_minimum;
    out << fmt::format(
        "second minimum   c_e {:.4g} N/mm^2, alpha {:.4g} 1/s: RSS of log v "
        "{:.4g} against {:.4g} at the fit, {}; the data do not decide between "
        "the two (forces nearer the full-immersion force c_e R^2 2^(3/2) or "
        "an indentation (probe) measurement would).\n",
        m.c_e_n_per_mm2, m.alpha_per_s, m.rss_log_v, r.rss_log_v,
        m.c_e_ci
            ? "its own part of the 95 % set of c_e is " + IntervalText(m.c_e_ci)
            : std::string("inside the 95 % interval of c_e"));
  }
  return 0;
}

}  // namespace burrlab::runner
