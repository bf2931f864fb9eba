// Calibration of c_e and alpha through the steady-state surrogate: variable
// projection of log alpha, bounded multi-start search over log c_e,
// identifiability by SVD and profile likelihood, profile intervals.
#include "burrlab/analysis/model_gap/calibration.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/tools/minima.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <span>

#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/analysis/model_gap/initial_velocity.h"
#include "model_gap/own_factor_fit.h"
#include "non_finite.h"

namespace burrlab::analysis {
namespace {

using detail::kInf;
constexpr int kGridPoints = 240;  // starts of the search over log c_e
// Refits with the initial velocity's transient factors refreshed, at most,
// and the change of their logs that ends them.
constexpr int kTransientRounds = 4;
constexpr double kTransientTolerance = 1e-3;

// The least-squares problem in (L, A) = (log c_e, log alpha). Runs at one
// force share their prediction, so the problem keeps one level per distinct
// force (its runs and their mean log v) and the runs' spread about their
// level's mean: with p_g the prediction at level g,
//   RSS = sum_i (y_i - p_g(i))^2 = within + sum_g n_g (ybar_g - p_g)^2,
// within = sum_i (y_i - ybar_g(i))^2, exactly. An evaluation then costs the
// levels, not the runs, and the initial velocity's transient factor (a
// continuum descent, milliseconds each) is computed once per level whatever
// the order of the runs in the file.
class LogVelocityProblem {
 public:
  LogVelocityProblem(const MeasuredData& data,
                     const CalibrationOptions& options)
      : ln_r_(std::log(options.radius_mm)),
        radius_mm_(options.radius_mm),
        definition_(options.definition) {
    double max_ln_f = -kInf;
    std::map<double, int> level_of_force;
    std::vector<double> ln_v;
    for (const MeasuredRun& run : data.runs) {
      const auto [it, added] = level_of_force.try_emplace(
          run.force_n, static_cast<int>(ln_f_.size()));
      if (added) {
        ln_f_.push_back(std::log(run.force_n));
        runs_at_.push_back(0.0);
        ln_transient_.push_back(0.0);
        max_ln_f = std::max(max_ln_f, ln_f_.back());
      }
      level_of_run_.push_back(it->second);
      runs_at_[static_cast<std::size_t>(it->second)] += 1.0;
      ln_v.push_back(std::log(run.velocity_mm_s));
    }
    set_ln_v(ln_v);
    // Every force must stay below the full-immersion load.
    l_domain_ = max_ln_f - 2.0 * ln_r_ - std::log(MaxSteadyLoad());
    l_min_ = std::max(std::log(options.c_e_min_n_per_mm2), l_domain_ + 1e-9);
    l_max_ = std::log(options.c_e_max_n_per_mm2);
  }

  int runs() const { return static_cast<int>(level_of_run_.size()); }
  int levels() const { return static_cast<int>(ln_f_.size()); }
  // The force level of run i (in the order of the file).
  int LevelOf(int run) const {
    return level_of_run_[static_cast<std::size_t>(run)];
  }
  double RunsAt(int g) const { return runs_at_[static_cast<std::size_t>(g)]; }
  // The full-immersion bound of log c_e (the largest force's).
  double l_domain() const { return l_domain_; }
  double l_min() const { return l_min_; }
  double l_max() const { return l_max_; }

  double Load(int g, double l) const {
    return std::exp(ln_f_[g] - l - 2.0 * ln_r_);
  }
  // Model log v at level g without log alpha: log R - log kappa(load) (the
  // initial velocity's kappa of the ideal window, and its transient factor
  // held).
  double Shape(int g, double l) const {
    if (definition_ == sim::VelocityDefinition::kInitial) {
      const double x = std::cbrt(Load(g, l) * Load(g, l));
      if (!(x < 2.0)) return -kInf;  // past full immersion: unreachable
      return ln_r_ - std::log(IdealInitialKappa(x)) + ln_transient_[g];
    }
    return ln_r_ - std::log(KappaAtLoad(Load(g, l)));
  }
  // d log v / d L = d log kappa / d log load.
  double ShapeSlope(int g, double l) const {
    if (definition_ == sim::VelocityDefinition::kInitial) {
      double slope = 0.0;
      IdealInitialKappa(std::cbrt(Load(g, l) * Load(g, l)), &slope);
      return 2.0 / 3.0 * slope;
    }
    return KappaLogSlopeAtLoad(Load(g, l));
  }
  // The initial velocity's transient factors at (l, a), held from now on;
  // returns the largest change of their logs.
  double RefreshTransient(double l, double a) {
    double change = 0.0;
    for (int g = 0; g < levels(); ++g) {
      DescentSurrogateInput in;
      in.force_n = std::exp(ln_f_[g]);
      in.c_e_n_per_mm2 = std::exp(l);
      in.alpha_per_s = std::exp(a);
      in.radius_mm = radius_mm_;
      const double ln = std::log(InitialTransientFactor(in));
      change = std::max(change, std::abs(ln - ln_transient_[g]));
      ln_transient_[g] = ln;
    }
    return change;
  }
  // Model log v at level g.
  double PredictLogV(int g, double l, double a) const {
    return a + Shape(g, l);
  }

  double Rss(double l, double a) const {
    double rss = within_;
    for (int g = 0; g < levels(); ++g) {
      const double r = mean_ln_v_[g] - PredictLogV(g, l, a);
      rss += runs_at_[g] * r * r;
    }
    return rss;
  }
  // The best log alpha for log c_e = l: the mean offset over the runs. alpha
  // has no box: a box would cut the valley of a non-identifiable fit and
  // fake a closed profile.
  double BestA(double l) const {
    double sum = 0.0;
    for (int g = 0; g < levels(); ++g) {
      sum += runs_at_[g] * (mean_ln_v_[g] - Shape(g, l));
    }
    return sum / runs();
  }
  double ProfileRss(double l) const { return Rss(l, BestA(l)); }
  // Replaces the measured log velocities, one per run (parametric bootstrap):
  // the levels' means, then the runs' spread about them.
  void set_ln_v(std::span<const double> ln_v) {
    mean_ln_v_.assign(ln_f_.size(), 0.0);
    for (std::size_t i = 0; i < ln_v.size(); ++i) {
      mean_ln_v_[level_of_run_[i]] += ln_v[i];
    }
    for (std::size_t g = 0; g < mean_ln_v_.size(); ++g) {
      mean_ln_v_[g] /= runs_at_[g];
    }
    within_ = 0.0;
    for (std::size_t i = 0; i < ln_v.size(); ++i) {
      const double d = ln_v[i] - mean_ln_v_[level_of_run_[i]];
      within_ += d * d;
    }
  }

 private:
  // Per level: log force, runs, mean log v, log transient factor.
  std::vector<double> ln_f_, runs_at_, mean_ln_v_, ln_transient_;
  std::vector<int> level_of_run_;
  double within_ = 0.0;  // sum of squares of the runs about their level
  double ln_r_, radius_mm_, l_domain_ = 0.0, l_min_ = 0.0, l_max_ = 0.0;
  sim::VelocityDefinition definition_;
};

// Minimises f over [lo, hi]: a grid of starts, Brent's method (to `bits` of
// precision) from every local minimum of the grid. Returns the argmin.
double MinimiseOnInterval(const std::function<double(double)>& f, double lo,
                          double hi, int points, double* value, int bits = 40) {
  std::vector<double> x(points), y(points);
  for (int k = 0; k < points; ++k) {
    x[k] = lo + (hi - lo) * k / (points - 1);
    y[k] = f(x[k]);
  }
  double best_x = x[0], best_y = kInf;
  for (int k = 0; k < points; ++k) {
    const bool local =
        (k == 0 || y[k] <= y[k - 1]) && (k == points - 1 || y[k] <= y[k + 1]);
    if (!local || !std::isfinite(y[k])) continue;
    const double a = x[std::max(k - 1, 0)], b = x[std::min(k + 1, points - 1)];
    const auto [xm, ym] = boost::math::tools::brent_find_minima(f, a, b, bits);
    const double cx = ym < y[k] ? xm : x[k], cy = std::min(ym, y[k]);
    if (cy < best_y) {
      best_y = cy;
      best_x = cx;
    }
  }
  *value = best_y;
  return best_x;
}

// The initial velocity's fit: the transient factors are held at the fit and
// refreshed, refitting, until they stop moving. Near full immersion the
// factor moves so fast with c_e (PVC at 3 N, R = 2 mm: 1.34 at c_e 0.462,
// 1.75 at 0.42) that the held-factor refits cycle instead: then the fit is a
// search of (log c_e, log alpha) with the factors computed at every point
// (BOBYQA, about a hundred points of milliseconds per level), from the
// point of the rounds that fitted best with its own factors and from the
// best point of a scan of log c_e up from the full-immersion bound
// (own_factor_fit.h: the search alone can stop on a flat valley far from the
// minimum).
void FitWithTransient(LogVelocityProblem& problem,
                      const std::function<double(double)>& profile_l,
                      double* l_hat, double* rss_min) {
  double best_rss = kInf, best_l = *l_hat, best_a = problem.BestA(*l_hat);
  for (int round = 0; round < kTransientRounds; ++round) {
    const double a = problem.BestA(*l_hat);
    const double change = problem.RefreshTransient(*l_hat, a);
    const double rss = problem.Rss(*l_hat, a);  // with the point's own factors
    if (rss < best_rss) {
      best_rss = rss;
      best_l = *l_hat;
      best_a = a;
    }
    if (change < kTransientTolerance) return;
    *l_hat = MinimiseOnInterval(profile_l, problem.l_min(), problem.l_max(),
                                kGridPoints, rss_min);
  }
  detail::OwnFactorProblem own;
  own.held_alpha = [&problem](double l) { return problem.BestA(l); };
  own.own_rss = [&problem](double l, double a) {
    problem.RefreshTransient(l, a);
    return problem.Rss(l, a);
  };
  own.l_bound = problem.l_domain();
  own.l_lower = problem.l_min();
  own.l_upper = problem.l_max();
  const detail::OwnFactorMinimum found =
      detail::FitWithOwnFactors(own, {best_l, best_a});
  const std::array<double, 2> at = found.rss < best_rss
                                       ? std::array<double, 2>{found.l, found.a}
                                       : std::array<double, 2>{best_l, best_a};
  // Hold the factors of the point found; alpha is then the closed form's,
  // which moves it by less than the factors' own change.
  problem.RefreshTransient(at[0], at[1]);
  *l_hat = at[0];
  *rss_min = problem.ProfileRss(*l_hat);
}

// The end of the profile interval on one side of `at` (direction +1 or -1):
// where `rss` first exceeds `threshold` on the way to `bound`; nullopt when it
// never does (the interval is open on that side).
std::optional<double> ProfileEnd(const std::function<double(double)>& rss,
                                 double at, double bound, double threshold) {
  const double direction = bound > at ? 1.0 : -1.0;
  double inside = at, step = 0.01;
  while (true) {
    double next = inside + direction * step;
    if ((next - bound) * direction >= 0.0) next = bound;
    if (rss(next) > threshold) {
      double lo = inside, hi = next;  // rss(lo) <= threshold < rss(hi)
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (rss(mid) > threshold ? hi : lo) = mid;
      }
      return 0.5 * (lo + hi);
    }
    if (next == bound) return std::nullopt;
    inside = next;
    step *= 1.6;
  }
}

std::optional<Interval> ProfileInterval(
    const std::function<double(double)>& rss, double at, double lo_bound,
    double hi_bound, double threshold) {
  const std::optional<double> lo = ProfileEnd(rss, at, lo_bound, threshold);
  const std::optional<double> hi = ProfileEnd(rss, at, hi_bound, threshold);
  if (!lo || !hi) return std::nullopt;
  return Interval{std::exp(*lo), std::exp(*hi)};
}

// The profile of one parameter (log c_e, log alpha or the combination) on a
// problem whose transient factors are held: `rss` its profile RSS at a value,
// `point` the (log c_e, log alpha) where that profile value is attained.
// alpha's and the combination's minimise over log c_e in [l_lo, l_hi].
struct HeldProfile {
  std::function<double(const LogVelocityProblem&, double, double, double)> rss;
  std::function<std::array<double, 2>(const LogVelocityProblem&, double, double,
                                      double)>
      point;
};

// The initial velocity's profile interval with each end's own transient
// factors. The fit holds the factors at the fit; an interval end lies
// elsewhere, where they differ (PVC near full immersion, R = 2 mm: the c_e
// interval [0.453, 0.618] with the fit's factors, and at 0.618 the RSS with
// its own factors is 2.2 times the threshold). Each end starts from the
// held-factor end; the profile is then evaluated with the factors of the
// profile point itself (found with held factors and refreshed twice:
// milliseconds per level each time) and the crossing bracketed and found to
// kEndTolerance in log units. alpha's and the combination's profiles
// minimise over log c_e in [l_lo, l_hi], the c_e interval with its own
// factors widened by its width on each side: beyond it the held factors are
// stale and make spurious minima.
constexpr double kEndTolerance = 3e-4;

// `limits`, where given, cap the held-factor start on that side (a ridge of
// the own-factor profile that the held one does not see); the end then lies
// between `at` and the limit, at the limit when the profile stays below the
// threshold up to it.
std::optional<Interval> ProfileIntervalOwnFactors(
    const LogVelocityProblem& problem, const HeldProfile& profile, double at,
    double lo_bound, double hi_bound, double threshold, double l_lo,
    double l_hi, const std::array<std::optional<double>, 2>& limits = {}) {
  const std::function<double(double)> held = [&](double x) {
    return profile.rss(problem, x, l_lo, l_hi);
  };
  LogVelocityProblem own = problem;
  const auto own_rss = [&](double x) {
    std::array<double, 2> p = profile.point(problem, x, l_lo, l_hi);
    own.RefreshTransient(p[0], p[1]);
    p = profile.point(own, x, l_lo, l_hi);
    own.RefreshTransient(p[0], p[1]);
    return profile.rss(own, x, l_lo, l_hi);
  };
  std::array<std::optional<double>, 2> ends;
  const std::array<double, 2> bounds = {lo_bound, hi_bound};
  for (int side = 0; side < 2; ++side) {
    std::optional<double> start = ProfileEnd(held, at, bounds[side], threshold);
    const double direction = bounds[side] > at ? 1.0 : -1.0;
    const bool limited =
        limits[side] && (!start || (*start - *limits[side]) * direction > 0.0);
    if (limited) start = limits[side];
    if (!start) return std::nullopt;
    // At the fit the own factors are the held ones.
    double inside = at, outside = *start, step = std::abs(*start - at);
    double f_in = held(at) - threshold, f_out = own_rss(outside) - threshold;
    // Where the factors hardly vary the held end is the own one; a limit the
    // profile stays below is the end.
    if (limited ? !(f_out > 0.0) : std::abs(f_out) <= 1e-3 * threshold) {
      ends[side] = outside;
      continue;
    }
    // Walk out until the own-factor profile exceeds the threshold.
    while (!(f_out > 0.0)) {
      if (outside == bounds[side]) return std::nullopt;
      inside = outside;
      f_in = f_out;
      step *= 1.6;
      outside = inside + direction * step;
      if ((outside - bounds[side]) * direction >= 0.0) outside = bounds[side];
      f_out = own_rss(outside) - threshold;
    }
    // The crossing by the Illinois variant of false position (the profile is
    // smooth: a few points instead of bisection's dozen).
    int kept = 0;  // which end the last step kept: -1 inside, +1 outside
    double end = 0.5 * (inside + outside);
    for (int it = 0; it < 20 && std::abs(outside - inside) > kEndTolerance;
         ++it) {
      end = outside - f_out * (outside - inside) / (f_out - f_in);
      const double f = own_rss(end) - threshold;
      if (std::abs(f) <= 1e-6 * threshold) break;
      if (f > 0.0) {
        outside = end;
        f_out = f;
        if (kept == 1) f_in *= 0.5;
        kept = 1;
      } else {
        inside = end;
        f_in = f;
        if (kept == -1) f_out *= 0.5;
        kept = -1;
      }
    }
    ends[side] = end;
  }
  return Interval{std::exp(*ends[0]), std::exp(*ends[1])};
}

// Another minimum of the c_e profile (CalibrationSummary::second_minimum).
// Candidates are the local minima of the held-factor profile on a grid over
// the box outside the fit's basin (the stretch between the grid's local
// maxima around the fit), each refined over its own basin on `profile`: for
// the initial velocity the profile with each point's own transient factors,
// since the held one is stale away from the fit (a bone design, R = 1 mm,
// loads 0.7-1.45: the held profile's other minimum at c_e 1.80, RSS 0.0494;
// with own factors at 2.02, 0.0441). A candidate counts when its minimum is
// interior to its basin, `profile` at the ridge between it and the fit lies
// above both (so there are two minima), and its RSS is within `threshold`.
struct OtherMinimum {
  double l = 0.0, rss = 0.0;
  double ridge = 0.0;  // a point between it and the fit where profile is above
};
std::optional<OtherMinimum> FindOtherMinimum(
    const LogVelocityProblem& problem,
    const std::function<double(double)>& profile, double l_hat, double rss_hat,
    double threshold) {
  const double lo = problem.l_min(), hi = problem.l_max();
  const double step = (hi - lo) / (kGridPoints - 1);
  std::vector<double> y(kGridPoints);
  for (int k = 0; k < kGridPoints; ++k)
    y[k] = problem.ProfileRss(lo + step * k);
  // Basin edges: the ends and the grid's local maxima.
  std::vector<int> edges{0};
  for (int k = 1; k + 1 < kGridPoints; ++k) {
    if (y[k] > y[k - 1] && y[k] >= y[k + 1]) edges.push_back(k);
  }
  edges.push_back(kGridPoints - 1);
  // Held-factor candidates, best first; the held profile's bias allows
  // twice the threshold.
  struct Basin {
    int left, right, at;
  };
  std::vector<Basin> basins;
  for (std::size_t b = 0; b + 1 < edges.size(); ++b) {
    const int left = edges[b], right = edges[b + 1];
    if (l_hat >= lo + step * left && l_hat <= lo + step * right) continue;
    const int at = static_cast<int>(
        std::min_element(y.begin() + left, y.begin() + right + 1) - y.begin());
    if (at == left || at == right || !(y[at] <= 2.0 * threshold)) continue;
    basins.push_back({left, right, at});
  }
  std::sort(basins.begin(), basins.end(),
            [&](const Basin& a, const Basin& b) { return y[a.at] < y[b.at]; });
  if (basins.size() > 3) basins.resize(3);  // each costs a refined search
  std::optional<OtherMinimum> best;
  for (const Basin& basin : basins) {
    const double left = lo + step * basin.left, right = lo + step * basin.right;
    double rss = 0.0;
    // To about 1e-4 in log c_e: each point costs two refreshes of the
    // factors.
    const double l = MinimiseOnInterval(profile, left, right, 6, &rss, 14);
    if (!(rss <= threshold) || (best && rss >= best->rss)) continue;
    if (l - left < step || right - l < step) continue;  // not interior
    const double ridge = l < l_hat ? right : left;
    if (!(profile(ridge) > std::max(rss, rss_hat))) continue;
    best = OtherMinimum{l, rss, ridge};
  }
  return best;
}

std::string FormatInterval(const Interval& ci) {
  return fmt::format("[{:.4g}, {:.4g}]", ci[0], ci[1]);
}

}  // namespace

Status CalibrationOptions::Validate() const {
  if (!std::isfinite(radius_mm) || radius_mm <= 0.0) {
    return Error{fmt::format(
        "radius_mm must be a positive finite number of mm, got {}", radius_mm)};
  }
  if (bootstrap_replicates < 0 || bootstrap_replicates > 100000) {
    return Error{
        fmt::format("bootstrap_replicates must lie in [0, 100000], "
                    "got {}",
                    bootstrap_replicates)};
  }
  if (!(confidence > 0.0 && confidence < 1.0)) {
    return Error{
        fmt::format("confidence must lie in (0, 1), got {}", confidence)};
  }
  if (!(c_e_min_n_per_mm2 > 0.0 && c_e_min_n_per_mm2 < c_e_max_n_per_mm2 &&
        std::isfinite(c_e_max_n_per_mm2))) {
    return Error{fmt::format(
        "the c_e box must satisfy 0 < min < max < inf, got [{}, {}]",
        c_e_min_n_per_mm2, c_e_max_n_per_mm2)};
  }
  return {};
}

std::string CombinationName(double exponent) {
  return fmt::format("alpha * c_e^{:.3g}", exponent);
}

Result<CalibrationSummary> Calibrate(const MeasuredData& data,
                                     const CalibrationOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  const int n = static_cast<int>(data.runs.size());
  if (n <= kCalibrationParameters || data.force_levels < 2) {
    return Error{fmt::format(
        "calibration needs more runs than parameters and at least 2 force "
        "levels, got {} runs at {} levels",
        n, data.force_levels)};
  }
  if (Status s =
          CheckVelocityDefinition("measured data", data, options.definition);
      !s.ok()) {
    return s.error();
  }
  LogVelocityProblem problem(data, options);
  if (problem.l_min() >= problem.l_max()) {
    double max_f = 0.0;
    for (const MeasuredRun& run : data.runs)
      max_f = std::max(max_f, run.force_n);
    return Error{fmt::format(
        "the largest force {} N exceeds the full-immersion force c_e R^2 "
        "2^(3/2) of every c_e up to {} N/mm^2 with R = {} mm: no steady "
        "descent in the model",
        max_f, options.c_e_max_n_per_mm2, options.radius_mm)};
  }
  // Fit: log alpha profiled in closed form, bounded multi-start over log c_e.
  const std::function<double(double)> profile_l = [&](double l) {
    return problem.ProfileRss(l);
  };
  double rss_min = 0.0;
  double l_hat = MinimiseOnInterval(profile_l, problem.l_min(), problem.l_max(),
                                    kGridPoints, &rss_min);
  // The initial velocity's transient factors (milliseconds each) are held at
  // the fit and refreshed until they stop moving.
  if (options.definition == sim::VelocityDefinition::kInitial) {
    FitWithTransient(problem, profile_l, &l_hat, &rss_min);
  }
  const double a_hat = problem.BestA(l_hat);

  CalibrationSummary out;
  out.runs = n;
  out.force_levels = data.force_levels;
  out.c_e_n_per_mm2 = std::exp(l_hat);
  out.alpha_per_s = std::exp(a_hat);
  out.rss_log_v = rss_min;
  out.rmse_log_v = std::sqrt(rss_min / n);
  out.sigma_log_v = std::sqrt(rss_min / (n - kCalibrationParameters));
  for (int i = 0; i < n; ++i) {
    out.fitted_velocity_mm_s.push_back(
        std::exp(problem.PredictLogV(problem.LevelOf(i), l_hat, a_hat)));
  }

  // Jacobian of log v with respect to (log c_e, log alpha) and its SVD. The
  // n_g runs of a level share one row; J^T J is that of the levels' rows
  // scaled by sqrt(n_g), which therefore has the runs' singular values.
  const int levels = problem.levels();
  Eigen::MatrixXd jacobian(levels, 2);
  double mean_slope = 0.0;
  for (int g = 0; g < levels; ++g) {
    const double slope = problem.ShapeSlope(g, l_hat);
    const double weight = std::sqrt(problem.RunsAt(g));
    jacobian(g, 0) = weight * slope;
    jacobian(g, 1) = weight;
    mean_slope += problem.RunsAt(g) * slope / n;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian);
  out.singular_values = {svd.singularValues()(0), svd.singularValues()(1)};
  out.condition_number = out.singular_values[1] > 0.0
                             ? out.singular_values[0] / out.singular_values[1]
                             : kInf;

  // Profiles: c_e's is the closed-form one; those of alpha and of the
  // combination psi = log alpha + b log c_e minimise over log c_e.
  const auto profile_over_l = [](const LogVelocityProblem& p,
                                 const std::function<double(double)>& rss_l,
                                 int starts = 80) {
    double value = 0.0;
    MinimiseOnInterval(rss_l, p.l_min(), p.l_max(), starts, &value);
    return value;
  };
  const double b = mean_slope;
  const double psi_hat = a_hat + b * l_hat;

  // Profile likelihood with unknown sigma: the interval holds the values whose
  // profile RSS stays below RSS_min (1 + q / (n - 2)). q = F_{1, n-2}(conf) is
  // exact for a linear model; here c_e is weakly determined and the profile
  // far from quadratic, which makes that q too small (coverage 85-89 % for a
  // nominal 95 %). So q is calibrated by a parametric bootstrap: data drawn
  // from the fit with the fitted sigma, the statistic
  // (RSS_profile(estimate) - RSS_min) / (RSS_min / (n - 2)) per replicate, q
  // its conf quantile per parameter, never below the F quantile.
  const int dof = n - kCalibrationParameters;
  const boost::math::fisher_f_distribution<double> f_dist(1.0, dof);
  const double f_quantile = boost::math::quantile(f_dist, options.confidence);
  std::array<double, 3> quantile = {f_quantile, f_quantile, f_quantile};
  if (options.bootstrap_replicates > 0 && rss_min > 0.0) {
    boost::random::mt19937_64 rng(options.seed);
    boost::random::normal_distribution<double> normal;
    std::array<std::vector<double>, 3> stats;
    LogVelocityProblem replicate = problem;
    std::vector<double> ln_v(n);
    for (int r = 0; r < options.bootstrap_replicates; ++r) {
      for (int i = 0; i < n; ++i) {
        ln_v[i] = problem.PredictLogV(problem.LevelOf(i), l_hat, a_hat) +
                  out.sigma_log_v * normal(rng);
      }
      replicate.set_ln_v(ln_v);
      double rss = 0.0;
      MinimiseOnInterval([&](double l) { return replicate.ProfileRss(l); },
                         replicate.l_min(), replicate.l_max(), 60, &rss);
      if (!(rss > 0.0)) continue;
      const double scale = rss / dof;
      // Replicates are drawn near the fit: fewer starts suffice.
      const double at[3] = {
          replicate.ProfileRss(l_hat),
          profile_over_l(
              replicate, [&](double l) { return replicate.Rss(l, a_hat); }, 40),
          profile_over_l(
              replicate,
              [&](double l) { return replicate.Rss(l, psi_hat - b * l); }, 40)};
      for (int k = 0; k < 3; ++k) {
        stats[k].push_back(std::max(0.0, at[k] - rss) / scale);
      }
    }
    for (int k = 0; k < 3; ++k) {
      if (stats[k].size() < 20) continue;
      std::sort(stats[k].begin(), stats[k].end());
      const std::size_t index = std::min(
          stats[k].size() - 1,
          static_cast<std::size_t>(options.confidence *
                                   static_cast<double>(stats[k].size())));
      quantile[k] = std::max(f_quantile, stats[k][index]);
    }
  }
  out.profile_quantiles = quantile;
  const double rss_floor = std::max(rss_min, 1e-14 * n);
  const auto threshold = [&](int k) {
    return rss_floor * (1.0 + quantile[k] / dof);
  };

  // The intervals' profiles. For the initial velocity each interval end is
  // found with its own transient factors (ProfileIntervalOwnFactors); the
  // bootstrap's quantiles above hold the fit's, a calibration of the
  // statistic that the factors hardly move.
  const auto interval = [&](const HeldProfile& profile, double at, double lo,
                            double hi, double rss_threshold, double l_lo,
                            double l_hi) {
    if (options.definition == sim::VelocityDefinition::kInitial) {
      return ProfileIntervalOwnFactors(problem, profile, at, lo, hi,
                                       rss_threshold, l_lo, l_hi);
    }
    return ProfileInterval(
        [&](double x) { return profile.rss(problem, x, l_lo, l_hi); }, at, lo,
        hi, rss_threshold);
  };
  // Minimises over log c_e in [l_lo, l_hi] at log alpha = a_of_l(log c_e);
  // the argmin to `l`.
  const auto min_over_l = [](const LogVelocityProblem& p,
                             const std::function<double(double)>& a_of_l,
                             double l_lo, double l_hi, double* l) {
    double value = 0.0;
    *l = MinimiseOnInterval([&](double x) { return p.Rss(x, a_of_l(x)); }, l_lo,
                            l_hi, 80, &value);
    return value;
  };
  // A profile over log c_e at a fixed a(l): alpha's (a constant) and the
  // combination's (psi - b l); a_of_l_at(x) is a(l) at the profiled value x.
  using AOfL = std::function<double(double)>;
  const auto over_l = [&](std::function<AOfL(double)> a_of_l_at) {
    return HeldProfile{
        [=](const LogVelocityProblem& p, double x, double l_lo, double l_hi) {
          double l = 0.0;
          return min_over_l(p, a_of_l_at(x), l_lo, l_hi, &l);
        },
        [=](const LogVelocityProblem& p, double x, double l_lo, double l_hi) {
          double l = 0.0;
          min_over_l(p, a_of_l_at(x), l_lo, l_hi, &l);
          return std::array<double, 2>{l, a_of_l_at(x)(l)};
        }};
  };
  const HeldProfile c_e_profile{
      [](const LogVelocityProblem& p, double l, double, double) {
        return p.ProfileRss(l);
      },
      [](const LogVelocityProblem& p, double l, double, double) {
        return std::array<double, 2>{l, p.BestA(l)};
      }};
  const HeldProfile alpha_profile =
      over_l([](double a) { return AOfL([a](double) { return a; }); });
  const HeldProfile psi_profile = over_l([b](double psi) {
    return AOfL([psi, b](double l) { return psi - b * l; });
  });
  out.c_e_ci = interval(c_e_profile, l_hat, problem.l_min(), problem.l_max(),
                        threshold(0), problem.l_min(), problem.l_max());
  const bool initial = options.definition == sim::VelocityDefinition::kInitial;
  if (out.c_e_ci) {
    // A second minimum of c_e's profile inside the confidence set.
    LogVelocityProblem own = problem;
    const std::function<double(double)> c_e_rss = [&](double l) {
      if (!initial) return problem.ProfileRss(l);
      own.RefreshTransient(l, problem.BestA(l));
      own.RefreshTransient(l, own.BestA(l));
      return own.ProfileRss(l);
    };
    if (const std::optional<OtherMinimum> other =
            FindOtherMinimum(problem, c_e_rss, l_hat, rss_min, threshold(0))) {
      c_e_rss(other->l);  // own's factors at the minimum
      const double a = initial ? own.BestA(other->l) : problem.BestA(other->l);
      SecondMinimum second;
      second.c_e_n_per_mm2 = std::exp(other->l);
      second.alpha_per_s = std::exp(a);
      second.rss_log_v = other->rss;
      const bool inside = second.c_e_n_per_mm2 >= (*out.c_e_ci)[0] &&
                          second.c_e_n_per_mm2 <= (*out.c_e_ci)[1];
      if (!inside) {
        // Its own part of the set, found as the fit's is, from the factors
        // at the second minimum.
        LogVelocityProblem there = problem;
        if (initial) there.RefreshTransient(other->l, a);
        // The held profile there need not rise over the ridge toward the
        // fit: the ridge limits that side.
        std::array<std::optional<double>, 2> limits;
        limits[other->ridge > other->l ? 1 : 0] = other->ridge;
        second.c_e_ci =
            initial
                ? ProfileIntervalOwnFactors(there, c_e_profile, other->l,
                                            problem.l_min(), problem.l_max(),
                                            threshold(0), problem.l_min(),
                                            problem.l_max(), limits)
                : ProfileInterval(
                      [&](double l) { return problem.ProfileRss(l); }, other->l,
                      problem.l_min(), problem.l_max(), threshold(0));
      }
      out.second_minimum = second;
    }
  }
  // For the initial velocity, where c_e's interval closes, the others
  // minimise over it widened by its width on each side (see
  // ProfileIntervalOwnFactors); else over the whole box.
  double l_lo = problem.l_min(), l_hi = problem.l_max();
  if (out.c_e_ci && initial) {
    const double lo = std::log((*out.c_e_ci)[0]);
    const double hi = std::log((*out.c_e_ci)[1]);
    l_lo = std::max(problem.l_min(), lo - (hi - lo));
    l_hi = std::min(problem.l_max(), hi + (hi - lo));
  }
  const double span = 30.0;  // e^30: far beyond any plausible interval
  if (out.c_e_ci) {
    out.alpha_ci = interval(alpha_profile, a_hat, a_hat - span, a_hat + span,
                            threshold(1), l_lo, l_hi);
  }
  out.identifiable = out.c_e_ci.has_value() && out.alpha_ci.has_value();
  out.combination_exponent = b;
  out.combination_value = std::exp(psi_hat);
  // The combination keeps the fit's factors (not checked with its ends'
  // own): along it the held-factor minimum over log c_e lies in the flat
  // valley where the factors are stale, and an own-factor search there would
  // cost a refresh per point of the inner search.
  out.combination_ci = ProfileInterval(
      [&](double x) { return psi_profile.rss(problem, x, l_lo, l_hi); },
      psi_hat, psi_hat - span, psi_hat + span, threshold(2));
  const std::string combination = CombinationName(b);
  const std::string combination_text =
      out.combination_ci
          ? fmt::format("{} = {:.4g} ({:.0f} % interval {})", combination,
                        out.combination_value, 100 * options.confidence,
                        FormatInterval(*out.combination_ci))
          : fmt::format("{} = {:.4g}", combination, out.combination_value);
  if (out.identifiable) {
    out.identifiability = fmt::format(
        "v(F) determines c_e and alpha separately (Jacobian condition number "
        "{:.3g}); the best-determined combination is {}.",
        out.condition_number, combination_text);
  } else {
    out.identifiability = fmt::format(
        "v(F) determines only the combination {}: the profile likelihood "
        "of c_e or alpha does not close for c_e between {:.3g} and {:.3g} "
        "N/mm^2 (Jacobian condition number {:.3g}), so c_e and alpha are not "
        "identifiable separately; forces nearer the full-immersion force "
        "c_e R^2 2^(3/2) or an indentation (probe) measurement would "
        "separate them.",
        combination_text, std::exp(problem.l_min()), std::exp(problem.l_max()),
        out.condition_number);
  }
  return out;
}

}  // namespace burrlab::analysis
