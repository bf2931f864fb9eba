// Hidden-effect scenarios: truth, noise, distortions, CSV, Discover.
#include "burrlab/analysis/model_gap/discover_scenarios.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_01.hpp>
#include <cmath>
#include <optional>
#include <thread>

#include "burrlab/analysis/model_gap/calibration.h"
#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/analysis/model_gap/synthetic_measurement.h"

namespace burrlab::analysis {
namespace {

// Noise draws behind a projected SNR.
constexpr int kSnrDraws = 48;

SyntheticMeasurementOptions GeneratorOptions(const ScenarioDesign& d,
                                             const sim::Effects& effects) {
  SyntheticMeasurementOptions o;
  o.material = d.material;
  o.effects = effects;
  o.forces_n = d.ForcesN();
  o.replicates = d.replicates;
  o.noise_cv = d.noise_cv;
  o.radius_mm = d.radius_mm;
  o.definition = ScenarioDesign::kDefinition;
  return o;
}

std::vector<double> SurrogateVelocities(const ScenarioDesign& d,
                                        const sim::Effects& effects) {
  std::vector<double> v;
  for (double f : d.ForcesN()) {
    DescentSurrogateInput in;
    in.force_n = f;
    in.c_e_n_per_mm2 = d.material.c_e_n_per_mm2;
    in.alpha_per_s = d.material.alpha_per_s;
    in.radius_mm = d.radius_mm;
    in.effects = effects;
    const double x = SteadyVelocityMmS(in);
    v.push_back(x > 0.0 && std::isfinite(x) ? x : 0.0);
  }
  return v;
}

// The largest strength worth trying for effect `spec` in the design.
double MaxStrength(const ScenarioDesign& d, const sim::EffectSpec& spec) {
  const std::vector<double> forces = d.ForcesN();
  const double f_min = *std::min_element(forces.begin(), forces.end());
  const double f_max = *std::max_element(forces.begin(), forces.end());
  const std::vector<double> v = SurrogateVelocities(d, {});
  const double v_top = v.back() > 0.0 ? v.back() : 1.0;
  const std::string_view id = spec.Family();
  const double r = d.radius_mm;
  const double shape = spec.shape_value;
  if (id == "motor_power_limit") {
    const double load = f_max / (d.material.c_e_n_per_mm2 * r * r);
    return 20.0 / (v_top * r * r * RemovalAreaAtKappa(KappaAtLoad(load)));
  }
  if (id == "spindle_slowdown") return 0.97 / f_max;
  if (id == "cutting_threshold") return 0.9 * f_min;
  if (id == "viscous_resistance") {
    return 3.0 * f_max / (r * r * std::pow(v_top, shape));
  }
  if (id == "friction_erosion") {
    return 20.0 * d.material.alpha_per_s / std::pow(f_max, shape);
  }
  if (id == "contact_exponent") return 0.5;
  if (id == "porosity") return 0.5;
  return 1.0;
}

}  // namespace

std::vector<double> ScenarioDesign::ForcesN() const {
  std::vector<double> f;
  for (double load : loads) {
    f.push_back(load * material.c_e_n_per_mm2 * radius_mm * radius_mm);
  }
  return f;
}

double ScenarioDesign::SigmaLogV() const {
  return std::sqrt(std::log1p(noise_cv * noise_cv));
}

Result<double> ProjectedSnr(const ScenarioDesign& d,
                            const sim::Effects& effects) {
  const std::vector<double> v = SurrogateVelocities(d, effects);
  const std::vector<double> forces = d.ForcesN();
  const double sigma = d.SigmaLogV();
  // Noise draws shared by every strength (common random numbers), so the
  // SNR is a smooth function of the strength for the bisection.
  boost::random::mt19937_64 rng(0x5eed5eedULL);
  boost::random::normal_distribution<double> normal;
  double sum = 0.0;
  for (int draw = 0; draw < kSnrDraws; ++draw) {
    MeasuredData data;
    double rss_truth = 0.0;
    for (std::size_t k = 0; k < v.size(); ++k) {
      if (!(v[k] > 0.0)) continue;
      for (int r = 0; r < d.replicates; ++r) {
        const double e = sigma * normal(rng);
        MeasuredRun run;
        run.force_n = forces[k];
        run.velocity_mm_s = v[k] * std::exp(e);
        data.runs.push_back(run);
        rss_truth += e * e;
      }
      ++data.force_levels;
    }
    Result<double> rss_base = BaseModelRss(data, d.radius_mm);
    if (!rss_base.ok()) return rss_base.error();
    sum += (*rss_base - rss_truth) / (sigma * sigma);
  }
  // E[RSS_base - RSS_truth] / sigma^2 = lambda - 2 for a linear base model;
  // the 2 fitted parameters are added back.
  const double lambda = sum / kSnrDraws + 2.0;
  return std::sqrt(std::max(lambda, 0.0));
}

Result<sim::Effects> EffectAtSnr(const ScenarioDesign& d, const std::string& id,
                                 double target) {
  const sim::EffectSpec* spec = sim::FindEffect(id);
  if (spec == nullptr) return Error{fmt::format("unknown effect '{}'", id)};
  const auto at = [&](double strength) {
    sim::Effects fx;
    sim::ApplyEffect(*spec, sim::ParameterAtStrength(*spec, strength), &fx);
    return fx;
  };
  double lo = 0.0, hi = MaxStrength(d, *spec);
  Result<double> top = ProjectedSnr(d, at(hi));
  if (!top.ok()) return top.error();
  if (*top < target) {
    return Error{fmt::format(
        "{} reaches a projected SNR of only {:.3g} in this design", id, *top)};
  }
  for (int it = 0; it < 30; ++it) {
    const double mid = 0.5 * (lo + hi);
    Result<double> snr = ProjectedSnr(d, at(mid));
    if (!snr.ok()) return snr.error();
    (*snr < target ? lo : hi) = mid;
  }
  return at(hi);
}

Result<std::vector<double>> TruthVelocitiesMmS(const ScenarioDesign& d,
                                               const sim::Effects& effects,
                                               int jobs) {
  if (!d.full_rig) return SurrogateVelocities(d, effects);
  SyntheticMeasurementOptions o = GeneratorOptions(d, effects);
  o.jobs = std::clamp(jobs, 1, 256);
  return RigVelocitiesMmS(o);
}

std::string ScenarioCsv(const ScenarioDesign& d,
                        const std::vector<double>& truth_mm_s,
                        const Distortion& distortion, std::uint64_t seed) {
  SyntheticMeasurementOptions o = GeneratorOptions(d, {});
  o.seed = seed;
  SyntheticMeasurement m = DrawReplicates(o, truth_mm_s);
  const std::vector<double> forces = d.ForcesN();
  const double lo = std::log(*std::min_element(forces.begin(), forces.end()));
  const double hi = std::log(*std::max_element(forces.begin(), forces.end()));
  boost::random::mt19937_64 rng(seed * 7919 + 17);
  boost::random::uniform_01<double> uniform;
  for (SyntheticRun& run : m.runs) {
    if (distortion.bump_log_v != 0.0) {
      const double z =
          (std::log(run.force_n) - 0.5 * (lo + hi)) / ((hi - lo) / 6.0);
      run.velocity_mm_s *= std::exp(distortion.bump_log_v * std::exp(-z * z));
    }
    if (distortion.outlier_fraction > 0.0 &&
        uniform(rng) < distortion.outlier_fraction) {
      run.velocity_mm_s *= uniform(rng) < 0.5 ? distortion.outlier_factor
                                              : 1.0 / distortion.outlier_factor;
    }
  }
  return FormatMeasuredCsv(m, d.material_name, o);
}

Result<ScenarioOutcome> RunScenario(const ScenarioDesign& d,
                                    const std::vector<double>& truth_mm_s,
                                    const Distortion& distortion,
                                    const std::string& expected_id,
                                    std::uint64_t first_seed, int seeds,
                                    const DiscoverOptions& options, int jobs) {
  // One slot per seed, filled by whichever worker takes it and summed in
  // seed order, so the outcome does not depend on `jobs`.
  struct Slot {
    std::optional<Error> error;
    Verdict verdict = Verdict::kNone;
    std::vector<std::string> named;
    bool physical = false, hit = false;
    double cv_before = 0.0, cv_after = 0.0;
    bool held_out_better = false;
  };
  std::vector<Slot> slots(std::max(seeds, 0));
  // A variant (a shape) counts as its family, which is what reports name.
  std::string expected = expected_id;
  if (const sim::EffectSpec* spec = sim::FindEffect(expected_id)) {
    expected = std::string(spec->Family());
  }
  std::atomic<int> next{0};
  const auto work = [&] {
    for (int k = next++; k < seeds; k = next++) {
      Slot& slot = slots[k];
      const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
      const std::string csv = ScenarioCsv(d, truth_mm_s, distortion, seed);
      Result<MeasuredData> data =
          ParseMeasuredData(fmt::format("seed-{}.csv", seed), csv);
      if (!data.ok()) {
        slot.error = data.error();
        continue;
      }
      DiscoverOptions o = options;
      o.radius_mm = d.radius_mm;
      o.definition = ScenarioDesign::kDefinition;
      Result<DiscoverReport> report = Discover(*data, o);
      if (!report.ok()) {
        slot.error = report.error();
        continue;
      }
      slot.verdict = report->verdict;
      slot.physical = report->verdict == Verdict::kNamed ||
                      report->verdict == Verdict::kAmbiguous;
      if (slot.physical) {
        for (const std::vector<std::string>& set : report->alias_sets) {
          slot.named.insert(slot.named.end(), set.begin(), set.end());
        }
        if (slot.named.empty()) slot.named = report->alias_set;
      }
      const bool in_set =
          std::find(report->alias_set.begin(), report->alias_set.end(),
                    expected) != report->alias_set.end();
      const bool first =
          !report->effects.empty() && report->effects[0] == expected;
      slot.hit = !expected.empty() &&
                 ((slot.physical && (first || in_set)) ||
                  (report->verdict == Verdict::kAbsorbed && first));
      slot.cv_before = report->baseline.cv_rmse_log_v;
      slot.cv_after = report->augmented.cv_rmse_log_v;
      slot.held_out_better =
          PredictsHeldOutBetter(report->augmented, report->baseline);
    }
  };
  std::vector<std::thread> workers;
  for (int j = 1; j < std::min(jobs, seeds); ++j) workers.emplace_back(work);
  work();
  for (std::thread& t : workers) t.join();
  ScenarioOutcome out;
  std::uint64_t seed = first_seed;
  for (const Slot& slot : slots) {
    if (slot.error) return *slot.error;
    out.per_seed.push_back({seed++, slot.verdict, slot.named});
    ++out.seeds;
    ++out.verdicts[slot.verdict];
    out.named_physical += slot.physical;
    if (slot.hit) {
      ++out.hits;
      out.mean_cv_before += slot.cv_before;
      out.mean_cv_after += slot.cv_after;
      out.cv_shrank += slot.cv_after < slot.cv_before;
      out.held_out_better += slot.held_out_better;
    }
  }
  if (out.hits > 0) {
    out.mean_cv_before /= out.hits;
    out.mean_cv_after /= out.hits;
  }
  return out;
}

std::vector<std::uint64_t> NamedBeyond(const ScenarioOutcome& scenario,
                                       const ScenarioOutcome& control) {
  std::map<std::uint64_t, bool> control_named;
  for (const SeedOutcome& s : control.per_seed) {
    control_named[s.seed] = !s.named.empty();
  }
  std::vector<std::uint64_t> beyond;
  for (const SeedOutcome& s : scenario.per_seed) {
    const auto it = control_named.find(s.seed);
    if (!s.named.empty() && (it == control_named.end() || !it->second)) {
      beyond.push_back(s.seed);
    }
  }
  return beyond;
}

}  // namespace burrlab::analysis
