// `burrlab sim ...`: force-depth curves as CSV, the constant-force descent rig
// of dissertation ch. 8, and the step and haptic-loop benchmarks.
#include "cli/sim_commands.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "burrlab/analysis/model_gap/synthetic_measurement.h"
#include "burrlab/sim/bench.h"
#include "burrlab/sim/descent.h"
#include "burrlab/sim/effects.h"
#include "burrlab/sim/force_curve.h"
#include "burrlab/sim/nrrd.h"
#include "burrlab/stimuli/interval.h"
#include "burrlab/stimuli/materials.h"
#include "cli/flags.h"
#include "cli/sim_materials_command.h"
#include "devices/loop_bench.h"
#include "studies/progress.h"

namespace burrlab::runner {
namespace {

// Surgical burrs are 1-5 mm; beyond 10 mm the sample volumes grow large.
constexpr double kMaxRadiusMm = 10.0;

const char* MethodName(sim::MomentMethod method) {
  return method == sim::MomentMethod::kMono ? "mono" : "octree";
}

std::string MaterialFlagHelp() {
  std::string names;
  for (const std::string& name : stimuli::BuiltinMaterialNames()) {
    names += (names.empty() ? "" : ", ") + name;
  }
  return "built-in material set (" + names +
         ") or the path of a material file (*.toml)";
}

// A material by built-in name, or from a file when the argument is a path,
// with the file's notes (an old spelling) printed on `err`.
Result<stimuli::MaterialSet> LoadMaterial(const std::string& name_or_path,
                                          std::ostream& err) {
  Result<stimuli::MaterialSet> set = stimuli::LoadMaterial(name_or_path);
  if (set.ok()) {
    for (const std::string& note : set->notes) err << note << '\n';
  }
  return set;
}

// Exactly one way of naming the material: --material NAME, or the constants
// (--c-e, and --alpha when the command erodes).
Status CheckMaterialChoice(const FlagSet& flags, bool erodes) {
  const bool by_name = flags.Given("--material");
  const bool c_e = flags.Given("--c-e");
  const bool alpha = erodes && flags.Given("--alpha");
  const char* constants = erodes ? "--c-e X --alpha Y" : "--c-e X";
  if (by_name && (c_e || alpha)) {
    return Error{fmt::format(
        "--material and {} are mutually exclusive; give --material NAME or {}",
        c_e ? "--c-e" : "--alpha", constants)};
  }
  if (!by_name && !c_e && !alpha) {
    return Error{
        fmt::format("no material: give --material NAME or {}", constants)};
  }
  if (erodes && c_e && !alpha) {
    return Error{"--c-e needs --alpha Y, the erosion constant in 1/s"};
  }
  if (erodes && alpha && !c_e) {
    return Error{"--alpha needs --c-e X, the elastic constant in N/mm^2"};
  }
  return {};
}

// The rig's --voxel-mm (sim descent, sim measure).
std::string VoxelFlagHelp() {
  return fmt::format(
      "voxel size of the sample, mm (default: R/{0} at loads F/(c_e R^2) of "
      "{2} and above, finer below, to R/{1}: the rig resolves the thin skin "
      "the burr cuts at light loads)",
      sim::kRigVoxelsPerRadius, sim::kRigMaxVoxelsPerRadius,
      sim::kRigResolvedLoad);
}

// The rig's --ell-over-r (sim descent, sim measure).
std::string EllFlagHelp() {
  return fmt::format(
      "octree accuracy scale ell as a fraction of R (default: {} from the "
      "load y = F/(c_e R^2) = {} up, {} (y/{})^0.94 below, at least {}: "
      "about the skin the burr cuts; smaller is finer and slower, 0 refines "
      "every partial block to voxels)",
      sim::Model{}.ell_over_r, sim::kRigResolvedLoad, sim::Model{}.ell_over_r,
      sim::kRigResolvedLoad, sim::kRigMinEllOverR);
}

// The rig's --moment-reuse (sim descent, sim measure).
std::string MomentReuseFlagHelp() {
  return fmt::format(
      "reuse the moments while the burr has moved less than this fraction of "
      "its depth h (and eroded less than this fraction of m0) since they were "
      "last computed (default {}: the elastic force within 1.5 times it of "
      "computing them every step, at under half the cost; 0 computes them "
      "every step; at most 0.1)",
      sim::DescentOptions{}.moment_reuse_over_h);
}

Status CheckMomentReuse(double moment_reuse_over_h) {
  if (moment_reuse_over_h > 0.1) {
    return Error{fmt::format("--moment-reuse must be at most 0.1, got '{}'",
                             moment_reuse_over_h)};
  }
  return {};
}

Status CheckVoxelFitsBurr(double voxel_mm, double radius_mm) {
  if (voxel_mm > radius_mm) {
    return Error{
        fmt::format("--voxel-mm must be at most --radius-mm = {} mm, got '{}'",
                    radius_mm, voxel_mm)};
  }
  return {};
}

int RunForceCurve(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Force against depth of a burr pressed into a flat half-space "
      "(probing: no friction, no erosion; dissertation figs. 6.4(a), "
      "7.1(a)). Prints CSV with the columns depth_mm,h_mm,m0_mm3,force_n.",
      "burrlab sim force-curve"};
  sim::ForceCurveOptions options;
  std::string material_name;
  int method = options.method == sim::MomentMethod::kMono ? 0 : 1;
  FlagSet flags(&app);
  flags.AddText("--material", MaterialFlagHelp(), &material_name)
      ->type_name("NAME");
  flags.AddPositive("--c-e",
                    "elastic constant c_e, N/mm^2 (instead of --material)",
                    "N/mm^2", &options.c_e_n_per_mm2);
  flags
      .AddPositive("--radius-mm", "burr radius R, mm (at most 10)", "mm",
                   &options.radius_mm, kMaxRadiusMm)
      ->required();
  flags.AddPositive(
      "--voxel-mm",
      fmt::format("voxel size, mm (default {})", options.voxel_mm), "mm",
      &options.voxel_mm);
  flags.AddPositive("--max-depth-mm",
                    "deepest immersion, mm (default R, at most 2R)", "mm",
                    &options.max_depth_mm);
  flags.AddInteger(
      "--points",
      fmt::format("samples, evenly spaced up to the deepest (default {})",
                  options.points),
      2, 100000, &options.points);
  flags.AddChoice("--method",
                  "moments from every voxel (mono) or the octree (default "
                  "octree)",
                  {"mono", "octree"}, &method);
  flags.AddNonNegative(
      "--ell-over-r",
      fmt::format("octree accuracy scale ell as a fraction of R (default {})",
                  options.ell_over_r),
      "", &options.ell_over_r);
  flags.AddDirection("--normal",
                     "outward normal of the surface (default 0,0,1)",
                     &options.normal);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = CheckMaterialChoice(flags, /*erodes=*/false); !s.ok()) {
    return Fail(err, s.error().message);
  }
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  if (Status s = CheckVoxelFitsBurr(options.voxel_mm, options.radius_mm);
      !s.ok()) {
    return Fail(err, s.error().message);
  }
  if (options.max_depth_mm > 2.0 * options.radius_mm) {
    return Fail(err,
                fmt::format("--max-depth-mm must be at most 2 x "
                            "--radius-mm = {} mm, got '{}'",
                            2.0 * options.radius_mm, options.max_depth_mm));
  }
  options.method =
      method == 0 ? sim::MomentMethod::kMono : sim::MomentMethod::kOctree;
  if (flags.Given("--material")) {
    Result<stimuli::MaterialSet> set = LoadMaterial(material_name, err);
    if (!set.ok()) return Fail(err, set.error().message);
    options.c_e_n_per_mm2 = set->material.c_e_n_per_mm2;
  }
  Result<std::vector<sim::ForceCurvePoint>> curve =
      sim::ComputeForceCurve(options);
  if (!curve.ok())
    return Fail(err, "sim force-curve: " + curve.error().message);
  out << "depth_mm,h_mm,m0_mm3,force_n\n";
  for (const sim::ForceCurvePoint& point : *curve) {
    out << fmt::format("{:.6g},{:.6g},{:.6g},{:.6g}\n", point.depth_mm,
                       point.h_mm, point.m0_mm3, point.force_n);
  }
  return 0;
}

// Writes the descent trace as CSV; false when the stream failed.
bool WriteTrace(const std::vector<sim::DescentSample>& trace,
                std::ostream& csv) {
  csv << "t_s,depth_mm,force_n,velocity_mm_s\n";
  for (const sim::DescentSample& sample : trace) {
    csv << fmt::format("{:.9g},{:.6g},{:.6g},{:.6g}\n", sample.t_s,
                       sample.depth_mm, sample.force_n, sample.velocity_mm_s);
  }
  csv.flush();
  return csv.good();
}

// "cannot write --trace file 'x': reason".
std::string TraceError(std::string_view what, const std::string& path,
                       int error_number) {
  return error_number == 0
             ? fmt::format("cannot {} --trace file '{}'", what, path)
             : fmt::format("cannot {} --trace file '{}': {}", what, path,
                           std::strerror(error_number));
}

// What to change when the rig measured no velocity: more time when the
// window ran out of it, nothing a flag can fix otherwise.
std::string NoVelocityAdvice(const sim::DescentResult& r) {
  if (r.needed_duration_s <= 0.0) return "";
  return fmt::format(
      " (raise --duration-s to at least {:.0f}, or use a larger "
      "--force-n)",
      std::ceil(r.needed_duration_s));
}

int RunDescentCommand(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Constant-force descent of a spinning burr into a flat sample, the "
      "virtual calibration rig of dissertation ch. 8. Reports the penetration "
      "velocity under --velocity-definition: the initial one of §8.6 (the "
      "plateau after the impact transient, over the first R/3 cut) or the "
      "settled one.",
      "burrlab sim descent"};
  sim::DescentOptions options;
  std::string material_name, trace_path;
  int definition =
      options.definition == sim::VelocityDefinition::kInitial ? 0 : 1;
  bool json = false;
  FlagSet flags(&app);
  flags.AddText("--material", MaterialFlagHelp(), &material_name)
      ->type_name("NAME");
  flags.AddPositive("--c-e",
                    "elastic constant c_e, N/mm^2 (with --alpha, instead of "
                    "--material; other constants keep the simulator defaults)",
                    "N/mm^2", &options.material.c_e_n_per_mm2);
  flags.AddNonNegative("--alpha", "erosion constant alpha, 1/s (with --c-e)",
                       "1/s", &options.material.alpha_per_s);
  flags
      .AddPositive("--force-n", "force held by the controller, N", "N",
                   &options.force_n)
      ->required();
  flags
      .AddPositive("--radius-mm", "burr radius R, mm (at most 10)", "mm",
                   &options.radius_mm, kMaxRadiusMm)
      ->required();
  flags.AddChoice("--velocity-definition",
                  fmt::format("what the velocity is (default {}): {}",
                              sim::VelocityDefinitionName(options.definition),
                              sim::VelocityDefinitionHelp()),
                  {"initial", "settled"}, &definition);
  flags.AddNonNegative(
      "--spindle-rad-s",
      fmt::format("burr spin, rad/s (default {})", options.spindle_rad_s),
      "rad/s", &options.spindle_rad_s);
  flags.AddPositive("--voxel-mm", VoxelFlagHelp(), "mm", &options.voxel_mm);
  flags.AddNonNegative("--ell-over-r", EllFlagHelp(), "", &options.ell_over_r);
  flags.AddNonNegative("--moment-reuse", MomentReuseFlagHelp(), "",
                       &options.moment_reuse_over_h);
  flags.AddPositive(
      "--duration-s",
      "longest simulated time after contact, s (default 3600 for the "
      "initial velocity, 36000 for the settled one)",
      "s", &options.duration_s);
  flags.AddUnsigned(
      "--seed", fmt::format("erosion random seed (default {})", options.seed),
      &options.seed);
  flags
      .AddText("--trace",
               "write the trace as CSV: t_s,depth_mm,force_n,velocity_mm_s",
               &trace_path)
      ->type_name("FILE.csv");
  flags.AddSwitch("--json", "print the inputs and results as JSON", &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = CheckMaterialChoice(flags, /*erodes=*/true); !s.ok()) {
    return Fail(err, s.error().message);
  }
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  options.definition = definition == 0 ? sim::VelocityDefinition::kInitial
                                       : sim::VelocityDefinition::kSettled;
  if (Status s = CheckVoxelFitsBurr(options.VoxelMm(), options.radius_mm);
      !s.ok()) {
    return Fail(err, s.error().message);
  }
  if (Status s = CheckMomentReuse(options.moment_reuse_over_h); !s.ok()) {
    return Fail(err, s.error().message);
  }
  if (flags.Given("--trace") && trace_path.empty()) {
    return Fail(err, "--trace needs a file name, got ''");
  }
  const bool by_name = flags.Given("--material");
  if (by_name) {
    Result<stimuli::MaterialSet> set = LoadMaterial(material_name, err);
    if (!set.ok()) return Fail(err, set.error().message);
    options.material = set->material;
    material_name = set->name;
  }
  if (Status s = options.Validate(); !s.ok()) {
    return Fail(err, "sim descent: " + s.error().message);
  }
  // Open the trace before the run so a bad path fails fast.
  std::ofstream trace;
  if (!trace_path.empty()) {
    errno = 0;
    trace.open(trace_path, std::ios::out | std::ios::trunc);
    if (!trace.is_open()) {
      return Fail(err, TraceError("write", trace_path, errno));
    }
  }
  Result<sim::DescentResult> result = [&] {
    // The bar runs up to the longest duration; most runs stop earlier.
    const int total_s = static_cast<int>(std::ceil(options.DurationS()));
    ProgressBar bar(err, total_s);
    options.progress = [&bar, total_s](double after_contact_s,
                                       double depth_mm) {
      bar.Update(
          std::min(static_cast<int>(after_contact_s), total_s),
          fmt::format("s after contact (at most), depth {:.3g} mm", depth_mm));
    };
    Result<sim::DescentResult> run = sim::RunDescent(options);
    options.progress = nullptr;
    return run;
  }();
  if (!result.ok()) {
    if (trace.is_open()) {
      trace.close();
      std::remove(trace_path.c_str());  // we emptied it; leave no stub
    }
    return Fail(err, "sim descent: " + result.error().message);
  }
  if (trace.is_open()) {
    errno = 0;
    if (!WriteTrace(result->trace, trace)) {
      return Fail(err, TraceError("write", trace_path, errno));
    }
    trace.close();
    if (trace.fail()) return Fail(err, TraceError("close", trace_path, errno));
  }
  const sim::DescentResult& r = *result;
  const std::string_view definition_name =
      sim::VelocityDefinitionName(options.definition);
  if (!r.velocity_mm_s) {
    err << fmt::format("burrlab: warning: no {} velocity: {}{}\n",
                       definition_name, r.no_velocity_reason,
                       NoVelocityAdvice(r));
  }
  if (json) {
    nlohmann::ordered_json j;
    j["material"] = by_name ? nlohmann::ordered_json(material_name)
                            : nlohmann::ordered_json(nullptr);
    j["c_e_n_per_mm2"] = options.material.c_e_n_per_mm2;
    j["alpha_per_s"] = options.material.alpha_per_s;
    j["force_n"] = options.force_n;
    j["radius_mm"] = options.radius_mm;
    j["spindle_rad_s"] = options.spindle_rad_s;
    j["voxel_mm"] = options.VoxelMm();
    j["ell_over_r"] = options.EllOverR();
    j["moment_reuse_over_h"] = options.moment_reuse_over_h;
    j["duration_s"] = options.DurationS();
    j["seed"] = options.seed;
    j["velocity_definition"] = definition_name;
    j["velocity_mm_s"] = r.velocity_mm_s
                             ? nlohmann::ordered_json(*r.velocity_mm_s)
                             : nlohmann::ordered_json(nullptr);
    j["no_velocity_reason"] =
        r.velocity_mm_s ? nlohmann::ordered_json(nullptr)
                        : nlohmann::ordered_json(r.no_velocity_reason);
    j["contact_s"] = r.contact_s;
    j["transient_end_s"] = r.transient_end_s;
    j["window_start_s"] = r.window_start_s;
    j["window_end_s"] = r.window_end_s;
    j["window_start_depth_mm"] = r.window_start_depth_mm;
    j["window_end_depth_mm"] = r.window_end_depth_mm;
    j["final_depth_mm"] = r.final_depth_mm;
    j["removed_mm3"] = r.removed_mm3;
    j["steps"] = r.steps;
    j["simulated_s"] = static_cast<double>(r.steps) * options.dt_s;
    j["trace"] = trace_path.empty() ? nlohmann::ordered_json(nullptr)
                                    : nlohmann::ordered_json(trace_path);
    out << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace)
        << '\n';
    return 0;
  }
  const std::string material =
      by_name
          ? fmt::format("{}: c_e {} N/mm^2, alpha {} 1/s", material_name,
                        options.material.c_e_n_per_mm2,
                        options.material.alpha_per_s)
          : fmt::format(
                "c_e {} N/mm^2, alpha {} 1/s (other constants: "
                "simulator defaults)",
                options.material.c_e_n_per_mm2, options.material.alpha_per_s);
  out << fmt::format("material         {}\n", material);
  out << fmt::format(
      "rig              {} N on a {} mm burr at {} rad/s, voxel {:.4g} mm, "
      "seed {}\n",
      options.force_n, options.radius_mm, options.spindle_rad_s,
      options.VoxelMm(), options.seed);
  out << (r.velocity_mm_s ? fmt::format("{} velocity {:.4g} mm/s\n",
                                        fmt::format("{:<7}", definition_name),
                                        *r.velocity_mm_s)
                          : fmt::format("{} velocity not measured\n",
                                        fmt::format("{:<7}", definition_name)));
  if (r.velocity_mm_s) {
    out << fmt::format(
        "window           {:.4g} to {:.4g} s, depth {:.4g} to {:.4g} mm "
        "(contact at {:.4g} s, force settled at {:.4g} s)\n",
        r.window_start_s, r.window_end_s, r.window_start_depth_mm,
        r.window_end_depth_mm, r.contact_s, r.transient_end_s);
  }
  out << fmt::format("final depth      {:.4g} mm\n", r.final_depth_mm);
  out << fmt::format("removed          {:.4g} mm^3\n", r.removed_mm3);
  out << fmt::format("simulated        {:.4g} s ({} steps)\n",
                     static_cast<double>(r.steps) * options.dt_s, r.steps);
  if (!trace_path.empty()) {
    out << fmt::format("trace            {} ({} samples)\n", trace_path,
                       r.trace.size());
  }
  return 0;
}

// Longest --seconds of `sim bench --loop`.
constexpr double kMaxLoopSeconds = 3600.0;

// `sim bench --loop`: runs the haptic loop and prints its timing.
int RunLoopBenchCommand(double seconds, bool json, std::ostream& out,
                        std::ostream& err) {
  LoopBenchOptions options;
  options.seconds = seconds;
  err << fmt::format("burrlab: running the haptic loop for {} s at {} Hz...\n",
                     seconds, options.rate_hz);
  Result<LoopBenchResult> result = RunLoopBench(options);
  if (!result.ok()) return Fail(err, "sim bench: " + result.error().message);
  const LoopBenchResult& r = *result;
  const LoopStats& stats = r.stats;
  if (json) {
    nlohmann::ordered_json j;
    j["seconds"] = seconds;
    j["rate_hz"] = options.rate_hz;
    j["ticks"] = r.counters.ticks;
    j["planned_ticks"] = r.planned_ticks;
    j["material"] = options.material;
    j["radius_mm"] = options.radius_mm;
    j["max_force_n"] = r.max_force_n;
    j["sched_fifo"] = r.realtime.fifo;
    j["memory_locked"] = r.realtime.memory_locked;
    j["realtime_note"] = r.realtime.note;
    j["period_error_p50_us"] = stats.p50_us;
    j["period_error_p99_us"] = stats.p99_us;
    j["period_error_max_us"] = stats.max_us;
    j["overruns"] = stats.overruns;
    j["skipped_ticks"] = r.counters.skipped_ticks;
    j["non_finite"] = r.counters.non_finite;
    j["clamped"] = r.counters.clamped;
    out << j.dump(2) << '\n';
    return 0;
  }
  out << fmt::format(
      "haptic loop   {} s at {} Hz ({} ticks): simulated device ({} N "
      "limit), octree R {} mm drilling {}\n",
      seconds, options.rate_hz, r.counters.ticks, r.max_force_n,
      options.radius_mm, options.material);
  out << fmt::format(
      "real time     {}, {}\n",
      r.realtime.fifo ? "SCHED_FIFO" : "normal priority (no SCHED_FIFO)",
      r.realtime.memory_locked ? "memory locked" : "memory not locked");
  if (!r.realtime.note.empty()) {
    out << fmt::format("note          {}\n", r.realtime.note);
  }
  out << fmt::format(
      "period error  p50 {:.1f} µs, p99 {:.1f} µs, max {:.1f} µs (tick start "
      "minus deadline)\n",
      stats.p50_us, stats.p99_us, stats.max_us);
  out << fmt::format(
      "overruns      {} (force not ready within the period: zero force "
      "sent)\n",
      stats.overruns);
  out << fmt::format(
      "skipped       {} ticks (the loop fell more than a period behind)\n",
      r.counters.skipped_ticks);
  return 0;
}

// One interval as studies render it (stimuli::PresentSimulatedInterval at
// its defaults: R 2 mm, voxels of 0.3 mm, presses to 2 N, drilling at 3 N),
// timed whole.
struct IntervalBenchResult {
  std::string material;
  stimuli::Task task = stimuli::Task::kProbe;
  double duration_s = 0.0;
  double wall_s = 0.0;
  std::int64_t steps = 0;
  std::int64_t moment_evaluations = 0;  // steps that computed the moments
  double cue = 0.0;
  std::string cue_name;
};

Result<IntervalBenchResult> RunIntervalBench(const std::string& material,
                                             stimuli::Task task,
                                             double duration_s) {
  Result<stimuli::MaterialSet> set = stimuli::LoadBuiltinMaterial(material);
  if (!set.ok()) return set.error();
  stimuli::IntervalOptions options;
  options.material = set->material;
  options.task = task;
  options.duration_s = duration_s;
  const auto start = std::chrono::steady_clock::now();
  Result<stimuli::IntervalResult> interval =
      stimuli::PresentSimulatedInterval(options);
  const auto stop = std::chrono::steady_clock::now();
  if (!interval.ok()) return interval.error();
  IntervalBenchResult r;
  r.material = material;
  r.task = task;
  r.duration_s = duration_s;
  r.wall_s = std::chrono::duration<double>(stop - start).count();
  r.steps = interval->steps;
  r.moment_evaluations = interval->moment_evaluations;
  r.cue = interval->cue;
  r.cue_name = interval->cue_name;
  return r;
}

int RunBench(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Times simulator steps (force + erosion): the burr slides at 10 mm/s a "
      "quarter of its radius deep in a solid half-space. Cases: mono and "
      "octree moments x R = 1, 2, 3, 5 mm x probe and drill. A step over "
      "1000 us misses the 1 kHz haptic deadline. Then the intervals studies "
      "render (probe and drill on each built-in material, R 2 mm, voxels of "
      "0.3 mm, 20 s), each timed whole, with its real-time factor (simulated "
      "over wall time). With --loop, runs the 1 kHz "
      "haptic loop on its own thread (SCHED_FIFO and mlockall when "
      "permitted) with a simulated device and reports how late ticks start "
      "(p50, p99, max) and the overruns.",
      "burrlab sim bench"};
  std::vector<sim::BenchCase> cases = sim::DefaultBenchCases();
  int steps = cases.empty() ? 0 : cases.front().steps;
  bool json = false;
  bool loop = false;
  double seconds = 10.0;
  double interval_s = 20.0;
  FlagSet flags(&app);
  flags.AddInteger("--steps",
                   fmt::format("timed steps per case (default {})", steps), 1,
                   1000000, &steps);
  flags.AddSwitch("--loop", "benchmark the 1 kHz haptic loop instead", &loop);
  flags.AddPositive("--seconds",
                    "length of the --loop run, s (default 10, at most 3600)",
                    "s", &seconds, kMaxLoopSeconds);
  flags.AddPositive("--interval-s",
                    "length of each interval case, s (default 20, as studies "
                    "render them; from 1, one press, to 60)",
                    "s", &interval_s, 60.0);
  flags.AddSwitch("--json", "print the results as JSON", &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  if (flags.Given("--interval-s") && loop) {
    return Fail(err,
                "--interval-s and --loop are mutually exclusive; the loop "
                "runs for --seconds");
  }
  if (flags.Given("--seconds") && !loop) {
    return Fail(err,
                "--seconds needs --loop (the step benchmark uses --steps)");
  }
  if (flags.Given("--steps") && loop) {
    return Fail(err,
                "--steps and --loop are mutually exclusive; the loop runs for "
                "--seconds");
  }
  if (loop) return RunLoopBenchCommand(seconds, json, out, err);
  for (sim::BenchCase& bench_case : cases) {
    if (flags.Given("--steps")) bench_case.steps = steps;
  }
  std::vector<sim::BenchCaseResult> results;
  std::vector<IntervalBenchResult> intervals;
  const std::vector<std::string> materials = stimuli::BuiltinMaterialNames();
  {
    ProgressBar progress(err,
                         static_cast<int>(cases.size() + 2 * materials.size()));
    for (const sim::BenchCase& bench_case : cases) {
      progress.Update(
          static_cast<int>(results.size()),
          fmt::format("{} R {} mm {}", MethodName(bench_case.method),
                      bench_case.radius_mm,
                      bench_case.drill ? "drill" : "probe"));
      results.push_back(sim::RunBenchCase(bench_case));
      if (!(results.back().max_us > 0.0)) {
        return Fail(err, fmt::format("sim bench: the {} R {} mm {} case did "
                                     "not run",
                                     MethodName(bench_case.method),
                                     bench_case.radius_mm,
                                     bench_case.drill ? "drill" : "probe"));
      }
    }
    for (const std::string& material : materials) {
      for (stimuli::Task task :
           {stimuli::Task::kProbe, stimuli::Task::kDrill}) {
        progress.Update(
            static_cast<int>(results.size() + intervals.size()),
            fmt::format("{} {} interval", material, stimuli::TaskName(task)));
        Result<IntervalBenchResult> r =
            RunIntervalBench(material, task, interval_s);
        if (!r.ok()) {
          return Fail(err, fmt::format("sim bench: the {} {} interval did not "
                                       "run: {}",
                                       material, stimuli::TaskName(task),
                                       r.error().message));
        }
        intervals.push_back(std::move(*r));
      }
    }
  }
  const unsigned hardware_threads = std::thread::hardware_concurrency();
  if (json) {
    nlohmann::ordered_json j;
    j["steps"] = steps;
    j["hardware_threads"] = hardware_threads;
    j["cases"] = nlohmann::ordered_json::array();
    for (const sim::BenchCaseResult& result : results) {
      const sim::BenchCase& c = result.bench_case;
      j["cases"].push_back({{"method", MethodName(c.method)},
                            {"radius_mm", c.radius_mm},
                            {"task", c.drill ? "drill" : "probe"},
                            {"voxel_mm", c.voxel_mm},
                            {"steps", c.steps},
                            {"median_us", result.median_us},
                            {"p99_us", result.p99_us},
                            {"max_us", result.max_us},
                            {"removed_mm3", result.removed_mm3}});
    }
    j["intervals"] = nlohmann::ordered_json::array();
    for (const IntervalBenchResult& r : intervals) {
      j["intervals"].push_back(
          {{"material", r.material},
           {"task", stimuli::TaskName(r.task)},
           {"radius_mm", stimuli::kDefaultBurrRadiusMm},
           {"voxel_mm", stimuli::IntervalOptions{}.voxel_mm},
           {"duration_s", r.duration_s},
           {"steps", r.steps},
           {"wall_s", r.wall_s},
           {"real_time_factor", r.duration_s / r.wall_s},
           {"us_per_step", 1e6 * r.wall_s / static_cast<double>(r.steps)},
           {"moments_computed_fraction",
            static_cast<double>(r.moment_evaluations) /
                static_cast<double>(r.steps)},
           {r.cue_name, r.cue}});
    }
    out << j.dump(2) << '\n';
    return 0;
  }
  out << fmt::format(
      "{} timed steps per case, {} hardware threads; the 1 kHz haptic tick "
      "allows 1000 µs\n\n",
      steps, hardware_threads);
  out << fmt::format("{:<6}  {:>4}  {:<5}  {:>9}  {:>9}  {:>9}\n", "method",
                     "R mm", "task", "median µs", "p99 µs", "max µs");
  for (const sim::BenchCaseResult& result : results) {
    const sim::BenchCase& c = result.bench_case;
    out << fmt::format("{:<6}  {:>4}  {:<5}  {:>9.1f}  {:>9.1f}  {:>9.1f}\n",
                       MethodName(c.method), c.radius_mm,
                       c.drill ? "drill" : "probe", result.median_us,
                       result.p99_us, result.max_us);
  }
  out << fmt::format(
      "\nintervals as studies render them ({:g} s each, R {:g} mm, voxels of "
      "{:g} mm), each timed whole\n\n",
      interval_s, stimuli::kDefaultBurrRadiusMm,
      stimuli::IntervalOptions{}.voxel_mm);
  out << fmt::format("{:<24}  {:<5}  {:>7}  {:>11}  {:>8}  {:>9}\n", "material",
                     "task", "wall s", "× real time", "µs/step", "moments %");
  for (const IntervalBenchResult& r : intervals) {
    out << fmt::format(
        "{:<24}  {:<5}  {:>7.2f}  {:>11.0f}  {:>8.1f}  {:>9.1f}\n", r.material,
        stimuli::TaskName(r.task), r.wall_s, r.duration_s / r.wall_s,
        1e6 * r.wall_s / static_cast<double>(r.steps),
        100.0 * static_cast<double>(r.moment_evaluations) /
            static_cast<double>(r.steps));
  }
  out << "\nmoments %: the steps that computed the moments afresh; the "
         "others reuse those of a nearby centre (probe 0.005 h, drill 0.002 "
         "h)\n";
  return 0;
}

// "0.5,1,2" as positive forces in N.
Result<std::vector<double>> ParseForces(const std::string& text) {
  std::vector<double> forces;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    Result<double> f = ParsePositive(
        "--forces",
        text.substr(start, comma == std::string::npos ? std::string::npos
                                                      : comma - start),
        "N");
    if (!f.ok()) return f.error();
    forces.push_back(*f);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return forces;
}

// "ID=VALUE[,ID=VALUE...]" into the effects.
Status ParseEffects(const std::string& text, sim::Effects* effects) {
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(
        start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::size_t equals = item.find('=');
    if (equals == std::string::npos) {
      return Error{fmt::format(
          "--effect must be ID=VALUE (e.g. motor_power_limit=0.01), got '{}'",
          item)};
    }
    Result<double> value = ParseNumber("--effect", item.substr(equals + 1));
    if (!value.ok() && item.substr(equals + 1) != "inf") return value.error();
    if (Status s = sim::SetEffect(
            item.substr(0, equals),
            value.ok() ? *value : std::numeric_limits<double>::infinity(),
            effects);
        !s.ok()) {
      return Error{"--effect: " + s.error().message};
    }
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return {};
}

// "cannot write --traces file 'x': reason".
std::string TracesError(const std::string& path, int error_number) {
  return error_number == 0
             ? fmt::format("cannot write --traces file '{}'", path)
             : fmt::format("cannot write --traces file '{}': {}", path,
                           std::strerror(error_number));
}

int RunMeasure(const Args& args, std::ostream& out, std::ostream& err) {
  std::string effects_help = "hidden effects, ID=VALUE[,ID=VALUE]: ";
  for (const sim::EffectSpec& spec : sim::EffectLibrary()) {
    effects_help += fmt::format("{} ({}), ", spec.id, spec.help);
  }
  effects_help.resize(effects_help.size() - 2);
  CLI::App app{
      "Synthetic measured data for `burrlab calibrate`: the constant-force "
      "descent rig of `burrlab sim descent` (dissertation ch. 8) run once per "
      "force level, with hidden physical effects and log-normal run-to-run "
      "noise. Prints CSV: run,material,burr_radius_mm,spindle_rad_s,force_n,"
      "velocity_mm_s,velocity_definition.",
      "burrlab sim measure"};
  analysis::SyntheticMeasurementOptions options;
  std::string material_name, forces_text, effects_text, traces_path;
  int replicates = options.replicates;
  int definition =
      options.definition == sim::VelocityDefinition::kInitial ? 0 : 1;
  FlagSet flags(&app);
  flags.AddText("--material", MaterialFlagHelp(), &material_name)
      ->type_name("NAME")
      ->required();
  flags.AddText("--forces", "force levels, N, comma-separated", &forces_text)
      ->type_name("F1,F2,...")
      ->required();
  flags
      .AddInteger("--replicates", "runs per force level", 1, 10000, &replicates)
      ->required();
  flags.AddText("--effect", effects_help, &effects_text)->type_name("ID=VALUE");
  flags.AddChoice("--velocity-definition",
                  fmt::format("what the velocity is (default {}): {}",
                              sim::VelocityDefinitionName(options.definition),
                              sim::VelocityDefinitionHelp()),
                  {"initial", "settled"}, &definition);
  flags.AddNonNegative(
      "--noise-cv",
      fmt::format("run-to-run coefficient of variation of the velocity "
                  "(log-normal; default {})",
                  options.noise_cv),
      "", &options.noise_cv);
  flags.AddUnsigned(
      "--seed",
      fmt::format("erosion and noise seed (default {})", options.seed),
      &options.seed);
  flags.AddPositive(
      "--radius-mm",
      fmt::format("burr radius R, mm (default {})", options.radius_mm), "mm",
      &options.radius_mm, kMaxRadiusMm);
  flags
      .AddText("--traces",
               "also write each run's force and depth trace to FILE as "
               "run,t_s,force_n,depth_mm (100 Hz for the first 10 s after "
               "contact, coarser after; replicates share their level's rig "
               "trace, each with its own sensor noise)",
               &traces_path)
      ->type_name("FILE");
  flags.AddNonNegative(
      "--trace-force-noise-n",
      fmt::format("the traces' force sensor noise, standard deviation, N "
                  "(default {})",
                  options.trace_force_noise_n),
      "N", &options.trace_force_noise_n);
  flags.AddNonNegative(
      "--trace-depth-noise-mm",
      fmt::format("the traces' depth sensor noise, standard deviation, mm "
                  "(default {})",
                  options.trace_depth_noise_mm),
      "mm", &options.trace_depth_noise_mm);
  flags.AddPositive("--voxel-mm", VoxelFlagHelp(), "mm", &options.voxel_mm);
  flags.AddNonNegative("--ell-over-r", EllFlagHelp(), "", &options.ell_over_r);
  flags.AddNonNegative("--moment-reuse", MomentReuseFlagHelp(), "",
                       &options.moment_reuse_over_h);
  options.jobs = static_cast<int>(
      std::clamp(std::thread::hardware_concurrency(), 1u, 256u));
  flags.AddInteger("--jobs",
                   "force levels run at once (default: the core count; the "
                   "output does not depend on it)",
                   1, 256, &options.jobs);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  options.replicates = replicates;
  options.definition = definition == 0 ? sim::VelocityDefinition::kInitial
                                       : sim::VelocityDefinition::kSettled;
  options.keep_traces = !traces_path.empty();
  if (Status s = CheckVoxelFitsBurr(options.voxel_mm, options.radius_mm);
      !s.ok()) {
    return Fail(err, s.error().message);
  }
  if (Status s = CheckMomentReuse(options.moment_reuse_over_h); !s.ok()) {
    return Fail(err, s.error().message);
  }
  Result<std::vector<double>> forces = ParseForces(forces_text);
  if (!forces.ok()) return Fail(err, forces.error().message);
  options.forces_n = *forces;
  if (!effects_text.empty()) {
    if (Status s = ParseEffects(effects_text, &options.effects); !s.ok()) {
      return Fail(err, s.error().message);
    }
  }
  Result<stimuli::MaterialSet> set = LoadMaterial(material_name, err);
  if (!set.ok()) return Fail(err, set.error().message);
  options.material = set->material;
  // Open the traces before the runs so a bad path fails fast.
  std::ofstream traces;
  if (options.keep_traces) {
    errno = 0;
    traces.open(traces_path, std::ios::out | std::ios::trunc);
    if (!traces.is_open()) {
      return Fail(err, TracesError(traces_path, errno));
    }
  }
  Result<analysis::SyntheticMeasurement> m = [&] {
    ProgressBar bar(err, static_cast<int>(options.forces_n.size()));
    bar.Update(0, "descent rig, one run per force level");
    options.progress = [&bar](int done, int) {
      bar.Update(done, "descent rig, one run per force level");
    };
    Result<analysis::SyntheticMeasurement> result =
        analysis::MeasureSynthetic(options);
    options.progress = nullptr;
    return result;
  }();
  if (!m.ok()) {
    if (traces.is_open()) {
      traces.close();
      std::remove(traces_path.c_str());  // we emptied it; leave no stub
    }
    return Fail(err, "sim measure: " + m.error().message);
  }
  if (traces.is_open()) {
    errno = 0;
    traces << analysis::FormatTraceCsv(*m, options);
    traces.close();
    if (traces.fail()) return Fail(err, TracesError(traces_path, errno));
  }
  for (std::size_t k = 0; k < m->skipped_forces_n.size(); ++k) {
    err << fmt::format(
        "burrlab: warning: no {} velocity at {} N ({}); the level is left "
        "out\n",
        sim::VelocityDefinitionName(options.definition), m->skipped_forces_n[k],
        m->skipped_reasons[k]);
  }
  if (m->runs.empty()) {
    return Fail(err,
                fmt::format("sim measure: no force level gave a {} "
                            "velocity",
                            sim::VelocityDefinitionName(options.definition)));
  }
  out << analysis::FormatMeasuredCsv(*m, set->name, options);
  return 0;
}

// `burrlab sim volume FILE.nrrd`: loads a CT-derived volume as the simulator
// would and summarises it, so users can check a scan and its mapping.
int RunVolume(const Args& args, std::ostream& out, std::ostream& err) {
  CLI::App app{
      "Loads an NRRD volume (raw or gzip, 8- or 16-bit) with a threshold or a "
      "linear intensity-to-occupancy mapping and prints its extents, voxel "
      "size and material volume.",
      "burrlab sim volume"};
  std::string path, range;
  double threshold = 0.0;
  bool json = false;
  FlagSet flags(&app);
  app.add_option("file", path, "the NRRD file")->required();
  flags.AddNonNegative("--threshold",
                       "intensity at and above which a voxel is solid",
                       "intensity units", &threshold);
  flags
      .AddText("--range",
               "LO,HI: occupancy rises linearly from 0 at LO to 255 at HI",
               &range)
      ->type_name("LO,HI");
  flags.AddSwitch("--json", "print the summary as JSON", &json);
  if (std::optional<int> code = flags.Parse(args, out, err)) return *code;
  if (Status s = flags.Convert(); !s.ok()) return Fail(err, s.error().message);
  sim::IntensityMapping mapping;
  if (flags.Given("--threshold") == flags.Given("--range")) {
    return Fail(err, "give exactly one of --threshold T and --range LO,HI");
  }
  if (flags.Given("--threshold")) {
    mapping.kind = sim::IntensityMapping::Kind::kThreshold;
    mapping.threshold = threshold;
  } else {
    const std::size_t comma = range.find(',');
    Result<double> low = ParseNumber("--range", range.substr(0, comma));
    Result<double> high = comma == std::string::npos
                              ? Result<double>(Error{})
                              : ParseNumber("--range", range.substr(comma + 1));
    if (!low.ok() || !high.ok() || !(*low < *high)) {
      return Fail(
          err,
          fmt::format("--range must be LO,HI with LO < HI, got '{}'", range));
    }
    mapping.kind = sim::IntensityMapping::Kind::kLinear;
    mapping.low = *low;
    mapping.high = *high;
  }
  Result<sim::Volume> volume = sim::LoadNrrd(path, mapping);
  if (!volume.ok()) return Fail(err, volume.error().message);
  std::size_t occupied = 0, solid = 0;
  for (std::size_t n = 0; n < volume->size(); ++n) {
    occupied += volume->occupancy()[n] > 0;
    solid += volume->occupancy()[n] == sim::kSolidOccupancy;
  }
  if (json) {
    nlohmann::ordered_json j;
    j["file"] = path;
    j["extents"] = {volume->nx(), volume->ny(), volume->nz()};
    j["voxel_mm"] = volume->voxel_mm();
    j["material_mm3"] = volume->MaterialMm3();
    j["occupied_voxels"] = occupied;
    j["solid_voxels"] = solid;
    out << j.dump(2) << '\n';
    return 0;
  }
  out << fmt::format("file             {}\n", path);
  out << fmt::format("extents          {} x {} x {} voxels\n", volume->nx(),
                     volume->ny(), volume->nz());
  out << fmt::format("voxel            {} mm\n", volume->voxel_mm());
  out << fmt::format("material         {:.4g} mm^3 (solid-equivalent)\n",
                     volume->MaterialMm3());
  out << fmt::format("occupied voxels  {} ({} solid)\n", occupied, solid);
  return 0;
}

int RunSimHelp(const Args& args, std::ostream& out, std::ostream& err);

constexpr Command kSimCommands[] = {
    {"force-curve",
     "force against depth of a burr pressed into a flat material (CSV)",
     RunForceCurve},
    {"descent",
     "constant-force descent into a flat sample: the penetration velocity, "
     "initial or settled",
     RunDescentCommand},
    {"bench",
     "time simulator steps (mono and octree x R = 1, 2, 3, 5 mm x probe and "
     "drill), or the 1 kHz haptic loop with --loop",
     RunBench},
    {"measure",
     "synthetic measured data (CSV) for calibrate: the descent rig with "
     "hidden effects and run-to-run noise",
     RunMeasure},
    {"volume", "load an NRRD volume with an intensity mapping and summarise it",
     RunVolume},
    {"materials",
     "the built-in materials: force-depth curves and constant-force descents, "
     "with figures",
     RunSimMaterialsCommand},
    {"help", "list the sim commands; 'sim help COMMAND' shows the flags of one",
     RunSimHelp},
};

int RunSimHelp(const Args& args, std::ostream& out, std::ostream& err) {
  return RunHelp("burrlab sim", kSimCommands, args, out, err);
}

}  // namespace

int RunSimCommand(const Args& args, std::ostream& out, std::ostream& err) {
  return Dispatch("burrlab sim", kSimCommands, args, out, err);
}

}  // namespace burrlab::runner
