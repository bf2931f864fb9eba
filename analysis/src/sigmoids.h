// Private: every sigmoid of psychometric.h as a location-scale family
// F = G((u - m) / s) of a standard distribution G in u = x (Weibull: u = ln x,
// m = ln alpha, s = 1 / beta, G the Gumbel minimum distribution), so the
// likelihood code handles all four alike.
#ifndef BURRLAB_ANALYSIS_SRC_SIGMOIDS_H_
#define BURRLAB_ANALYSIS_SRC_SIGMOIDS_H_

#include "burrlab/analysis/psychometric.h"

namespace burrlab::analysis::detail {

// G(z), 1 - G(z) (computed without cancellation) and G'(z).
struct StandardPoint {
  double f = 0.0;
  double fc = 1.0;
  double density = 0.0;
};
StandardPoint Standard(Sigmoid sigmoid, double z);
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
