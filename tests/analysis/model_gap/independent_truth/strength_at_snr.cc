// Projected SNR and the strength that reaches a target (strength_at_snr.h).
#include "independent_truth/strength_at_snr.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/analysis/model_gap/measured_data.h"

namespace burrlab::analysis::independent_truth {
namespace {

// The base model's RSS of log v on the data of `runs`, through the CSV.
Result<double> BaseRss(const Design& design,
                       const std::vector<MeasuredRunValue>& runs) {
  Result<MeasuredData> data =
      ParseMeasuredData("truth.csv", FormatCsv(design, runs));
  if (!data.ok()) return data.error();
  return BaseModelRss(*data, design.radius_mm);
}

Status CheckCuts(const Design& design, const std::vector<double>& truth) {
  const std::vector<double> forces = design.ForcesN();
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (!(truth[k] > 0.0 && std::isfinite(truth[k]))) {
      return Error{fmt::format("the burr has no settled velocity at {:.4g} N",
                               forces[k])};
    }
  }
  return {};
}

}  // namespace

Result<double> ProjectedSnr(const Design& design,
                            const std::vector<double>& truth_mm_s,
                            const SnrOptions& options) {
  if (Status s = CheckCuts(design, truth_mm_s); !s.ok()) return s.error();
  const double sigma = design.SigmaLogV();
  if (options.definition == SnrDefinition::kNoiseFree) {
    Design quiet = design;
    quiet.noise_cv = 0.0;
    Result<double> rss = BaseRss(quiet, DrawRuns(quiet, truth_mm_s, 1));
    if (!rss.ok()) return rss.error();
    return std::sqrt(*rss / (sigma * sigma));
  }
  double sum = 0.0;
  for (int k = 0; k < options.draws; ++k) {
    const std::vector<MeasuredRunValue> runs = DrawRuns(
        design, truth_mm_s, options.first_seed + static_cast<unsigned>(k));
    double rss_truth = 0.0;
    std::size_t i = 0;
    for (std::size_t level = 0; level < truth_mm_s.size(); ++level) {
      for (int r = 0; r < design.replicates; ++r, ++i) {
        const double e = std::log(runs[i].velocity_mm_s / truth_mm_s[level]);
        rss_truth += e * e;
      }
    }
    Result<double> rss = BaseRss(design, runs);
    if (!rss.ok()) return rss.error();
    sum += (*rss - rss_truth) / (sigma * sigma);
  }
  return std::sqrt(std::max(sum / options.draws + 2.0, 0.0));
}

double NaturalStrength(const Design& design, Mechanism mechanism) {
  const std::vector<double> forces = design.ForcesN();
  const double f_min = *std::min_element(forces.begin(), forces.end());
  const double f_max = *std::max_element(forces.begin(), forces.end());
  const double r = design.radius_mm;
  const double v_top =
      SettledVelocityMmS(TruthFor(design, Mechanism::kNone, 0.0), f_max);
  switch (mechanism) {
    case Mechanism::kNone:
      return 0.0;
    case Mechanism::kPowerCap:
    case Mechanism::kPowerDroop:
      return 1.0 / (v_top * std::numbers::pi * r * r);  // the whole hole
    case Mechanism::kSpindleLinear:
    case Mechanism::kSpindleExponential:
      return 1.0 / f_max;
    case Mechanism::kThresholdHard:
    case Mechanism::kThresholdSoft:
    case Mechanism::kThresholdOffset:
      return 0.5 * f_min;
    case Mechanism::kViscousLinear:
      return f_max / (r * r * v_top);
    case Mechanism::kViscousSqrt:
      return f_max / (r * r * std::sqrt(v_top));
    case Mechanism::kFrictionLinear:
      return design.alpha_per_s / f_max;
    case Mechanism::kFrictionPower:
      return design.alpha_per_s / (f_max * std::sqrt(f_max));
    case Mechanism::kContactSofter:
    case Mechanism::kContactStiffer:
      return 0.1;
    case Mechanism::kPorositySquare:
    case Mechanism::kPorosityPower15:
      return 0.2;
    case Mechanism::kLogBump:
      return 0.3;
  }
  return 1.0;
}

Result<StrengthAtSnr> FindStrengthAtSnr(const Design& design,
                                        Mechanism mechanism, double target,
                                        const SnrOptions& options) {
  // At strength s: the SNR, or nothing when the burr stops cutting at a
  // level (too strong).
  struct Point {
    bool cuts = false;
    double snr = 0.0;
    std::vector<double> truth;
  };
  const auto at = [&](double s) -> Result<Point> {
    Point p;
    p.truth = NoiseFreeVelocitiesMmS(design, TruthFor(design, mechanism, s));
    if (!CheckCuts(design, p.truth).ok()) return p;
    Result<double> snr = ProjectedSnr(design, p.truth, options);
    if (!snr.ok()) return snr.error();
    p.cuts = true;
    p.snr = *snr;
    return p;
  };
  // "Too strong": past the target or past where the burr cuts.
  const auto above = [target](const Point& p) {
    return !p.cuts || p.snr >= target;
  };
  double lo = NaturalStrength(design, mechanism);
  if (!(lo > 0.0)) {
    return Error{fmt::format("{} has no strength", InfoOf(mechanism).name)};
  }
  Result<Point> p_lo = at(lo);
  if (!p_lo.ok()) return p_lo.error();
  double hi = lo;
  Point p_hi = *p_lo;
  constexpr int kDoublings = 40;
  int k = 0;
  if (above(*p_lo)) {
    for (; k < kDoublings && above(*p_lo); ++k) {
      hi = lo;
      p_hi = *p_lo;
      lo *= 0.5;
      p_lo = at(lo);
      if (!p_lo.ok()) return p_lo.error();
    }
  } else {
    for (; k < kDoublings && !above(p_hi); ++k) {
      lo = hi;
      p_lo = p_hi;
      hi *= 2.0;
      Result<Point> p = at(hi);
      if (!p.ok()) return p.error();
      p_hi = *p;
    }
  }
  if (k == kDoublings) {
    return Error{fmt::format("{}: no bracket of SNR {} found",
                             InfoOf(mechanism).name, target)};
  }
  while (hi / lo > 1.001) {
    const double mid = std::sqrt(lo * hi);
    Result<Point> p = at(mid);
    if (!p.ok()) return p.error();
    if (above(*p)) {
      hi = mid;
      p_hi = *p;
    } else {
      lo = mid;
      p_lo = *p;
    }
  }
  if (!p_hi.cuts) {
    return Error{fmt::format(
        "{} reaches a projected SNR of only {:.3g} before the burr stops "
        "cutting at strength {:.4g}",
        InfoOf(mechanism).name, p_lo->snr, hi)};
  }
  StrengthAtSnr out;
  out.strength = hi;
  out.snr = p_hi.snr;
  out.truth_mm_s = p_hi.truth;
  SnrOptions other = options;
  other.definition = SnrDefinition::kNoiseFree;
  Result<double> free_snr = ProjectedSnr(design, p_hi.truth, other);
  other.definition = SnrDefinition::kNoiseAveraged;
  Result<double> averaged_snr = ProjectedSnr(design, p_hi.truth, other);
  if (!free_snr.ok()) return free_snr.error();
  if (!averaged_snr.ok()) return averaged_snr.error();
  out.snr_noise_free = *free_snr;
  out.snr_noise_averaged = *averaged_snr;
  return out;
}

}  // namespace burrlab::analysis::independent_truth
