// Designs, noise and CSV of the independent truth (measured_csv.h).
#include "independent_truth/measured_csv.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>

namespace burrlab::analysis::independent_truth {
namespace {

// Spreads consecutive seeds over the generator's state (SplitMix64's
// finaliser), so seeds 1, 2, 3 give unrelated streams.
std::uint64_t Mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace

std::vector<double> Design::ForcesN() const {
  std::vector<double> f;
  for (double load : loads)
    f.push_back(load * c_e_n_per_mm2 * radius_mm * radius_mm);
  return f;
}

double Design::SigmaLogV() const {
  return std::sqrt(std::log1p(noise_cv * noise_cv));
}

Design BoneDesign() { return Design{}; }

Design PvcDesign() {
  Design d;
  d.material_name = "pvc_k70";
  d.c_e_n_per_mm2 = 0.462;
  d.alpha_per_s = 0.296;
  return d;
}

Truth TruthFor(const Design& design, Mechanism mechanism, double strength) {
  Truth t;
  t.c_e_n_per_mm2 = design.c_e_n_per_mm2;
  t.alpha_per_s = design.alpha_per_s;
  t.radius_mm = design.radius_mm;
  t.mechanism = mechanism;
  t.strength = strength;
  const std::vector<double> forces = design.ForcesN();
  const double lo = std::log(*std::min_element(forces.begin(), forces.end()));
  const double hi = std::log(*std::max_element(forces.begin(), forces.end()));
  t.bump_centre_ln_force = 0.5 * (lo + hi);
  t.bump_width_ln_force = hi > lo ? (hi - lo) / 6.0 : 1.0;
  return t;
}

std::vector<double> NoiseFreeVelocitiesMmS(const Design& design,
                                           const Truth& truth) {
  std::vector<double> v;
  for (double f : design.ForcesN()) v.push_back(SettledVelocityMmS(truth, f));
  return v;
}

std::vector<MeasuredRunValue> DrawRuns(const Design& design,
                                       const std::vector<double>& truth_mm_s,
                                       std::uint64_t seed) {
  boost::random::mt19937_64 rng(Mix(seed));
  boost::random::normal_distribution<double> normal;
  const double sigma = design.SigmaLogV();
  const std::vector<double> forces = design.ForcesN();
  std::vector<MeasuredRunValue> runs;
  int run = 0;
  for (std::size_t level = 0; level < forces.size(); ++level) {
    const double v = level < truth_mm_s.size() ? truth_mm_s[level] : 0.0;
    for (int k = 0; k < design.replicates; ++k) {
      const double z = normal(rng);
      if (!(v > 0.0 && std::isfinite(v))) continue;
      runs.push_back({++run, forces[level], v * std::exp(sigma * z)});
    }
  }
  return runs;
}

std::string FormatCsv(const Design& design,
                      const std::vector<MeasuredRunValue>& runs) {
  std::string csv =
      "run,material,burr_radius_mm,force_n,velocity_mm_s,velocity_definition\n";
  for (const MeasuredRunValue& r : runs) {
    csv += fmt::format("{},{},{},{},{:.10g},{}\n", r.run, design.material_name,
                       design.radius_mm, r.force_n, r.velocity_mm_s,
                       design.velocity_definition);
  }
  return csv;
}

std::string MeasuredCsv(const Design& design,
                        const std::vector<double>& truth_mm_s,
                        std::uint64_t seed) {
  return FormatCsv(design, DrawRuns(design, truth_mm_s, seed));
}

}  // namespace burrlab::analysis::independent_truth
