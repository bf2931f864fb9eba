// Percentile and BCa bootstrap limits (Efron 1987; Davison & Hinkley 1997,
// sec. 5.3), with psignifit 2.5.6's conventions for the cpe, the
// acceleration estimate and the interpolation between order statistics.
#include "burrlab/analysis/bootstrap.h"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <limits>

#include "non_finite.h"

namespace burrlab::analysis {
namespace {

using detail::kNaN;

double NormalQuantile(double p) {
  if (!(p > 0.0 && p < 1.0)) return kNaN;
  return boost::math::quantile(boost::math::normal_distribution<double>(), p);
}

double NormalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

}  // namespace

double CumulativeProbabilityEstimate(std::span<const double> samples,
                                     double estimate) {
  std::size_t below = 0;
  for (double t : samples) below += t < estimate;
  return static_cast<double>(below) /
         (static_cast<double>(samples.size()) + 1.0);
}

double BcaAcceleration(std::span<const double> scores) {
  const std::size_t count = scores.size();
  if (count < 2) return 0.0;
  double sum = 0.0, sum3 = 0.0;
  for (double s : scores) {
    sum += s;
    sum3 += s * s * s;
  }
  const double mean = sum / static_cast<double>(count);
  double squares = 0.0;
  for (double s : scores) squares += (s - mean) * (s - mean);
  const double variance = squares / static_cast<double>(count - 1);
  if (!(variance > 0.0)) return 0.0;
  return sum3 / static_cast<double>(count) /
         (6.0 * variance * std::sqrt(variance));
}

double BootstrapQuantile(std::span<const double> sorted, double level) {
  const double position = level * (static_cast<double>(sorted.size()) + 1.0);
  if (!std::isfinite(position) || position < 1.0 ||
      position > static_cast<double>(sorted.size())) {
    return kNaN;
  }
  const double below = std::floor(position);
  const auto index = static_cast<std::size_t>(below) - 1;  // 0-based
  if (index + 1 >= sorted.size()) return sorted[index];
  const double fraction = position - below;
  return sorted[index] + fraction * (sorted[index + 1] - sorted[index]);
}

double BcaLevel(double z0, double acceleration, double conf) {
  const double z = z0 + NormalQuantile(conf);
  const double denominator = 1.0 - acceleration * z;
  if (!std::isfinite(z) || !(denominator > 0.0)) return kNaN;
  return NormalCdf(z0 + z / denominator);
}

std::vector<double> PercentileLimits(std::span<const double> sorted,
                                     std::span<const double> conf) {
  std::vector<double> limits;
  limits.reserve(conf.size());
  for (double c : conf) limits.push_back(BootstrapQuantile(sorted, c));
  return limits;
}

std::vector<double> BcaLimits(std::span<const double> sorted, double z0,
                              double acceleration,
                              std::span<const double> conf) {
  std::vector<double> limits;
  limits.reserve(conf.size());
  for (double c : conf) {
    const double level = BcaLevel(z0, acceleration, c);
    limits.push_back(std::isfinite(level) ? BootstrapQuantile(sorted, level)
                                          : kNaN);
  }
  return limits;
}

BootstrapLimits ComputeBootstrapLimits(std::span<const double> replicates,
                                       std::span<const double> scores,
                                       double estimate,
                                       std::span<const double> conf) {
  BootstrapLimits limits;
  std::vector<double> sorted(replicates.begin(), replicates.end());
  // A refit at extreme parameters can give a non-finite value; it sorts to
  // the top.
  for (double& v : sorted) {
    if (std::isnan(v)) v = std::numeric_limits<double>::infinity();
  }
  limits.cpe = CumulativeProbabilityEstimate(sorted, estimate);
  std::sort(sorted.begin(), sorted.end());
  limits.percentile = PercentileLimits(sorted, conf);
  limits.bias_z0 = NormalQuantile(limits.cpe);
  if (scores.empty()) {
    limits.acceleration = kNaN;
    limits.bca.assign(conf.size(), kNaN);
  } else {
    limits.acceleration = BcaAcceleration(scores);
    limits.bca = BcaLimits(sorted, limits.bias_z0, limits.acceleration, conf);
  }
  return limits;
}

}  // namespace burrlab::analysis
