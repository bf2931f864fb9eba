// The model-gap workflow: outlier screen, base fit, gap tests, attribution
// over the effect library, augmented fits and their confirmation.
#include "burrlab/analysis/model_gap/discover.h"

#include <fmt/format.h>
#include <nlopt.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/non_central_f.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/statistics/runs_test.hpp>
#include <boost/math/tools/minima.hpp>
#include <boost/random/chi_squared_distribution.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <optional>

#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/analysis/model_gap/trace_gap.h"
#include "burrlab/sim/effects.h"
#include "nlopt_ptr.h"
#include "non_finite.h"

namespace burrlab::analysis {
namespace {

using detail::kInf;
using detail::kNaN;
// Residual charged to a run the model cannot reach (v = 0 or inf), so the
// optimiser stays where every run is modelled.
constexpr double kUnreachableResidual = 30.0;
// The omnibus gap tests' share of the gap family's level (the library's
// focused test has the rest).
constexpr double kOmnibusShare = 0.2;

// The runs a fit uses: log F, log v, level index, file line.
struct Runs {
  std::vector<double> force_n, ln_v;
  std::vector<int> level, line;
  int levels = 0;
  double radius_mm = 1.0;
  int size() const { return static_cast<int>(ln_v.size()); }
};

Runs MakeRuns(const MeasuredData& data, double radius_mm) {
  Runs runs;
  runs.radius_mm = radius_mm;
  std::map<double, int> index;
  for (const MeasuredRun& r : data.runs) index.emplace(r.force_n, 0);
  int k = 0;
  for (auto& [force, i] : index) i = k++;
  runs.levels = k;
  for (const MeasuredRun& r : data.runs) {
    runs.force_n.push_back(r.force_n);
    runs.ln_v.push_back(std::log(r.velocity_mm_s));
    runs.level.push_back(index[r.force_n]);
    runs.line.push_back(r.line);
  }
  return runs;
}

// The model's parameters: log c_e, log alpha and each active effect's
// strength in its unit (strength = u * unit, u of order 1; times the point's
// alpha for an effect whose shape depends on its ratio to alpha).
struct ActiveEffect {
  const sim::EffectSpec* spec = nullptr;
  double unit = 1.0;       // strength per u
  double upper = 1.0;      // largest u
  bool per_alpha = false;  // strength = u * unit * alpha
};

struct Point {
  double ln_c_e = 0.0, ln_alpha = 0.0;
  std::vector<double> u;  // one per active effect
};

double Strength(const ActiveEffect& e, const Point& p, std::size_t k) {
  return p.u[k] * e.unit * (e.per_alpha ? std::exp(p.ln_alpha) : 1.0);
}

sim::Effects MakeEffects(const std::vector<ActiveEffect>& active,
                         const Point& p) {
  sim::Effects effects;
  for (std::size_t k = 0; k < active.size(); ++k) {
    effects.*(active[k].spec->field) =
        sim::ParameterAtStrength(*active[k].spec, Strength(active[k], p, k));
  }
  return effects;
}

std::vector<double> Predict(const Runs& runs,
                            const std::vector<ActiveEffect>& active,
                            const Point& p) {
  const sim::Effects effects = MakeEffects(active, p);
  std::vector<double> y(runs.size());
  for (int i = 0; i < runs.size(); ++i) {
    y[i] = ModelLogVelocity(runs.force_n[i], std::exp(p.ln_c_e),
                            std::exp(p.ln_alpha), runs.radius_mm, effects);
  }
  return y;
}

// RSS over the runs with use[i] (all when `use` is empty).
double Rss(const Runs& runs, const std::vector<ActiveEffect>& active,
           const Point& p, const std::vector<char>& use) {
  const std::vector<double> y = Predict(runs, active, p);
  double rss = 0.0;
  for (int i = 0; i < runs.size(); ++i) {
    if (!use.empty() && !use[i]) continue;
    const double r =
        std::isfinite(y[i]) ? runs.ln_v[i] - y[i] : kUnreachableResidual;
    rss += r * r;
  }
  return rss;
}

// log alpha that best fits the other parameters when log alpha enters
// additively (exact without a power limit; a start otherwise).
double OffsetAlpha(const Runs& runs, const std::vector<ActiveEffect>& active,
                   Point p, const std::vector<char>& use) {
  const std::vector<double> y = Predict(runs, active, p);
  double sum = 0.0;
  int n = 0;
  for (int i = 0; i < runs.size(); ++i) {
    if ((!use.empty() && !use[i]) || !std::isfinite(y[i])) continue;
    sum += runs.ln_v[i] - y[i];
    ++n;
  }
  return n > 0 ? p.ln_alpha + sum / n : p.ln_alpha;
}

struct FitObjective {
  const Runs* runs;
  const std::vector<ActiveEffect>* active;
  const std::vector<char>* use;
  // The best point evaluated: BOBYQA on the power limit's kinked RSS can
  // stop at a point worse than its start, so the search keeps its own best.
  std::vector<double> best_x;
  double best = std::numeric_limits<double>::infinity();
};

double NloptObjective(unsigned n, const double* x, double*, void* data) {
  FitObjective& o = *static_cast<FitObjective*>(data);
  Point p;
  p.ln_c_e = x[0];
  p.ln_alpha = x[1];
  p.u.assign(x + 2, x + n);
  const double rss = Rss(*o.runs, *o.active, p, *o.use);
  if (rss < o.best) {
    o.best = rss;
    o.best_x.assign(x, x + n);
  }
  return rss;
}

// Bounded local fit (NLopt BOBYQA) from each start; the best.
// With `fixed` an index into `active`, that effect's strength stays at each
// start's value (a profile point).
Point FitFromStarts(const Runs& runs, const std::vector<ActiveEffect>& active,
                    const std::vector<Point>& starts,
                    const std::vector<char>& use, const Point& centre,
                    double* rss_out, std::optional<std::size_t> fixed = {}) {
  const unsigned dim = 2 + static_cast<unsigned>(active.size());
  std::vector<double> lower(dim), upper(dim);
  lower[0] = std::log(1e-3);
  upper[0] = std::log(1e3);
  // log alpha: wide, and not only around the current fit, which may sit far
  // along the c_e-alpha valley (e.g. c_e at its box end, alpha huge).
  lower[1] = std::min(centre.ln_alpha - 12.0, std::log(1e-6));
  upper[1] = std::max(centre.ln_alpha + 12.0, std::log(1e6));
  for (std::size_t k = 0; k < active.size(); ++k) {
    lower[2 + k] = 0.0;
    upper[2 + k] = active[k].upper;
  }
  FitObjective objective{&runs, &active, &use, {}, kInf};
  detail::NloptPtr opt(nlopt_create(NLOPT_LN_BOBYQA, dim));
  nlopt_set_lower_bounds(opt.get(), lower.data());
  nlopt_set_upper_bounds(opt.get(), upper.data());
  nlopt_set_min_objective(opt.get(), NloptObjective, &objective);
  nlopt_set_xtol_abs1(opt.get(), 1e-7);
  nlopt_set_ftol_rel(opt.get(), 1e-10);
  nlopt_set_maxeval(opt.get(), 400);
  std::vector<double> step(dim, 0.1);
  for (std::size_t k = 0; k < active.size(); ++k) {
    step[2 + k] = 0.1 * active[k].upper;
  }
  nlopt_set_initial_step(opt.get(), step.data());
  Point best;
  double best_rss = kInf;
  for (const Point& start : starts) {
    std::vector<double> x(dim);
    x[0] = std::clamp(start.ln_c_e, lower[0], upper[0]);
    x[1] = std::clamp(start.ln_alpha, lower[1], upper[1]);
    for (std::size_t k = 0; k < active.size(); ++k) {
      x[2 + k] = std::clamp(start.u[k], 0.0, active[k].upper);
    }
    if (fixed.has_value()) {  // equal bounds: NLopt drops the dimension
      lower[2 + *fixed] = upper[2 + *fixed] = x[2 + *fixed];
      nlopt_set_lower_bounds(opt.get(), lower.data());
      nlopt_set_upper_bounds(opt.get(), upper.data());
    }
    // Steps in the strengths scaled to the start, so a search near a small
    // strength does not begin by jumping across the whole range.
    for (std::size_t k = 0; k < active.size(); ++k) {
      step[2 + k] = std::min(0.1 * active[k].upper,
                             std::max(0.01 * active[k].upper, 0.2 * x[2 + k]));
    }
    nlopt_set_initial_step(opt.get(), step.data());
    objective.best = kInf;
    double value = kInf;
    nlopt_optimize(opt.get(), x.data(), &value);
    if (objective.best < value) {
      value = objective.best;
      x = objective.best_x;
    }
    if (value < best_rss) {
      best_rss = value;
      best.ln_c_e = x[0];
      best.ln_alpha = x[1];
      best.u.assign(x.begin() + 2, x.end());
    }
  }
  *rss_out = best_rss;
  return best;
}

// The largest |change of log v| over the runs that effect `k` of `active`
// makes at u, the others held at p.
double MaxChange(const Runs& runs, const std::vector<ActiveEffect>& active,
                 Point p, std::size_t k, double u,
                 const std::vector<double>& y0) {
  p.u[k] = u;
  const std::vector<double> y = Predict(runs, active, p);
  double change = 0.0;
  for (int i = 0; i < runs.size(); ++i) {
    change =
        std::max(change, std::isfinite(y[i]) ? std::abs(y[i] - y0[i]) : kInf);
  }
  return change;
}

// The u at which effect k changes log v by `target` at most (bisection; the
// upper bound when it never does).
double UForChange(const Runs& runs, const std::vector<ActiveEffect>& active,
                  const Point& p, std::size_t k, double target) {
  const std::vector<double> y0 = Predict(runs, active, p);
  double lo = 0.0, hi = active[k].upper;
  if (MaxChange(runs, active, p, k, hi, y0) <= target) return hi;
  for (int it = 0; it < 30; ++it) {
    const double mid = 0.5 * (lo + hi);
    (MaxChange(runs, active, p, k, mid, y0) > target ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

// Unit and range of an effect's strength for these data at the base fit: the
// strength scale where the effect starts to matter for this design.
ActiveEffect ScaleEffect(const sim::EffectSpec& spec, const Runs& runs,
                         double c_e, double alpha) {
  ActiveEffect e;
  e.spec = &spec;
  const double f_min =
      *std::min_element(runs.force_n.begin(), runs.force_n.end());
  const double f_max =
      *std::max_element(runs.force_n.begin(), runs.force_n.end());
  const double r = runs.radius_mm;
  SteadyDescentInput top;
  top.force_n = f_max;
  top.c_e_n_per_mm2 = c_e;
  top.alpha_per_s = alpha;
  top.radius_mm = r;
  double v_top = SteadyVelocityMmS(top);
  if (!(v_top > 0.0 && std::isfinite(v_top))) v_top = alpha * r;
  const std::string_view id = spec.id;
  if (id == "motor_power_limit") {
    // 1/Q_max in units of 1/Q_top, Q the free removal rate at the top force:
    // the cap binds from u = 1 on.
    const double load = f_max / (c_e * r * r);
    const double q_top = v_top * r * r * RemovalAreaAtKappa(KappaAtLoad(load));
    e.unit = 1.0 / q_top;
    e.upper = 50.0;
  } else if (id == "spindle_slowdown") {
    e.unit = 1.0 / f_max;  // the stall force above the largest force
    e.upper = 0.98;
  } else if (id == "cutting_threshold") {
    e.unit = f_min;  // the threshold below the smallest force
    e.upper = 0.98;
  } else if (id == "viscous_resistance") {
    // c_i R^2 (h/R) v comparable with the top force at u = 1.
    e.unit = f_max / (r * r * v_top);
    e.upper = 5.0;
  } else if (id == "friction_erosion") {
    // The rate alpha + k |F_e| = alpha (1 + u |F_e| / F_max): k relative to
    // the point's own alpha, so that log alpha still enters additively and
    // a strength means one shape whatever the base fit's alpha (which may
    // sit at the end of its box, where k would need many decades less).
    e.unit = 1.0 / f_max;
    e.per_alpha = true;
    e.upper = 50.0;
  } else if (id == "contact_exponent") {
    e.unit = 1.0;
    e.upper = 0.5;  // n down to 1 (fully plastic)
  } else if (id == "porosity") {
    e.unit = 1.0;
    e.upper = 0.9;
  } else {
    e.unit = 1.0;
    e.upper = 1.0;
  }
  return e;
}

// Jacobian of the predictions with respect to (log c_e, log alpha, u...) by
// differences (forward for u at its lower bound).
Eigen::MatrixXd Jacobian(const Runs& runs,
                         const std::vector<ActiveEffect>& active,
                         const Point& p) {
  const int n = runs.size();
  const int dim = 2 + static_cast<int>(active.size());
  Eigen::MatrixXd j(n, dim);
  for (int c = 0; c < dim; ++c) {
    Point lo = p, hi = p;
    double h = 1e-5;
    if (c == 0) {
      lo.ln_c_e -= h;
      hi.ln_c_e += h;
    } else if (c == 1) {
      lo.ln_alpha -= h;
      hi.ln_alpha += h;
    } else {
      h = 1e-5 * active[c - 2].upper;
      if (p.u[c - 2] - h < 0.0) {
        lo.u[c - 2] = p.u[c - 2];
        hi.u[c - 2] = p.u[c - 2] + 2.0 * h;
      } else {
        lo.u[c - 2] -= h;
        hi.u[c - 2] += h;
      }
    }
    const std::vector<double> yl = Predict(runs, active, lo);
    const std::vector<double> yh = Predict(runs, active, hi);
    for (int i = 0; i < n; ++i) {
      const double d = (yh[i] - yl[i]) / (2.0 * h);
      j(i, c) = std::isfinite(d) ? d : 0.0;
    }
  }
  return j;
}

// An orthonormal basis of the column space of J (SVD, numerical rank).
Eigen::MatrixXd ColumnBasis(const Eigen::MatrixXd& j) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeThinU);
  const Eigen::VectorXd& s = svd.singularValues();
  int rank = 0;
  while (rank < s.size() && s(rank) > 1e-9 * s(0)) ++rank;
  return svd.matrixU().leftCols(rank);
}

// P_perp x = x - U U^T x.
Eigen::VectorXd Project(const Eigen::MatrixXd& basis,
                        const Eigen::VectorXd& x) {
  return x - basis * (basis.transpose() * x);
}

// Pure error: within-level sum of squares of `values` and its dof.
void PureError(const Runs& runs, const std::vector<double>& values, double* ss,
               int* dof) {
  std::vector<double> sum(runs.levels, 0.0);
  std::vector<int> count(runs.levels, 0);
  for (int i = 0; i < runs.size(); ++i) {
    sum[runs.level[i]] += values[i];
    ++count[runs.level[i]];
  }
  *ss = 0.0;
  for (int i = 0; i < runs.size(); ++i) {
    const double d = values[i] - sum[runs.level[i]] / count[runs.level[i]];
    *ss += d * d;
  }
  *dof = runs.size() - runs.levels;
}

double FUpper(double f, double d1, double d2) {
  if (!(f > 0.0)) return 1.0;
  return boost::math::cdf(
      boost::math::complement(boost::math::fisher_f_distribution<>(d1, d2), f));
}

// Holm-adjusted p-values (NaN entries stay NaN and do not count).
std::vector<double> Holm(const std::vector<double>& p) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!std::isnan(p[i])) order.push_back(i);
  }
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return p[a] < p[b]; });
  std::vector<double> adjusted(p.size(), kNaN);
  const double m = static_cast<double>(order.size());
  double running = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    running = std::max(
        running, std::min(1.0, (m - static_cast<double>(k)) * p[order[k]]));
    adjusted[order[k]] = running;
  }
  return adjusted;
}

// Single-step max-T adjusted p-values (Westfall & Young 1993) of one-sided
// likelihood-ratio tests whose signed roots are jointly normal under the null
// with correlation `corr` (the cosines of the effects' projected signatures):
// p_k = P(max_j max(z_j, 0) / s >= sqrt(LR_k)), z ~ N(0, corr), s = 1 or,
// when the statistics share a variance estimate with `dof` > 0 degrees of
// freedom, s^2 ~ chi^2_dof / dof (multivariate t), by Monte Carlo
// with a fixed seed so a report is reproducible. Near-aliased effects test
// nearly the same thing, so this is much less conservative than Holm. An
// LR of 0 gets 1.
std::vector<double> MaxTAdjusted(const std::vector<double>& lr,
                                 const Eigen::MatrixXd& corr, int dof) {
  const int m = static_cast<int>(lr.size());
  std::vector<double> adjusted(m, 1.0);
  if (m == 0) return adjusted;
  // A factor L with L L^T = corr; the eigen-decomposition tolerates a
  // rank-deficient (exactly aliased) matrix.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(corr);
  const Eigen::VectorXd values = eig.eigenvalues().cwiseMax(0.0);
  const Eigen::MatrixXd factor =
      eig.eigenvectors() * values.cwiseSqrt().asDiagonal();
  constexpr int kDraws = 20000;
  boost::random::mt19937_64 engine(20261124);
  boost::random::normal_distribution<double> normal;
  boost::random::chi_squared_distribution<double> chi2(dof > 0 ? dof : 1);
  std::vector<int> exceed(m, 0);
  std::vector<double> roots(m);
  for (int k = 0; k < m; ++k) roots[k] = std::sqrt(std::max(lr[k], 0.0));
  Eigen::VectorXd e(m);
  for (int d = 0; d < kDraws; ++d) {
    for (int k = 0; k < m; ++k) e(k) = normal(engine);
    const Eigen::VectorXd z = factor * e;
    const double scale = dof > 0 ? std::sqrt(chi2(engine) / dof) : 1.0;
    const double top = std::max(0.0, z.maxCoeff()) / scale;
    for (int k = 0; k < m; ++k) exceed[k] += top >= roots[k];
  }
  for (int k = 0; k < m; ++k) {
    adjusted[k] = roots[k] > 0.0 ? (exceed[k] + 1.0) / (kDraws + 1.0) : 1.0;
  }
  return adjusted;
}

// The family-wise verdict of the gap tests: Holm over the three omnibus
// tests (NaN ones left out) at a fifth of the level, and the library's
// focused test at four fifths (weighted Bonferroni, so the whole family stays
// at the level): the focused test carries the power against the library's
// shapes, the omnibus tests catch what lies outside it.
void CombineGapTests(GapTests* g, double level) {
  const std::vector<double> adjusted =
      Holm({g->lack_of_fit_p, g->curvature_p, g->runs_p});
  double omnibus = 1.0;
  for (double a : adjusted) {
    if (!std::isnan(a)) omnibus = std::min(omnibus, a);
  }
  g->holm_min_p = std::isnan(g->library_p)
                      ? omnibus
                      : std::min({1.0, omnibus / kOmnibusShare,
                                  g->library_p / (1.0 - kOmnibusShare)});
  g->detected = g->holm_min_p < level;
}

// The residual tests of `g` for a message: "lack of fit p = 0.031,
// curvature p = 0.014, runs p = 0.51; Holm p = 0.042".
std::string DescribeGap(const GapTests& g) {
  std::string text;
  const auto add = [&](const char* name, double p) {
    if (std::isnan(p)) return;
    text += fmt::format("{}{} p = {:.2g}", text.empty() ? "" : ", ", name, p);
  };
  add("lack of fit", g.lack_of_fit_p);
  add("curvature", g.curvature_p);
  add("runs", g.runs_p);
  return fmt::format("{}; Holm p = {:.3g}", text, g.holm_min_p);
}

// The omnibus gap tests on the residuals of a fit with Jacobian `jacobian`
// (lack of fit, curvature, runs); the library's test is added by the caller.
GapTests RunGapTests(const Runs& runs, const std::vector<double>& fitted,
                     const Eigen::MatrixXd& jacobian, double level) {
  const int n = runs.size();
  const int p = static_cast<int>(jacobian.cols());
  GapTests g;
  Eigen::VectorXd r(n);
  std::vector<double> residual(n);
  for (int i = 0; i < n; ++i) residual[i] = r(i) = runs.ln_v[i] - fitted[i];
  const double rss = r.squaredNorm();
  double ss_pe = 0.0;
  int dof_pe = 0;
  PureError(runs, residual, &ss_pe, &dof_pe);
  // Lack of fit (pure error from the replicates).
  const int dof_lof = runs.levels - p;
  g.lack_of_fit_p = kNaN;
  if (dof_pe >= 1 && dof_lof >= 1 && ss_pe > 0.0) {
    g.lack_of_fit_p =
        FUpper(((rss - ss_pe) / dof_lof) / (ss_pe / dof_pe), dof_lof, dof_pe);
  }
  // Curvature: x^2 and x^3 of the standardised log force, projected off the
  // model's Jacobian; an F test of their fit to the residuals.
  g.curvature_p = kNaN;
  const int q = std::min(2, runs.levels - p);
  if (q >= 1) {
    double mean = 0.0, var = 0.0;
    for (int i = 0; i < n; ++i) mean += std::log(runs.force_n[i]) / n;
    for (int i = 0; i < n; ++i) {
      var += std::pow(std::log(runs.force_n[i]) - mean, 2) / n;
    }
    const double sd = var > 0.0 ? std::sqrt(var) : 1.0;
    Eigen::MatrixXd extra(n, q);
    for (int i = 0; i < n; ++i) {
      const double x = (std::log(runs.force_n[i]) - mean) / sd;
      extra(i, 0) = x * x;
      if (q > 1) extra(i, 1) = x * x * x;
    }
    const Eigen::MatrixXd basis = ColumnBasis(jacobian);
    for (int c = 0; c < q; ++c) extra.col(c) = Project(basis, extra.col(c));
    const Eigen::MatrixXd extra_basis = ColumnBasis(extra);
    const int rank = static_cast<int>(extra_basis.cols());
    if (rank >= 1) {
      const double ss_q = (extra_basis.transpose() * r).squaredNorm();
      double sigma2 = 0.0;
      int dof = 0;
      if (dof_pe >= 2 && ss_pe > 0.0) {
        sigma2 = ss_pe / dof_pe;
        dof = dof_pe;
      } else {
        dof = n - p - rank;
        sigma2 = dof > 0 ? (rss - ss_q) / dof : 0.0;
      }
      if (dof >= 1 && sigma2 > 0.0) {
        g.curvature_p = FUpper((ss_q / rank) / sigma2, rank, dof);
      }
    }
  }
  // Runs of residual signs ordered by force (too few runs: a trend).
  g.runs_p = kNaN;
  if (n >= 6) {
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return runs.force_n[a] < runs.force_n[b];
    });
    std::vector<double> sorted;
    for (int i : order) sorted.push_back(residual[i]);
    try {
      const auto [z, two_sided] =
          boost::math::statistics::runs_above_and_below_threshold(sorted, 0.0);
      (void)two_sided;
      if (std::isfinite(z)) {
        g.runs_p = boost::math::cdf(boost::math::normal_distribution<>(), z);
      }
    } catch (const std::exception&) {
      g.runs_p = kNaN;
    }
  }
  g.library_p = kNaN;
  CombineGapTests(&g, level);
  return g;
}

double Aicc(double rss, int n, int parameters) {
  const int k = parameters + 1;  // and sigma
  const double floor = std::max(rss, 1e-300);
  double aicc = n * std::log(floor / n) + 2.0 * k;
  aicc += n - k - 1 > 0 ? 2.0 * k * (k + 1) / (n - k - 1) : kInf;
  return aicc;
}

// p of the likelihood ratio for one parameter on its null boundary: the
// 50:50 mixture of chi^2_0 and chi^2_1 (Self & Liang 1987).
double ChiBarP(double lr) {
  if (!(lr > 0.0)) return 1.0;
  return 0.5 * boost::math::cdf(boost::math::complement(
                   boost::math::chi_squared_distribution<>(1.0), lr));
}

// The whole state of one model in the workflow.
struct Model {
  std::vector<ActiveEffect> active;
  Point point;
  double rss = 0.0;
};

class Workflow {
 public:
  Workflow(const Runs& runs, const DiscoverOptions& options)
      : runs_(runs), options_(options) {}

  // The base fit on the runs with use[i] (all if empty), as calibration.h
  // does it: log alpha profiled in closed form (it enters additively), a
  // bounded search over log c_e (grid, then Brent's method around the best
  // grid point). Fails when every c_e in the box pushes the burr through.
  Result<Point> BaseFit(const std::vector<char>& use) const {
    double max_f = 0.0;
    for (int i = 0; i < runs_.size(); ++i) {
      if (use.empty() || use[i]) max_f = std::max(max_f, runs_.force_n[i]);
    }
    const double r = runs_.radius_mm;
    const double l_min = std::max(
        std::log(1e-3), std::log(max_f / (r * r * MaxSteadyLoad())) + 1e-9);
    const double l_max = std::log(1e3);
    if (l_min >= l_max) {
      return Error{fmt::format(
          "the largest force {} N exceeds the full-immersion force c_e R^2 "
          "2^(3/2) of every c_e up to 1000 N/mm^2 with R = {} mm: no steady "
          "descent in the model",
          max_f, r)};
    }
    const auto profile = [&](double l) {
      Point p;
      p.ln_c_e = l;
      p.ln_alpha = 0.0;
      p.ln_alpha = OffsetAlpha(runs_, {}, p, use);
      return Rss(runs_, {}, p, use);
    };
    constexpr int kGrid = 120;
    double best_l = l_min, best = kInf;
    int best_k = 0;
    for (int k = 0; k < kGrid; ++k) {
      const double l = l_min + (l_max - l_min) * k / (kGrid - 1);
      const double value = profile(l);
      if (value < best) {
        best = value;
        best_l = l;
        best_k = k;
      }
    }
    const double step = (l_max - l_min) / (kGrid - 1);
    const double a = best_k > 0 ? best_l - step : best_l;
    const double b = best_k < kGrid - 1 ? best_l + step : best_l;
    if (b > a) {
      const auto [l, value] =
          boost::math::tools::brent_find_minima(profile, a, b, 40);
      if (value < best) best_l = l;
    }
    Point p;
    p.ln_c_e = best_l;
    p.ln_alpha = 0.0;
    p.ln_alpha = OffsetAlpha(runs_, {}, p, use);
    return p;
  }

  // Fits `active` (the last one new) from `from` (the model without it) over
  // the runs with use[i].
  Model FitAugmented(const std::vector<ActiveEffect>& active, const Point& from,
                     const std::vector<char>& use) const {
    // A grid over the new effect's strength (where it changes log v by 1 %
    // to 80 %, and its upper end), each with the best log c_e of a grid over
    // the whole box and log alpha in closed form: the base fit can sit far
    // along the weakly determined valley (even at the box's end, where v(F)
    // is a power law) and the effect may need the other end. BOBYQA then
    // polishes the three best grid points and the plain start.
    Point base = from;
    base.u.resize(active.size(), 0.0);
    const std::size_t k = active.size() - 1;
    double f_max = 0.0;
    for (double f : runs_.force_n) f_max = std::max(f_max, f);
    const double r = runs_.radius_mm;
    const double l_lo = std::max(
        std::log(1e-3), std::log(f_max / (r * r * MaxSteadyLoad())) - 1.0);
    const double l_hi = std::log(1e3);
    // Profile over the strength: at each strength of the ladder, the best
    // (log c_e, log alpha) from the c_e grid and a 2-D polish. A kinked effect
    // (the power limit's cap) leaves the RSS non-smooth in u, where a 3-D
    // local search from a few points can stop short of the truth.
    // The ladder: strengths where the effect changes log v by 0.5 % to 80 %
    // at the current fit, and fractions of the whole range (the current fit
    // may sit where the effect acts far more strongly than at the truth,
    // e.g. at the end of the c_e box).
    std::vector<double> ladder;
    for (double change : {0.005, 0.01, 0.02, 0.04, 0.07, 0.1, 0.15, 0.2, 0.3,
                          0.4, 0.5, 0.65, 0.8}) {
      ladder.push_back(UForChange(runs_, active, base, k, change));
    }
    for (double fraction : {0.01, 0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.75, 1.0}) {
      ladder.push_back(fraction * active[k].upper);
    }
    // ... and decades below them: an effect scaled by a base fit at the end
    // of the c_e box (alpha ~ 1e6, so friction's unit alpha / F_max is huge)
    // acts at the truth's alpha with a strength many decades below the
    // rungs above.
    for (double fraction = 1e-9; fraction < 5e-3; fraction *= 10.0) {
      ladder.push_back(fraction * active[k].upper);
    }
    std::sort(ladder.begin(), ladder.end());
    ladder.erase(std::unique(ladder.begin(), ladder.end()), ladder.end());
    std::vector<std::pair<double, Point>> profile;
    for (double u : ladder) {
      Point s = base;
      s.u[k] = u;
      constexpr int kCe = 40;
      std::vector<std::pair<double, Point>> grid;
      for (int c = 0; c < kCe; ++c) {
        Point t = s;
        t.ln_c_e = l_lo + (l_hi - l_lo) * c / (kCe - 1);
        t.ln_alpha = OffsetAlpha(runs_, active, t, use);
        grid.emplace_back(Rss(runs_, active, t, use), t);
      }
      std::sort(grid.begin(), grid.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      Point from_base = s;
      from_base.ln_c_e = base.ln_c_e;
      from_base.ln_alpha = OffsetAlpha(runs_, active, from_base, use);
      double rss = 0.0;
      const Point polished = FitFromStarts(
          runs_, active, {grid[0].second, grid[1].second, from_base}, use, from,
          &rss, k);
      profile.emplace_back(rss, polished);
    }
    std::sort(profile.begin(), profile.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Point> starts = {base};
    for (std::size_t g = 0; g < profile.size() && starts.size() < 4; ++g) {
      starts.push_back(profile[g].second);
    }
    Model m;
    m.active = active;
    m.point = FitFromStarts(runs_, active, starts, use, from, &m.rss);
    return m;
  }

  // Leave-one-force-level-out RMSE of log v for `model` (NaN with < 3
  // levels).
  double CrossValidate(const Model& model) const {
    if (runs_.levels < 3) return kNaN;
    double sum = 0.0;
    int count = 0;
    for (int held = 0; held < runs_.levels; ++held) {
      std::vector<char> use(runs_.size());
      for (int i = 0; i < runs_.size(); ++i) use[i] = runs_.level[i] != held;
      Result<Point> base = BaseFit(use);
      if (!base.ok()) return kNaN;
      Point p = *base;
      if (!model.active.empty()) {
        Point start = model.point;
        Point from_base = *base;
        from_base.u = model.point.u;
        from_base.ln_alpha = OffsetAlpha(runs_, model.active, from_base, use);
        double rss = 0.0;
        p = FitFromStarts(runs_, model.active, {start, from_base}, use,
                          model.point, &rss);
      }
      const std::vector<double> y = Predict(runs_, model.active, p);
      for (int i = 0; i < runs_.size(); ++i) {
        if (use[i]) continue;
        const double r =
            std::isfinite(y[i]) ? runs_.ln_v[i] - y[i] : kUnreachableResidual;
        sum += r * r;
        ++count;
      }
    }
    return count > 0 ? std::sqrt(sum / count) : kNaN;
  }

  ModelFit Describe(const Model& m) const {
    ModelFit f;
    f.c_e_n_per_mm2 = std::exp(m.point.ln_c_e);
    f.alpha_per_s = std::exp(m.point.ln_alpha);
    for (std::size_t k = 0; k < m.active.size(); ++k) {
      const double strength = Strength(m.active[k], m.point, k);
      f.effects.emplace_back(m.active[k].spec->id);
      f.strengths.push_back(strength);
      f.effect_values.push_back(
          sim::ParameterAtStrength(*m.active[k].spec, strength));
    }
    f.parameters = 2 + static_cast<int>(m.active.size());
    f.rss_log_v = m.rss;
    f.rmse_log_v = std::sqrt(m.rss / runs_.size());
    f.aicc = Aicc(m.rss, runs_.size(), f.parameters);
    f.cv_rmse_log_v = CrossValidate(m);
    f.fitted_log_v = Predict(runs_, m.active, m.point);
    return f;
  }

  GapTests Gap(const Model& m) const {
    return RunGapTests(runs_, Predict(runs_, m.active, m.point),
                       Jacobian(runs_, m.active, m.point), options_.test_level);
  }

  // Scores and augmented fits of every library effect not in `current`.
  std::vector<EffectAttribution> Attribute(const Model& current,
                                           std::vector<Model>* fits,
                                           std::vector<Eigen::VectorXd>* sigs,
                                           int* progress_done) const {
    const int n = runs_.size();
    const std::vector<double> y0 =
        Predict(runs_, current.active, current.point);
    Eigen::VectorXd r(n);
    for (int i = 0; i < n; ++i) r(i) = runs_.ln_v[i] - y0[i];
    const Eigen::MatrixXd basis =
        ColumnBasis(Jacobian(runs_, current.active, current.point));
    // Noise scale: pure error when the replicates give it.
    std::vector<double> residual(r.data(), r.data() + n);
    double ss_pe = 0.0;
    int dof_pe = 0;
    PureError(runs_, residual, &ss_pe, &dof_pe);
    const int p = 2 + static_cast<int>(current.active.size());
    double sigma = 0.0;
    int dof = 0;
    const bool pure_error = dof_pe >= 2 && ss_pe > 0.0;
    if (pure_error) {
      sigma = std::sqrt(ss_pe / dof_pe);
      dof = dof_pe;
    } else {
      dof = std::max(1, n - p);
      sigma = std::sqrt(current.rss / dof);
    }
    std::vector<EffectAttribution> out;
    fits->clear();
    sigs->clear();
    const double c_e = std::exp(current.point.ln_c_e);
    const double alpha = std::exp(current.point.ln_alpha);
    for (const sim::EffectSpec& spec : sim::EffectLibrary()) {
      if (spec.trace_only) continue;  // v(F) cannot see it (trace_gap.h)
      bool used = false;
      for (const ActiveEffect& a : current.active) used |= a.spec == &spec;
      if (used) continue;
      if (options_.progress) {
        options_.progress((*progress_done)++, total_tasks_,
                          fmt::format("attributing: {}", spec.id));
      }
      EffectAttribution e;
      e.id = spec.id;
      std::vector<ActiveEffect> active = current.active;
      active.push_back(ScaleEffect(spec, runs_, c_e, alpha));
      const std::size_t k = active.size() - 1;
      Point at = current.point;
      at.u.push_back(0.0);
      // Signature: the change of the fit per unit u at a small strength
      // (2 % at most), a secant for effects with a kink such as the cap.
      const double u_small = UForChange(runs_, active, at, k, 0.02);
      Point moved = at;
      moved.u[k] = u_small;
      const std::vector<double> y1 = Predict(runs_, active, moved);
      Eigen::VectorXd s(n);
      for (int i = 0; i < n; ++i) {
        s(i) = std::isfinite(y1[i]) ? (y1[i] - y0[i]) / u_small : 0.0;
      }
      const Eigen::VectorXd s_perp = Project(basis, s);
      const double norm = s.norm();
      e.identifiability = norm > 0.0 ? s_perp.norm() / norm : 0.0;
      e.absorbed = e.identifiability < options_.absorbed_index;
      sigs->push_back(s_perp);
      if (!e.absorbed && sigma > 0.0) {
        e.score_z = s_perp.dot(r) / (sigma * s_perp.norm());
        e.score_p = boost::math::cdf(boost::math::complement(
            boost::math::students_t_distribution<>(dof), e.score_z));
      }
      Model fit;
      if (!e.absorbed) {
        fit = FitAugmented(active, current.point, {});
        if (fit.rss > current.rss) {  // never worse than the nested model
          fit.point = at;
          fit.rss = current.rss;
        }
        if (pure_error) {
          // The likelihood ratio with the variance held at the replicates'
          // pure-error estimate, which no model touches: the drop in RSS
          // over sigma^2, F(1, dof) on the boundary's 50:50 mixture. (With
          // the variance profiled out, n ln(RSS_0 / RSS_1) gives away about
          // a fifth of the signal at these sizes.)
          e.lr = std::max(current.rss - fit.rss, 0.0) / (sigma * sigma);
          e.lr_p = e.lr > 0.0 ? 0.5 * FUpper(e.lr, 1.0, dof) : 1.0;
        } else {
          e.lr = n * std::log(current.rss / std::max(fit.rss, 1e-300));
          e.lr_p = ChiBarP(e.lr);
        }
        e.aicc = Aicc(fit.rss, n, 2 + static_cast<int>(active.size()));
        e.value =
            sim::ParameterAtStrength(spec, Strength(active[k], fit.point, k));
      } else {
        fit.active = active;
        fit.point = at;
        fit.rss = current.rss;
        e.aicc = kInf;
        e.value = spec.null_value;
      }
      fits->push_back(fit);
      out.push_back(e);
    }
    // Family-wise: max-T over the testable effects, correlated through
    // their projected signatures.
    std::vector<std::size_t> testable;
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (!out[i].absorbed && (*sigs)[i].norm() > 0.0) testable.push_back(i);
    }
    const int m = static_cast<int>(testable.size());
    Eigen::MatrixXd corr(m, m);
    std::vector<double> lr(m);
    for (int a = 0; a < m; ++a) {
      const Eigen::VectorXd& sa = (*sigs)[testable[a]];
      lr[a] = out[testable[a]].lr;
      for (int b = 0; b < m; ++b) {
        const Eigen::VectorXd& sb = (*sigs)[testable[b]];
        corr(a, b) = sa.dot(sb) / (sa.norm() * sb.norm());
      }
    }
    const std::vector<double> adjusted =
        MaxTAdjusted(lr, corr, pure_error ? dof : 0);
    for (EffectAttribution& e : out) e.lr_p_adjusted = 1.0;
    for (int a = 0; a < m; ++a) out[testable[a]].lr_p_adjusted = adjusted[a];
    return out;
  }

  void set_total_tasks(int total) { total_tasks_ = total; }

 private:
  const Runs& runs_;
  const DiscoverOptions& options_;
  int total_tasks_ = 1;
};

// Gross outliers: runs far from the other replicates of their level, one at a
// time (the largest first), against a robust scale of all runs.
std::vector<char> ScreenOutliers(const Runs& runs, double sigmas) {
  std::vector<char> keep(runs.size(), 1);
  const auto deviations = [&]() {
    std::vector<double> d(runs.size(), kNaN);
    std::vector<double> sum(runs.levels, 0.0);
    std::vector<int> count(runs.levels, 0);
    for (int i = 0; i < runs.size(); ++i) {
      if (!keep[i]) continue;
      sum[runs.level[i]] += runs.ln_v[i];
      ++count[runs.level[i]];
    }
    for (int i = 0; i < runs.size(); ++i) {
      const int c = count[runs.level[i]];
      if (!keep[i] || c < 3) continue;
      const double others = (sum[runs.level[i]] - runs.ln_v[i]) / (c - 1);
      // Var(y - mean of the other c - 1) = sigma^2 (1 + 1/(c - 1)).
      d[i] = (runs.ln_v[i] - others) / std::sqrt(1.0 + 1.0 / (c - 1));
    }
    return d;
  };
  std::vector<double> d = deviations();
  std::vector<double> abs_d;
  for (double x : d) {
    if (!std::isnan(x)) abs_d.push_back(std::abs(x));
  }
  if (abs_d.size() < 6) return keep;
  std::nth_element(abs_d.begin(), abs_d.begin() + abs_d.size() / 2,
                   abs_d.end());
  const double scale = 1.4826 * abs_d[abs_d.size() / 2];
  if (!(scale > 0.0)) return keep;
  const int max_removed = runs.size() / 4;
  for (int removed = 0; removed < max_removed; ++removed) {
    int worst = -1;
    double worst_z = sigmas;
    for (int i = 0; i < runs.size(); ++i) {
      if (!std::isnan(d[i]) && std::abs(d[i]) / scale > worst_z) {
        worst_z = std::abs(d[i]) / scale;
        worst = i;
      }
    }
    if (worst < 0) break;
    keep[worst] = 0;
    d = deviations();
  }
  return keep;
}

Runs Subset(const Runs& runs, const std::vector<char>& keep) {
  Runs out;
  out.radius_mm = runs.radius_mm;
  std::map<double, int> index;
  for (int i = 0; i < runs.size(); ++i) {
    if (keep[i]) index.emplace(runs.force_n[i], 0);
  }
  int k = 0;
  for (auto& [force, i] : index) i = k++;
  out.levels = k;
  for (int i = 0; i < runs.size(); ++i) {
    if (!keep[i]) continue;
    out.force_n.push_back(runs.force_n[i]);
    out.ln_v.push_back(runs.ln_v[i]);
    out.level.push_back(index[runs.force_n[i]]);
    out.line.push_back(runs.line[i]);
  }
  return out;
}

// The RMS shift of log v (orthogonal to the model, spread over the levels)
// the lack-of-fit test detects with probability 1/2.
double DetectableRms(const Runs& runs, int parameters, double sigma,
                     double level) {
  const int d1 = runs.levels - parameters, d2 = runs.size() - runs.levels;
  if (d1 < 1 || d2 < 1 || !(sigma > 0.0)) return kNaN;
  const double critical = boost::math::quantile(
      boost::math::fisher_f_distribution<>(d1, d2), 1.0 - level);
  const auto power = [&](double lambda) {
    return boost::math::cdf(boost::math::complement(
        boost::math::non_central_f_distribution<>(d1, d2, lambda), critical));
  };
  double lo = 0.0, hi = 1.0;
  while (power(hi) < 0.5 && hi < 1e6) hi *= 2.0;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (power(mid) < 0.5 ? lo : hi) = mid;
  }
  // lambda = sum_i delta_i^2 / sigma^2 = n rms^2 / sigma^2.
  return sigma * std::sqrt(0.5 * (lo + hi) / runs.size());
}

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

}  // namespace

double ModelLogVelocity(double force_n, double c_e_n_per_mm2,
                        double alpha_per_s, double radius_mm,
                        const sim::Effects& effects) {
  SteadyDescentInput in;
  in.force_n = force_n;
  in.c_e_n_per_mm2 = c_e_n_per_mm2;
  in.alpha_per_s = alpha_per_s;
  in.radius_mm = radius_mm;
  in.effects = effects;
  const double v = SteadyVelocityMmS(in);
  return v > 0.0 && std::isfinite(v) ? std::log(v) : kNaN;
}

Result<double> BaseModelRss(const MeasuredData& data, double radius_mm) {
  const Runs runs = MakeRuns(data, radius_mm);
  DiscoverOptions options;
  options.radius_mm = radius_mm;
  const Workflow flow(runs, options);
  Result<Point> p = flow.BaseFit({});
  if (!p.ok()) return p.error();
  return Rss(runs, {}, *p, {});
}

Status DiscoverOptions::Validate() const {
  if (!std::isfinite(radius_mm) || radius_mm <= 0.0) {
    return Error{fmt::format(
        "radius_mm must be a positive finite number of mm, got {}", radius_mm)};
  }
  if (!(test_level > 0.0 && test_level < 0.5)) {
    return Error{
        fmt::format("test_level must lie in (0, 0.5), got {}", test_level)};
  }
  if (max_effects < 0 || max_effects > 2) {
    return Error{
        fmt::format("max_effects must lie in [0, 2], got {}", max_effects)};
  }
  if (!(alias_separation >= 0.0 && std::isfinite(alias_separation))) {
    return Error{
        fmt::format("alias_separation must be a finite number >= 0, got {}",
                    alias_separation)};
  }
  if (!(alias_cosine > 0.0 && alias_cosine < 1.0)) {
    return Error{
        fmt::format("alias_cosine must lie in (0, 1), got {}", alias_cosine)};
  }
  if (!(absorbed_index >= 0.0 && absorbed_index < 1.0)) {
    return Error{fmt::format("absorbed_index must lie in [0, 1), got {}",
                             absorbed_index)};
  }
  if (!(outlier_sigmas > 2.0)) {
    return Error{
        fmt::format("outlier_sigmas must exceed 2, got {}", outlier_sigmas)};
  }
  if (!(absorbed_margin >= 0.0 && std::isfinite(absorbed_margin))) {
    return Error{fmt::format("absorbed_margin must be finite and >= 0, got {}",
                             absorbed_margin)};
  }
  if (reference) {
    if (Status s = reference->Validate(); !s.ok()) return s;
  }
  return {};
}

namespace {

// The trace stage of Discover: tests the trace-only effects (trace_gap.h) on
// options.traces with the report's base fit and records the result in
// report->trace_gap. A significant effect is named when v(F) found nothing
// (verdict none -> named) and added after the v(F) effects when it found
// one; the summary says what the traces show either way.
Status AddTraceGap(const MeasuredData& data, const DiscoverOptions& options,
                   DiscoverReport* report) {
  if (!options.traces) return {};
  const std::vector<TraceRun> runs = PairTraces(*options.traces, data);
  if (runs.empty()) {
    return Error{"none of the traces belongs to a run of the measured data"};
  }
  TraceGapOptions o;
  o.c_e_n_per_mm2 = report->baseline.c_e_n_per_mm2;
  o.alpha_per_s = report->baseline.alpha_per_s;
  o.radius_mm = options.radius_mm;
  o.test_level = options.test_level;
  Result<TraceGapResult> gap = TestTraceEffects(runs, o);
  if (!gap.ok()) return Error{"traces: " + gap.error().message};
  report->trace_gap = *gap;
  if (gap->named.empty()) {
    double min_p = 1.0;
    for (const TraceEffectTest& e : gap->effects) {
      min_p = std::min(min_p, e.p_holm);
    }
    report->summary += fmt::format(
        " The traces ({} runs) show no trace-only effect (smallest "
        "Holm-adjusted p = {:.3g}).",
        gap->runs, min_p);
    return {};
  }
  const TraceEffectTest* named = nullptr;
  for (const TraceEffectTest& e : gap->effects) {
    if (e.id == gap->named) named = &e;
  }
  const sim::EffectSpec* spec = sim::FindEffect(named->id);
  const std::string finding = fmt::format(
      "The traces ({} runs) show {} ({}): {} = {:.4g} {}, likelihood ratio "
      "{:.3g}, Holm-adjusted p = {:.3g} (boundary-corrected), trace RMSE "
      "{:.3g} -> {:.3g} N and {:.3g} -> {:.3g} mm. Steady v(F) cannot see "
      "it.",
      gap->runs, named->id, spec->signature, spec->parameter, named->value,
      spec->unit, named->lr, named->p_holm, gap->rmse_force_n,
      named->rmse_force_n, gap->rmse_depth_mm, named->rmse_depth_mm);
  // The v(F) model is unchanged by a trace-only effect: the augmented fit
  // keeps its numbers and gains the parameter.
  const auto add = [&](ModelFit* fit) {
    fit->effects.push_back(named->id);
    fit->effect_values.push_back(named->value);
    fit->strengths.push_back(sim::StrengthOfParameter(*spec, named->value));
    ++fit->parameters;
  };
  if (report->verdict == "none") {
    report->verdict = "named";
    report->effects = {named->id};
    report->alias_set = {named->id};
    report->alias_sets = {report->alias_set};
    add(&report->augmented);
    report->summary = finding + " " + report->summary;
  } else if (report->verdict == "named" || report->verdict == "ambiguous") {
    report->effects.push_back(named->id);
    report->alias_sets.push_back({named->id});
    add(&report->augmented);
    report->summary += " " + finding;
  } else {
    report->summary += " " + finding;
  }
  return {};
}

}  // namespace

Result<DiscoverReport> Discover(const MeasuredData& data,
                                const DiscoverOptions& options) {
  // ---- Trace-only effects (trace_gap.h) -------------------------------
  // v(F) cannot see load_cell_lag or arm_compliance: the workflow runs on
  // v(F) alone, then its base fit feeds the trace-gap test.
  if (options.traces) {
    DiscoverOptions steady = options;
    steady.traces.reset();
    Result<DiscoverReport> report = Discover(data, steady);
    if (!report.ok()) return report;
    if (Status s = AddTraceGap(data, options, &*report); !s.ok()) {
      return s.error();
    }
    return report;
  }
  // ----------------------------------------------------------------------
  if (Status s = options.Validate(); !s.ok()) return s.error();
  const int n_all = static_cast<int>(data.runs.size());
  if (n_all <= kCalibrationParameters || data.force_levels < 2) {
    return Error{fmt::format(
        "discover needs more runs than parameters and at least 2 force "
        "levels, got {} runs at {} levels",
        n_all, data.force_levels)};
  }
  DiscoverReport report;
  const Runs all = MakeRuns(data, options.radius_mm);
  const std::vector<char> keep = ScreenOutliers(all, options.outlier_sigmas);
  for (int i = 0; i < all.size(); ++i) {
    if (!keep[i]) report.outlier_lines.push_back(all.line[i]);
  }
  const Runs runs = Subset(all, keep);
  const int n = runs.size();
  const double level = options.test_level;
  Workflow flow(runs, options);
  const int library = static_cast<int>(
      std::count_if(sim::EffectLibrary().begin(), sim::EffectLibrary().end(),
                    [](const sim::EffectSpec& e) { return !e.trace_only; }));
  flow.set_total_tasks(2 + library * std::max(1, options.max_effects));
  int done = 0;
  if (options.progress) options.progress(done++, 2, "base fit");

  // 1. The base model.
  Result<Point> base_point = flow.BaseFit({});
  if (!base_point.ok()) return base_point.error();
  Model base;
  base.point = *base_point;
  base.rss = Rss(runs, {}, base.point, {});
  report.baseline = flow.Describe(base);
  report.augmented = report.baseline;

  // 2. Is there a gap? The omnibus tests and the library's focused test
  // (the best effect's max-T adjusted likelihood ratio), Holm over the four.
  report.gap_before = flow.Gap(base);
  std::vector<Model> fits0;
  std::vector<Eigen::VectorXd> sigs0;
  report.rounds.push_back(flow.Attribute(base, &fits0, &sigs0, &done));
  report.gap_before.library_p = 1.0;
  for (const EffectAttribution& e : report.rounds[0]) {
    report.gap_before.library_p =
        std::min(report.gap_before.library_p, e.lr_p_adjusted);
  }
  CombineGapTests(&report.gap_before, level);
  report.gap_after = report.gap_before;
  {
    std::vector<double> residual(n);
    for (int i = 0; i < n; ++i) {
      residual[i] = runs.ln_v[i] - report.baseline.fitted_log_v[i];
    }
    double ss_pe = 0.0;
    int dof_pe = 0;
    PureError(runs, residual, &ss_pe, &dof_pe);
    const double sigma = dof_pe >= 1 && ss_pe > 0.0
                             ? std::sqrt(ss_pe / dof_pe)
                             : std::sqrt(base.rss / std::max(1, n - 2));
    report.detectable_rms_log_v = DetectableRms(runs, 2, sigma, level);
  }
  report.reference_p = kNaN;
  report.reference_effect_p = kNaN;
  const std::string outliers_text =
      report.outlier_lines.empty()
          ? std::string()
          : fmt::format(
                " {} run(s) far outside their replicates were left "
                "out as gross outliers.",
                report.outlier_lines.size());

  // Absorbed: with a reference material, the simplest account of the data
  // is tried first: the reference with one effect that v(F) cannot see
  // (porosity: c_e scaled), its strength the only free parameter. It wins
  // when the data reject the bare reference, but not the reference with the
  // effect, and the latter passes the omnibus gap tests: a chance gap of the
  // free fit does not outrank it.
  if (options.reference) {
    Point ref;
    ref.ln_c_e = std::log(options.reference->c_e_n_per_mm2);
    ref.ln_alpha = std::log(options.reference->alpha_per_s);
    const double rss_ref = Rss(runs, {}, ref, {});
    // The reference (0 free parameters) against the free base fit (2).
    const int dof = n - 2;
    report.reference_p =
        FUpper(((rss_ref - base.rss) / 2.0) / (base.rss / dof), 2, dof);
    double best_p = -1.0;
    const EffectAttribution* best = nullptr;
    for (const EffectAttribution& e : report.rounds[0]) {
      if (!e.absorbed) continue;
      const sim::EffectSpec* spec = sim::FindEffect(e.id);
      std::vector<ActiveEffect> active = {
          ScaleEffect(*spec, runs, options.reference->c_e_n_per_mm2,
                      options.reference->alpha_per_s)};
      // Reference + effect: only the strength is free (1 parameter).
      double lo = 0.0, hi = active[0].upper;
      const auto rss_at = [&](double u) {
        Point p = ref;
        p.u = {u};
        return Rss(runs, active, p, {});
      };
      const double u =
          boost::math::tools::brent_find_minima(rss_at, lo, hi, 40).first;
      double value = 0.0;
      value = rss_at(u);
      const double p_effect =
          FUpper(((value - base.rss) / 1.0) / (base.rss / dof), 1, dof);
      // The change the effect makes, as an RMS of log v.
      Point with = ref;
      with.u = {u};
      const std::vector<double> y1 = Predict(runs, active, with);
      const std::vector<double> y0 = Predict(runs, {}, ref);
      double change = 0.0;
      for (int i = 0; i < n; ++i) change += std::pow(y1[i] - y0[i], 2) / n;
      change = std::sqrt(change);
      if (change > std::log1p(options.absorbed_margin) && p_effect > best_p) {
        best_p = p_effect;
        best = &e;
        report.augmented = flow.Describe(Model{active, with, value});
        report.augmented.c_e_n_per_mm2 = options.reference->c_e_n_per_mm2;
        report.augmented.alpha_per_s = options.reference->alpha_per_s;
      }
    }
    // Reference + effect must also pass the omnibus gap tests itself.
    GapTests ref_gap;
    if (best != nullptr) {
      ref_gap = RunGapTests(runs, report.augmented.fitted_log_v,
                            Jacobian(runs, {}, base.point), level);
    }
    // ... at the share of the level the omnibus tests have in the gap
    // family, while the library's focused test finds no shape on the free
    // fit (a real shape effect on the reference material also moves c_e and
    // alpha, so that reference + porosity fits as well as the base).
    const bool no_shape =
        !(report.gap_before.library_p < (1.0 - kOmnibusShare) * level);
    if (best != nullptr && report.reference_p < level && best_p >= level &&
        ref_gap.holm_min_p >= kOmnibusShare * level && no_shape) {
      report.reference_effect_p = best_p;
      report.verdict = "absorbed";
      report.effects = {best->id};
      report.alias_set = {best->id};
      report.alias_sets = {report.alias_set};
      report.summary = fmt::format(
          "Effect {} is absorbed by the base parameters: v(F) alone cannot "
          "show it (identifiability index {:.2g}), but the data reject the "
          "reference material (p = {:.3g}) while the reference with {} = "
          "{:.4g} fits as well as free c_e and alpha (p = {:.3g}); the fit "
          "absorbs it into c_e = {:.4g} and alpha = {:.4g}.{}",
          best->id, best->identifiability, report.reference_p, best->id,
          report.augmented.effect_values[0], best_p,
          report.baseline.c_e_n_per_mm2, report.baseline.alpha_per_s,
          outliers_text);
      if (report.gap_before.detected) {
        report.summary += fmt::format(
            " The gap tests on the free fit fired (p = {:.3g}), but the "
            "reference with {} alone passes them, and it is the simpler "
            "model (1 free parameter against 3).",
            report.gap_before.holm_min_p, best->id);
      }
      return report;
    } else {
      report.augmented = report.baseline;
      if (best != nullptr) report.reference_effect_p = best_p;
    }
  }
  if (!report.gap_before.detected) {
    report.verdict = "none";
    report.summary = fmt::format(
        "No discrepancy detected: the base model (c_e, alpha) fits v(F) "
        "within the replicates' scatter (smallest Holm-adjusted gap p = "
        "{:.3g}). This design would detect an RMS change of log v of about "
        "{:.3g} with probability 1/2.{}",
        report.gap_before.holm_min_p, report.detectable_rms_log_v,
        outliers_text);
    return report;
  }

  // 3-4. Attribute and augment, one effect at a time.
  Model current = base;
  std::vector<std::string> tried;
  std::string failure;
  bool explained = false;
  // A step was taken on AICc alone (see below): the final model must then
  // lower the held-out error against the base model.
  bool held_out_deferred = false;
  for (int step = 0; step < options.max_effects; ++step) {
    // A model must leave the lack-of-fit test at least 3 degrees of freedom
    // (levels - parameters) to be checked at all.
    const int parameters = 3 + step;
    if (runs.levels - parameters < 3 && step > 0) {
      failure = fmt::format(
          "after {} the residual tests still fail ({}), and {} force levels "
          "leave too few degrees of freedom to check a model with a further "
          "effect",
          Join(report.effects), DescribeGap(report.gap_after), runs.levels);
      break;
    }
    std::vector<Model> fits;
    std::vector<Eigen::VectorXd> sigs;
    if (step == 0) {
      fits = fits0;
      sigs = sigs0;
    } else {
      report.rounds.push_back(flow.Attribute(current, &fits, &sigs, &done));
    }
    const std::vector<EffectAttribution> round = report.rounds.back();
    // Candidates: significant after the max-T correction, best AICc first.
    std::vector<std::size_t> candidates;
    for (std::size_t i = 0; i < round.size(); ++i) {
      if (!round[i].absorbed && round[i].lr_p_adjusted < level) {
        candidates.push_back(i);
      }
    }
    std::sort(candidates.begin(), candidates.end(),
              [&](std::size_t a, std::size_t b) {
                return round[a].aicc < round[b].aicc;
              });
    if (candidates.empty()) {
      failure = step == 0
                    ? "no effect's likelihood-ratio test is significant after "
                      "the family-wise (max-T) correction"
                    : fmt::format(
                          "after {} the residual tests still fail ({}) and no "
                          "further effect is significant",
                          Join(report.effects), DescribeGap(report.gap_after));
      break;
    }
    // The best candidate that passes the confirmation; the runners-up
    // within 2 of its AICc (which the data cannot rank) are tried in turn.
    // Preferred: the first that lowers AICc and the held-out error and whose
    // residual tests pass; then the first that lowers both (the next step
    // looks for a further effect); then, when a further effect can still be
    // checked, the first that lowers AICc and leaves the residual tests
    // failing: with two effects in the data one alone may not predict a
    // held-out end level better, so the held-out error is then required of
    // the final model against the base model instead.
    ModelFit before = step == 0 ? report.baseline : report.augmented;
    const bool further_step_possible =
        step + 1 < options.max_effects && runs.levels - (parameters + 1) >= 3;
    struct Pick {
      std::size_t k = 0;
      ModelFit fit;
      GapTests gap;
    };
    std::optional<Pick> clean, open_gap, provisional;
    for (std::size_t c = 0; c < candidates.size() && !clean; ++c) {
      const std::size_t k = candidates[c];
      if (c > 0 && round[k].aicc - round[candidates[0]].aicc >= 2.0) break;
      Pick pick{k, flow.Describe(fits[k]), {}};
      tried.push_back(round[k].id);
      const double delta_aicc = pick.fit.aicc - before.aicc;
      if (!(delta_aicc < 0.0)) {
        failure = fmt::format("adding {} does not lower AICc ({:+.3g})",
                              round[k].id, delta_aicc);
        continue;
      }
      pick.gap = flow.Gap(fits[k]);
      // NaN passes.
      const bool held_out_drops =
          !(pick.fit.cv_rmse_log_v >= before.cv_rmse_log_v);
      if (!held_out_drops) {
        failure = fmt::format(
            "adding {} does not lower the held-out error ({:.4g} -> {:.4g})",
            round[k].id, before.cv_rmse_log_v, pick.fit.cv_rmse_log_v);
        if (further_step_possible && pick.gap.detected && !provisional) {
          provisional = pick;
        }
        continue;
      }
      if (pick.gap.detected) {
        if (!open_gap) open_gap = pick;
        continue;
      }
      clean = pick;
    }
    const std::optional<Pick>& chosen = clean      ? clean
                                        : open_gap ? open_gap
                                                   : provisional;
    if (!chosen) break;
    if (!clean && !open_gap) held_out_deferred = true;
    const std::size_t best = chosen->k;
    const ModelFit after = chosen->fit;
    const GapTests after_gap = chosen->gap;
    failure.clear();
    const Model& augmented = fits[best];
    report.lr_p = round[best].lr_p;
    report.delta_aicc = after.aicc - before.aicc;
    report.delta_aicc_runner_up =
        candidates.size() > 1
            ? round[candidates[1]].aicc - round[candidates[0]].aicc
            : kNaN;
    {
      // Alias set: effects the design cannot separate from the best, given
      // the effects already added. Their local signatures may be nearly
      // parallel, or their fitted contributions (augmented minus current
      // predictions, projected off the current Jacobian: for a capped effect
      // such as the power limit the local signature sits at the top force
      // only) are.
      std::vector<std::string> alias = {round[best].id};
      const std::vector<double> y_now =
          Predict(runs, current.active, current.point);
      const Eigen::MatrixXd basis =
          ColumnBasis(Jacobian(runs, current.active, current.point));
      const auto contribution = [&](std::size_t k) {
        const std::vector<double> y =
            Predict(runs, fits[k].active, fits[k].point);
        Eigen::VectorXd d(n);
        for (int i = 0; i < n; ++i) {
          d(i) = std::isfinite(y[i]) ? y[i] - y_now[i] : 0.0;
        }
        return Eigen::VectorXd(Project(basis, d));
      };
      const Eigen::VectorXd c_best = contribution(best);
      // Separation: what a test between the best and effect j could see.
      // The other effect, fitted (with its own c_e and alpha, and the
      // effects already added) to a model's noise-free predictions, leaves a
      // remainder; over the noise variance it is the noncentrality of a
      // test between the two on this design were the best the truth; below
      // options.alias_separation the design would not tell them apart.
      // (The reverse, the best fitted to j's model, was tried: it did not
      // change the second set of the two-effect test's seed 6.)
      double sigma2 = 0.0;
      {
        std::vector<double> residual(n);
        for (int i = 0; i < n; ++i) residual[i] = runs.ln_v[i] - y_now[i];
        double ss_pe = 0.0;
        int dof_pe = 0;
        PureError(runs, residual, &ss_pe, &dof_pe);
        sigma2 = dof_pe >= 2 && ss_pe > 0.0
                     ? ss_pe / dof_pe
                     : fits[best].rss / std::max(1, n - 3);
      }
      // The current model (base plus the effects already added) refitted to
      // `target`'s predictions, then with `spec` added: the remainder over
      // sigma^2.
      struct Pseudo {
        Runs runs;
        std::optional<Model> current;
      };
      const auto make_pseudo = [&](const Model& target) {
        Pseudo ps{runs, std::nullopt};
        ps.runs.ln_v = target.active.empty()
                           ? y_now
                           : Predict(runs, target.active, target.point);
        const Workflow flow_t(ps.runs, options);
        const Result<Point> b = flow_t.BaseFit({});
        if (b.ok()) {
          ps.current = current.active.empty()
                           ? Model{{}, *b, Rss(ps.runs, {}, *b, {})}
                           : flow_t.FitAugmented(current.active, *b, {});
        }
        return ps;
      };
      const auto remainder = [&](const Pseudo& ps,
                                 const sim::EffectSpec& spec) {
        if (!ps.current || !(sigma2 > 0.0)) return kInf;
        const Workflow flow_t(ps.runs, options);
        std::vector<ActiveEffect> active = ps.current->active;
        active.push_back(ScaleEffect(spec, ps.runs,
                                     std::exp(ps.current->point.ln_c_e),
                                     std::exp(ps.current->point.ln_alpha)));
        const Model m = flow_t.FitAugmented(active, ps.current->point, {});
        return std::min(m.rss, ps.current->rss) / sigma2;
      };
      const Pseudo as_best = make_pseudo(fits[best]);
      const auto separation = [&](std::size_t j) {
        return remainder(as_best, *fits[j].active.back().spec);
      };
      for (std::size_t j = 0; j < round.size(); ++j) {
        if (j == best || round[j].absorbed) continue;
        if (separation(j) < options.alias_separation) {
          alias.push_back(round[j].id);
          continue;
        }
        if (std::find(candidates.begin(), candidates.end(), j) ==
            candidates.end()) {
          continue;
        }
        const double denom = sigs[best].norm() * sigs[j].norm();
        const Eigen::VectorXd c_j = contribution(j);
        const double fitted_denom = c_best.norm() * c_j.norm();
        const double cosine = std::max(
            denom > 0.0 ? std::abs(sigs[best].dot(sigs[j])) / denom : 0.0,
            fitted_denom > 0.0 ? std::abs(c_best.dot(c_j)) / fitted_denom
                               : 0.0);
        if (cosine > options.alias_cosine ||
            round[j].aicc - round[best].aicc < 2.0) {
          alias.push_back(round[j].id);
        }
      }
      if (step == 0) report.alias_set = alias;
      report.alias_sets.push_back(std::move(alias));
    }
    current = augmented;
    report.effects.push_back(round[best].id);
    report.augmented = after;
    report.gap_after = after_gap;
    if (!report.gap_after.detected) {
      explained = true;
      break;
    }
  }
  if (explained && held_out_deferred &&
      report.augmented.cv_rmse_log_v >= report.baseline.cv_rmse_log_v) {
    explained = false;
    failure = fmt::format(
        "adding {} does not lower the held-out error ({:.4g} -> {:.4g})",
        Join(report.effects), report.baseline.cv_rmse_log_v,
        report.augmented.cv_rmse_log_v);
  }
  if (explained) {
    bool ambiguous = false;
    for (const auto& set : report.alias_sets) ambiguous |= set.size() > 1;
    report.verdict = ambiguous ? "ambiguous" : "named";
    std::string params;
    for (std::size_t k = 0; k < report.augmented.effects.size(); ++k) {
      const sim::EffectSpec* spec =
          sim::FindEffect(report.augmented.effects[k]);
      params += fmt::format("{}{} = {:.4g} {}", params.empty() ? "" : ", ",
                            spec->parameter, report.augmented.effect_values[k],
                            spec->unit);
    }
    // What step k found: the effect with its signature, or the set the
    // design cannot tell apart.
    const auto found = [&](std::size_t k) {
      const std::vector<std::string>& set = report.alias_sets[k];
      return set.size() > 1
                 ? fmt::format(
                       "an effect of the set {{{}}}, which this design cannot "
                       "tell apart (projected signatures nearly parallel, "
                       "fitted contributions alike or AICc within 2)",
                       Join(set))
                 : fmt::format("{} ({})", report.effects[k],
                               sim::FindEffect(report.effects[k])->signature);
    };
    // A second effect, when one was needed after the first.
    const std::string second =
        report.effects.size() > 1
            ? fmt::format(" and, once it is added, {}", found(1))
            : std::string();
    const std::string adding =
        report.effects.size() > 1
            ? fmt::format("Adding {} and {}", report.effects[0],
                          report.effects[1])
            : std::string("Adding it");
    report.summary =
        report.verdict == "named"
            ? fmt::format(
                  "The base model misses {}{}. {} ({}) closes the gap: "
                  "likelihood ratio p = {:.3g} (boundary-corrected), AICc "
                  "{:+.3g}, held-out RMSE of log v {:.3g} -> {:.3g}, and the "
                  "residual tests pass (Holm p = {:.3g}).{}",
                  found(0), second, adding, params, report.lr_p,
                  report.augmented.aicc - report.baseline.aicc,
                  report.baseline.cv_rmse_log_v, report.augmented.cv_rmse_log_v,
                  report.gap_after.holm_min_p, outliers_text)
            : fmt::format(
                  "The base model misses {}{}. {} ({}), the best of {}, "
                  "closes the gap: AICc {:+.3g}, held-out RMSE of log v "
                  "{:.3g} -> {:.3g}. Force levels where their predictions "
                  "differ most would separate them.{}",
                  found(0), second, adding, params,
                  report.effects.size() > 1 ? "each set" : "the set",
                  report.augmented.aicc - report.baseline.aicc,
                  report.baseline.cv_rmse_log_v, report.augmented.cv_rmse_log_v,
                  outliers_text);
    return report;
  }
  // Something outside the library (or not confirmed): no forced name.
  report.verdict = "unexplained";
  report.summary = fmt::format(
      "The base model does not fit (smallest Holm-adjusted gap p = {:.3g}), "
      "and no effect of the library explains the gap{}: {}.{}",
      report.gap_before.holm_min_p,
      tried.empty() ? "" : fmt::format(" (tried: {})", Join(tried)),
      failure.empty()
          ? fmt::format("after {} the residual tests still fail ({})",
                        Join(report.effects), DescribeGap(report.gap_after))
          : failure,
      outliers_text);
  report.effects.clear();
  report.alias_set.clear();
  report.alias_sets.clear();
  report.augmented = report.baseline;
  report.gap_after = report.gap_before;
  return report;
}

}  // namespace burrlab::analysis
