// Synthetic measured data from the full descent rig plus log-normal noise.
#include "burrlab/analysis/model_gap/synthetic_measurement.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <mutex>
#include <thread>

#include "burrlab/sim/descent.h"

namespace burrlab::analysis {

Status SyntheticMeasurementOptions::Validate() const {
  if (Status s = material.Validate(); !s.ok()) return s;
  if (Status s = effects.Validate(); !s.ok()) return s;
  if (forces_n.empty()) return Error{"forces_n must name at least one force"};
  for (double f : forces_n) {
    if (!std::isfinite(f) || f <= 0.0) {
      return Error{fmt::format(
          "every force must be a positive finite number of N, got {}", f)};
    }
  }
  if (replicates < 1 || replicates > 10000) {
    return Error{
        fmt::format("replicates must lie in [1, 10000], got {}", replicates)};
  }
  if (!std::isfinite(noise_cv) || noise_cv < 0.0) {
    return Error{fmt::format("noise_cv must be finite and at least 0, got {}",
                             noise_cv)};
  }
  if (!std::isfinite(trace_force_noise_n) || trace_force_noise_n < 0.0) {
    return Error{
        fmt::format("trace_force_noise_n must be finite and at least 0, got {}",
                    trace_force_noise_n)};
  }
  if (!std::isfinite(trace_depth_noise_mm) || trace_depth_noise_mm < 0.0) {
    return Error{fmt::format(
        "trace_depth_noise_mm must be finite and at least 0, got {}",
        trace_depth_noise_mm)};
  }
  if (!std::isfinite(radius_mm) || radius_mm <= 0.0) {
    return Error{fmt::format("radius_mm must be positive, got {}", radius_mm)};
  }
  if (!std::isfinite(voxel_mm) || voxel_mm < 0.0) {
    return Error{fmt::format(
        "voxel_mm must be finite and at least 0 (0: the rig's default), got {}",
        voxel_mm)};
  }
  if (voxel_mm > radius_mm) {
    return Error{
        fmt::format("a voxel of {:g} mm is larger than the burr radius {:g} mm",
                    voxel_mm, radius_mm)};
  }
  if (voxel_mm > 0.0 && radius_mm / voxel_mm > 200.0) {
    return Error{
        fmt::format("a voxel of {:g} mm is finer than the rig allows (R/200 = "
                    "{:g} mm)",
                    voxel_mm, radius_mm / 200.0)};
  }
  if (!std::isfinite(dt_s) || dt_s <= 0.0 || dt_s > 0.01) {
    return Error{fmt::format("dt_s must lie in (0, 0.01] s, got {}", dt_s)};
  }
  if (jobs < 1 || jobs > 256) {
    return Error{fmt::format("jobs must lie in [1, 256], got {}", jobs)};
  }
  return {};
}

namespace {

// The rig of one force level: `burrlab sim descent`'s rig with the options'
// definition, discretisation and seed.
sim::DescentOptions RigAt(const SyntheticMeasurementOptions& o, double force_n,
                          std::uint64_t seed) {
  sim::DescentOptions rig;
  rig.material = o.material;
  rig.effects = o.effects;
  rig.force_n = force_n;
  rig.radius_mm = o.radius_mm;
  rig.spindle_rad_s = o.spindle_rad_s;
  rig.voxel_mm = o.voxel_mm;
  rig.ell_over_r = o.ell_over_r;
  rig.moment_reuse_over_h = o.moment_reuse_over_h;
  rig.dt_s = o.dt_s;
  rig.seed = seed;
  rig.definition = o.definition;
  // A viscous load (viscous_resistance, eq. 7.14) closes a loop from the
  // commanded velocity straight back into the measured force, with gain
  // k_p c_i R^2 (h/R) per step; above about 1 the force loop oscillates. The
  // rig's gains are detuned as an experimenter would, to keep that gain at
  // 0.3 or below up to full immersion (h = 2R), integral to proportional
  // kept at the default ratio.
  const double c_i =
      o.effects.impact_c_i_n_s_per_mm3 + o.material.c_i_n_s_per_mm3;
  if (c_i > 0.0) {
    const double kp_max = 0.3 / (2.0 * c_i * o.radius_mm * o.radius_mm);
    if (rig.kp_mm_per_n_s > kp_max) {
      rig.ki_mm_per_n_s2 *= kp_max / rig.kp_mm_per_n_s;
      rig.kp_mm_per_n_s = kp_max;
    }
  }
  return rig;
}

}  // namespace

Result<std::vector<sim::DescentSample>> RigTransientTrace(
    const SyntheticMeasurementOptions& o, double force_n, std::uint64_t seed,
    double after_contact_s) {
  if (Status s = o.Validate(); !s.ok()) return s.error();
  if (!(after_contact_s > 0.0 && after_contact_s <= 1000.0)) {
    return Error{fmt::format("after_contact_s must lie in (0, 1000] s, got {}",
                             after_contact_s)};
  }
  // The same rig and seed as the steady run, stopped early with a 10 ms
  // trace: its samples are the steady run's first ones.
  sim::DescentOptions rig = RigAt(o, force_n, seed);
  rig.trace_period_s = 0.01;
  rig.duration_s = after_contact_s;
  rig.run_on_s = after_contact_s;
  Result<sim::DescentResult> result = sim::RunDescent(rig);
  if (!result.ok()) return result.error();
  return std::move(result->trace);
}

Result<double> RigSteadyVelocityMmS(const SyntheticMeasurementOptions& o,
                                    double force_n, std::uint64_t seed,
                                    std::vector<sim::DescentSample>* trace,
                                    std::string* no_velocity_reason) {
  Result<sim::DescentResult> result = sim::RunDescent(RigAt(o, force_n, seed));
  if (!result.ok()) return result.error();
  if (no_velocity_reason) *no_velocity_reason = result->no_velocity_reason;
  if (trace) {
    // 100 Hz through the transient, then the steady run's coarser samples.
    Result<std::vector<sim::DescentSample>> head =
        RigTransientTrace(o, force_n, seed, o.trace_fine_s);
    if (!head.ok()) return head.error();
    *trace = std::move(*head);
    const double t_end = trace->empty() ? -1.0 : trace->back().t_s;
    for (const sim::DescentSample& s : result->trace) {
      if (s.t_s > t_end + 1e-9) trace->push_back(s);
    }
  }
  return result->velocity_mm_s.value_or(0.0);
}

Result<std::vector<double>> RigVelocitiesMmS(
    const SyntheticMeasurementOptions& o,
    std::vector<std::vector<sim::DescentSample>>* traces,
    std::vector<std::string>* no_velocity_reasons) {
  if (Status s = o.Validate(); !s.ok()) return s.error();
  const int levels = static_cast<int>(o.forces_n.size());
  // One slot per level, filled by whichever worker takes it; the first
  // failing level in the given order is the error, whatever `jobs` is.
  std::vector<Result<double>> velocities(levels, 0.0);
  if (traces) traces->assign(levels, {});
  std::vector<std::string> reasons(levels);
  std::atomic<int> next{0};
  std::mutex progress_mutex;
  int done = 0;
  const auto work = [&] {
    for (int level = next++; level < levels; level = next++) {
      velocities[level] = RigSteadyVelocityMmS(
          o, o.forces_n[level], o.seed * 1000 + level,
          traces ? &(*traces)[level] : nullptr, &reasons[level]);
      std::lock_guard<std::mutex> lock(progress_mutex);
      ++done;
      if (o.progress) o.progress(done, levels);
    }
  };
  std::vector<std::thread> workers;
  for (int j = 1; j < std::min(o.jobs, levels); ++j) workers.emplace_back(work);
  work();
  for (std::thread& t : workers) t.join();
  std::vector<double> out;
  for (int level = 0; level < levels; ++level) {
    const Result<double>& v = velocities[level];
    if (!v.ok()) {
      return Error{fmt::format("the rig at {} N: {}", o.forces_n[level],
                               v.error().message)};
    }
    out.push_back(*v > 0.0 ? *v : 0.0);
  }
  if (no_velocity_reasons) *no_velocity_reasons = std::move(reasons);
  return out;
}

SyntheticMeasurement DrawReplicates(const SyntheticMeasurementOptions& o,
                                    const std::vector<double>& rig_mm_s) {
  SyntheticMeasurement out;
  boost::random::mt19937_64 noise_rng(o.seed ^ 0x9e3779b97f4a7c15ULL);
  boost::random::normal_distribution<double> normal;
  const double s = std::sqrt(std::log1p(o.noise_cv * o.noise_cv));
  int run = 0;
  for (std::size_t level = 0; level < o.forces_n.size(); ++level) {
    const double force = o.forces_n[level];
    const double v = level < rig_mm_s.size() ? rig_mm_s[level] : 0.0;
    if (!(v > 0.0)) {
      out.skipped_forces_n.push_back(force);
      out.skipped_reasons.push_back("the rig measured none");
      continue;
    }
    for (int k = 0; k < o.replicates; ++k) {
      const double factor = s > 0.0 ? std::exp(s * normal(noise_rng)) : 1.0;
      out.runs.push_back({++run, force, v * factor, v});
    }
  }
  return out;
}

Result<SyntheticMeasurement> MeasureSynthetic(
    const SyntheticMeasurementOptions& o) {
  std::vector<std::vector<sim::DescentSample>> traces;
  std::vector<std::string> reasons;
  Result<std::vector<double>> rig =
      RigVelocitiesMmS(o, o.keep_traces ? &traces : nullptr, &reasons);
  if (!rig.ok()) return rig.error();
  SyntheticMeasurement m = DrawReplicates(o, *rig);
  m.skipped_reasons.clear();
  for (std::size_t level = 0; level < rig->size(); ++level) {
    if (!((*rig)[level] > 0.0)) m.skipped_reasons.push_back(reasons[level]);
  }
  m.level_traces = std::move(traces);
  return m;
}

std::string FormatTraceCsv(const SyntheticMeasurement& m,
                           const SyntheticMeasurementOptions& o) {
  std::string csv = "run,t_s,force_n,depth_mm\n";
  for (const SyntheticRun& r : m.runs) {
    const auto level =
        std::find(o.forces_n.begin(), o.forces_n.end(), r.force_n) -
        o.forces_n.begin();
    if (level >= static_cast<std::ptrdiff_t>(m.level_traces.size())) continue;
    // The run's own sensor noise.
    boost::random::mt19937_64 rng(o.seed * 0x100000001b3ULL +
                                  static_cast<std::uint64_t>(r.run));
    boost::random::normal_distribution<double> normal;
    for (const sim::DescentSample& s : m.level_traces[level]) {
      const double force_n = s.force_n + o.trace_force_noise_n * normal(rng);
      const double depth_mm = s.depth_mm + o.trace_depth_noise_mm * normal(rng);
      csv += fmt::format("{},{:.4f},{:.6g},{:.6g}\n", r.run, s.t_s, force_n,
                         depth_mm);
    }
  }
  return csv;
}

std::string FormatMeasuredCsv(const SyntheticMeasurement& m,
                              const std::string& material_name,
                              const SyntheticMeasurementOptions& o) {
  std::string csv =
      "run,material,burr_radius_mm,spindle_rad_s,force_n,velocity_mm_s,"
      "velocity_definition\n";
  const std::string_view definition = sim::VelocityDefinitionName(o.definition);
  for (const SyntheticRun& r : m.runs) {
    csv += fmt::format("{},{},{},{},{},{:.9g},{}\n", r.run, material_name,
                       o.radius_mm, o.spindle_rad_s, r.force_n, r.velocity_mm_s,
                       definition);
  }
  return csv;
}

}  // namespace burrlab::analysis
