// The four sigmoids of psignifit 2.5.6: values, slopes, inverses and the
// derivatives the BCa method needs, all through the standard location-scale
// forms of sigmoids.h.
#include "sigmoids.h"

#include <boost/math/special_functions/erf.hpp>
#include <cmath>
#include <limits>
#include <numbers>

namespace burrlab::analysis {
namespace detail {

double StandardInverse(Sigmoid sigmoid, double cut) {
  switch (sigmoid) {
    case Sigmoid::kLogistic:
      return std::log(cut / (1.0 - cut));
    case Sigmoid::kCumulativeNormal:
      return -std::numbers::sqrt2 * boost::math::erfc_inv(2.0 * cut);
    case Sigmoid::kWeibull:
    case Sigmoid::kGumbel:
      return std::log(-std::log1p(-cut));
  }
  return std::numeric_limits<double>::quiet_NaN();
}

LocationScale ToLocationScale(Sigmoid sigmoid, double alpha, double beta) {
  if (UsesLogLevels(sigmoid)) return {std::log(alpha), 1.0 / beta};
  return {alpha, beta};
}

std::array<double, 2> FromLocationScale(Sigmoid sigmoid,
                                        const LocationScale& ls) {
  if (UsesLogLevels(sigmoid)) return {std::exp(ls.m), 1.0 / ls.s};
  return {ls.m, ls.s};
}

std::array<double, 2> PsiGradientAlphaBeta(Sigmoid sigmoid, double alpha,
                                           double beta, double z, double g,
                                           double w) {
  if (UsesLogLevels(sigmoid)) {
    // z = beta (ln x - ln alpha).
    return {-w * g * beta / alpha, w * g * z / beta};
  }
  // z = (x - alpha) / beta.
  return {-w * g / beta, -w * g * z / beta};
}

}  // namespace detail

using detail::Standard;
using detail::StandardInverse;
using detail::UsesLogLevels;

std::string_view SigmoidName(Sigmoid sigmoid) {
  switch (sigmoid) {
    case Sigmoid::kLogistic:
      return "logistic";
    case Sigmoid::kCumulativeNormal:
      return "cumnorm";
    case Sigmoid::kWeibull:
      return "weibull";
    case Sigmoid::kGumbel:
      return "gumbel";
  }
  return "?";
}

std::optional<Sigmoid> SigmoidFromName(std::string_view name) {
  for (Sigmoid s : {Sigmoid::kLogistic, Sigmoid::kCumulativeNormal,
                    Sigmoid::kWeibull, Sigmoid::kGumbel}) {
    if (SigmoidName(s) == name) return s;
  }
  return std::nullopt;
}

double SigmoidValue(Sigmoid sigmoid, double x, double alpha, double beta) {
  if (UsesLogLevels(sigmoid) && !(x > 0.0)) return 0.0;
  const detail::LocationScale ls =
      detail::ToLocationScale(sigmoid, alpha, beta);
  const double u = UsesLogLevels(sigmoid) ? std::log(x) : x;
  return Standard(sigmoid, (u - ls.m) / ls.s).f;
}

double SigmoidSlope(Sigmoid sigmoid, double x, double alpha, double beta) {
  if (UsesLogLevels(sigmoid) && !(x > 0.0)) return 0.0;
  const detail::LocationScale ls =
      detail::ToLocationScale(sigmoid, alpha, beta);
  const double u = UsesLogLevels(sigmoid) ? std::log(x) : x;
  const double du_dx = UsesLogLevels(sigmoid) ? 1.0 / x : 1.0;
  return Standard(sigmoid, (u - ls.m) / ls.s).density / ls.s * du_dx;
}

double SigmoidInverse(Sigmoid sigmoid, double cut, double alpha, double beta) {
  const detail::LocationScale ls =
      detail::ToLocationScale(sigmoid, alpha, beta);
  const double u = ls.m + ls.s * StandardInverse(sigmoid, cut);
  return UsesLogLevels(sigmoid) ? std::exp(u) : u;
}

std::array<double, 2> ThresholdGradient(Sigmoid sigmoid, double cut,
                                        double alpha, double beta) {
  const double q = StandardInverse(sigmoid, cut);
  if (UsesLogLevels(sigmoid)) {
    // t = alpha exp(q / beta).
    const double t = alpha * std::exp(q / beta);
    return {t / alpha, -t * q / (beta * beta)};
  }
  // t = alpha + beta q.
  return {1.0, q};
}

std::array<double, 2> SlopeGradient(Sigmoid sigmoid, double cut, double alpha,
                                    double beta) {
  const double q = StandardInverse(sigmoid, cut);
  const double g = Standard(sigmoid, q).density;
  if (UsesLogLevels(sigmoid)) {
    // slope = g beta / t with t = alpha exp(q / beta).
    const double t = alpha * std::exp(q / beta);
    const double slope = g * beta / t;
    return {-slope / alpha, g / t * (1.0 + q / beta)};
  }
  // slope = g / beta.
  return {0.0, -g / (beta * beta)};
}

double Psi(Sigmoid sigmoid, const PsychometricParams& params, double x) {
  return params.gamma + (1.0 - params.gamma - params.lambda) *
                            SigmoidValue(sigmoid, x, params.alpha, params.beta);
}

}  // namespace burrlab::analysis
