// The trace-gap test: a lumped transient model of the descent rig fitted to
// its traces with and without each trace-only effect.
#include "burrlab/analysis/model_gap/trace_gap.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/tools/minima.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <span>

#include "burrlab/analysis/box_search.h"
#include "burrlab/analysis/model_gap/descent_surrogate.h"

namespace burrlab::analysis {
namespace {

// The rig's contact rule (sim/descent.cc): the measured force passes 5 % of
// the held force.
constexpr double kContactFraction = 0.05;

// Upper bounds of the fitted parameters: a lag of 1 s, a compliance of
// 2 mm/N, far beyond what a burring rig would tolerate.
double UpperBound(const sim::EffectSpec& spec) {
  return spec.field == &sim::Effects::load_cell_lag_s ? 1.0 : 2.0;
}

// Hertz contact (eq. 7.3) at tip depth h below the eroded surface; the
// sphere is whole at h = 2R.
double ContactForceN(double h_mm, double c_e, double r) {
  if (!(h_mm > 0.0)) return 0.0;
  const double x = std::min(h_mm, 2.0 * r) / r;
  return c_e * r * r * x * std::sqrt(x);
}

// The time of the first sample above the contact threshold, or NaN.
double ContactTimeS(const RunTrace& trace, double force_n) {
  for (std::size_t k = 0; k < trace.t_s.size(); ++k) {
    if (trace.force_n[k] > kContactFraction * force_n) return trace.t_s[k];
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// Residual sums of one model over all runs, per channel (0 force, 1 depth),
// in units of the held force and of the static immersion.
struct Sums {
  double rss[2] = {0.0, 0.0};
  double lag1[2] = {0.0, 0.0};  // sum of products of consecutive residuals
  double sq_n[2] = {0.0, 0.0};  // sum of squared residuals in N and mm
  double n = 0.0;               // weighted sample count
  int samples = 0;
};

struct Prepared {
  const TraceRun* run = nullptr;
  double until_s = 0.0;
  double immersion_mm = 0.0;
  // The runs this trace stands for over the runs at its force: replicates
  // share the rig's systematic transient (synthetic ones its very trace), so
  // a force level weighs as much as one trace.
  double weight = 1.0;
};

Sums Residuals(const std::vector<Prepared>& runs, const TraceGapOptions& o,
               const sim::Effects& effects) {
  Sums sums;
  for (const Prepared& p : runs) {
    const RunTrace& t = p.run->trace;
    const LumpedTrace model =
        SimulateLumpedRig(t, p.run->force_n, o, effects, p.until_s);
    double previous[2] = {0.0, 0.0};
    for (std::size_t k = 0; k < model.t_s.size(); ++k) {
      const double e_n = t.force_n[k] - model.force_n[k];
      const double e_mm = t.depth_mm[k] - model.depth_mm[k];
      const double e[2] = {e_n / p.run->force_n, e_mm / p.immersion_mm};
      const double w = p.weight;
      for (int c = 0; c < 2; ++c) {
        sums.rss[c] += w * e[c] * e[c];
        if (k > 0) sums.lag1[c] += w * e[c] * previous[c];
        previous[c] = e[c];
      }
      sums.sq_n[0] += w * e_n * e_n;
      sums.sq_n[1] += w * e_mm * e_mm;
      sums.n += w;
      ++sums.samples;
    }
  }
  return sums;
}

}  // namespace

std::vector<TraceRun> PairTraces(const TraceData& traces,
                                 const MeasuredData& measured) {
  std::map<std::string, double, std::less<>> force;
  for (const MeasuredRun& r : measured.runs) force[r.run] = r.force_n;
  std::vector<TraceRun> out;
  for (const RunTrace& t : traces.runs) {
    auto it = force.find(t.run);
    if (it == force.end()) continue;
    out.push_back({t, it->second});
  }
  return out;
}

Status TraceGapOptions::Validate() const {
  const auto positive = [](const char* name, double value) -> Status {
    if (!std::isfinite(value) || value <= 0.0) {
      return Error{fmt::format("{} must be a positive finite number, got {}",
                               name, value)};
    }
    return {};
  };
  for (const Status& s :
       {positive("c_e_n_per_mm2", c_e_n_per_mm2),
        positive("alpha_per_s", alpha_per_s), positive("radius_mm", radius_mm),
        positive("window_s", window_s),
        positive("model_error_fraction", model_error_fraction)}) {
    if (!s.ok()) return s;
  }
  if (!(test_level > 0.0 && test_level < 1.0)) {
    return Error{
        fmt::format("test_level must lie in (0, 1), got {}", test_level)};
  }
  sim::DescentOptions rig_check = rig;
  rig_check.radius_mm = radius_mm;
  if (Status s = rig_check.Validate(); !s.ok()) return s;
  return {};
}

LumpedTrace SimulateLumpedRig(const RunTrace& trace, double force_n,
                              const TraceGapOptions& o,
                              const sim::Effects& effects, double until_s) {
  LumpedTrace out;
  const std::size_t samples = trace.t_s.size();
  if (samples == 0) return out;
  const double r = o.radius_mm, c_e = o.c_e_n_per_mm2, dt = o.rig.dt_s;
  const double compliance = effects.arm_compliance_mm_per_n;
  const double max_load = 0.999 * MaxSteadyLoad();
  sim::LoadCell cell(o.rig.filter_hz, effects.load_cell_lag_s, dt);
  double t = trace.t_s[0];
  double arm = trace.depth_mm[0];  // the arm's depth, as the rig records it
  double surface = 0.0, deflection = 0.0;
  double integral = 0.0, previous_measured = 0.0, velocity = 0.0;
  bool contact = false;
  // The previous tick's record, for linear interpolation at sample times.
  double t_prev = t, f_prev = 0.0, a_prev = arm, b_prev = arm, s_prev = 0.0;
  std::size_t k = 0;
  const auto record = [&](double t_now, double f, double a, double b,
                          double s) {
    while (k < samples && trace.t_s[k] <= t_now && trace.t_s[k] <= until_s) {
      const double w =
          t_now > t_prev
              ? std::clamp((trace.t_s[k] - t_prev) / (t_now - t_prev), 0.0, 1.0)
              : 1.0;
      out.t_s.push_back(trace.t_s[k]);
      out.force_n.push_back(f_prev + w * (f - f_prev));
      out.depth_mm.push_back(a_prev + w * (a - a_prev));
      out.burr_depth_mm.push_back(b_prev + w * (b - b_prev));
      out.surface_mm.push_back(s_prev + w * (s - s_prev));
      ++k;
    }
    t_prev = t_now;
    f_prev = f;
    a_prev = a;
    b_prev = b;
    s_prev = s;
  };
  const std::size_t max_ticks =
      static_cast<std::size_t>((std::min(until_s, trace.t_s.back()) - t) / dt) +
      2;
  for (std::size_t tick = 0; tick < max_ticks + 1; ++tick) {
    // The spring: deflection d = C F(arm - d - s), solved by Newton from the
    // left (g(d) = d - C F is increasing and concave, so the iterates climb
    // monotonically to the root).
    if (compliance > 0.0) {
      const double gap = arm - surface;
      double d = std::clamp(deflection, 0.0, std::max(gap, 0.0));
      if (d - compliance * ContactForceN(gap - d, c_e, r) > 0.0) d = 0.0;
      for (int it = 0; it < 50; ++it) {
        const double h = gap - d;
        const double g = d - compliance * ContactForceN(h, c_e, r);
        const double x = std::clamp(h / r, 0.0, 2.0);
        const double slope =
            1.0 +
            compliance *
                (h > 0.0 && h < 2.0 * r ? 1.5 * c_e * r * std::sqrt(x) : 0.0);
        const double step = -g / slope;
        d += step;
        if (std::abs(step) < 1e-13) break;
      }
      deflection = std::max(d, 0.0);
    }
    const double tip = arm - deflection;
    const double h = tip - surface;
    const double force = ContactForceN(h, c_e, r);
    const double measured = cell.Read(force);
    record(t, measured, arm, tip, surface);
    if (k >= samples || trace.t_s[k] > until_s) break;
    // The rig's PI law (sim/descent.cc).
    if (!contact && measured > kContactFraction * force_n) contact = true;
    const double error = force_n - measured;
    if (contact) integral += error * dt;
    const double derivative = (measured - previous_measured) / dt;
    previous_measured = measured;
    velocity = o.rig.kp_mm_per_n_s * error + o.rig.ki_mm_per_n_s2 * integral -
               o.rig.kd_mm_per_n * derivative;
    velocity =
        std::clamp(velocity, -o.rig.max_speed_mm_s, o.rig.max_speed_mm_s);
    // Quasi-steady erosion: the surface recedes at the steady velocity of
    // the current load (descent_surrogate.h), alpha R / kappa(y).
    if (h > 0.0) {
      const double load = std::min(force / (c_e * r * r), max_load);
      surface += o.alpha_per_s * r / KappaAtLoad(load) * dt;
    }
    arm += velocity * dt;
    t += dt;
  }
  return out;
}

Result<TraceGapResult> TestTraceEffects(const std::vector<TraceRun>& runs,
                                        const TraceGapOptions& o) {
  if (Status s = o.Validate(); !s.ok()) return s.error();
  if (runs.empty()) return Error{"the trace-gap test needs at least one trace"};
  const double r = o.radius_mm;
  // Runs with the very same trace (synthetic replicates share their level's)
  // are simulated once and weighted.
  std::vector<Prepared> prepared;
  double force_max = 0.0;
  for (const TraceRun& run : runs) {
    const double contact_s = ContactTimeS(run.trace, run.force_n);
    if (!std::isfinite(contact_s)) {
      return Error{fmt::format(
          "the trace of run {} never reaches {} % of its force {} N: no "
          "contact",
          run.trace.run, 100.0 * kContactFraction, run.force_n)};
    }
    force_max = std::max(force_max, run.force_n);
    const double weight =
        1.0 / static_cast<double>(std::count_if(
                  runs.begin(), runs.end(),
                  [&](const TraceRun& q) { return q.force_n == run.force_n; }));
    bool merged = false;
    for (Prepared& p : prepared) {
      const RunTrace& t = p.run->trace;
      if (p.run->force_n == run.force_n && t.t_s == run.trace.t_s &&
          t.force_n == run.trace.force_n && t.depth_mm == run.trace.depth_mm) {
        p.weight += weight;
        merged = true;
        break;
      }
    }
    if (merged) continue;
    Prepared p;
    p.run = &run;
    p.until_s = contact_s + o.window_s;
    p.immersion_mm =
        r * std::cbrt(std::pow(run.force_n / (o.c_e_n_per_mm2 * r * r), 2.0));
    p.weight = weight;
    prepared.push_back(p);
  }
  // c_e is a nuisance parameter: v(F) pins only a combination of c_e and
  // alpha (calibration.h), and an error in c_e moves the indentation depth
  // as a spring would. It is fitted to the traces under the null and under
  // each effect, alpha following it along the v(F) fit: v = alpha R /
  // kappa(F / (c_e R^2)) (descent_surrogate.h), so log alpha moves by the
  // runs' mean change of log kappa, which keeps v(F) fitted as well as the
  // base fit does (exactly when every run of the base fit is traced).
  const auto mean_log_kappa = [&](double c_e) {
    double sum = 0.0;
    for (const TraceRun& run : runs) {
      sum += std::log(KappaAtLoad(run.force_n / (c_e * r * r)));
    }
    return sum / static_cast<double>(runs.size());
  };
  const double base_log_kappa = mean_log_kappa(o.c_e_n_per_mm2);
  // The whole sphere in at the largest force bounds c_e from below.
  const double ln_c_e_base = std::log(o.c_e_n_per_mm2);
  const double ln_lo =
      std::max(ln_c_e_base - std::log(30.0),
               std::log(force_max / (0.95 * MaxSteadyLoad() * r * r)));
  const double ln_hi = std::max(ln_c_e_base + std::log(30.0), ln_lo + 1.0);
  const auto evaluate = [&](double ln_c_e, const sim::Effects& effects) {
    TraceGapOptions at = o;
    at.c_e_n_per_mm2 = std::exp(ln_c_e);
    at.alpha_per_s = o.alpha_per_s * std::exp(mean_log_kappa(at.c_e_n_per_mm2) -
                                              base_log_kappa);
    return Residuals(prepared, at, effects);
  };
  // Deviance: each channel's profile Gaussian likelihood on its effective
  // sample count, with the model-error floor (set from the null below).
  double n_eff[2] = {0.0, 0.0}, floor_ss[2] = {0.0, 0.0};
  const auto deviance = [&](const Sums& s) {
    double d = 0.0;
    for (int c = 0; c < 2; ++c) {
      d += n_eff[c] * std::log(s.rss[c] + floor_ss[c]);
    }
    return d;
  };
  // Minimises the deviance over log c_e in [lo, hi] for fixed effects: a
  // grid (when grid_points > 1), then Brent.
  const auto profile = [&](const sim::Effects& effects, double lo, double hi,
                           int grid_points, int bits, double* ln_c_e) {
    double best_x = 0.5 * (lo + hi);
    double best_f = std::numeric_limits<double>::infinity();
    double bracket_lo = lo, bracket_hi = hi;
    if (grid_points > 1) {
      const double step = (hi - lo) / (grid_points - 1);
      for (int i = 0; i < grid_points; ++i) {
        const double x = lo + step * i;
        const double f = deviance(evaluate(x, effects));
        if (f < best_f) {
          best_f = f;
          best_x = x;
        }
      }
      bracket_lo = std::max(lo, best_x - step);
      bracket_hi = std::min(hi, best_x + step);
    }
    const auto [x, f] = boost::math::tools::brent_find_minima(
        [&](double v) { return deviance(evaluate(v, effects)); }, bracket_lo,
        bracket_hi, bits);
    if (f < best_f) {
      best_f = f;
      best_x = x;
    }
    *ln_c_e = best_x;
    return best_f;
  };
  const sim::Effects null_effects;
  // The error model comes from a first null fit with unit counts: the AR(1)
  // effective counts and the floor from its residuals; then c_e again.
  n_eff[0] = n_eff[1] = 1.0;
  double ln_c_e_null = ln_c_e_base;
  profile(null_effects, ln_lo, ln_hi, 15, 16, &ln_c_e_null);
  const Sums first = evaluate(ln_c_e_null, null_effects);
  if (first.samples == 0) return Error{"the traces hold no samples to fit"};
  for (int c = 0; c < 2; ++c) {
    const double rho = first.rss[c] > 0.0
                           ? std::clamp(first.lag1[c] / first.rss[c], 0.0, 0.98)
                           : 0.0;
    n_eff[c] = first.n * (1.0 - rho) / (1.0 + rho);
    floor_ss[c] = first.n * o.model_error_fraction * o.model_error_fraction;
  }
  const double null_deviance =
      profile(null_effects, std::max(ln_lo, ln_c_e_null - 0.2),
              std::min(ln_hi, ln_c_e_null + 0.2), 1, 16, &ln_c_e_null);
  const Sums null = evaluate(ln_c_e_null, null_effects);
  TraceGapResult result;
  result.runs = static_cast<int>(runs.size());
  result.samples = null.samples;
  result.c_e_n_per_mm2 = std::exp(ln_c_e_null);
  result.rmse_force_n = std::sqrt(null.sq_n[0] / null.n);
  result.rmse_depth_mm = std::sqrt(null.sq_n[1] / null.n);
  for (const sim::EffectSpec& spec : sim::EffectLibrary()) {
    if (!spec.trace_only) continue;
    const auto with = [&](double value) {
      sim::Effects effects;
      sim::ApplyEffect(spec, value, &effects);
      return effects;
    };
    // The effect's parameter on a geometric grid from 1e-3 of its bound,
    // c_e profiled near the null's at each point; then a bounded local fit
    // of both (NLopt BOBYQA) from the best point.
    const double upper = UpperBound(spec);
    constexpr int kGrid = 7;
    const double lo = std::max(ln_lo, ln_c_e_null - std::log(2.0));
    const double hi = std::min(ln_hi, ln_c_e_null + std::log(2.0));
    double best_value = 0.0, best_deviance = null_deviance,
           best_ln_c_e = ln_c_e_null;
    for (int i = 0; i < kGrid; ++i) {
      const double value = upper * std::pow(1e-3, 1.0 - i / (kGrid - 1.0));
      double x = 0.0;
      const double f = profile(with(value), lo, hi, 1, 12, &x);
      if (f < best_deviance) {
        best_deviance = f;
        best_value = value;
        best_ln_c_e = x;
      }
    }
    {
      // x = (log c_e, parameter / bound).
      BoxSearch box;
      box.lower = {lo, 0.0};
      box.upper = {hi, 1.0};
      box.initial_step = {0.05, std::max(0.25 * best_value / upper, 1e-4)};
      box.max_evaluations = 80;
      const BoxMinimum found = MinimiseInBox(
          [&](std::span<const double> x) {
            return deviance(evaluate(x[0], with(x[1] * upper)));
          },
          box, {best_ln_c_e, best_value / upper});
      if (found.value < best_deviance) {
        best_deviance = found.value;
        best_ln_c_e = found.x[0];
        best_value = found.x[1] * upper;
      }
    }
    const double fitted = best_value;
    TraceEffectTest test;
    test.id = std::string(spec.id);
    test.value = fitted;
    test.c_e_n_per_mm2 = std::exp(best_ln_c_e);
    test.lr = std::max(0.0, null_deviance - best_deviance);
    test.p =
        test.lr > 0.0
            ? 0.5 * boost::math::cdf(boost::math::complement(
                        boost::math::chi_squared_distribution<>(1.0), test.lr))
            : 1.0;
    const Sums s = evaluate(best_ln_c_e, with(fitted));
    test.rmse_force_n = std::sqrt(s.sq_n[0] / s.n);
    test.rmse_depth_mm = std::sqrt(s.sq_n[1] / s.n);
    result.effects.push_back(test);
  }
  // Holm over the trace effects.
  std::vector<std::size_t> order(result.effects.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return result.effects[a].p < result.effects[b].p;
  });
  double running = 0.0;
  for (std::size_t rank = 0; rank < order.size(); ++rank) {
    TraceEffectTest& e = result.effects[order[rank]];
    running = std::max(
        running, std::min(1.0, e.p * static_cast<double>(order.size() - rank)));
    e.p_holm = running;
  }
  double best_lr = 0.0;
  for (const TraceEffectTest& e : result.effects) {
    if (e.p_holm < o.test_level && e.lr > best_lr) {
      best_lr = e.lr;
      result.named = e.id;
    }
  }
  return result;
}

}  // namespace burrlab::analysis
