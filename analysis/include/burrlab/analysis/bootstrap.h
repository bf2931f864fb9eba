// Bootstrap confidence limits from a sample of R bootstrap replicates of a
// statistic: percentile limits and Efron's (1987) bias-corrected and
// accelerated (BCa) limits, computed as psignifit 2.5.6 computes them
// (Davison & Hinkley 1997, sec. 5.3):
//   cpe = #(t* < t) / (R + 1),  z0 = Phi^-1(cpe),
//   a   = mean(s^3) / (6 var(s)^(3/2)),  s_r = score_r . least-favourable dir.
//   BCa level of conf c: Phi(z0 + (z0 + z_c) / (1 - a (z0 + z_c)))
// and a limit at level p is the order statistic at position p (R + 1),
// linearly interpolated between neighbours.
#ifndef BURRLAB_ANALYSIS_BOOTSTRAP_H_
#define BURRLAB_ANALYSIS_BOOTSTRAP_H_

#include <span>
#include <vector>

namespace burrlab::analysis {

// #(samples < estimate) / (R + 1), R = samples.size().
double CumulativeProbabilityEstimate(std::span<const double> samples,
                                     double estimate);

// Efron's acceleration from the scores s_r along the least-favourable
// direction: mean(s^3) / (6 var(s)^(3/2)), var with R - 1; 0 when var is 0.
double BcaAcceleration(std::span<const double> scores);

// The value at cumulative probability `level` of the sorted sample:
// position level (R + 1) counted from 1, linear between order statistics;
// NaN when the position is below 1 or above R.
double BootstrapQuantile(std::span<const double> sorted, double level);

// Efron's BCa level for conf c: Phi(z0 + (z0 + z_c) / (1 - a (z0 + z_c)));
// NaN when the denominator is not positive or z0 is not finite.
double BcaLevel(double z0, double acceleration, double conf);

// Percentile limits at each of `conf` (sorted sample).
std::vector<double> PercentileLimits(std::span<const double> sorted,
                                     std::span<const double> conf);

// BCa limits at each of `conf` from the sorted sample, the bias correction z0
// and the acceleration a; NaN where the adjusted level is not finite or lies
// beyond the sample.
std::vector<double> BcaLimits(std::span<const double> sorted, double z0,
                              double acceleration,
                              std::span<const double> conf);

// Every limit of one statistic from its bootstrap replicates.
struct BootstrapLimits {
  double cpe = 0.0;                // CumulativeProbabilityEstimate
  double bias_z0 = 0.0;            // Phi^-1(cpe); NaN when cpe is 0
  double acceleration = 0.0;       // BcaAcceleration of the scores
  std::vector<double> bca;         // per conf; NaN without scores
  std::vector<double> percentile;  // per conf
};
// From the replicates in any order, their scores along the least-favourable
// direction (same order; empty: no BCa limits) and the estimate from the
// data.
BootstrapLimits ComputeBootstrapLimits(std::span<const double> replicates,
                                       std::span<const double> scores,
                                       double estimate,
                                       std::span<const double> conf);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_BOOTSTRAP_H_
