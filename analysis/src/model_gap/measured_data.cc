// The measured-data CSV of the calibration workflow, with a diagnostic naming
// the line and column of the first problem.
#include "burrlab/analysis/model_gap/measured_data.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "burrlab/analysis/psychometric_data.h"
#include "csv_text.h"

namespace burrlab::analysis {

Result<MeasuredData> ParseMeasuredData(std::string_view path,
                                       std::string_view text) {
  Result<CsvTable> table =
      CsvTable::Split(path, text, CsvTable::Delimiter::kComma,
                      "the file is empty; expected a header line with the "
                      "columns force_n,velocity_mm_s");
  if (!table.ok()) return table.error();
  const auto fail = [&](int line, int column, const std::string& message) {
    return table->Fail(line, column, message);
  };
  const auto find = [&](std::string_view name) { return table->Find(name); };
  const Line& header_line = table->header_line();
  if (Status distinct = table->CheckDistinctColumns(); !distinct.ok()) {
    return distinct.error();
  }
  const int force_at = find("force_n"), velocity_at = find("velocity_mm_s");
  if (force_at < 0 || velocity_at < 0) {
    return fail(header_line.number, 1,
                fmt::format("the header has no {} column; measured data need "
                            "the columns force_n and velocity_mm_s "
                            "(comma-separated)",
                            force_at < 0 ? "force_n" : "velocity_mm_s"));
  }
  const int run_at = find("run"), material_at = find("material"),
            radius_at = find("burr_radius_mm"),
            spindle_at = find("spindle_rad_s"),
            definition_at = find("velocity_definition");
  MeasuredData data;
  int radius_line = 0, spindle_line = 0;
  std::set<double> levels;
  for (const Line& line : table->rows()) {
    Result<std::vector<Cell>> row = table->Cells(line);
    if (!row.ok()) return row.error();
    const std::vector<Cell>& cells = *row;
    const auto cell = [&](int k) { return cells[static_cast<std::size_t>(k)]; };
    MeasuredRun run;
    run.line = line.number;
    const Cell force = cell(force_at), velocity = cell(velocity_at);
    const std::optional<double> f = ParseFinite(force.text);
    if (!f || *f <= 0.0) {
      return fail(line.number, force.column,
                  fmt::format("force_n '{}' is not a positive finite number "
                              "of N",
                              force.text));
    }
    const std::optional<double> v = ParseFinite(velocity.text);
    if (!v || *v <= 0.0) {
      return fail(line.number, velocity.column,
                  fmt::format("velocity_mm_s '{}' is not a positive finite "
                              "number of mm/s (the fit is on log v; leave out "
                              "runs that did not cut)",
                              velocity.text));
    }
    run.force_n = *f;
    run.velocity_mm_s = *v;
    if (run_at >= 0) run.run = std::string(cell(run_at).text);
    if (material_at >= 0) run.material = std::string(cell(material_at).text);
    if (radius_at >= 0) {
      const Cell c = cell(radius_at);
      const std::optional<double> r = ParseFinite(c.text);
      if (!r || *r <= 0.0) {
        return fail(line.number, c.column,
                    fmt::format("burr_radius_mm '{}' is not a positive finite "
                                "number of mm",
                                c.text));
      }
      if (data.burr_radius_mm && *data.burr_radius_mm != *r) {
        return fail(line.number, c.column,
                    fmt::format("burr_radius_mm {} differs from {} on line {}; "
                                "calibrate one burr at a time",
                                *r, *data.burr_radius_mm, radius_line));
      }
      data.burr_radius_mm = *r;
      radius_line = line.number;
    }
    if (spindle_at >= 0) {
      const Cell c = cell(spindle_at);
      const std::optional<double> w = ParseFinite(c.text);
      if (!w || *w < 0.0) {
        return fail(line.number, c.column,
                    fmt::format("spindle_rad_s '{}' is not a finite number of "
                                "at least 0 rad/s",
                                c.text));
      }
      if (data.spindle_rad_s && *data.spindle_rad_s != *w) {
        return fail(line.number, c.column,
                    fmt::format("spindle_rad_s {} differs from {} on line {}; "
                                "calibrate one spindle speed at a time",
                                *w, *data.spindle_rad_s, spindle_line));
      }
      data.spindle_rad_s = *w;
      spindle_line = line.number;
    }
    if (definition_at >= 0) {
      const Cell c = cell(definition_at);
      const std::optional<sim::VelocityDefinition> d =
          sim::ParseVelocityDefinition(c.text);
      if (!d) {
        return fail(line.number, c.column,
                    fmt::format("velocity_definition '{}' is not one of "
                                "initial, settled",
                                c.text));
      }
      if (data.velocity_definition && *data.velocity_definition != *d) {
        return fail(
            line.number, c.column,
            fmt::format("velocity_definition {} differs from {} on line {}; "
                        "one file holds one kind of velocity",
                        c.text,
                        sim::VelocityDefinitionName(*data.velocity_definition),
                        data.velocity_definition_line));
      }
      if (!data.velocity_definition)
        data.velocity_definition_line = line.number;
      data.velocity_definition = *d;
    }
    levels.insert(run.force_n);
    data.runs.push_back(std::move(run));
  }
  data.force_levels = static_cast<int>(levels.size());
  const int runs = static_cast<int>(data.runs.size());
  if (runs == 0) return fail(0, 0, "no data rows after the header");
  if (runs <= kCalibrationParameters) {
    return fail(
        0, 0,
        fmt::format("only {} run{}: fitting c_e and alpha needs more "
                    "runs than parameters (at least {})",
                    runs, runs == 1 ? "" : "s", kCalibrationParameters + 1));
  }
  if (data.force_levels < 2) {
    return fail(0, 0,
                fmt::format("all {} runs are at one force level ({} N); v(F) "
                            "needs at least 2 force levels",
                            runs, data.runs.front().force_n));
  }
  return data;
}

Status CheckVelocityDefinition(std::string_view path, const MeasuredData& data,
                               sim::VelocityDefinition model) {
  if (!data.velocity_definition || *data.velocity_definition == model) {
    return {};
  }
  return Error{fmt::format(
      "{}:{}: error: the measured velocities are {} velocities "
      "(velocity_definition column) but the model predicts {} velocities; "
      "the two are different quantities (the initial one is taken "
      "before the density in the burr has settled)",
      path, data.velocity_definition_line,
      sim::VelocityDefinitionName(*data.velocity_definition),
      sim::VelocityDefinitionName(model))};
}

Result<MeasuredData> ReadMeasuredData(const std::string& path) {
  Result<std::string> text = ReadTextFile(path);
  if (!text.ok()) return text.error();
  return ParseMeasuredData(path, *text);
}

}  // namespace burrlab::analysis
