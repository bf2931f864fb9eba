// The ideal-control continuum descent of initial_velocity.h, part 1: an
// axisymmetric density field on columns parallel to the axis, eroded by
// f = 1 - (r / R)^2 (eq. 7.12) while the burr sinks to keep the moment m0 of
// eq. 7.2 at the cap volume of the held indentation.
#include <algorithm>
#include <array>
#include <boost/math/quadrature/gauss.hpp>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <vector>

#include "burrlab/analysis/model_gap/initial_velocity.h"
#include "continuum_field.h"

namespace burrlab::analysis {
namespace {

constexpr double kContinuumPi = std::numbers::pi;

// 16-point Gauss-Legendre on [-1, 1]: Boost's positive half (nodes and
// weights), mirrored.
using GaussLegendre16 = boost::math::quadrature::gauss<double, 16>;

// exp(-e) for 0 <= e <= kSmallErosion by its Taylor polynomial to e^8: the
// remainder e^9 / 9! is below 6e-18, under half an ulp of the result, and the
// polynomial costs a tenth of a libm exp in the erosion loop.
constexpr double kSmallErosion = 0.05;
inline double ExpOfSmallNegative(double e) {
  double p = 1.0 / 40320.0;
  for (const double inverse_factorial :
       {1.0 / 5040.0, 1.0 / 720.0, 1.0 / 120.0, 1.0 / 24.0, 1.0 / 6.0, 0.5, 1.0,
        1.0}) {
    p = p * -e + inverse_factorial;
  }
  return p;
}

}  // namespace

namespace continuum {

Field::Field(const ContinuumGrid& grid, double depth_ratio, double deepest)
    : dz_(std::min(grid.depth_step, depth_ratio / 60.0)) {
  // Columns farther out than s_max never reach material above `deepest`:
  // w >= 1 - deepest. Equal panels over the rest.
  const double w_min = std::max(0.0, 1.0 - deepest);
  const double width = (1.0 - w_min) / grid.radial_panels;
  for (int p = 0; p < grid.radial_panels; ++p) {
    const double mid = w_min + (p + 0.5) * width, half = 0.5 * width;
    const auto& nodes = GaussLegendre16::abscissa();
    const auto& weights = GaussLegendre16::weights();
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      for (const double sign : {-1.0, 1.0}) {
        const double w = mid + sign * half * nodes[k];
        w_.push_back(w);
        weight_.push_back(2.0 * kContinuumPi * w * half * weights[k]);
      }
    }
  }
  nodes_ = static_cast<int>(std::ceil((deepest + 2.0) / dz_)) + 2;
  rho_.assign(w_.size() * nodes_, 1.0);
  // Fresh columns: the running integral is k dz, all of it in the tail.
  cumulative_.assign(w_.size() * nodes_, 0.0);
  tail_.assign(w_.size(), 0);
  dirty_.assign(w_.size(), {nodes_, -1});
}

double Field::Rho(std::size_t i, double z) const {
  const double u = z / dz_;
  const int k = std::clamp(static_cast<int>(u), 0, nodes_ - 2);
  const double t = u - k;
  // exp(-phi) with phi linear between the nodes.
  return std::pow(NodeRho(i, k), 1.0 - t) * std::pow(NodeRho(i, k + 1), t);
}

double Field::Moment(double c, double* derivative) const {
  double m = 0.0, dm = 0.0;
  for (std::size_t i = 0; i < w_.size(); ++i) {
    const double top = c - w_[i], bottom = c + w_[i];
    if (bottom <= 0.0) continue;
    const double a = std::max(0.0, top);
    // Trapezoid over the nodes inside [a, bottom], exact at both ends.
    double z_prev = a, rho_prev = Rho(i, a), sum = 0.0;
    for (int k = static_cast<int>(std::floor(a / dz_)) + 1;
         k * dz_ < bottom && k < nodes_; ++k) {
      const double z = k * dz_, rho = NodeRho(i, k);
      sum += 0.5 * (rho_prev + rho) * (z - z_prev);
      z_prev = z;
      rho_prev = rho;
    }
    const double rho_bottom = Rho(i, bottom);
    sum += 0.5 * (rho_prev + rho_bottom) * (bottom - z_prev);
    m += weight_[i] * sum;
    dm += weight_[i] * (rho_bottom - (top > 0.0 ? Rho(i, top) : 0.0));
  }
  *derivative = dm;
  return m;
}

double Field::Integral(std::size_t i, double z) const {
  if (z <= 0.0) return 0.0;
  const double u = z / dz_;
  const int k = std::min(static_cast<int>(u), nodes_ - 2);
  const double* cum = &cumulative_[i * nodes_];
  const int tail = tail_[i];
  if (k >= tail) return cum[tail] + (u - tail) * dz_;  // fresh below the tail
  return cum[k] + (u - k) * (cum[k + 1] - cum[k]);
}

double Field::FastMoment(double c) const {
  double m = 0.0;
  for (std::size_t i = 0; i < w_.size(); ++i) {
    const double bottom = c + w_[i];
    if (bottom <= 0.0) continue;
    m += weight_[i] * (Integral(i, bottom) - Integral(i, c - w_[i]));
  }
  return m;
}

void Field::Refresh() {
  for (std::size_t i = 0; i < w_.size(); ++i) {
    auto& [lo, hi] = dirty_[i];
    if (hi < lo) continue;
    const double* rho = &rho_[i * nodes_];
    double* cum = &cumulative_[i * nodes_];
    // Trapezoid between nodes, from the first eroded one down to the deepest
    // ever eroded (the burr can rise between erosions, so material below this
    // round's stretch may have been eroded before); fresh below that.
    const int from = std::max(lo, 1);
    const int last = std::min(std::max(hi + 1, tail_[i]), nodes_ - 1);
    for (int k = from; k <= last; ++k)
      cum[k] = cum[k - 1] + 0.5 * (rho[k - 1] + rho[k]) * dz_;
    tail_[i] = last;
    lo = nodes_;
    hi = -1;
  }
}

void Field::Erode(double c, double dtau) {
  for (std::size_t i = 0; i < w_.size(); ++i) {
    const double w2 = w_[i] * w_[i];
    const int k0 = std::max(0, static_cast<int>(std::ceil((c - w_[i]) / dz_)));
    const int k1 =
        std::min(nodes_ - 1, static_cast<int>(std::floor((c + w_[i]) / dz_)));
    if (k0 > k1) continue;
    double* rho = &rho_[i * nodes_];
    if (w2 * dtau <= kSmallErosion) {
      for (int k = k0; k <= k1; ++k) {
        const double u = k * dz_ - c;
        rho[k] *= ExpOfSmallNegative(std::max(0.0, w2 - u * u) * dtau);
      }
    } else {
      for (int k = k0; k <= k1; ++k) {
        const double u = k * dz_ - c;
        rho[k] *= std::exp(-std::max(0.0, w2 - u * u) * dtau);
      }
    }
    dirty_[i].first = std::min(dirty_[i].first, k0);
    dirty_[i].second = std::max(dirty_[i].second, k1);
  }
}

}  // namespace continuum

ContinuumTrajectory IdealDescent(double x, double until_delta,
                                 const ContinuumGrid& grid) {
  // The cap volume m0 / R^3 = pi x^2 (1 - x / 3) the force holds (eq. 7.2).
  const double target = kContinuumPi * x * x * (1.0 - x / 3.0);
  continuum::Field field(grid, x, x + until_delta);
  // Fresh material: the lowest point at x, the centre at x - 1.
  double c = x - 1.0, tau = 0.0, v = 0.0, dtau = 0.0;
  ContinuumTrajectory out;
  const auto solve = [&](double guess) {
    double centre = guess;
    for (int it = 0; it < 60; ++it) {
      double dm = 0.0;
      const double m = field.Moment(centre, &dm);
      const double step = (m - target) / dm;
      centre -= step;
      if (std::abs(step) < 1e-13) break;
    }
    return centre;
  };
  // The grid's own equilibrium in fresh material (within a fraction of a
  // depth step of x - 1) is delta = 0.
  c = solve(c);
  const double c0 = c;
  out.tau.push_back(0.0);
  out.delta.push_back(0.0);
  // The first step is short enough to find the starting velocity.
  dtau = 1e-6;
  while (out.delta.back() < until_delta) {
    // Erode at the middle of the step (the centre moves at about v).
    field.Erode(c + 0.5 * v * dtau, dtau);
    const double next = solve(c + v * dtau);
    v = (next - c) / dtau;
    c = next;
    tau += dtau;
    out.tau.push_back(tau);
    out.delta.push_back(c - c0);
    dtau = std::min(grid.advance_per_step * field.dz() / std::max(v, 1e-300),
                    4.0 * dtau);
  }
  return out;
}

double TrajectorySlope(const ContinuumTrajectory& tr, double tau1,
                       double tau2) {
  // Moments of the piecewise-linear delta(tau) over [tau1, tau2], segment by
  // segment (Simpson is exact for the quadratic integrands).
  const auto at = [&](double tau) {
    const auto it = std::upper_bound(tr.tau.begin(), tr.tau.end(), tau);
    const std::size_t j = std::clamp<std::size_t>(
        static_cast<std::size_t>(it - tr.tau.begin()), 1, tr.tau.size() - 1);
    const double u = (tau - tr.tau[j - 1]) / (tr.tau[j] - tr.tau[j - 1]);
    return tr.delta[j - 1] + u * (tr.delta[j] - tr.delta[j - 1]);
  };
  std::vector<double> knots{tau1};
  for (double t : tr.tau) {
    if (t > tau1 && t < tau2) knots.push_back(t);
  }
  knots.push_back(tau2);
  double s1 = 0.0, st = 0.0, sd = 0.0, stt = 0.0, std_ = 0.0;
  for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
    const double a = knots[k], b = knots[k + 1], m = 0.5 * (a + b);
    const double da = at(a), db = at(b), dm = 0.5 * (da + db);
    const double h = (b - a) / 6.0;
    s1 += b - a;
    st += h * (a + 4.0 * m + b);
    sd += h * (da + 4.0 * dm + db);
    stt += h * (a * a + 4.0 * m * m + b * b);
    std_ += h * (a * da + 4.0 * m * dm + b * db);
  }
  return (std_ - st * sd / s1) / (stt - st * st / s1);
}

}  // namespace burrlab::analysis
