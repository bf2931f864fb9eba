// QUEST threshold tracking; see quest.h. The grid, tables, normalisation and
// clamping follow the behaviour documented for Psychtoolbox-3's Quest
// functions (Watson & Pelli 1983; placement quantile from Pelli 1987), so that
// traces replay to rounding error; the comments mark where burrlab differs.
#include "burrlab/protocols/quest.h"

#include <fmt/format.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <limits>

namespace burrlab::protocols {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Intensities are limited to +-1e10 before rounding to a table step (PTB
// does the same so that +-inf, e.g. log10(0), has a table position).
constexpr double kIntensityLimit = 1e10;
// Largest range/grain accepted: the tables hold 3*(range/grain) doubles.
constexpr double kMaxTableSteps = 1e6;

// Positive and finite, reported as two rules so the message names the right
// one ("must be positive, got 0" / "must be finite, got inf").
Status CheckPositive(const char* field, double value) {
  if (!(value > 0.0)) {
    return Error{
        fmt::format("quest: {} must be positive, got {}", field, value)};
  }
  if (!std::isfinite(value)) {
    return Error{fmt::format("quest: {} must be finite, got {}", field, value)};
  }
  return Status();
}

// Linear interpolation at v in the increasing table (xs, ys), v within
// [xs.front(), xs.back()]: the interval is the last xs[j] <= v, at most the
// last interval (Octave interp1 "linear" evaluates slope*(v - xs[j]) + ys[j]).
double Interpolate(std::span<const double> xs, std::span<const double> ys,
                   double v) {
  const std::size_t n = xs.size();
  std::size_t j = static_cast<std::size_t>(
      std::upper_bound(xs.begin(), xs.end(), v) - xs.begin());
  j = std::clamp<std::size_t>(j, 1, n - 1) - 1;
  const double slope = (ys[j + 1] - ys[j]) / (xs[j + 1] - xs[j]);
  return slope * (v - xs[j]) + ys[j];
}

// The Weibull of QuestCreate at every x2 + offset.
void FillWeibull(const QuestOptions& o, std::span<const double> x2,
                 double offset, std::vector<double>& p) {
  p.resize(x2.size());
  for (std::size_t k = 0; k < x2.size(); ++k) {
    p[k] = o.delta * o.gamma +
           (1.0 - o.delta) *
               (1.0 - (1.0 - o.gamma) *
                          std::exp(-std::pow(10.0, o.beta * (x2[k] + offset))));
  }
}

bool AllFinite(std::span<const double> v) {
  return std::all_of(v.begin(), v.end(),
                     [](double d) { return std::isfinite(d); });
}

double Sum(std::span<const double> v) {
  double s = 0.0;
  for (double d : v) s += d;
  return s;
}

}  // namespace

Status QuestOptions::Validate() const {
  if (!std::isfinite(t_guess)) {
    return Error{fmt::format("quest: t_guess must be finite, got {}", t_guess)};
  }
  if (Status s = CheckPositive("t_guess_sd", t_guess_sd); !s.ok()) return s;
  if (Status s = CheckPositive("beta", beta); !s.ok()) return s;
  if (!(delta >= 0.0 && delta < 1.0)) {
    return Error{fmt::format("quest: delta must be in [0, 1), got {}", delta)};
  }
  if (!(gamma >= 0.0 && gamma < 1.0)) {
    return Error{fmt::format("quest: gamma must be in [0, 1), got {}", gamma)};
  }
  if (!(p_threshold > 0.0 && p_threshold < 1.0)) {
    return Error{fmt::format("quest: p_threshold must be in (0, 1), got {}",
                             p_threshold)};
  }
  // PTB's QuestRecompute silently resets gamma to 0.5 here; we refuse instead.
  if (!(p_threshold > gamma)) {
    return Error{
        fmt::format("quest: p_threshold must be above gamma = {}, got {}",
                    gamma, p_threshold)};
  }
  const double ceiling = delta * gamma + (1.0 - delta);
  if (!(p_threshold < ceiling)) {
    return Error{
        fmt::format("quest: p_threshold must be below the ceiling "
                    "delta*gamma + 1 - delta = {:.6g}, got {}",
                    ceiling, p_threshold)};
  }
  if (Status s = CheckPositive("grain", grain); !s.ok()) return s;
  if (Status s = CheckPositive("range", range); !s.ok()) return s;
  if (!(range / grain <= kMaxTableSteps)) {
    return Error{fmt::format(
        "quest: range/grain must be at most {:.0f} table steps, got {:.0f} "
        "(range {}, grain {})",
        kMaxTableSteps, range / grain, range, grain)};
  }
  if (quantile_order.has_value() &&
      !(*quantile_order >= 0.0 && *quantile_order <= 1.0)) {
    return Error{fmt::format("quest: quantile_order must be in [0, 1], got {}",
                             *quantile_order)};
  }
  if (reserve_trials < 0) {
    return Error{
        fmt::format("quest: reserve_trials must be zero or positive, got {}",
                    reserve_trials)};
  }
  return Status();
}

Result<Quest> Quest::Create(const QuestOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  Quest q(options);
  const QuestOptions& o = q.options_;

  // dim: range/grain rounded up to an even number of steps.
  const double dim_d = 2.0 * std::ceil((o.range / o.grain) / 2.0);
  const int dim = static_cast<int>(dim_d);
  q.half_dim_ = dim / 2;

  // Prior: a Gaussian of sd t_guess_sd around t_guess, normalised.
  q.x_.resize(static_cast<std::size_t>(dim) + 1);
  q.pdf_.resize(q.x_.size());
  for (int j = 0; j <= dim; ++j) {
    const double x = static_cast<double>(j - q.half_dim_) * o.grain;
    const double z = x / o.t_guess_sd;
    q.x_[j] = x;
    q.pdf_[j] = std::exp(-0.5 * (z * z));
  }
  const double prior_sum = Sum(q.pdf_);
  for (double& p : q.pdf_) p /= prior_sum;
  if (!AllFinite(q.pdf_)) {
    return Error{
        "quest: the prior is not finite; t_guess_sd is too small "
        "for the grain"};
  }

  // Psychometric table over intensity - threshold, first without the offset
  // that puts p_threshold at 0, then with it.
  q.x2_.resize(2 * static_cast<std::size_t>(dim) + 1);
  for (int k = 0; k <= 2 * dim; ++k) {
    q.x2_[k] = static_cast<double>(k - dim) * o.grain;
  }
  FillWeibull(o, q.x2_, 0.0, q.p1_);
  const double lo = std::min(q.p1_.front(), q.p1_.back());
  const double hi = std::max(q.p1_.front(), q.p1_.back());
  if (lo > o.p_threshold || hi < o.p_threshold) {
    return Error{fmt::format(
        "quest: the psychometric function spans [{:.4f}, {:.4f}] over the "
        "table and misses p_threshold = {}; increase range or beta",
        lo, hi, o.p_threshold)};
  }
  if (!AllFinite(q.p1_)) {
    return Error{"quest: the psychometric function is not finite"};
  }
  // The points where the table changes (strictly increasing for beta > 0).
  std::vector<double> p_strict;
  std::vector<double> x_strict;
  for (std::size_t k = 0; k + 1 < q.p1_.size(); ++k) {
    if (q.p1_[k + 1] != q.p1_[k]) {
      p_strict.push_back(q.p1_[k]);
      x_strict.push_back(q.x2_[k]);
    }
  }
  if (p_strict.size() < 2 || o.p_threshold < p_strict.front() ||
      o.p_threshold > p_strict.back()) {
    return Error{fmt::format(
        "quest: the psychometric function has no p_threshold = {} point on "
        "the table; increase range or reduce grain",
        o.p_threshold)};
  }
  q.x_threshold_ = Interpolate(p_strict, x_strict, o.p_threshold);
  FillWeibull(o, q.x2_, q.x_threshold_, q.p1_);
  if (!AllFinite(q.p1_)) {
    return Error{"quest: the psychometric function is not finite"};
  }
  q.p0_.resize(q.p1_.size());
  for (std::size_t k = 0; k < q.p1_.size(); ++k) q.p0_[k] = 1.0 - q.p1_[k];

  // Pelli (1987): the most informative quantile depends only on the floor pL
  // and ceiling pH of the function (0.60 for pL = 0.5, pH = 1). x*log(x + eps)
  // keeps x = 0 finite.
  if (o.quantile_order.has_value()) {
    q.quantile_order_ = *o.quantile_order;
  } else {
    const double eps = DBL_EPSILON;
    const double pl = q.p1_.front();
    const double ph = q.p1_.back();
    double pe = ph * std::log(ph + eps) - pl * std::log(pl + eps) +
                (1.0 - ph + eps) * std::log(1.0 - ph + eps) -
                (1.0 - pl + eps) * std::log(1.0 - pl + eps);
    pe = 1.0 / (1.0 + std::exp(pe / (pl - ph)));
    q.quantile_order_ = (pe - pl) / (ph - pl);
  }

  q.trials_.reserve(static_cast<std::size_t>(o.reserve_trials));
  return q;
}

double Quest::intensity_min() const {
  return static_cast<double>(-half_dim_) * options_.grain + options_.t_guess;
}

double Quest::intensity_max() const {
  return static_cast<double>(half_dim_) * options_.grain + options_.t_guess;
}

Result<QuestUpdateReport> Quest::Update(double intensity, bool response) {
  if (std::isnan(intensity)) {
    return Error{
        fmt::format("quest: intensity of trial {} is NaN", trial_count() + 1)};
  }
  // The intensity's table step relative to t_guess; beyond +-dim/2 the
  // likelihood row would leave the table, so it is shifted to the edge.
  const double limited =
      std::max(-kIntensityLimit, std::min(kIntensityLimit, intensity));
  double step = std::round((limited - options_.t_guess) / options_.grain);
  QuestUpdateReport report;
  const double h = static_cast<double>(half_dim_);
  if (step > h || step < -h) {
    report.clamped = true;
    step = std::clamp(step, -h, h);
  }
  report.table_intensity = options_.t_guess + step * options_.grain;

  if (options_.update_pdf) {
    // pdf[j] is threshold t_guess + x[j]; the tested intensity sits at
    // (step - (j - h)) grains above it, which is x2_[step - j + 3h].
    const std::vector<double>& like = response ? p1_ : p0_;
    const int offset = static_cast<int>(step) + 3 * half_dim_;
    const int n = static_cast<int>(pdf_.size());
    for (int j = 0; j < n; ++j) pdf_[j] *= like[offset - j];
    if (options_.normalize_pdf) {
      const double sum = Sum(pdf_);
      for (double& p : pdf_) p /= sum;
    }
  }
  trials_.push_back(QuestTrial{intensity, response});
  return report;
}

Result<double> Quest::Quantile() const { return Quantile(quantile_order_); }

Result<double> Quest::Quantile(double order) const {
  if (!(order >= 0.0 && order <= 1.0)) {
    return Error{
        fmt::format("quest: quantile order must be in [0, 1], got {}", order)};
  }
  const double total = Sum(pdf_);
  if (!std::isfinite(total)) return Error{"quest: the posterior is not finite"};
  if (total == 0.0) return Error{"quest: the posterior is all zero"};
  // The target is a fraction of the posterior's total. PTB 3.0.18 compares the
  // unscaled order with the cumulative sum in its two range checks, which with
  // normalizePdf = 0 sends every trial to the table top once the total drops
  // below the order; scaling keeps the quantile independent of normalisation
  // and equals PTB whenever the posterior is normalised.
  const double target = order * total;
  if (target < pdf_[0]) return options_.t_guess + x_[0];

  // Linear interpolation in the cumulative sum, over the points where it
  // grows (zero-density points would make it flat).
  double cum = 0.0;
  int kept = 0;
  double below_c = 0.0, below_x = 0.0;  // last kept point with cum <= target
  double above_c = 0.0, above_x = 0.0;  // first kept point with cum > target
  bool found_above = false;
  double prev_c = 0.0, prev_x = 0.0;  // the last two kept points
  double last_c = 0.0, last_x = 0.0;
  for (std::size_t j = 0; j < pdf_.size(); ++j) {
    const double c = cum + pdf_[j];
    const bool keep = j == 0 || c > cum;
    cum = c;
    if (!keep) continue;
    ++kept;
    prev_c = last_c;
    prev_x = last_x;
    last_c = c;
    last_x = x_[j];
    if (found_above) continue;
    if (c <= target) {
      below_c = c;
      below_x = x_[j];
    } else {
      above_c = c;
      above_x = x_[j];
      found_above = true;
    }
  }
  if (kept < 2) {
    return Error{
        fmt::format("quest: the posterior has only {} nonzero point(s)", kept)};
  }
  if (!found_above) {  // target is the total: the last interval
    below_c = prev_c;
    below_x = prev_x;
    above_c = last_c;
    above_x = last_x;
  }
  const double slope = (above_x - below_x) / (above_c - below_c);
  return options_.t_guess + (slope * (target - below_c) + below_x);
}

double Quest::Mean() const {
  double sum = 0.0;
  double sum_x = 0.0;
  for (std::size_t j = 0; j < pdf_.size(); ++j) {
    sum += pdf_[j];
    sum_x += pdf_[j] * x_[j];
  }
  return options_.t_guess + sum_x / sum;
}

double Quest::Sd() const {
  // Two passes (PTB uses E[x^2] - E[x]^2, equal to rounding error here, but
  // it can go negative for a posterior concentrated on one point).
  double sum = 0.0;
  double sum_x = 0.0;
  for (std::size_t j = 0; j < pdf_.size(); ++j) {
    sum += pdf_[j];
    sum_x += pdf_[j] * x_[j];
  }
  const double mean = sum_x / sum;
  double sum_d2 = 0.0;
  for (std::size_t j = 0; j < pdf_.size(); ++j) {
    const double d = x_[j] - mean;
    sum_d2 += pdf_[j] * d * d;
  }
  return std::sqrt(sum_d2 / sum);
}

double Quest::Mode() const {
  std::size_t best = 0;
  for (std::size_t j = 1; j < pdf_.size(); ++j) {
    if (pdf_[j] > pdf_[best]) best = j;
  }
  return x_[best] + options_.t_guess;
}

double Quest::P(double x) const {
  if (std::isnan(x)) return kNaN;
  if (x < x2_.front()) return p1_.front();
  if (x > x2_.back()) return p1_.back();
  return Interpolate(x2_, p1_, x);
}

}  // namespace burrlab::protocols
