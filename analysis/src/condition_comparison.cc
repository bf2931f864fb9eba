// Several conditions' psychometric functions fitted at once with shared or
// separate thresholds and slopes, and likelihood-ratio tests between them.
#include "burrlab/analysis/condition_comparison.h"

#include <fmt/format.h>
#include <nlopt.h>

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/random/binomial_distribution.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>

#include "burrlab/analysis/group_stats.h"
#include "nlopt_ptr.h"

namespace burrlab::analysis {
namespace {

// The search box, in levels normalised over every condition as the
// single-condition fit normalises them (psychometric.cc): locations within 5
// spans of the middle of the tested range, scales from 1e-4 to 100 spans.
constexpr double kJointLocationSpans = 5.0;
constexpr double kJointMinScaleSpans = 1e-4;
constexpr double kJointMaxScaleSpans = 100.0;
constexpr double kJointTinyProbability = 1e-300;

// The joint problem: internal parameters v = (m per condition or shared,
// ln s per condition or shared, lambda if free, gamma if free).
struct JointProblem {
  Sigmoid sigmoid = Sigmoid::kLogistic;
  ConditionModel model = ConditionModel::kSeparate;
  std::size_t conditions = 0;
  bool lambda_free = false, gamma_free = false;
  double gamma_fixed = 0.5;
  double middle = 0.0, span = 1.0;
  // Per condition: levels and counts (r may be simulated).
  std::vector<std::vector<double>> levels, n, r;

  std::size_t Locations() const {
    return model == ConditionModel::kShared ? 1 : conditions;
  }
  std::size_t Scales() const {
    return model == ConditionModel::kSeparate ? conditions : 1;
  }
  std::size_t Dimension() const {
    return Locations() + Scales() + (lambda_free ? 1 : 0) +
           (gamma_free ? 1 : 0);
  }
  // Condition k's parameters in the user's units (psychometric.h).
  PsychometricParams Params(const double* v, std::size_t k) const {
    const double m = v[Locations() == 1 ? 0 : k];
    const double ls = v[Locations() + (Scales() == 1 ? 0 : k)];
    std::size_t next = Locations() + Scales();
    PsychometricParams p;
    p.lambda = lambda_free ? v[next++] : 0.0;
    p.gamma = gamma_free ? v[next] : gamma_fixed;
    const double location = middle + span * m;
    const double scale = span * std::exp(ls);
    if (sigmoid == Sigmoid::kWeibull) {  // a Gumbel in ln x
      p.alpha = std::exp(location);
      p.beta = 1.0 / scale;
    } else {
      p.alpha = location;
      p.beta = scale;
    }
    return p;
  }
  // (m, ln s) of user parameters, clamped to the box.
  std::pair<double, double> Internal(const PsychometricParams& p) const {
    const bool weibull = sigmoid == Sigmoid::kWeibull;
    const double location = weibull ? std::log(p.alpha) : p.alpha;
    const double scale = weibull ? 1.0 / p.beta : p.beta;
    const double m = std::clamp((location - middle) / span,
                                -kJointLocationSpans, kJointLocationSpans);
    const double ls =
        std::clamp(std::log(scale / span), std::log(kJointMinScaleSpans),
                   std::log(kJointMaxScaleSpans));
    return {m, ls};
  }
  double LogLikelihood(const double* v) const {
    double log_l = 0.0;
    for (std::size_t k = 0; k < conditions; ++k) {
      const PsychometricParams p = Params(v, k);
      for (std::size_t i = 0; i < levels[k].size(); ++i) {
        const double psi = Psi(sigmoid, p, levels[k][i]);
        const double yes = std::max(psi, kJointTinyProbability);
        const double no = std::max(1.0 - psi, kJointTinyProbability);
        log_l += r[k][i] * std::log(yes) + (n[k][i] - r[k][i]) * std::log(no);
      }
    }
    return log_l;
  }
};

double JointNegativeLogLikelihood(unsigned /*dim*/, const double* v,
                                  double* /*gradient*/, void* data) {
  const double log_l = static_cast<const JointProblem*>(data)->LogLikelihood(v);
  return std::isfinite(log_l) ? -log_l : std::numeric_limits<double>::max();
}

double JointSaturatedLogLikelihood(const JointProblem& problem) {
  double log_l = 0.0;
  for (std::size_t k = 0; k < problem.conditions; ++k) {
    for (std::size_t i = 0; i < problem.n[k].size(); ++i) {
      const double r = problem.r[k][i], n = problem.n[k][i];
      if (r > 0.0) log_l += r * std::log(r / n);
      if (r < n) log_l += (n - r) * std::log((n - r) / n);
    }
  }
  return log_l;
}

// Internal starting vectors of `model` from per-condition parameters.
std::vector<double> JointStart(const JointProblem& problem,
                               const std::vector<PsychometricParams>& params) {
  std::vector<double> m, ls;
  double lambda = 0.0, gamma = 0.0;
  for (const PsychometricParams& p : params) {
    const auto [mk, lsk] = problem.Internal(p);
    m.push_back(mk);
    ls.push_back(lsk);
    lambda += p.lambda / static_cast<double>(params.size());
    gamma += p.gamma / static_cast<double>(params.size());
  }
  const auto mean = [](const std::vector<double>& x) { return Mean(x); };
  std::vector<double> v;
  if (problem.Locations() == 1) {
    v.push_back(mean(m));
  } else {
    v.insert(v.end(), m.begin(), m.end());
  }
  if (problem.Scales() == 1) {
    v.push_back(mean(ls));
  } else {
    v.insert(v.end(), ls.begin(), ls.end());
  }
  if (problem.lambda_free) v.push_back(lambda);
  if (problem.gamma_free) v.push_back(gamma);
  return v;
}

struct Optimum {
  std::vector<double> v;
  double log_likelihood = -std::numeric_limits<double>::infinity();
  bool converged = false;
};

// The best of BOBYQA runs from each start.
Optimum MaximiseJoint(
    JointProblem& problem,
    const std::vector<std::vector<PsychometricParams>>& starts,
    double lambda_max, double gamma_max, int max_evaluations) {
  const std::size_t dim = problem.Dimension();
  std::vector<double> lower, upper;
  for (std::size_t i = 0; i < problem.Locations(); ++i) {
    lower.push_back(-kJointLocationSpans);
    upper.push_back(kJointLocationSpans);
  }
  for (std::size_t i = 0; i < problem.Scales(); ++i) {
    lower.push_back(std::log(kJointMinScaleSpans));
    upper.push_back(std::log(kJointMaxScaleSpans));
  }
  if (problem.lambda_free) {
    lower.push_back(0.0);
    upper.push_back(lambda_max);
  }
  if (problem.gamma_free) {
    lower.push_back(0.0);
    upper.push_back(gamma_max);
  }
  Optimum best;
  for (const std::vector<PsychometricParams>& start : starts) {
    detail::NloptPtr opt(
        nlopt_create(NLOPT_LN_BOBYQA, static_cast<unsigned>(dim)));
    nlopt_set_lower_bounds(opt.get(), lower.data());
    nlopt_set_upper_bounds(opt.get(), upper.data());
    nlopt_set_min_objective(opt.get(), JointNegativeLogLikelihood, &problem);
    nlopt_set_xtol_rel(opt.get(), 1e-10);
    nlopt_set_ftol_abs(opt.get(), 1e-11);
    nlopt_set_maxeval(opt.get(), max_evaluations * static_cast<int>(dim));
    std::vector<double> v = JointStart(problem, start);
    for (std::size_t i = 0; i < dim; ++i) {
      v[i] = std::clamp(v[i], lower[i], upper[i]);
    }
    double value = 0.0;
    const nlopt_result rc = nlopt_optimize(opt.get(), v.data(), &value);
    if (rc < 0) continue;
    const double log_l = problem.LogLikelihood(v.data());
    if (log_l > best.log_likelihood) {
      best.v = v;
      best.log_likelihood = log_l;
      best.converged = rc != NLOPT_MAXEVAL_REACHED;
    }
  }
  return best;
}

int FreeParameters(const JointProblem& problem) {
  return static_cast<int>(problem.Dimension());
}

JointProblem MakeJointProblem(std::span<const ConditionData> conditions,
                              const PsychometricOptions& options,
                              ConditionModel model) {
  JointProblem problem;
  problem.sigmoid = options.sigmoid;
  problem.model = model;
  problem.conditions = conditions.size();
  problem.lambda_free = options.lambda_max > 0.0;
  problem.gamma_free = options.n_intervals == 1;
  problem.gamma_fixed =
      options.n_intervals == 1 ? 0.0 : 1.0 / options.n_intervals;
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const ConditionData& c : conditions) {
    std::vector<double> levels, n, r;
    for (const DataBlock& b : c.blocks) {
      levels.push_back(b.level);
      n.push_back(b.n_total);
      r.push_back(b.n_correct);
      const double u =
          options.sigmoid == Sigmoid::kWeibull ? std::log(b.level) : b.level;
      low = std::min(low, u);
      high = std::max(high, u);
    }
    problem.levels.push_back(std::move(levels));
    problem.n.push_back(std::move(n));
    problem.r.push_back(std::move(r));
  }
  problem.middle = 0.5 * (low + high);
  problem.span = high > low ? high - low : 1.0;
  return problem;
}

ConditionFit MakeConditionFit(const JointProblem& problem,
                              const Optimum& optimum) {
  ConditionFit fit;
  fit.model = problem.model;
  for (std::size_t k = 0; k < problem.conditions; ++k) {
    fit.params.push_back(problem.Params(optimum.v.data(), k));
  }
  fit.log_likelihood = optimum.log_likelihood;
  fit.deviance =
      2.0 * (JointSaturatedLogLikelihood(problem) - fit.log_likelihood);
  fit.free_parameters = FreeParameters(problem);
  fit.converged = optimum.converged;
  return fit;
}

Status CheckConditions(std::span<const ConditionData> conditions,
                       const PsychometricOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s;
  if (conditions.size() < 2) {
    return Error{fmt::format("comparing conditions needs at least 2, got {}",
                             conditions.size())};
  }
  for (const ConditionData& c : conditions) {
    if (Status s = ValidateData(c.blocks, options.sigmoid); !s.ok()) {
      return Error{
          fmt::format("condition '{}': {}", c.name, s.error().message)};
    }
  }
  return {};
}

// Fits `model` from the single-condition fits and any `extra` starts.
Result<ConditionFit> FitJointFrom(
    std::span<const ConditionData> conditions,
    const PsychometricOptions& options, ConditionModel model,
    const std::vector<std::vector<PsychometricParams>>& starts) {
  JointProblem problem = MakeJointProblem(conditions, options, model);
  const Optimum optimum =
      MaximiseJoint(problem, starts, options.lambda_max, options.gamma_max,
                    options.max_evaluations);
  if (optimum.v.empty()) {
    return Error{fmt::format("the {} fit failed from every start",
                             ConditionModelName(model))};
  }
  return MakeConditionFit(problem, optimum);
}

Result<std::vector<PsychometricParams>> SingleFits(
    std::span<const ConditionData> conditions,
    const PsychometricOptions& options) {
  std::vector<PsychometricParams> params;
  for (const ConditionData& c : conditions) {
    Result<PsychometricFit> fit = FitPsychometric(c.blocks, options);
    if (!fit.ok()) {
      return Error{
          fmt::format("condition '{}': {}", c.name, fit.error().message)};
    }
    params.push_back(fit->params);
  }
  return params;
}

// The likelihood-ratio test of `lesser` against `fuller` (fitted to the
// data), with `samples` bootstrap data sets simulated from `lesser`.
LikelihoodRatioTest LikelihoodRatio(std::span<const ConditionData> conditions,
                                    const PsychometricOptions& options,
                                    const ConditionFit& lesser,
                                    const ConditionFit& fuller,
                                    std::string question,
                                    std::uint64_t stream) {
  LikelihoodRatioTest test;
  test.question = std::move(question);
  test.lesser = lesser.model;
  test.fuller = fuller.model;
  test.lr =
      std::max(0.0, 2.0 * (fuller.log_likelihood - lesser.log_likelihood));
  test.df = fuller.free_parameters - lesser.free_parameters;
  const boost::math::chi_squared_distribution<double> chi2(test.df);
  test.p_chi_square = boost::math::cdf(boost::math::complement(chi2, test.lr));
  const int samples = options.bootstrap_samples;
  test.bootstrap_samples = samples;
  test.p_bootstrap = std::numeric_limits<double>::quiet_NaN();
  if (samples == 0) return test;
  std::vector<ConditionData> simulated(conditions.begin(), conditions.end());
  int at_least = 0, done = 0;
  for (int b = 0; b < samples; ++b) {
    // Data set b of test `stream` draws from its own seed sequence.
    std::seed_seq seeds{static_cast<std::uint32_t>(options.seed),
                        static_cast<std::uint32_t>(options.seed >> 32),
                        static_cast<std::uint32_t>(stream),
                        static_cast<std::uint32_t>(b)};
    boost::random::mt19937_64 rng(seeds);
    for (std::size_t k = 0; k < simulated.size(); ++k) {
      for (DataBlock& block : simulated[k].blocks) {
        const double psi = std::clamp(
            Psi(options.sigmoid, lesser.params[k], block.level), 0.0, 1.0);
        boost::random::binomial_distribution<int, double> draw(block.n_total,
                                                               psi);
        block.n_correct = draw(rng);
      }
    }
    Result<ConditionFit> l =
        FitJointFrom(simulated, options, lesser.model, {lesser.params});
    Result<ConditionFit> f =
        l.ok() ? FitJointFrom(simulated, options, fuller.model,
                              {l->params, fuller.params})
               : l;
    if (!f.ok()) {
      ++test.bootstrap_failures;
      if (options.progress) options.progress(b + 1, samples);
      continue;
    }
    const double lr = 2.0 * (f->log_likelihood - l->log_likelihood);
    if (lr >= test.lr) ++at_least;
    ++done;
    if (options.progress) options.progress(b + 1, samples);
  }
  test.p_bootstrap = (1.0 + at_least) / (1.0 + done);
  return test;
}

}  // namespace

std::string ConditionModelName(ConditionModel model) {
  switch (model) {
    case ConditionModel::kSeparate:
      return "separate";
    case ConditionModel::kSharedSlope:
      return "shared slope";
    case ConditionModel::kShared:
      return "shared";
  }
  return "?";
}

Result<ConditionFit> FitConditions(std::span<const ConditionData> conditions,
                                   const PsychometricOptions& options,
                                   ConditionModel model) {
  if (Status s = CheckConditions(conditions, options); !s.ok()) {
    return s.error();
  }
  Result<std::vector<PsychometricParams>> single =
      SingleFits(conditions, options);
  if (!single.ok()) return single.error();
  return FitJointFrom(conditions, options, model, {*single});
}

Result<ConditionComparison> CompareConditions(
    std::span<const ConditionData> conditions,
    const PsychometricOptions& options) {
  if (Status s = CheckConditions(conditions, options); !s.ok()) {
    return s.error();
  }
  Result<std::vector<PsychometricParams>> single =
      SingleFits(conditions, options);
  if (!single.ok()) return single.error();
  // Nested fits: each fuller model also starts from the lesser one's
  // optimum, so its likelihood is never below it.
  Result<ConditionFit> shared =
      FitJointFrom(conditions, options, ConditionModel::kShared, {*single});
  if (!shared.ok()) return shared.error();
  Result<ConditionFit> shared_slope =
      FitJointFrom(conditions, options, ConditionModel::kSharedSlope,
                   {*single, shared->params});
  if (!shared_slope.ok()) return shared_slope.error();
  Result<ConditionFit> separate =
      FitJointFrom(conditions, options, ConditionModel::kSeparate,
                   {*single, shared_slope->params});
  if (!separate.ok()) return separate.error();

  ConditionComparison out;
  for (const ConditionData& c : conditions) out.names.push_back(c.name);
  out.fits = {*separate, *shared_slope, *shared};
  out.tests.push_back(LikelihoodRatio(conditions, options, *shared,
                                      *shared_slope, "thresholds differ", 1));
  out.tests.push_back(LikelihoodRatio(conditions, options, *shared_slope,
                                      *separate, "slopes differ", 2));
  for (const PsychometricParams& p : separate->params) {
    std::vector<double> at_cuts;
    for (double cut : options.cuts) {
      at_cuts.push_back(SigmoidInverse(options.sigmoid, cut, p.alpha, p.beta));
    }
    out.thresholds.push_back(std::move(at_cuts));
  }
  for (const ConditionFit& fit : out.fits) {
    if (!fit.converged) {
      out.warnings.push_back(fmt::format(
          "the {} fit did not converge within {} likelihood evaluations per "
          "parameter",
          ConditionModelName(fit.model), options.max_evaluations));
    }
  }
  for (const LikelihoodRatioTest& t : out.tests) {
    if (t.bootstrap_failures > 0) {
      out.warnings.push_back(fmt::format(
          "{}: {} of {} simulated data sets could not be refitted and were "
          "left out of the bootstrap p-value",
          t.question, t.bootstrap_failures, t.bootstrap_samples));
    }
  }
  return out;
}

}  // namespace burrlab::analysis
