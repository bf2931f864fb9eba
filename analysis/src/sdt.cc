// d' by closed forms where they exist and by root finding (TOMS 748) on
// Gauss-Kronrod integrals where they do not.
#include "burrlab/analysis/sdt.h"

#include <fmt/format.h>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <cstdint>
#include <exception>
#include <numbers>
#include <optional>
#include <string>

namespace burrlab::analysis {
namespace {

double Z(double p) {
  return boost::math::quantile(boost::math::normal_distribution<double>(), p);
}
double Phi(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }

Status CheckRate(std::string_view what, double rate) {
  if (!(rate > 0.0 && rate < 1.0)) {
    return Error{fmt::format(
        "{} must be in (0, 1), got {} (correct rates of 0 or 1 first, e.g. "
        "to 1/(2N) or 1 - 1/(2N))",
        what, rate)};
  }
  return {};
}

// A root of f on [low, high] to full double precision; nullopt when f does
// not change sign there.
template <typename F>
std::optional<double> Root(F f, double low, double high) {
  const double f_low = f(low), f_high = f(high);
  if (f_low == 0.0) return low;
  if (f_high == 0.0) return high;
  if ((f_low < 0.0) == (f_high < 0.0)) return std::nullopt;
  std::uintmax_t iterations = 200;
  const auto [a, b] = boost::math::tools::toms748_solve(
      f, low, high, f_low, f_high, boost::math::tools::eps_tolerance<double>(),
      iterations);
  return 0.5 * (a + b);
}

}  // namespace

std::string_view SameDifferentModelName(SameDifferentModel model) {
  return model == SameDifferentModel::kDifferencing ? "differencing"
                                                    : "independent-observation";
}

static Result<double> DPrimeYesNoUnchecked(double hit_rate,
                                           double false_alarm_rate) {
  if (Status s = CheckRate("the hit rate", hit_rate); !s.ok()) {
    return s.error();
  }
  if (Status s = CheckRate("the false-alarm rate", false_alarm_rate); !s.ok()) {
    return s.error();
  }
  return Z(hit_rate) - Z(false_alarm_rate);
}

static Result<double> DPrimeMAfcUnchecked(double proportion_correct,
                                          int alternatives) {
  if (alternatives < 2) {
    return Error{
        fmt::format("the number of alternatives m must be at least 2, got {}",
                    alternatives)};
  }
  if (Status s = CheckRate("the proportion correct", proportion_correct);
      !s.ok()) {
    return s.error();
  }
  if (alternatives == 2) return std::numbers::sqrt2 * Z(proportion_correct);
  const double others = alternatives - 1;
  const auto pc = [&](double d) {
    const auto integrand = [&](double x) {
      return std::exp(-0.5 * (x - d) * (x - d)) /
             std::sqrt(2.0 * std::numbers::pi) * std::pow(Phi(x), others);
    };
    // phi(x - d) is below 1e-40 outside d +- 14.
    return boost::math::quadrature::gauss_kronrod<double, 61>::integrate(
        integrand, d - 14.0, d + 14.0, 15, 1e-14);
  };
  const std::optional<double> d =
      Root([&](double x) { return pc(x) - proportion_correct; }, -10.0, 10.0);
  if (!d) {
    return Error{fmt::format("no d' in [-10, 10] gives {} correct in {}-AFC",
                             proportion_correct, alternatives)};
  }
  return *d;
}

static Result<double> DPrimeSameDifferentUnchecked(double hit_rate,
                                                   double false_alarm_rate,
                                                   SameDifferentModel model) {
  if (Status s = CheckRate("the hit rate", hit_rate); !s.ok()) {
    return s.error();
  }
  if (Status s = CheckRate("the false-alarm rate", false_alarm_rate); !s.ok()) {
    return s.error();
  }
  if (model == SameDifferentModel::kIndependentObservation) {
    const double pc_max = Phi((Z(hit_rate) - Z(false_alarm_rate)) / 2.0);
    const double p = std::max(pc_max, 1.0 - pc_max);
    const double d = 2.0 * Z(0.5 * (1.0 + std::sqrt(2.0 * p - 1.0)));
    return pc_max < 0.5 ? -d : d;
  }
  if (hit_rate == false_alarm_rate) return 0.0;
  if (hit_rate < false_alarm_rate) {
    return Error{fmt::format(
        "the differencing model needs the hit rate ({}) to be at least the "
        "false-alarm rate ({})",
        hit_rate, false_alarm_rate)};
  }
  const double k = std::numbers::sqrt2 * Z(false_alarm_rate / 2.0);
  const std::optional<double> d = Root(
      [&](double x) {
        return hit_rate - Phi((k + x) / std::numbers::sqrt2) -
               Phi((k - x) / std::numbers::sqrt2);
      },
      0.0, 10.0);
  if (!d) {
    return Error{fmt::format(
        "no d' in [0, 10] gives a hit rate of {} with a false-alarm rate of {} "
        "under the differencing model",
        hit_rate, false_alarm_rate)};
  }
  return *d;
}

Result<double> DPrimeYesNo(double hit_rate, double false_alarm_rate) {
  // Boost.Math reports domain errors by throwing; none may leave the library.
  try {
    return DPrimeYesNoUnchecked(hit_rate, false_alarm_rate);
  } catch (const std::exception& e) {
    return Error{std::string("DPrimeYesNo: ") + e.what()};
  }
}

Result<double> DPrimeMAfc(double proportion_correct, int alternatives) {
  // Boost.Math reports domain errors by throwing; none may leave the library.
  try {
    return DPrimeMAfcUnchecked(proportion_correct, alternatives);
  } catch (const std::exception& e) {
    return Error{std::string("DPrimeMAfc: ") + e.what()};
  }
}

Result<double> DPrimeSameDifferent(double hit_rate, double false_alarm_rate,
                                   SameDifferentModel model) {
  // Boost.Math reports domain errors by throwing; none may leave the library.
  try {
    return DPrimeSameDifferentUnchecked(hit_rate, false_alarm_rate, model);
  } catch (const std::exception& e) {
    return Error{std::string("DPrimeSameDifferent: ") + e.what()};
  }
}

}  // namespace burrlab::analysis
