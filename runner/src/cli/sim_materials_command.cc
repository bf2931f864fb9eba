// `burrlab sim materials`: force-depth curves and constant-force descents of
// the three built-in materials, and whether the descents keep the order the
// dissertation measured (§8.7: PVC faster than Pettigrew faster than bone).
#include "cli/sim_materials_command.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <future>
#include <string>
#include <vector>

#include "burrlab/analysis/plot.h"
#include "burrlab/sim/descent.h"
#include "burrlab/sim/force_curve.h"
#include "burrlab/stimuli/materials.h"
#include "cli/flags.h"
#include "studies/progress.h"

namespace burrlab::runner {
namespace {

constexpr double kRadiusMm = 3.0;
constexpr int kCurvePoints = 10;  // depths 0.1 R, 0.2 R, ..., R
constexpr std::array<double, 3> kForcesN = {3.0, 4.0, 6.0};
// Fastest first: the order the initial velocities should keep.
constexpr std::array<std::string_view, 3> kMaterials = {
    "pvc_k70", "pettigrew_temporal_bone", "human_temporal_bone"};

std::string Label(const stimuli::MaterialSet& set) {
  return set.display_name.empty() ? set.name : set.display_name;
}

void PrintMaterials(const std::vector<stimuli::MaterialSet>& sets,
                    std::ostream& out) {
  std::size_t width = 0;
  for (const stimuli::MaterialSet& set : sets) {
    width = std::max(width, set.name.size());
  }
  out << "Built-in materials (dissertation §8.7; --material NAME):\n";
  for (const stimuli::MaterialSet& set : sets) {
    out << fmt::format("  {:<{}}  c_e {:>5} N/mm^2  alpha {:>5} 1/s  {}\n",
                       set.name, width, set.material.c_e_n_per_mm2,
                       set.material.alpha_per_s, Label(set));
  }
}

void PrintForceCurves(
    const std::vector<stimuli::MaterialSet>& sets,
    const std::vector<std::vector<sim::ForceCurvePoint>>& curves,
    const sim::ForceCurveOptions& options, std::ostream& out) {
  out << fmt::format(
      "\nForce-depth curves, R = {} mm, voxel {} mm, octree moments "
      "(F = c_e R^2 (h/R)^1.5, eq. 7.3):\n\n",
      options.radius_mm, options.voxel_mm);
  constexpr int kDepthWidth = 8, kHWidth = 6, kForceWidth = 7, kGap = 4;
  std::vector<int> group_widths;
  std::string groups = fmt::format("{:<{}}", "", kDepthWidth);
  std::string columns = fmt::format("{:>{}}", "depth mm", kDepthWidth);
  for (const stimuli::MaterialSet& set : sets) {
    const int width = std::max(static_cast<int>(Label(set).size()),
                               kHWidth + 2 + kForceWidth);
    group_widths.push_back(width);
    groups += fmt::format("{:{}}{:>{}}", "", kGap, Label(set), width);
    columns += fmt::format("{:{}}{:>{}}  {:>{}}", "", kGap, "h mm",
                           width - kForceWidth - 2, "force N", kForceWidth);
  }
  out << groups << '\n' << columns << '\n';
  for (std::size_t row = 0; row < curves.front().size(); ++row) {
    std::string line =
        fmt::format("{:>{}.2f}", curves.front()[row].depth_mm, kDepthWidth);
    for (std::size_t m = 0; m < curves.size(); ++m) {
      const sim::ForceCurvePoint& point = curves[m][row];
      line += fmt::format("{:{}}{:>{}.3f}  {:>{}.3f}", "", kGap, point.h_mm,
                          group_widths[m] - kForceWidth - 2, point.force_n,
                          kForceWidth);
    }
    out << line << '\n';
  }
}

// results[m][f]: the descent of material m (table order) at kForcesN[f].
using DescentTable =
    std::vector<std::array<sim::DescentResult, kForcesN.size()>>;

void PrintDescents(const std::vector<stimuli::MaterialSet>& sets,
                   const DescentTable& table,
                   const sim::DescentOptions& options, std::ostream& out) {
  out << fmt::format(
      "\nConstant-force descents, R = {} mm, {} rad/s, voxel {:.4g} mm: "
      "initial velocity (§8.6), mm/s\n\n",
      options.radius_mm, options.spindle_rad_s, options.VoxelMm());
  std::size_t width = std::string_view("material").size();
  for (const stimuli::MaterialSet& set : sets) {
    width = std::max(width, Label(set).size());
  }
  std::string header = fmt::format("{:<{}}", "material", width);
  for (double force_n : kForcesN) {
    header += fmt::format("  {:>8}", fmt::format("{} N", force_n));
  }
  out << header << '\n';
  for (std::size_t m = 0; m < sets.size(); ++m) {
    std::string line = fmt::format("{:<{}}", Label(sets[m]), width);
    for (const sim::DescentResult& result : table[m]) {
      line += result.velocity_mm_s
                  ? fmt::format("  {:>8.4f}", *result.velocity_mm_s)
                  : fmt::format("  {:>8}", "n/a");
    }
    out << line << '\n';
  }
  bool any_missing = false;
  for (const auto& row : table) {
    for (const sim::DescentResult& result : row) {
      any_missing = any_missing || !result.velocity_mm_s;
    }
  }
  if (any_missing) {
    out << fmt::format(
        "n/a: the burr did not cut R/3 after the impact transient within {} "
        "s\n",
        options.DurationS());
  }
  out << '\n';
  // sets are in table order (bone, Pettigrew, PVC): the order holds when each
  // velocity exceeds the one before it.
  for (std::size_t f = 0; f < kForcesN.size(); ++f) {
    std::string values, missing;
    bool holds = true;
    for (std::size_t m = sets.size(); m-- > 0;) {
      const sim::DescentResult& result = table[m][f];
      if (!result.velocity_mm_s) {
        missing += (missing.empty() ? "" : ", ") + Label(sets[m]);
      }
      values += fmt::format("{}{:.4f}", values.empty() ? "" : ", ",
                            result.velocity_mm_s.value_or(0.0));
      if (m > 0) {
        holds = holds && result.velocity_mm_s.value_or(0.0) >
                             table[m - 1][f].velocity_mm_s.value_or(0.0);
      }
    }
    const std::string at = fmt::format("at {} N:", kForcesN[f]);
    if (!missing.empty()) {
      out << fmt::format(
          "{:<8} cannot tell whether PVC > Pettigrew > bone: no initial "
          "descent for {}\n",
          at, missing);
    } else {
      out << fmt::format("{:<8} PVC > Pettigrew > bone {} ({} mm/s)\n", at,
                         holds ? "holds" : "does NOT hold", values);
    }
  }
}

// The demo's figures: force-depth curves with the closed form of eq. 7.3, the
// depth-time traces of the descents at the middle force (fig. 8.6), and initial
// velocity against force (figs. 8.7-8.9).
Result<std::vector<std::string>> WritePlots(
    const std::vector<stimuli::MaterialSet>& sets,
    const std::vector<std::vector<sim::ForceCurvePoint>>& curves,
    const DescentTable& table, const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    return Error{
        fmt::format("cannot create folder {}: {}", dir, error.message())};
  }
  std::vector<std::string> written;
  const auto write = [&](const analysis::LinePlot& plot,
                         const std::string& name) -> Status {
    const std::string path = (std::filesystem::path(dir) / name).string();
    if (Status s = analysis::WritePlot(plot, path); !s.ok()) return s;
    written.push_back(path);
    return {};
  };

  analysis::LinePlot force;
  force.title = fmt::format(
      "Force against depth, R = {} mm (points: simulator; lines: c_e R^2 "
      "(h/R)^1.5)",
      kRadiusMm);
  force.x_label = "immersion depth (mm)";
  force.y_label = "elastic force (N)";
  for (std::size_t m = 0; m < sets.size(); ++m) {
    const int colour = static_cast<int>(m);
    analysis::Series points{Label(sets[m]), {}, {}, false, true, colour};
    analysis::Series closed{"", {}, {}, true, false, colour};
    for (int i = 0; i <= 60; ++i) {
      const double depth = kRadiusMm * i / 60.0;
      closed.x.push_back(depth);
      closed.y.push_back(sets[m].material.c_e_n_per_mm2 * kRadiusMm *
                         kRadiusMm * std::pow(depth / kRadiusMm, 1.5));
    }
    for (const sim::ForceCurvePoint& p : curves[m]) {
      points.x.push_back(p.depth_mm);
      points.y.push_back(p.force_n);
    }
    force.series.push_back(std::move(points));
    force.series.push_back(std::move(closed));
  }
  if (Status s = write(force, "force_depth.png"); !s.ok()) return s.error();

  analysis::LinePlot depth;
  const std::size_t middle = kForcesN.size() / 2;
  depth.title = fmt::format(
      "Constant-force descent at {} N, R = {} mm: depth below the surface",
      kForcesN[middle], kRadiusMm);
  depth.x_label = "time (s)";
  depth.y_label = "depth (mm)";
  for (std::size_t m = 0; m < sets.size(); ++m) {
    analysis::Series trace{Label(sets[m]), {}, {}, true, false};
    for (const sim::DescentSample& sample : table[m][middle].trace) {
      trace.x.push_back(sample.t_s);
      trace.y.push_back(sample.depth_mm);
    }
    depth.series.push_back(std::move(trace));
  }
  if (Status s = write(depth, "descent_depth.png"); !s.ok()) return s.error();

  analysis::LinePlot velocity;
  velocity.title = fmt::format(
      "Initial penetration velocity (§8.6) against force, R = {} mm",
      kRadiusMm);
  velocity.x_label = "force (N)";
  velocity.y_label = "initial velocity (mm/s, log scale)";
  velocity.log_y = true;
  for (std::size_t m = 0; m < sets.size(); ++m) {
    analysis::Series series{Label(sets[m]), {}, {}, true, true};
    for (std::size_t f = 0; f < kForcesN.size(); ++f) {
      if (!table[m][f].velocity_mm_s) continue;
      series.x.push_back(kForcesN[f]);
      series.y.push_back(*table[m][f].velocity_mm_s);
    }
    velocity.series.push_back(std::move(series));
  }
  if (Status s = write(velocity, "descent_velocity.png"); !s.ok()) {
    return s.error();
  }
  return written;
}

}  // namespace

int RunSimMaterialsCommand(const Args& args, std::ostream& out,
                           std::ostream& err) {
  CLI::App app{
      "The burr simulator on the three built-in materials: force-depth "
      "curves at R = 3 mm, then constant-force descents at 3, 4 and 6 N and "
      "whether their initial velocities keep the order PVC > Pettigrew > "
      "bone (dissertation §8.7).",
      "burrlab sim materials"};
  std::string plots_dir;
  FlagSet flags(&app);
  flags
      .AddText("--plots",
               "folder for PNG figures: force_depth.png, descent_depth.png, "
               "descent_velocity.png (created if missing; files replaced)",
               &plots_dir)
      ->type_name("DIR");
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  if (flags.Given("--plots") && plots_dir.empty()) {
    return Fail(err, "--plots needs a folder name, got ''");
  }

  // Loaded in table order: bone, Pettigrew, PVC.
  std::vector<stimuli::MaterialSet> sets;
  for (auto it = kMaterials.rbegin(); it != kMaterials.rend(); ++it) {
    Result<stimuli::MaterialSet> set = stimuli::LoadBuiltinMaterial(*it);
    if (!set.ok()) return Fail(err, set.error().message);
    sets.push_back(std::move(*set));
  }
  const int tasks = static_cast<int>(sets.size() * (1 + kForcesN.size()));
  int done = 0;
  ProgressBar progress(err, tasks);

  sim::ForceCurveOptions curve_options;
  curve_options.radius_mm = kRadiusMm;
  curve_options.points = kCurvePoints;
  curve_options.max_depth_mm = kRadiusMm;
  std::vector<std::vector<sim::ForceCurvePoint>> curves;
  for (const stimuli::MaterialSet& set : sets) {
    progress.Update(done, fmt::format("force curve: {}", set.name));
    curve_options.c_e_n_per_mm2 = set.material.c_e_n_per_mm2;
    Result<std::vector<sim::ForceCurvePoint>> curve =
        sim::ComputeForceCurve(curve_options);
    if (!curve.ok()) {
      return Fail(err, fmt::format("demo: force curve of {}: {}", set.name,
                                   curve.error().message));
    }
    if (curve->size() != static_cast<std::size_t>(kCurvePoints)) {
      return Fail(err, fmt::format("demo: force curve of {} has {} points, "
                                   "expected {}",
                                   set.name, curve->size(), kCurvePoints));
    }
    curves.push_back(std::move(*curve));
    ++done;
  }

  // The nine descents are independent and deterministic (each has its own
  // seeded stream), so they run in parallel; results are read in order.
  sim::DescentOptions descent_options;
  descent_options.radius_mm = kRadiusMm;
  descent_options.definition = sim::VelocityDefinition::kInitial;
  // One voxel size for the table (the rig's coarsest): the order of the
  // materials is what is shown, and bone at 3 N (load 0.16) would otherwise
  // take R/35 and minutes; its velocity reads about 6 % low here.
  descent_options.voxel_mm = kRadiusMm / sim::kRigVoxelsPerRadius;
  std::vector<std::future<Result<sim::DescentResult>>> futures;
  for (const stimuli::MaterialSet& set : sets) {
    for (double force_n : kForcesN) {
      sim::DescentOptions options = descent_options;
      options.material = set.material;
      options.force_n = force_n;
      futures.push_back(std::async(
          std::launch::async, [options] { return sim::RunDescent(options); }));
    }
  }
  DescentTable table(sets.size());
  for (std::size_t m = 0; m < sets.size(); ++m) {
    for (std::size_t f = 0; f < kForcesN.size(); ++f) {
      progress.Update(
          done, fmt::format("descent: {} at {} N", sets[m].name, kForcesN[f]));
      Result<sim::DescentResult> result =
          futures[m * kForcesN.size() + f].get();
      if (!result.ok()) {
        return Fail(err,
                    fmt::format("demo: descent of {} at {} N: {}", sets[m].name,
                                kForcesN[f], result.error().message));
      }
      table[m][f] = std::move(*result);
      ++done;
    }
  }

  PrintMaterials(sets, out);
  PrintForceCurves(sets, curves, curve_options, out);
  PrintDescents(sets, table, descent_options, out);
  if (!plots_dir.empty()) {
    Result<std::vector<std::string>> written =
        WritePlots(sets, curves, table, plots_dir);
    if (!written.ok()) return Fail(err, "demo: " + written.error().message);
    out << "\nFigures:\n";
    for (const std::string& path : *written) out << "  " << path << "\n";
  }
  return 0;
}

}  // namespace burrlab::runner
