// The steady-state surrogate of the descent rig: quadrature of the continuum
// profile, a table of y(kappa) and its monotone inverse.
#include "burrlab/analysis/model_gap/descent_surrogate.h"

#include <algorithm>
#include <array>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "burrlab/analysis/model_gap/initial_velocity.h"

namespace burrlab::analysis {
namespace {

constexpr double kPi = std::numbers::pi;

// 16-point Gauss-Legendre nodes and weights on [-1, 1] (positive half).
constexpr std::array<double, 8> kNodes = {
    0.0950125098376374, 0.2816035507792589, 0.4580167776572274,
    0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
    0.9445750230732326, 0.9894009349916499};
constexpr std::array<double, 8> kWeights = {
    0.1894506104550685, 0.1826034150449236, 0.1691565193950025,
    0.1495959888165767, 0.1246289712555339, 0.0951585116824928,
    0.0622535239386479, 0.0271524594117541};

// int_a^b g by 16-point Gauss-Legendre.
template <typename G>
double Gauss(double a, double b, const G& g) {
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double sum = 0.0;
  for (std::size_t k = 0; k < kNodes.size(); ++k) {
    sum +=
        kWeights[k] * (g(mid - half * kNodes[k]) + g(mid + half * kNodes[k]));
  }
  return sum * half;
}

// int_0^length g over panels [2^-(k+1), 2^-k] length, k < 24, and the rest
// near 0: the integrands vary on the scale kappa^(-1/3) near 0. A decreasing
// integrand stops at the first panel where it is negligible.
template <bool kDecreasing, typename G>
double GeometricPanels(double length, const G& g) {
  constexpr int kPanels = 24;
  double lo = std::ldexp(length, -kPanels);
  double sum = Gauss(0.0, lo, g);
  for (int k = 0; k < kPanels; ++k) {
    if (kDecreasing && g(lo) < 1e-18 * sum) break;
    sum += Gauss(lo, 2.0 * lo, g);
    lo *= 2.0;
  }
  return sum;
}

// m0 / R^3 at kappa (R = 1). Columns at distance s from the axis are
// parametrised by w = sqrt(1 - s^2) (s ds = w dw); along a column the erosion
// integral from the entry point z = -w is
// Phi(z) = w^2 (z + w) - (z^3 + w^3) / 3, and rho / rho0 = exp(-kappa Phi).
double M0AtKappa(double kappa) {
  const auto column = [kappa](double w) {
    // int_{-w}^{w} exp(-kappa Phi) dz in d = z + w, panels shrinking towards
    // the entry point where the layer is thin.
    const auto integrand = [kappa, w](double d) {
      const double z = d - w;
      const double phi = w * w * d - (z * z * z + w * w * w) / 3.0;
      return std::exp(-kappa * std::max(phi, 0.0));
    };
    return GeometricPanels<true>(2.0 * w, integrand);
  };
  return 2.0 * kPi *
         GeometricPanels<false>(1.0, [&](double w) { return w * column(w); });
}

// h / R from m0 / R^3 = pi x^2 (1 - x/3) (eq. 7.2), x in [0, 2].
double DepthRatioFromM0(double m0) {
  double lo = 0.0, hi = 2.0;
  for (int i = 0; i < 80; ++i) {
    const double x = 0.5 * (lo + hi);
    (kPi * x * x * (1.0 - x / 3.0) < m0 ? lo : hi) = x;
  }
  return 0.5 * (lo + hi);
}

// ln y against ln kappa on a grid, with Fritsch-Carlson slopes of ln kappa as
// a function of ln y (y decreases with kappa).
class LoadTable {
 public:
  LoadTable() {
    constexpr int kPoints = 241;
    constexpr double kLnKappaMin = -6.0 * std::numbers::ln10 / 2.0;  // 1e-3
    constexpr double kLnKappaMax = 7.0 * std::numbers::ln10;         // 1e7
    for (int i = 0; i < kPoints; ++i) {
      const double ln_kappa =
          kLnKappaMax - (kLnKappaMax - kLnKappaMin) * i / (kPoints - 1);
      ln_kappa_.push_back(ln_kappa);
      ln_y_.push_back(std::log(LoadAtKappa(std::exp(ln_kappa))));
    }
    // Now ln_y_ increases with i. Secants and monotone slopes.
    const std::size_t n = ln_y_.size();
    std::vector<double> secant(n - 1);
    for (std::size_t i = 0; i + 1 < n; ++i) {
      secant[i] = (ln_kappa_[i + 1] - ln_kappa_[i]) / (ln_y_[i + 1] - ln_y_[i]);
    }
    slope_.resize(n);
    slope_[0] = secant[0];
    slope_[n - 1] = secant[n - 2];
    for (std::size_t i = 1; i + 1 < n; ++i) {
      slope_[i] = secant[i - 1] * secant[i] <= 0.0
                      ? 0.0
                      : 2.0 / (1.0 / secant[i - 1] + 1.0 / secant[i]);
    }
  }

  double max_ln_y() const { return ln_y_.back(); }

  // ln kappa and d ln kappa / d ln y at ln y; beyond the table's low end
  // (very slow cutting) the last slope continues.
  void Evaluate(double ln_y, double* ln_kappa, double* slope) const {
    if (ln_y <= ln_y_.front()) {
      *slope = slope_.front();
      *ln_kappa = ln_kappa_.front() + slope_.front() * (ln_y - ln_y_.front());
      return;
    }
    const std::size_t i = static_cast<std::size_t>(
        std::upper_bound(ln_y_.begin(), ln_y_.end(), ln_y) - ln_y_.begin() - 1);
    const std::size_t j = std::min(i, ln_y_.size() - 2);
    const double h = ln_y_[j + 1] - ln_y_[j];
    const double t = std::clamp((ln_y - ln_y_[j]) / h, 0.0, 1.0);
    const double t2 = t * t, t3 = t2 * t;
    const double y0 = ln_kappa_[j], y1 = ln_kappa_[j + 1];
    const double m0 = slope_[j] * h, m1 = slope_[j + 1] * h;
    *ln_kappa = (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * m0 +
                (-2 * t3 + 3 * t2) * y1 + (t3 - t2) * m1;
    *slope = ((6 * t2 - 6 * t) * y0 + (3 * t2 - 4 * t + 1) * m0 +
              (-6 * t2 + 6 * t) * y1 + (3 * t2 - 2 * t) * m1) /
             h;
  }

 private:
  std::vector<double> ln_kappa_, ln_y_, slope_;
};

const LoadTable& Table() {
  static const LoadTable table;
  return table;
}

// ln of the removal area against ln kappa, cubic Hermite with centred-
// difference slopes: the fits evaluate it millions of times, the quadrature
// costs about 400 exponentials.
class RemovalTable {
 public:
  static constexpr double kLnKappaMin = -8.0, kLnKappaMax = 17.0;
  static constexpr int kPoints = 501;

  RemovalTable() {
    for (int i = 0; i < kPoints; ++i) {
      ln_a_.push_back(std::log(RemovalAreaAtKappa(std::exp(LnKappa(i)))));
    }
    const double h = Step();
    slope_.resize(kPoints);
    for (int i = 0; i < kPoints; ++i) {
      const int lo = std::max(i - 1, 0), hi = std::min(i + 1, kPoints - 1);
      slope_[i] = (ln_a_[hi] - ln_a_[lo]) / ((hi - lo) * h);
    }
  }

  // The area at kappa; the quadrature outside the table.
  double Area(double kappa) const {
    const double x = std::log(kappa);
    if (!(x > kLnKappaMin && x < kLnKappaMax)) return RemovalAreaAtKappa(kappa);
    const double h = Step();
    const int j =
        std::min(static_cast<int>((x - kLnKappaMin) / h), kPoints - 2);
    const double t = (x - LnKappa(j)) / h;
    const double t2 = t * t, t3 = t2 * t;
    const double y =
        (2 * t3 - 3 * t2 + 1) * ln_a_[j] + (t3 - 2 * t2 + t) * h * slope_[j] +
        (-2 * t3 + 3 * t2) * ln_a_[j + 1] + (t3 - t2) * h * slope_[j + 1];
    return std::exp(y);
  }

 private:
  static double Step() { return (kLnKappaMax - kLnKappaMin) / (kPoints - 1); }
  static double LnKappa(int i) { return kLnKappaMin + Step() * i; }
  std::vector<double> ln_a_, slope_;
};

double TabulatedRemovalArea(double kappa) {
  static const RemovalTable table;
  return table.Area(kappa);
}

}  // namespace

double LoadAtKappa(double kappa) {
  const double x = DepthRatioFromM0(M0AtKappa(kappa));
  return x * std::sqrt(x);
}

double RemovalAreaAtKappa(double kappa) {
  return 2.0 * kPi * GeometricPanels<false>(1.0, [kappa](double w) {
           return w * -std::expm1(-4.0 / 3.0 * kappa * w * w * w);
         });
}

double MaxSteadyLoad() { return std::exp(Table().max_ln_y()); }

double KappaAtLoad(double load) {
  double ln_kappa = 0.0, slope = 0.0;
  Table().Evaluate(std::log(load), &ln_kappa, &slope);
  return std::exp(ln_kappa);
}

double KappaLogSlopeAtLoad(double load) {
  double ln_kappa = 0.0, slope = 0.0;
  Table().Evaluate(std::log(load), &ln_kappa, &slope);
  return slope;
}

namespace {

// The velocity at elastic force F_e = c_e' R^2 y_e (c_e' the effective
// elastic constant) under `definition`, every erosion effect applied and, for
// the initial velocity, times `transient`; 0 when the blades do not cut, +inf
// beyond full immersion. `depth_ratio`, when given, receives h / R.
double VelocityAtElasticLoad(const DescentSurrogateInput& in,
                             sim::VelocityDefinition definition,
                             double transient, double c_e, double elastic_load,
                             double* depth_ratio) {
  const double r = in.radius_mm;
  const sim::Effects& fx = in.effects;
  const bool initial = definition == sim::VelocityDefinition::kInitial;
  // h / R from F_e = c_e R^2 (h/R)^n (eq. 7.3 with the contact exponent);
  // the settled table is in the Hertz load (h/R)^{3/2}. (The fits call this
  // millions of times: h / R only when asked for or needed.)
  const bool hertz = fx.contact_exponent == 1.5;
  double load = elastic_load, x = 0.0;
  if (initial || !hertz || depth_ratio != nullptr) {
    x = hertz ? std::cbrt(elastic_load * elastic_load)
              : std::pow(elastic_load, 1.0 / fx.contact_exponent);
    if (depth_ratio != nullptr) *depth_ratio = x;
    if (!hertz) load = x * std::sqrt(x);
  }
  if (initial ? x >= 2.0 : load >= MaxSteadyLoad()) {
    return std::numeric_limits<double>::infinity();
  }
  const double elastic_n = c_e * r * r * elastic_load;
  // The erosion profile depends on kappa_eff = scale alpha R / v only, and the
  // load fixes kappa_eff: every effect that scales the rate of eq. 7.12
  // scales v (sim::ErosionRateScale, as the simulator applies it).
  const double scale = sim::ErosionRateScale(fx, elastic_n, in.alpha_per_s);
  if (!(scale > 0.0)) return 0.0;
  const double kappa = initial ? IdealInitialKappa(x) : KappaAtLoad(load);
  double v = scale * in.alpha_per_s * r / kappa;
  if (std::isfinite(fx.max_removal_mm3_per_s)) {
    const double area =
        initial ? InitialRemovalArea(x) : TabulatedRemovalArea(kappa);
    v *= sim::PowerLimitScale(fx, v * r * r * area);
  }
  return initial ? v * transient : v;
}

// The velocity and the elastic share y_e of the load that gives it.
struct Solution {
  double v = 0.0, c_e = 0.0, elastic_load = 0.0;
};

Solution Solve(const DescentSurrogateInput& in,
               sim::VelocityDefinition definition, double transient) {
  const double r = in.radius_mm;
  const sim::Effects& fx = in.effects;
  // Only the elastic force carries the load in steady vertical descent (the
  // cheap friction is horizontal) unless viscous_resistance adds an impact
  // term c_i R^2 (h/R) v (eq. 7.14) to what the load cell reads; the
  // material's own c_i is below 1e-3 of F_e at these speeds and left out.
  const double solid = 1.0 - fx.porosity;
  Solution out;
  out.c_e = in.c_e_n_per_mm2 * solid * solid;
  const double total_load = in.force_n / (out.c_e * r * r);
  out.elastic_load = total_load;
  out.v = VelocityAtElasticLoad(in, definition, transient, out.c_e, total_load,
                                nullptr);
  const double c_i = fx.impact_c_i_n_s_per_mm3;
  if (c_i <= 0.0 || !(out.v > 0.0)) return out;
  // F = c_e R^2 y_e + c_i R^2 (h/R) v(y_e): the root in the elastic share
  // y_e in (0, total_load]; the residual is -F at 0 and not negative at
  // total_load.
  const auto residual = [&](double y_e) {
    double x = 0.0;
    const double v =
        VelocityAtElasticLoad(in, definition, transient, out.c_e, y_e, &x);
    if (!std::isfinite(v)) return std::numeric_limits<double>::infinity();
    // c_i R^2 (h/R) v_ref (v / v_ref)^m, v_ref = 1 mm/s.
    const double resistance =
        fx.viscous_exponent == 1.0 ? v : std::pow(v, fx.viscous_exponent);
    return out.c_e * r * r * y_e + c_i * r * r * x * resistance - in.force_n;
  };
  // Alefeld-Potra-Shi (TOMS 748) where the residual changes sign over the
  // bracket: about 10 residuals to 50 bits where bisection took 48 (the
  // discover fits' viscous candidates spent most of their time here).
  // Otherwise (a resistance that rounds to nothing at the top, a bracket
  // that is not finite) the bisection, which ends at the top.
  const double at_bottom = -in.force_n, at_top = residual(total_load);
  if (at_bottom < 0.0 && at_top > 0.0 && std::isfinite(at_top)) {
    std::uintmax_t iterations = 64;
    const auto [lo, hi] = boost::math::tools::toms748_solve(
        residual, 0.0, total_load, at_bottom, at_top,
        boost::math::tools::eps_tolerance<double>(50), iterations);
    out.elastic_load = 0.5 * (lo + hi);
  } else {
    double lo = 0.0, hi = total_load;
    for (int it = 0; it < 48; ++it) {
      const double mid = 0.5 * (lo + hi);
      (residual(mid) < 0.0 ? lo : hi) = mid;
    }
    out.elastic_load = 0.5 * (lo + hi);
  }
  out.v = VelocityAtElasticLoad(in, definition, transient, out.c_e,
                                out.elastic_load, nullptr);
  return out;
}

}  // namespace

double SteadyVelocityMmS(const DescentSurrogateInput& in) {
  return Solve(in, sim::VelocityDefinition::kSettled, 1.0).v;
}

double SurrogateVelocityMmS(const DescentSurrogateInput& in,
                            sim::VelocityDefinition definition,
                            double transient_factor) {
  return Solve(in, definition, transient_factor).v;
}

double InitialTransientFactor(const DescentSurrogateInput& in) {
  const Solution ideal = Solve(in, sim::VelocityDefinition::kInitial, 1.0);
  if (!(ideal.v > 0.0 && std::isfinite(ideal.v))) return 1.0;
  const double r = in.radius_mm;
  const sim::Effects& fx = in.effects;
  const double x = std::pow(ideal.elastic_load, 1.0 / fx.contact_exponent);
  InitialVelocityInput rig;
  rig.depth_ratio = x;
  rig.force_n = in.force_n;
  rig.elastic_n = ideal.c_e * r * r * ideal.elastic_load;
  rig.contact_exponent = fx.contact_exponent;
  // Every effect on the rate (and the power limit at the window's removal
  // rate) is in the ideal velocity: the rate that gives it.
  rig.rate_per_s = ideal.v * IdealInitialKappa(x) / r;
  rig.radius_mm = r;
  rig.rig.effects = fx;  // the rig's own effects: load-cell lag, compliance
  const double v = InitialVelocityMmS(rig);
  return v > 0.0 ? v / ideal.v : 1.0;
}

}  // namespace burrlab::analysis
