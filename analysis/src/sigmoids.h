// Private: every sigmoid of psychometric.h as a location-scale family
// F = G((u - m) / s) of a standard distribution G in u = x (Weibull: u = ln x,
// m = ln alpha, s = 1 / beta, G the Gumbel minimum distribution), so the
// likelihood code handles all four alike.
#ifndef BURRLAB_ANALYSIS_SRC_SIGMOIDS_H_
#define BURRLAB_ANALYSIS_SRC_SIGMOIDS_H_

#include <cmath>
#include <cstddef>
#include <numbers>

#include "burrlab/analysis/psychometric.h"

namespace burrlab::analysis::detail {

// G(z), 1 - G(z) (computed without cancellation), G'(z) and G''(z).
struct StandardPoint {
  double f = 0.0;
  double fc = 1.0;
  double density = 0.0;
  double density_slope = 0.0;
};
// Inline: the likelihood calls it once per level per evaluation.
inline StandardPoint Standard(Sigmoid sigmoid, double z) {
  StandardPoint p;
  switch (sigmoid) {
    case Sigmoid::kLogistic: {
      // One exponential, of -|z|, serves both tails: 1 / (1 + t) is the
      // larger of G and 1 - G, t / (1 + t) the smaller, both without
      // cancellation or overflow.
      const double t = std::exp(-std::abs(z));
      const double large = 1.0 / (1.0 + t);
      const double small = t * large;
      p.f = z >= 0.0 ? large : small;
      p.fc = z >= 0.0 ? small : large;
      p.density = large * small;
      p.density_slope = p.density * (p.fc - p.f);  // g' = g (1 - 2G)
      break;
    }
    case Sigmoid::kCumulativeNormal:
      p.f = 0.5 * std::erfc(-z / std::numbers::sqrt2);
      p.fc = 0.5 * std::erfc(z / std::numbers::sqrt2);
      p.density = std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
      p.density_slope = -z * p.density;
      break;
    case Sigmoid::kWeibull:
    case Sigmoid::kGumbel: {
      // G(z) = 1 - exp(-exp(z)).
      const double e = std::exp(z);
      p.fc = std::exp(-e);
      p.f = -std::expm1(-e);
      p.density = std::exp(z - e);
      // g = exp(z - e^z); g underflows to 0 long before e^z overflows.
      p.density_slope = p.density == 0.0 ? 0.0 : p.density * (1.0 - e);
      break;
    }
  }
  return p;
}
// Standard() at each of z[0..count), into out: for the logistic the
// exponentials first, then the divisions, so neither waits on the other.
inline void StandardBlock(Sigmoid sigmoid, const double* z, std::size_t count,
                          StandardPoint* out) {
  if (sigmoid != Sigmoid::kLogistic) {
    for (std::size_t j = 0; j < count; ++j) out[j] = Standard(sigmoid, z[j]);
    return;
  }
  for (std::size_t j = 0; j < count; ++j) {
    out[j].density = std::exp(-std::abs(z[j]));  // t, for now
  }
  for (std::size_t j = 0; j < count; ++j) {
    const double t = out[j].density;
    const double large = 1.0 / (1.0 + t);
    const double small = t * large;
    out[j].f = z[j] >= 0.0 ? large : small;
    out[j].fc = z[j] >= 0.0 ? small : large;
    out[j].density = large * small;
    out[j].density_slope = out[j].density * (out[j].fc - out[j].f);
  }
}

// G^-1(cut) for cut in (0, 1).
double StandardInverse(Sigmoid sigmoid, double cut);

// Whether u = ln x (the Weibull) rather than u = x.
inline bool UsesLogLevels(Sigmoid sigmoid) {
  return sigmoid == Sigmoid::kWeibull;
}

struct LocationScale {
  double m = 0.0;  // location in u
  double s = 1.0;  // scale in u, > 0
};
LocationScale ToLocationScale(Sigmoid sigmoid, double alpha, double beta);
// (alpha, beta) of a location and scale in u.
std::array<double, 2> FromLocationScale(Sigmoid sigmoid,
                                        const LocationScale& ls);

// d psi / d(alpha, beta) at a level with z = (u - m) / s and density
// g = G'(z), for the amplitude w = 1 - gamma - lambda.
std::array<double, 2> PsiGradientAlphaBeta(Sigmoid sigmoid, double alpha,
                                           double beta, double z, double g,
                                           double w);

}  // namespace burrlab::analysis::detail

#endif  // BURRLAB_ANALYSIS_SRC_SIGMOIDS_H_
