// The base-model fit of the discover workflow: the runs a fit uses and the
// outlier screen, the model's predictions, bounded fits from several starts,
// each effect's strength scale, the Jacobian, the fitted model's numbers and
// its held-out error.
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/tools/minima.hpp>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "burrlab/analysis/box_search.h"
#include "burrlab/analysis/model_gap/descent_surrogate.h"
#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/analysis/model_gap/initial_velocity.h"
#include "burrlab/sim/effects.h"
#include "model_gap/discover_internal.h"
#include "model_gap/own_factor_fit.h"
#include "non_finite.h"

namespace burrlab::analysis {
namespace discover_internal {

using detail::kInf;
using detail::kNaN;

namespace {

// Residual charged to a run the model cannot reach (v = 0 or inf), so the
// optimiser stays where every run is modelled.
constexpr double kUnreachableResidual = 30.0;

sim::Effects MakeEffects(const std::vector<ActiveEffect>& active,
                         const Point& p) {
  sim::Effects effects;
  for (std::size_t k = 0; k < active.size(); ++k) {
    sim::ApplyEffect(
        *active[k].spec,
        sim::ParameterAtStrength(*active[k].spec, Strength(active[k], p, k)),
        &effects);
  }
  return effects;
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

}  // namespace

Runs MakeRuns(const MeasuredData& data, double radius_mm,
              sim::VelocityDefinition definition) {
  Runs runs;
  runs.radius_mm = radius_mm;
  runs.definition = definition;
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
  out.definition = runs.definition;
  for (int i = 0; i < runs.size(); ++i) {
    if (!keep[i]) continue;
    if (!runs.transient.empty()) out.transient.push_back(runs.transient[i]);
    out.force_n.push_back(runs.force_n[i]);
    out.ln_v.push_back(runs.ln_v[i]);
    out.level.push_back(index[runs.force_n[i]]);
    out.line.push_back(runs.line[i]);
  }
  return out;
}

double Strength(const ActiveEffect& e, const Point& p, std::size_t k) {
  return p.u[k] * e.unit * (e.per_alpha ? std::exp(p.ln_alpha) : 1.0);
}

std::vector<double> Predict(const Runs& runs,
                            const std::vector<ActiveEffect>& active,
                            const Point& p) {
  const sim::Effects effects = MakeEffects(active, p);
  // The runs of a level share their force and transient factor, so the
  // model (a steady-state solve) runs once per level, in whatever order the
  // runs come.
  std::vector<double> at_level(static_cast<std::size_t>(runs.levels), kNaN);
  std::vector<char> known(at_level.size(), 0);
  std::vector<double> y(runs.size());
  for (int i = 0; i < runs.size(); ++i) {
    const std::size_t g = static_cast<std::size_t>(runs.level[i]);
    if (!known[g]) {
      at_level[g] = ModelLogVelocity(
          runs.force_n[i], std::exp(p.ln_c_e), std::exp(p.ln_alpha),
          runs.radius_mm, effects, runs.definition,
          runs.transient.empty() ? 1.0 : runs.transient[i]);
      known[g] = 1;
    }
    y[i] = at_level[g];
  }
  return y;
}

double RefreshTransient(Runs* runs, const std::vector<ActiveEffect>& active,
                        const Point& p) {
  if (runs->definition != sim::VelocityDefinition::kInitial) return 0.0;
  const sim::Effects effects = MakeEffects(active, p);
  runs->transient.resize(runs->size(), 1.0);
  double change = 0.0;
  // Replicates share their level's factor (milliseconds each): one per
  // level, in whatever order the runs come.
  std::vector<double> factor(static_cast<std::size_t>(runs->levels), 0.0);
  for (int i = 0; i < runs->size(); ++i) {
    double& f = factor[static_cast<std::size_t>(runs->level[i])];
    if (f == 0.0) {
      DescentSurrogateInput in;
      in.force_n = runs->force_n[i];
      in.c_e_n_per_mm2 = std::exp(p.ln_c_e);
      in.alpha_per_s = std::exp(p.ln_alpha);
      in.radius_mm = runs->radius_mm;
      in.effects = effects;
      f = InitialTransientFactor(in);
    }
    change = std::max(change, std::abs(std::log(f / runs->transient[i])));
    runs->transient[i] = f;
  }
  return change;
}

Point FitBaseWithOwnTransient(Runs* runs, const Point& start, double* rss) {
  const auto point = [](double l, double a) {
    Point p;
    p.ln_c_e = l;
    p.ln_alpha = a;
    return p;
  };
  double max_f = 0.0;
  for (double f : runs->force_n) max_f = std::max(max_f, f);
  detail::OwnFactorProblem problem;
  problem.held_alpha = [&](double l) {
    return OffsetAlpha(*runs, {}, point(l, 0.0), {});
  };
  problem.own_rss = [&](double l, double a) {
    RefreshTransient(runs, {}, point(l, a));
    return Rss(*runs, {}, point(l, a), {});
  };
  problem.l_bound =
      std::log(max_f / (runs->radius_mm * runs->radius_mm * MaxSteadyLoad()));
  problem.l_lower = std::log(1e-3);
  problem.l_upper = std::log(1e3);
  const detail::OwnFactorMinimum found =
      detail::FitWithOwnFactors(problem, {start.ln_c_e, start.ln_alpha});
  const Point best = std::isfinite(found.rss) ? point(found.l, found.a) : start;
  RefreshTransient(runs, {}, best);
  *rss = Rss(*runs, {}, best, {});
  return best;
}

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

Point FitFromStarts(const Runs& runs, const std::vector<ActiveEffect>& active,
                    const std::vector<Point>& starts,
                    const std::vector<char>& use, const Point& centre,
                    double* rss_out, std::optional<std::size_t> fixed) {
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
  BoxSearch box;
  box.lower = lower;
  box.upper = upper;
  box.xtol_abs = 1e-7;
  box.ftol_rel = 1e-10;
  box.max_evaluations = 400;
  box.initial_step.assign(dim, 0.1);
  // The power limit's RSS is kinked: the search keeps the best point it
  // evaluated, which BOBYQA can stop above.
  const auto rss = [&](std::span<const double> x) {
    Point p;
    p.ln_c_e = x[0];
    p.ln_alpha = x[1];
    p.u.assign(x.begin() + 2, x.end());
    return Rss(runs, active, p, use);
  };
  Point best;
  double best_rss = kInf;
  for (const Point& start : starts) {
    std::vector<double> x(dim);
    x[0] = start.ln_c_e;
    x[1] = start.ln_alpha;
    for (std::size_t k = 0; k < active.size(); ++k) {
      x[2 + k] = std::clamp(start.u[k], 0.0, active[k].upper);
    }
    if (fixed.has_value()) {  // equal bounds: NLopt drops the dimension
      box.lower[2 + *fixed] = box.upper[2 + *fixed] = x[2 + *fixed];
    }
    // Steps in the strengths scaled to the start, so a search near a small
    // strength does not begin by jumping across the whole range.
    for (std::size_t k = 0; k < active.size(); ++k) {
      box.initial_step[2 + k] =
          std::min(0.1 * active[k].upper,
                   std::max(0.01 * active[k].upper, 0.2 * x[2 + k]));
    }
    const BoxMinimum found = MinimiseInBox(rss, box, x);
    if (found.value < best_rss) {
      best_rss = found.value;
      best.ln_c_e = found.x[0];
      best.ln_alpha = found.x[1];
      best.u.assign(found.x.begin() + 2, found.x.end());
    }
  }
  *rss_out = best_rss;
  return best;
}

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

ActiveEffect ScaleEffect(const sim::EffectSpec& spec, const Runs& runs,
                         double c_e, double alpha) {
  ActiveEffect e;
  e.spec = &spec;
  const double f_min =
      *std::min_element(runs.force_n.begin(), runs.force_n.end());
  const double f_max =
      *std::max_element(runs.force_n.begin(), runs.force_n.end());
  const double r = runs.radius_mm;
  DescentSurrogateInput top;
  top.force_n = f_max;
  top.c_e_n_per_mm2 = c_e;
  top.alpha_per_s = alpha;
  top.radius_mm = r;
  double v_top = SurrogateVelocityMmS(top, runs.definition);
  if (!(v_top > 0.0 && std::isfinite(v_top))) v_top = alpha * r;
  // Scaled by the family; the shapes within one share its scale.
  const std::string_view id = spec.Family();
  if (id == "motor_power_limit") {
    // 1/Q_max in units of 1/Q_top, Q the free removal rate at the top force:
    // the cap binds from u = 1 on.
    const double load = f_max / (c_e * r * r);
    const double area = runs.definition == sim::VelocityDefinition::kInitial
                            ? InitialRemovalArea(std::cbrt(load * load))
                            : RemovalAreaAtKappa(KappaAtLoad(load));
    const double q_top = v_top * r * r * area;
    e.unit = 1.0 / q_top;
    e.upper = 50.0;
  } else if (id == "spindle_slowdown") {
    e.unit = 1.0 / f_max;  // the stall force above the largest force
    e.upper = 0.98;
  } else if (id == "cutting_threshold") {
    e.unit = f_min;  // the threshold below the smallest force
    e.upper = 0.98;
  } else if (id == "viscous_resistance") {
    // c_i R^2 (h/R) v_ref (v / v_ref)^m comparable with the top force at
    // u = 1 (v_ref = 1 mm/s).
    const double m = spec.shape_field == &sim::Effects::viscous_exponent
                         ? spec.shape_value
                         : 1.0;
    e.unit = f_max / (r * r * std::pow(v_top, m));
    e.upper = 5.0;
  } else if (id == "friction_erosion") {
    // The rate alpha + k |F_e| = alpha (1 + u |F_e| / F_max): k relative to
    // the point's own alpha, so that log alpha still enters additively and
    // a strength means one shape whatever the base fit's alpha (which may
    // sit at the end of its box, where k would need many decades less).
    const double p =
        spec.shape_field == &sim::Effects::friction_erosion_exponent
            ? spec.shape_value
            : 1.0;
    e.unit = 1.0 / std::pow(f_max, p);
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

Eigen::MatrixXd ColumnBasis(const Eigen::MatrixXd& j) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeThinU);
  const Eigen::VectorXd& s = svd.singularValues();
  int rank = 0;
  while (rank < s.size() && s(rank) > 1e-9 * s(0)) ++rank;
  return svd.matrixU().leftCols(rank);
}

Eigen::VectorXd Project(const Eigen::MatrixXd& basis,
                        const Eigen::VectorXd& x) {
  return x - basis * (basis.transpose() * x);
}

double Aicc(double rss, int n, int parameters) {
  const int k = parameters + 1;  // and sigma
  const double floor = std::max(rss, 1e-300);
  double aicc = n * std::log(floor / n) + 2.0 * k;
  aicc += n - k - 1 > 0 ? 2.0 * k * (k + 1) / (n - k - 1) : kInf;
  return aicc;
}

Result<Point> Workflow::BaseFit(const std::vector<char>& use) const {
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

Model Workflow::FitAugmented(const std::vector<ActiveEffect>& active,
                             const Point& from,
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
  for (double change : {0.005, 0.01, 0.02, 0.04, 0.07, 0.1, 0.15, 0.2, 0.3, 0.4,
                        0.5, 0.65, 0.8}) {
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

double Workflow::CrossValidate(const Model& model,
                               std::vector<double>* per_level) const {
  if (per_level != nullptr) per_level->clear();
  if (runs_.levels < 3) return kNaN;
  double sum = 0.0;
  int count = 0;
  std::vector<double> levels;
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
    double level_sum = 0.0;
    int level_count = 0;
    for (int i = 0; i < runs_.size(); ++i) {
      if (use[i]) continue;
      const double r =
          std::isfinite(y[i]) ? runs_.ln_v[i] - y[i] : kUnreachableResidual;
      level_sum += r * r;
      ++level_count;
    }
    sum += level_sum;
    count += level_count;
    levels.push_back(level_count > 0 ? std::sqrt(level_sum / level_count)
                                     : kNaN);
  }
  if (count == 0) return kNaN;
  if (per_level != nullptr) *per_level = std::move(levels);
  return std::sqrt(sum / count);
}

ModelFit Workflow::Describe(const Model& m) const {
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
  f.cv_rmse_log_v = CrossValidate(m, &f.cv_level_rmse_log_v);
  f.fitted_log_v = Predict(runs_, m.active, m.point);
  return f;
}

}  // namespace discover_internal

double ModelLogVelocity(double force_n, double c_e_n_per_mm2,
                        double alpha_per_s, double radius_mm,
                        const sim::Effects& effects,
                        sim::VelocityDefinition definition,
                        double transient_factor) {
  DescentSurrogateInput in;
  in.force_n = force_n;
  in.c_e_n_per_mm2 = c_e_n_per_mm2;
  in.alpha_per_s = alpha_per_s;
  in.radius_mm = radius_mm;
  in.effects = effects;
  const double v = SurrogateVelocityMmS(in, definition, transient_factor);
  return v > 0.0 && std::isfinite(v) ? std::log(v) : detail::kNaN;
}

Result<double> BaseModelRss(const MeasuredData& data, double radius_mm) {
  const discover_internal::Runs runs = discover_internal::MakeRuns(
      data, radius_mm, sim::VelocityDefinition::kSettled);
  DiscoverOptions options;
  options.radius_mm = radius_mm;
  const discover_internal::Workflow flow(runs, options);
  Result<discover_internal::Point> p = flow.BaseFit({});
  if (!p.ok()) return p.error();
  return discover_internal::Rss(runs, {}, *p, {});
}

}  // namespace burrlab::analysis
