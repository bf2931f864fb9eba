// Maximum-likelihood fits of psi = gamma + (1 - gamma - lambda) F and the
// parametric bootstrap of Wichmann & Hill (2001b) as psignifit 2.5.6 runs it:
// simulate binomial counts from the fit, refit each simulated data set, and
// read percentile and BCa limits off the refitted thresholds and slopes.
//
// The optimiser is NLopt's SLSQP on (m, ln s, gamma, lambda) of the
// location-scale form in sigmoids.h, with levels normalised to the tested
// range; gamma and lambda are box-constrained, m and s are kept in a wide box
// (kLocationLimit, kScaleMin, kScaleMax) so degenerate data end at a reported
// bound instead of running off to infinity. The bootstrap's refits start at
// the fit and take Newton steps instead (Fitter::RefitByScoring), each one
// pass over the levels, with SLSQP as their fallback; the refits run in
// threads, each simulated data set drawn from a generator of its own.
#include "burrlab/analysis/psychometric.h"

#include <fmt/format.h>
#include <nlopt.h>

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <boost/random/binomial_distribution.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <random>
#include <set>
#include <span>
#include <system_error>
#include <thread>
#include <utility>

#include "burrlab/analysis/bootstrap.h"
#include "nlopt_ptr.h"
#include "non_finite.h"
#include "sigmoids.h"

namespace burrlab::analysis {
namespace {

using detail::LocationScale;
using detail::Standard;
using detail::StandardPoint;

using detail::kNaN;
// Search box in normalised levels (u - middle) / span: the location within 5
// spans of the middle of the tested range, the scale from 1e-4 to 100 spans.
constexpr double kLocationLimit = 5.0;
constexpr double kScaleMin = 1e-4;
constexpr double kScaleMax = 1e2;
// psignifit 2.5.6's default initial guesses (#EST_GAMMA, #EST_LAMBDA).
constexpr double kStartGamma = 0.01;
constexpr double kStartLambda = 0.01;
// Probabilities are kept at least this far from 0 and 1 inside log().
constexpr double kTinyProbability = 1e-300;
// SLSQP stops when a step changes every parameter by less than this
// fraction, or log L per trial by less than the next constant.
constexpr double kParameterTolerance = 1e-8;
constexpr double kLogLikelihoodTolerance = 1e-12;  // per trial
constexpr int kMaxBootstrapSamples = 1000000;
// A bootstrap refit by Fisher scoring takes at most this many steps, and
// halves a step at most this many times, before it hands over to SLSQP.
constexpr int kMaxScoringSteps = 50;
constexpr int kMaxStepHalvings = 30;
// A bootstrap refit of data with kFinalStepTrials trials or more (where a
// pass over the levels costs milliseconds) ends with a Newton step it does
// not evaluate when that step is predicted to raise log L by at most
// kFinalStepGain, a step of at most sqrt(2 * 0.01) = 0.14 standard errors,
// and the step before it rose log L by its predicted amount within
// kFinalStepAgreement: there log L is quadratic to third-order terms, which
// shrink as 1 / sqrt(trials). Smaller data sets, and likelihoods far from
// quadratic (a flat ridge towards a step function), converge step by step.
constexpr double kFinalStepTrials = 1e4;
constexpr double kFinalStepGain = 0.01;
constexpr double kFinalStepAgreement = 0.25;
// Step starts go into at most this many gaps between neighbouring levels:
// every gap of a design of up to 33 levels.
constexpr std::size_t kMaxStepGaps = 32;
// A likelihood evaluation shares its levels between threads, each taking
// at least this many (starting a thread costs about as much as 500 levels),
// so from twice as many levels on.
constexpr std::size_t kLevelsPerThread = 4096;
// The likelihood goes through the levels in chunks of this many (its sums
// over a chunk, then over the chunks in order, whatever the threads).
constexpr std::size_t kBlock = 256;

const char* const kParamNames[4] = {"alpha", "beta", "gamma", "lambda"};

// What the objective needs: normalised levels, trials, counts, and which of
// gamma and lambda are free.
struct Problem {
  Sigmoid sigmoid = Sigmoid::kLogistic;
  bool gamma_free = false;
  bool lambda_free = false;
  double gamma_fixed = 0.5;
  std::vector<double> u;  // (level or ln level - middle) / span
  std::vector<double> n;  // trials
  std::vector<double> r;  // correct responses of the data set being fitted
  double scale = 1.0;     // 1 / total trials: the objective is per trial
  int threads = 1;        // threads an evaluation of many levels may use
  // Scratch, one per chunk of kBlock levels: the chunk's log L, then its
  // d log L / d(m, ln s, gamma, lambda), each summed in the order of the
  // levels.
  std::vector<std::array<double, 5>> terms;
  int evaluations = 0;
};

// The internal parameter vector: m, ln s, then gamma and lambda when free.
using Internal = std::array<double, 4>;

struct Psi4 {
  double m, s, gamma, lambda;
};

Psi4 Unpack(const Problem& problem, const double* v) {
  std::size_t k = 2;
  Psi4 p{v[0], std::exp(v[1]), problem.gamma_fixed, 0.0};
  if (problem.gamma_free) p.gamma = v[k++];
  if (problem.lambda_free) p.lambda = v[k++];
  return p;
}

// A level's term of log L(saturated), r ln(r / n) + (n - r) ln((n - r) / n):
// 0 when r is 0 or n.
double SaturatedTerm(double r, double n) {
  if (r == 0.0 || r == n) return 0.0;
  return r * std::log(r / n) + (n - r) * std::log((n - r) / n);
}

// sum_j r_j ln yes_j + (n_j - r_j) ln no_j over a chunk, each term as
// Objective has always computed it (a term with r_j or n_j - r_j = 0 has no
// logarithm). A chunk of single trials (every n_j 0 or 1: each term is the
// logarithm of yes_j or no_j) takes one logarithm of their product, kept
// from underflow by moving its exponent aside (std::frexp) below 2^-20: a
// factor is at least kTinyProbability (2^-997), so the product stays a
// normal number (above 2^-1022). The logarithms are most of a pass over the
// levels.
double ChunkLogLikelihood(const double* r, const double* n, const double* yes,
                          const double* no, std::size_t count) {
  bool single_trials = true;
  for (std::size_t j = 0; j < count; ++j) {
    single_trials = single_trials && (n[j] == 0.0 || n[j] == 1.0);
  }
  if (!single_trials) {
    double log_l = 0.0;
    for (std::size_t j = 0; j < count; ++j) {
      const double wrong = n[j] - r[j];
      log_l += (r[j] > 0.0 ? r[j] * std::log(yes[j]) : 0.0) +
               (wrong > 0.0 ? wrong * std::log(no[j]) : 0.0);
    }
    return log_l;
  }
  static_assert(0x1p-20 * kTinyProbability >=
                std::numeric_limits<double>::min());
  double product = 1.0;
  int exponent = 0;
  for (std::size_t j = 0; j < count; ++j) {
    // yes_j, no_j or 1, without a branch on r_j (a coin toss).
    product *= r[j] * yes[j] + (n[j] - r[j]) * no[j] + (1.0 - n[j]);
    if (product < 0x1p-20) {
      int e = 0;
      product = std::frexp(product, &e);
      exponent += e;
    }
  }
  return std::log(product) + exponent * std::numbers::ln2;
}

// The log-likelihood of each chunk of kBlock levels and, with `gradient`,
// its d log L / d(m, ln s, gamma, lambda), for the chunks [first_chunk,
// end_chunk), into problem.terms.
void LevelTerms(Problem& problem, const Psi4& p, bool gradient,
                std::size_t first_chunk, std::size_t end_chunk) {
  const double w = 1.0 - p.gamma - p.lambda;
  const std::size_t levels = problem.u.size();
  // Each chunk through the sigmoid, then the logarithms, then the gradient,
  // so the exp() and log() calls run in tight loops.
  std::array<StandardPoint, kBlock> f;
  std::array<double, kBlock> z, yes, no;
  for (std::size_t chunk = first_chunk; chunk < end_chunk; ++chunk) {
    const std::size_t first = chunk * kBlock;
    const std::size_t count = std::min(kBlock, levels - first);
    for (std::size_t j = 0; j < count; ++j) {
      z[j] = (problem.u[first + j] - p.m) / p.s;
    }
    detail::StandardBlock(problem.sigmoid, z.data(), count, f.data());
    for (std::size_t j = 0; j < count; ++j) {
      yes[j] = std::max(p.gamma + w * f[j].f, kTinyProbability);
      no[j] = std::max(p.lambda + w * f[j].fc, kTinyProbability);
    }
    std::array<double, 5>& t = problem.terms[chunk];
    t = {};
    t[0] =
        ChunkLogLikelihood(problem.r.data() + first, problem.n.data() + first,
                           yes.data(), no.data(), count);
    if (!gradient) continue;
    for (std::size_t j = 0; j < count; ++j) {
      const double r = problem.r[first + j];
      const double wrong = problem.n[first + j] - r;
      const double e = r / yes[j] - wrong / no[j];  // d log L / d psi
      t[1] += e * (-w * f[j].density / p.s);
      t[2] += e * (-w * f[j].density * z[j]);
      t[3] += e * f[j].fc;
      t[4] += e * (-f[j].f);
    }
  }
}

// Negative log-likelihood per trial and its gradient (NLopt minimises; per
// trial keeps the objective's size and tolerances independent of the number
// of trials). The chunks' terms are computed in up to problem.threads
// threads of at least kLevelsPerThread levels each, then summed in one
// thread in the order of the chunks, so the result does not depend on the
// threads.
double Objective(unsigned /*dim*/, const double* v, double* gradient,
                 void* data) {
  Problem& problem = *static_cast<Problem*>(data);
  ++problem.evaluations;
  const Psi4 p = Unpack(problem, v);
  const bool with_gradient = gradient != nullptr;
  const std::size_t levels = problem.u.size();
  const std::size_t chunks = problem.terms.size();
  const std::size_t parts = std::clamp<std::size_t>(
      levels / kLevelsPerThread, 1, static_cast<std::size_t>(problem.threads));
  std::vector<std::thread> helpers;
  for (std::size_t k = 1; k < parts; ++k) {
    const std::size_t begin = chunks * k / parts;
    const std::size_t end = chunks * (k + 1) / parts;
    try {
      helpers.emplace_back(LevelTerms, std::ref(problem), std::cref(p),
                           with_gradient, begin, end);
    } catch (const std::system_error&) {  // no thread to be had: do it here
      LevelTerms(problem, p, with_gradient, begin, end);
    }
  }
  LevelTerms(problem, p, with_gradient, 0, chunks / parts);
  for (std::thread& helper : helpers) helper.join();
  double log_l = 0.0, d_m = 0.0, d_log_s = 0.0, d_gamma = 0.0, d_lambda = 0.0;
  for (const std::array<double, 5>& t : problem.terms) {
    log_l += t[0];
    if (with_gradient) {
      d_m += t[1];
      d_log_s += t[2];
      d_gamma += t[3];
      d_lambda += t[4];
    }
  }
  if (with_gradient) {
    std::size_t k = 0;
    gradient[k++] = -d_m * problem.scale;
    gradient[k++] = -d_log_s * problem.scale;
    if (problem.gamma_free) gradient[k++] = -d_gamma * problem.scale;
    if (problem.lambda_free) gradient[k++] = -d_lambda * problem.scale;
  }
  return -log_l * problem.scale;
}

struct Outcome {
  Internal v{};
  double log_likelihood = 0.0;
  bool converged = false;
  int evaluations = 0;
};

// log L of one data set at a point, its gradient and the expected (Fisher)
// information there, in the internal parameters (m, ln s, gamma, lambda),
// all four whether free or not.
struct LocalModel {
  double log_likelihood = 0.0;
  Eigen::Vector4d gradient = Eigen::Vector4d::Zero();
  // The observed Hessian (ModelAt) or the expected information
  // (ModelInCounts).
  Eigen::Matrix4d hessian = Eigen::Matrix4d::Zero();
  Eigen::Matrix4d information = Eigen::Matrix4d::Zero();
  bool has_hessian = false;
  bool has_information = false;
};

// The local model at a point of every data set with the same levels and
// trials, as linear functions of the counts (Fitter::ModelInCounts).
struct CountModel {
  LocalModel base;  // at r = 0
  // Per level: d log L / d r_i, then d gradient / d r_i.
  std::vector<std::array<double, 5>> per_correct;
};

// The model and one NLopt optimiser, reused for every refit of a bootstrap.
class Fitter {
 public:
  Fitter(std::span<const DataBlock> data, const PsychometricOptions& options)
      : options_(options) {
    problem_.sigmoid = options.sigmoid;
    problem_.gamma_free = options.n_intervals == 1 && options.gamma_max > 0.0;
    problem_.gamma_fixed =
        options.n_intervals == 1 ? 0.0 : 1.0 / options.n_intervals;
    problem_.lambda_free = options.lambda_max > 0.0;
    double low = std::numeric_limits<double>::infinity(), high = -low;
    double trials = 0.0;
    std::vector<double> u;
    for (const DataBlock& block : data) {
      u.push_back(detail::UsesLogLevels(options.sigmoid) ? std::log(block.level)
                                                         : block.level);
      low = std::min(low, u.back());
      high = std::max(high, u.back());
      problem_.n.push_back(block.n_total);
      problem_.r.push_back(block.n_correct);
      trials += block.n_total;
    }
    problem_.scale = 1.0 / trials;
    problem_.threads = options.threads > 0
                           ? options.threads
                           : static_cast<int>(std::clamp(
                                 std::thread::hardware_concurrency(), 1u, 64u));
    problem_.terms.resize((data.size() + kBlock - 1) / kBlock);
    middle_ = 0.5 * (low + high);
    span_ = high - low;
    for (double x : u) problem_.u.push_back((x - middle_) / span_);
    dimension_ =
        2 + (problem_.gamma_free ? 1 : 0) + (problem_.lambda_free ? 1 : 0);
    lower_ = {-kLocationLimit, std::log(kScaleMin), 0.0, 0.0};
    upper_ = {kLocationLimit, std::log(kScaleMax), 0.0, 0.0};
    std::size_t k = 2;
    if (problem_.gamma_free) upper_[k++] = options.gamma_max;
    if (problem_.lambda_free) upper_[k++] = options.lambda_max;
    opt_.reset(nlopt_create(NLOPT_LD_SLSQP, dimension_));
    nlopt_set_lower_bounds(opt_.get(), lower_.data());
    nlopt_set_upper_bounds(opt_.get(), upper_.data());
    nlopt_set_min_objective(opt_.get(), Objective, &problem_);
    nlopt_set_xtol_rel(opt_.get(), kParameterTolerance);
    nlopt_set_ftol_abs(opt_.get(), kLogLikelihoodTolerance);
    nlopt_set_maxeval(opt_.get(), options.max_evaluations);
  }

  // Starting points for the optimiser, with gamma and lambda at psignifit's
  // initial guesses: for each of 10 scales, the best of 21 locations (a
  // likelihood can have one maximum at a moderate slope and another at a
  // steep one, so every scale gets its own start), and the best 2 of the
  // steps placed between neighbouring levels (Steps()).
  std::vector<Internal> Starts() {
    std::vector<std::pair<double, Internal>> profile, steps;
    const double log_low = std::log(SteepestStart());
    for (int j = 0; j <= 9; ++j) {
      const double log_s = log_low + j * (std::log(2.0) - log_low) / 9.0;
      std::pair<double, Internal> best{std::numeric_limits<double>::infinity(),
                                       {}};
      for (int i = 0; i <= 20; ++i) {
        const Internal v =
            Pack({-1.0 + 0.1 * i, log_s, StartGamma(), StartLambda()});
        const double value = Evaluate(v);
        if (value < best.first) best = {value, v};
      }
      profile.push_back(best);
    }
    for (const auto& [m, log_s] : Steps()) {
      const Internal v = Pack({m, log_s, StartGamma(), StartLambda()});
      steps.emplace_back(Evaluate(v), v);
    }
    std::vector<Internal> starts;
    for (auto* list : {&profile, &steps}) {
      const std::size_t keep =
          std::min<std::size_t>(list == &profile ? 10 : 2, list->size());
      std::partial_sort(
          list->begin(), list->begin() + static_cast<std::ptrdiff_t>(keep),
          list->end(),
          [](const auto& a, const auto& b) { return a.first < b.first; });
      for (std::size_t k = 0; k < keep; ++k) {
        starts.push_back((*list)[k].second);
      }
    }
    return starts;
  }

  // A local fit (SLSQP) from `start`.
  Outcome Fit(const Internal& start) {
    Outcome out;
    out.v = ClampToBox(start);
    problem_.evaluations = 0;
    double value = 0.0;
    const nlopt_result rc = nlopt_optimize(opt_.get(), out.v.data(), &value);
    // gamma and lambda within round-off of a limit are put on it (SLSQP
    // leaves values like 1e-17).
    for (std::size_t k = 2; k < dimension_; ++k) {
      const double tolerance = 1e-9 * (upper_[k] - lower_[k]);
      if (std::abs(out.v[k] - lower_[k]) < tolerance) out.v[k] = lower_[k];
      if (std::abs(out.v[k] - upper_[k]) < tolerance) out.v[k] = upper_[k];
    }
    out.evaluations = problem_.evaluations;
    out.log_likelihood = -Evaluate(out.v) / problem_.scale;
    out.converged =
        std::isfinite(out.log_likelihood) &&
        (rc == NLOPT_SUCCESS || rc == NLOPT_FTOL_REACHED ||
         rc == NLOPT_XTOL_REACHED ||
         (rc == NLOPT_ROUNDOFF_LIMITED && ProjectedGradientIsSmall(out.v)));
    return out;
  }

  // The fit to the data: local fits from each of Starts(), then from the
  // best of them with gamma and lambda moved to each end of their ranges
  // (the likelihood can have a local maximum at either end); the best
  // converged result.
  Outcome FitFromScratch() {
    Outcome best;
    int evaluations = 0;
    bool have = false;
    const auto consider = [&](const Outcome& outcome) {
      evaluations += outcome.evaluations;
      if (!have || (outcome.converged && !best.converged) ||
          (outcome.converged == best.converged &&
           outcome.log_likelihood > best.log_likelihood)) {
        best = outcome;
        have = true;
      }
    };
    for (const Internal& start : Starts()) consider(Fit(start));
    std::vector<double> gammas = {0.0}, lambdas = {0.0};
    if (problem_.gamma_free) gammas = {0.0, options_.gamma_max};
    if (problem_.lambda_free) lambdas = {0.0, options_.lambda_max};
    const Internal from = best.v;
    for (double gamma : gammas) {
      for (double lambda : lambdas) {
        Internal start = from;
        std::size_t k = 2;
        if (problem_.gamma_free) start[k++] = gamma;
        if (problem_.lambda_free) start[k++] = lambda;
        if (k > 2) consider(Fit(start));
      }
    }
    best.evaluations = evaluations;
    return best;
  }

  // The smallest scale the starts use: a quarter of the smallest gap
  // between levels. Steeper starts sit on a plateau (no level on the rising
  // part) where the gradient vanishes and the optimiser cannot move.
  double SteepestStart() {
    if (steepest_ == 0.0) {
      std::vector<double> u = problem_.u;
      std::sort(u.begin(), u.end());
      u.erase(std::unique(u.begin(), u.end()), u.end());
      double gap = 1.0;
      for (std::size_t i = 0; i + 1 < u.size(); ++i) {
        gap = std::min(gap, u[i + 1] - u[i]);
      }
      steepest_ = std::max(kScaleMin, 0.25 * gap);
    }
    return steepest_;
  }

  // A refit of a bootstrap data set: a local fit from `warm` (the fit to the
  // data, as psignifit 2.5.6 starts its refits), made no steeper than
  // SteepestStart so the optimiser does not start on a plateau.
  Outcome Refit(Internal warm) {
    warm[1] = std::max(warm[1], std::log(SteepestStart()));
    return Fit(warm);
  }

  // The counts of the data set to fit next, written in place (one per
  // level, as doubles).
  std::span<double> Counts() { return problem_.r; }

  // log L of the current counts, its gradient and Hessian at v: one pass
  // over the levels in chunks of kBlock (AddChunk): the exp() and log()
  // calls in loops of their own (ChunkLogLikelihood), the rest as Eigen
  // array expressions (vector instructions), each sum over a chunk in
  // Eigen's fixed order.
  LocalModel ModelAt(const Internal& v) const {
    const Psi4 p = Unpack(problem_, v.data());
    ModelSums sums;
    const std::size_t levels = problem_.u.size();
    for (std::size_t begin = 0; begin < levels; begin += kBlock) {
      const std::size_t count = std::min(kBlock, levels - begin);
      // Full chunks in arrays of a size fixed at compile time (unrolled,
      // inlined); the last, shorter one in arrays of its own length.
      if (count == kBlock) {
        AddChunk<Eigen::Array<double, kBlock, 1>>(p, begin, count, sums);
      } else {
        AddChunk<Eigen::Array<double, Eigen::Dynamic, 1, 0, kBlock, 1>>(
            p, begin, count, sums);
      }
    }
    const double w = 1.0 - p.gamma - p.lambda;
    const double to_s = 1.0 / p.s;
    sums.e_mm *= w * to_s * to_s;
    sums.e_ms *= w * to_s;
    sums.e_ss *= w;
    sums.e_m *= to_s;
    LocalModel model;
    model.log_likelihood = sums.log_l;
    model.gradient = sums.g;
    model.has_hessian = true;
    model.hessian = sums.outer.selfadjointView<Eigen::Upper>();
    model.hessian = -model.hessian;
    const double second[4][4] = {{sums.e_mm, sums.e_ms, sums.e_m, sums.e_m},
                                 {sums.e_ms, sums.e_ss, sums.e_s, sums.e_s},
                                 {sums.e_m, sums.e_s, 0.0, 0.0},
                                 {sums.e_m, sums.e_s, 0.0, 0.0}};
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) model.hessian(a, b) += second[a][b];
    }
    return model;
  }

  // ModelAt's sums: log L, its gradient, sum q d d^T (q = r / psi^2 +
  // (n - r) / (1 - psi)^2, upper triangle), and the non-zero entries of
  // sum e d2psi (e = d log L / d psi): the Hessian is sum e d2psi - q d d^T.
  struct ModelSums {
    double log_l = 0.0;
    Eigen::Vector4d g = Eigen::Vector4d::Zero();
    Eigen::Matrix4d outer = Eigen::Matrix4d::Zero();
    double e_mm = 0.0, e_ms = 0.0, e_ss = 0.0, e_m = 0.0, e_s = 0.0;
  };

  // Adds the `count` levels from `begin` to `sums`, in arrays of type Block
  // (at most kBlock long, never on the heap).
  template <typename Block>
  void AddChunk(const Psi4& p, std::size_t begin, std::size_t count,
                ModelSums& sums) const {
    const double w = 1.0 - p.gamma - p.lambda;
    const double to_s = 1.0 / p.s;
    Block z, f, fc, density, slope, yes, no, r, n, e, q, d0, d1;
    Block large, small;  // scratch
    if constexpr (Block::SizeAtCompileTime == Eigen::Dynamic) {
      for (Block* b : {&z, &f, &fc, &density, &slope, &yes, &no, &r, &n, &e, &q,
                       &d0, &d1, &large, &small}) {
        b->resize(static_cast<Eigen::Index>(count));
      }
    }
    for (std::size_t j = 0; j < count; ++j) {
      const auto at = static_cast<Eigen::Index>(j);
      z[at] = (problem_.u[begin + j] - p.m) * to_s;
      r[at] = problem_.r[begin + j];
      n[at] = problem_.n[begin + j];
    }
    if (problem_.sigmoid == Sigmoid::kLogistic) {
      // Standard()'s logistic, the exponentials first.
      for (Eigen::Index j = 0; j < z.size(); ++j) {
        density[j] = std::exp(-std::abs(z[j]));  // t, for now
      }
      large = 1.0 / (1.0 + density);
      small = density * large;
      f = (z >= 0.0).select(large, small);
      fc = (z >= 0.0).select(small, large);
      density = large * small;
      slope = density * (fc - f);
    } else {
      for (Eigen::Index j = 0; j < z.size(); ++j) {
        const StandardPoint point = Standard(problem_.sigmoid, z[j]);
        f[j] = point.f;
        fc[j] = point.fc;
        density[j] = point.density;
        slope[j] = point.density_slope;
      }
    }
    yes = (p.gamma + w * f).max(kTinyProbability);
    no = (p.lambda + w * fc).max(kTinyProbability);
    sums.log_l +=
        ChunkLogLikelihood(r.data(), n.data(), yes.data(), no.data(), count);
    large = 1.0 / (yes * no);  // 1 / (psi (1 - psi))
    e = r * no * large - (n - r) * yes * large;
    q = r * (no * large).square() + (n - r) * (yes * large).square();
    d0 = -w * to_s * density;
    d1 = -w * density * z;
    // d = (d0, d1, fc, -f).
    sums.g[0] += (e * d0).sum();
    sums.g[1] += (e * d1).sum();
    sums.g[2] += (e * fc).sum();
    sums.g[3] -= (e * f).sum();
    large = q * d0;
    small = q * d1;
    sums.outer(0, 0) += (large * d0).sum();
    sums.outer(0, 1) += (large * d1).sum();
    sums.outer(0, 2) += (large * fc).sum();
    sums.outer(0, 3) -= (large * f).sum();
    sums.outer(1, 1) += (small * d1).sum();
    sums.outer(1, 2) += (small * fc).sum();
    sums.outer(1, 3) -= (small * f).sum();
    sums.outer(2, 2) += (q * fc * fc).sum();
    sums.outer(2, 3) -= (q * fc * f).sum();
    sums.outer(3, 3) += (q * f * f).sum();
    // d2psi: (m, m) w g' / s^2, (m, ln s) w (g' z + g) / s,
    // (ln s, ln s) w z (g' z + g), (m, gamma or lambda) g / s,
    // (ln s, gamma or lambda) g z; the rest 0.
    large = slope * z + density;  // g' z + g
    sums.e_mm += (e * slope).sum();
    sums.e_ms += (e * large).sum();
    sums.e_ss += (e * z * large).sum();
    sums.e_m += (e * density).sum();
    sums.e_s += (e * density * z).sum();
  }

  // The local model at v of any counts r: log L and its gradient are
  // base + sum_i r_i per_correct[i] (the same formulas as ModelAt, r_i
  // taken out), and the information does not depend on the counts.
  CountModel ModelInCounts(const Internal& v) const {
    const Psi4 p = Unpack(problem_, v.data());
    const double w = 1.0 - p.gamma - p.lambda;
    CountModel out;
    out.base.has_information = true;
    out.per_correct.resize(problem_.u.size());
    for (std::size_t i = 0; i < problem_.u.size(); ++i) {
      const double z = (problem_.u[i] - p.m) / p.s;
      const StandardPoint f = Standard(problem_.sigmoid, z);
      const double yes = std::max(p.gamma + w * f.f, kTinyProbability);
      const double no = std::max(p.lambda + w * f.fc, kTinyProbability);
      const double n = problem_.n[i];
      const Eigen::Vector4d d(-w * f.density / p.s, -w * f.density * z, f.fc,
                              -f.f);
      out.base.log_likelihood += n * std::log(no);
      out.base.gradient -= (n / no) * d;
      out.base.information += (n / (yes * no)) * d * d.transpose();
      std::array<double, 5>& per = out.per_correct[i];
      per[0] = std::log(yes) - std::log(no);
      for (int j = 0; j < 4; ++j) per[j + 1] = (1.0 / yes + 1.0 / no) * d[j];
    }
    return out;
  }

  // A refit of a bootstrap data set by Newton's method from the fit to the
  // data, given `model`, the current counts' local model at `fit`.
  // - A step solves H d = -gradient over the free parameters with the
  //   observed Hessian H where -H is positive definite, else with the
  //   expected information (Fisher scoring, as the first step from the fit,
  //   whose model has no Hessian); a gamma or lambda on a limit its gradient
  //   pushes against is held there. A step is halved while log L falls.
  // - The refit has converged when the step's predicted rise of log L,
  //   gradient.d / 2, is at most kLogLikelihoodTolerance per trial (where
  //   SLSQP stops): it stays where it is. With kFinalStepTrials trials or
  //   more, a Newton step that stays inside the limits, is predicted to
  //   rise by at most kFinalStepGain, and follows a step that rose as its
  //   quadratic model predicted (within kFinalStepAgreement) ends the refit
  //   too: it is taken unevaluated, and log L there is the model's
  //   L + gradient.d + d.H d / 2.
  // - It hands over to SLSQP (Refit) when the location or scale reaches its
  //   search limit, neither matrix is positive definite, or
  //   kMaxScoringSteps steps do not converge.
  Outcome RefitByScoring(const Internal& fit, LocalModel model) {
    Internal v = fit;
    int passes = 0;
    const double trials = 1.0 / problem_.scale;
    const double gain_tolerance = kLogLikelihoodTolerance * trials;
    // The rise of log L the last step predicted, and what it achieved.
    double predicted_rise = 0.0, actual_rise = 0.0;
    using Small =
        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;
    using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 4, 1>;
    for (int step = 0; step < kMaxScoringSteps; ++step) {
      // Internal index free[a] holds full parameter FullIndex(free[a]) (m,
      // ln s, gamma, lambda); the free ones are those not held on a limit.
      std::array<int, 4> free{};
      int free_count = 0;
      for (std::size_t k = 0; k < dimension_; ++k) {
        const double slope = model.gradient[FullIndex(k)];
        const bool held = (v[k] <= lower_[k] && slope <= 0.0) ||
                          (v[k] >= upper_[k] && slope >= 0.0);
        if (!held) free[free_count++] = static_cast<int>(k);
      }
      if (free_count == 0) return Converged(v, model, passes);
      Small curvature(free_count, free_count),
          information(free_count, free_count);
      SmallVector gradient(free_count);
      for (int a = 0; a < free_count; ++a) {
        const int ja = FullIndex(free[a]);
        gradient[a] = model.gradient[ja];
        for (int b = 0; b < free_count; ++b) {
          const int jb = FullIndex(free[b]);
          curvature(a, b) = -model.hessian(ja, jb);
          information(a, b) = model.information(ja, jb);
        }
      }
      bool newton = false;
      SmallVector direction;
      if (model.has_hessian) {
        const Eigen::LLT<Small> llt(curvature);
        if (llt.info() == Eigen::Success) {
          direction = llt.solve(gradient);
          newton = true;
        }
      }
      if (!newton) {
        if (!model.has_information) {
          // The rare case of a Hessian that is not negative definite: the
          // information does not depend on the counts.
          model.information = ModelInCounts(v).base.information;
          model.has_information = true;
          for (int a = 0; a < free_count; ++a) {
            for (int b = 0; b < free_count; ++b) {
              information(a, b) =
                  model.information(FullIndex(free[a]), FullIndex(free[b]));
            }
          }
        }
        const Eigen::LLT<Small> llt(information);
        if (llt.info() != Eigen::Success) break;
        direction = llt.solve(gradient);
      }
      const double gain = 0.5 * gradient.dot(direction);
      if (!std::isfinite(gain)) break;
      if (gain <= gain_tolerance) return Converged(v, model, passes);
      const bool quadratic =
          step > 0 && std::abs(actual_rise - predicted_rise) <=
                          kFinalStepAgreement * predicted_rise;
      if (newton && quadratic && trials >= kFinalStepTrials &&
          gain <= kFinalStepGain) {
        Internal next = v;
        for (int a = 0; a < free_count; ++a) next[free[a]] += direction[a];
        if (next == ClampToBox(next)) {
          Outcome out = Converged(next, model, passes);
          out.log_likelihood += gradient.dot(direction) -
                                0.5 * direction.dot(curvature * direction);
          return out;
        }
      }
      bool moved = false, at_search_limit = false;
      double length = 1.0;
      for (int halving = 0; halving <= kMaxStepHalvings; ++halving) {
        Internal next = v;
        for (int a = 0; a < free_count; ++a) {
          next[free[a]] += length * direction[a];
        }
        next = ClampToBox(next);
        if (next[0] <= lower_[0] || next[0] >= upper_[0] ||
            next[1] <= lower_[1] || next[1] >= upper_[1]) {
          at_search_limit = true;
          break;
        }
        LocalModel trial = ModelAt(next);
        ++passes;
        // Rounding in a sum over many levels may make log L appear to fall
        // by a hair at the maximum: that much is no fall.
        const double slack = 1e-12 * (1.0 + std::abs(model.log_likelihood));
        if (trial.log_likelihood >= model.log_likelihood - slack) {
          // The quadratic model's rise for this (possibly shortened) step.
          predicted_rise = length * (1.0 - 0.5 * length) * 2.0 * gain;
          actual_rise = trial.log_likelihood - model.log_likelihood;
          v = next;
          model = std::move(trial);
          moved = true;
          break;
        }
        length *= 0.5;
      }
      if (!moved || at_search_limit) break;
    }
    Outcome fallback = Refit(fit);
    fallback.evaluations += passes;
    return fallback;
  }

  PsychometricParams ToParams(const Internal& v) const {
    const Psi4 p = Unpack(problem_, v.data());
    const std::array<double, 2> ab = detail::FromLocationScale(
        options_.sigmoid, {middle_ + span_ * p.m, span_ * p.s});
    return {ab[0], ab[1], p.gamma, p.lambda};
  }

  // The internal parameters of `params`, clamped to the search box.
  Internal FromParams(const PsychometricParams& params) const {
    const LocationScale ls =
        detail::ToLocationScale(options_.sigmoid, params.alpha, params.beta);
    return Pack({(ls.m - middle_) / span_, std::log(ls.s / span_), params.gamma,
                 params.lambda});
  }

  // d(m, ln s, gamma, lambda) / d(alpha, beta, gamma, lambda) at `params`,
  // with the columns of fixed parameters 0 (m = (location - middle) / span,
  // s = scale / span; the Weibull's location is ln alpha and its scale
  // 1 / beta).
  Eigen::Matrix4d InternalJacobian(const PsychometricParams& params) const {
    Eigen::Matrix4d jacobian = Eigen::Matrix4d::Zero();
    const bool log_levels = detail::UsesLogLevels(options_.sigmoid);
    jacobian(0, 0) = 1.0 / (span_ * (log_levels ? params.alpha : 1.0));
    jacobian(1, 1) = (log_levels ? -1.0 : 1.0) / params.beta;
    jacobian(2, 2) = problem_.gamma_free ? 1.0 : 0.0;
    jacobian(3, 3) = problem_.lambda_free ? 1.0 : 0.0;
    return jacobian;
  }

  // The current counts' local model at v from ModelInCounts (log L, its
  // gradient and the expected information): what a refit from v starts
  // with.
  LocalModel FirstModel(const Internal& v) const {
    const CountModel at = ModelInCounts(v);
    LocalModel model = at.base;
    for (std::size_t i = 0; i < problem_.r.size(); ++i) {
      const double r = problem_.r[i];
      model.log_likelihood += r * at.per_correct[i][0];
      for (int j = 0; j < 4; ++j) {
        model.gradient[j] += r * at.per_correct[i][j + 1];
      }
    }
    return model;
  }

  // Which parameters of `v` sit on a limit of the search box.
  std::array<Bound, 4> BoundsOf(const Internal& v) const {
    std::array<Bound, 4> bounds{};
    const auto check = [&](std::size_t k) {
      const double tolerance = 1e-6 * (upper_[k] - lower_[k]);
      if (v[k] <= lower_[k] + tolerance) return Bound::kLower;
      if (v[k] >= upper_[k] - tolerance) return Bound::kUpper;
      return Bound::kNone;
    };
    bounds[0] = check(0);
    // ln s: for the Weibull beta = 1 / s, so the limits swap.
    const Bound scale = check(1);
    bounds[1] = detail::UsesLogLevels(options_.sigmoid) && scale != Bound::kNone
                    ? (scale == Bound::kLower ? Bound::kUpper : Bound::kLower)
                    : scale;
    std::size_t k = 2;
    if (problem_.gamma_free) bounds[2] = check(k++);
    if (problem_.lambda_free) bounds[3] = check(k++);
    return bounds;
  }

  // log L(saturated) of the current counts.
  double SaturatedLogLikelihood() const {
    double log_l = 0.0;
    for (std::size_t i = 0; i < problem_.n.size(); ++i) {
      log_l += SaturatedTerm(problem_.r[i], problem_.n[i]);
    }
    return log_l;
  }

 private:
  // (m, ln s) of steep functions centred between neighbouring levels, at
  // two steepnesses relative to the gap, for every gap when there are at
  // most kMaxStepGaps, else for the kMaxStepGaps gaps where a sharp step
  // fits best, in increasing order of level. The screen scores a step by
  // its log-likelihood with psi = gamma below the gap and 1 - lambda above
  // it (the starting gamma and lambda), one pass over running sums; scoring
  // every gap's start with the full likelihood instead costs a pass over the
  // levels per gap, quadratic in the number of levels.
  // The full parameter (0 m, 1 ln s, 2 gamma, 3 lambda) at internal index
  // k.
  int FullIndex(std::size_t k) const {
    if (k < 2) return static_cast<int>(k);
    return k == 2 && problem_.gamma_free ? 2 : 3;
  }

  Outcome Converged(const Internal& v, const LocalModel& model,
                    int passes) const {
    Outcome out;
    out.v = v;
    out.log_likelihood = model.log_likelihood;
    out.converged = std::isfinite(model.log_likelihood);
    out.evaluations = passes;
    return out;
  }

  std::vector<std::pair<double, double>> Steps() const {
    std::vector<std::size_t> order(problem_.u.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return problem_.u[a] < problem_.u[b];
    });
    // The distinct levels, increasing, with their pooled counts.
    std::vector<double> u, correct, wrong;
    for (std::size_t i : order) {
      if (u.empty() || problem_.u[i] != u.back()) {
        u.push_back(problem_.u[i]);
        correct.push_back(0.0);
        wrong.push_back(0.0);
      }
      correct.back() += problem_.r[i];
      wrong.back() += problem_.n[i] - problem_.r[i];
    }
    const std::size_t gaps = u.empty() ? 0 : u.size() - 1;
    std::vector<std::size_t> chosen(gaps);
    std::iota(chosen.begin(), chosen.end(), std::size_t{0});
    if (gaps > kMaxStepGaps) {
      // log L of the step in gap i (levels 0..i below it): the logs are
      // clamped as Objective clamps them at F = 0 and F = 1.
      const double gamma =
          problem_.gamma_free ? StartGamma() : problem_.gamma_fixed;
      const double lambda = problem_.lambda_free ? StartLambda() : 0.0;
      const double w = 1.0 - gamma - lambda;
      const double below_yes = std::log(std::max(gamma, kTinyProbability));
      const double below_no = std::log(std::max(lambda + w, kTinyProbability));
      const double above_yes = std::log(std::max(gamma + w, kTinyProbability));
      const double above_no = std::log(std::max(lambda, kTinyProbability));
      double correct_above = 0.0, wrong_above = 0.0;
      for (std::size_t i = 0; i < u.size(); ++i) {
        correct_above += correct[i];
        wrong_above += wrong[i];
      }
      double correct_below = 0.0, wrong_below = 0.0;
      std::vector<double> log_l(gaps);
      for (std::size_t i = 0; i < gaps; ++i) {
        correct_below += correct[i];
        wrong_below += wrong[i];
        correct_above -= correct[i];
        wrong_above -= wrong[i];
        log_l[i] = correct_below * below_yes + wrong_below * below_no +
                   correct_above * above_yes + wrong_above * above_no;
      }
      const auto better = [&](std::size_t a, std::size_t b) {
        return log_l[a] > log_l[b] || (log_l[a] == log_l[b] && a < b);
      };
      std::nth_element(chosen.begin(), chosen.begin() + kMaxStepGaps,
                       chosen.end(), better);
      chosen.resize(kMaxStepGaps);
      std::sort(chosen.begin(), chosen.end());
    }
    std::vector<std::pair<double, double>> steps;
    for (std::size_t i : chosen) {
      const double gap = u[i + 1] - u[i];
      for (double fraction : {0.25, 0.5}) {
        steps.emplace_back(0.5 * (u[i] + u[i + 1]),
                           std::log(std::max(kScaleMin, fraction * gap)));
      }
    }
    return steps;
  }

  double StartGamma() const {
    return std::min(kStartGamma, 0.5 * options_.gamma_max);
  }
  double StartLambda() const {
    return std::min(kStartLambda, 0.5 * options_.lambda_max);
  }

  // A full (m, ln s, gamma, lambda) packed into the free parameters and
  // clamped to the box.
  Internal Pack(const Internal& full) const {
    Internal v{full[0], full[1], 0.0, 0.0};
    std::size_t k = 2;
    if (problem_.gamma_free) v[k++] = full[2];
    if (problem_.lambda_free) v[k++] = full[3];
    return ClampToBox(v);
  }

  Internal ClampToBox(Internal v) const {
    for (std::size_t j = 0; j < dimension_; ++j) {
      v[j] = std::clamp(v[j], lower_[j], upper_[j]);
    }
    return v;
  }

  double Evaluate(const Internal& v) {
    return Objective(dimension_, v.data(), nullptr, &problem_);
  }

  // The gradient of -log L per trial, projected on the box, is small (used
  // when NLopt stops on round-off).
  bool ProjectedGradientIsSmall(const Internal& v) {
    Internal gradient{};
    Objective(dimension_, v.data(), gradient.data(), &problem_);
    for (std::size_t k = 0; k < dimension_; ++k) {
      const bool at_lower = v[k] <= lower_[k] && gradient[k] > 0.0;
      const bool at_upper = v[k] >= upper_[k] && gradient[k] < 0.0;
      if (!at_lower && !at_upper && std::abs(gradient[k]) > 1e-5) {
        return false;
      }
    }
    return true;
  }

  PsychometricOptions options_;
  Problem problem_;
  unsigned dimension_ = 2;
  Internal lower_{}, upper_{};
  double middle_ = 0.0, span_ = 1.0;
  double steepest_ = 0.0;
  detail::NloptPtr opt_;
};

// d psi / d(alpha, beta, gamma, lambda) and psi, 1 - psi at each level.
struct LevelDerivatives {
  std::vector<std::array<double, 4>> d_psi;
  std::vector<double> yes;  // psi
  std::vector<double> no;   // 1 - psi
};

LevelDerivatives DerivativesAt(std::span<const DataBlock> data,
                               const PsychometricOptions& options,
                               const PsychometricParams& params) {
  const bool gamma_free = options.n_intervals == 1 && options.gamma_max > 0.0;
  const bool lambda_free = options.lambda_max > 0.0;
  const LocationScale ls =
      detail::ToLocationScale(options.sigmoid, params.alpha, params.beta);
  const double w = 1.0 - params.gamma - params.lambda;
  LevelDerivatives out;
  for (const DataBlock& block : data) {
    const double u = detail::UsesLogLevels(options.sigmoid)
                         ? std::log(block.level)
                         : block.level;
    const double z = (u - ls.m) / ls.s;
    const StandardPoint f = Standard(options.sigmoid, z);
    const std::array<double, 2> ab = detail::PsiGradientAlphaBeta(
        options.sigmoid, params.alpha, params.beta, z, f.density, w);
    out.d_psi.push_back(
        {ab[0], ab[1], gamma_free ? f.fc : 0.0, lambda_free ? -f.f : 0.0});
    out.yes.push_back(std::max(params.gamma + w * f.f, kTinyProbability));
    out.no.push_back(std::max(params.lambda + w * f.fc, kTinyProbability));
  }
  return out;
}

std::string BoundWarning(std::size_t k, Bound bound,
                         const PsychometricOptions& options,
                         const PsychometricParams& params) {
  const char* side = bound == Bound::kLower ? "lower" : "upper";
  switch (k) {
    case 2:
      return fmt::format(
          "gamma = {:.6g} is at the {} limit of its range [0, {}]",
          params.gamma, side, options.gamma_max);
    case 3:
      return fmt::format(
          "lambda = {:.6g} is at the {} limit of its range [0, {}]",
          params.lambda, side, options.lambda_max);
    case 0:
      return fmt::format(
          "alpha = {:.6g} is at the {} limit of the search range: the data do "
          "not locate the psychometric function",
          params.alpha, side);
    default:
      return fmt::format(
          "beta = {:.6g} is at the {} limit of the search range: the data do "
          "not constrain the {}",
          params.beta, side,
          (bound == Bound::kLower) == (options.sigmoid == Sigmoid::kWeibull)
              ? "shallowness"
              : "steepness");
  }
}

// The threshold or slope at `cut` for parameters `p`.
double Threshold(const PsychometricOptions& o, double cut,
                 const PsychometricParams& p) {
  return SigmoidInverse(o.sigmoid, cut, p.alpha, p.beta);
}
double Slope(const PsychometricOptions& o, double cut,
             const PsychometricParams& p) {
  return SigmoidSlope(o.sigmoid, Threshold(o, cut, p), p.alpha, p.beta);
}

PsychometricFit MakeFit(const Fitter& fitter, const Outcome& outcome) {
  PsychometricFit fit;
  fit.params = fitter.ToParams(outcome.v);
  fit.log_likelihood = outcome.log_likelihood;
  fit.deviance = std::max(
      0.0, 2.0 * (fitter.SaturatedLogLikelihood() - outcome.log_likelihood));
  fit.converged = outcome.converged;
  fit.evaluations = outcome.evaluations;
  fit.at_bound = fitter.BoundsOf(outcome.v);
  return fit;
}

std::string FormatLimits(const std::vector<double>& conf,
                         const std::vector<double>& limits,
                         const std::vector<bool>& at_search_limit) {
  std::string text;
  for (std::size_t k = 0; k < conf.size(); ++k) {
    const bool at_limit = k < at_search_limit.size() && at_search_limit[k];
    text += at_limit
                ? fmt::format("{}{}: search limit", k == 0 ? "" : ", ", conf[k])
                : fmt::format("{}{}: {:.6g}", k == 0 ? "" : ", ", conf[k],
                              limits[k]);
  }
  return text;
}

// Whether bound `x` of the replicates comes from one that stopped at the
// search range: one of the order statistics next to x (the one it equals, or
// the two it lies between) is such a replicate.
bool FromSearchLimit(double x,
                     std::span<const std::pair<double, bool>> sorted) {
  if (!std::isfinite(x) || sorted.empty()) return false;
  const auto hi = std::lower_bound(
      sorted.begin(), sorted.end(), x,
      [](const std::pair<double, bool>& r, double v) { return r.first < v; });
  bool limited = false;
  if (hi != sorted.end()) {
    // Every replicate equal to the order statistic at or above x.
    for (auto it = hi; it != sorted.end() && it->first == hi->first; ++it) {
      limited = limited || it->second;
    }
  }
  if (hi != sorted.begin() && (hi == sorted.end() || hi->first > x)) {
    const double below = std::prev(hi)->first;
    for (auto it = std::prev(hi);; --it) {
      if (it->first != below) break;
      limited = limited || it->second;
      if (it == sorted.begin()) break;
    }
  }
  return limited;
}

}  // namespace

bool PsychometricFit::AtAnyBound() const {
  return std::any_of(at_bound.begin(), at_bound.end(),
                     [](Bound b) { return b != Bound::kNone; });
}

Status PsychometricOptions::Validate() const {
  if (n_intervals < 1 || n_intervals > 100) {
    return Error{fmt::format(
        "n_intervals must be 1 (yes/no) or the n of an n-AFC task (2 to 100), "
        "got {}",
        n_intervals)};
  }
  if (!(lambda_max >= 0.0 && lambda_max < 1.0)) {
    return Error{
        fmt::format("lambda_max must be in [0, 1), got {}", lambda_max)};
  }
  if (!(gamma_max >= 0.0 && gamma_max < 1.0)) {
    return Error{fmt::format("gamma_max must be in [0, 1), got {}", gamma_max)};
  }
  const double gamma_top = n_intervals == 1 ? gamma_max : 1.0 / n_intervals;
  if (!(gamma_top + lambda_max < 1.0)) {
    return Error{fmt::format(
        "{} + lambda_max must be below 1 (psi needs room to rise), got {} + {}",
        n_intervals == 1 ? "gamma_max" : "1 / n_intervals", gamma_top,
        lambda_max)};
  }
  if (max_evaluations < 1) {
    return Error{fmt::format("max_evaluations must be at least 1, got {}",
                             max_evaluations)};
  }
  if (threads < 0 || threads > 64) {
    return Error{fmt::format(
        "threads must be 0 (one per core) or 1 to 64, got {}", threads)};
  }
  for (std::size_t k = 0; k < cuts.size(); ++k) {
    if (!(cuts[k] > 0.0 && cuts[k] < 1.0)) {
      return Error{
          fmt::format("cuts[{}] must be in (0, 1), got {}", k, cuts[k])};
    }
  }
  for (std::size_t k = 0; k < conf.size(); ++k) {
    if (!(conf[k] > 0.0 && conf[k] < 1.0)) {
      return Error{
          fmt::format("conf[{}] must be in (0, 1), got {}", k, conf[k])};
    }
  }
  if (bootstrap_samples < 0 || bootstrap_samples > kMaxBootstrapSamples) {
    return Error{fmt::format("bootstrap_samples must be in [0, {}], got {}",
                             kMaxBootstrapSamples, bootstrap_samples)};
  }
  return {};
}

Status ValidateData(std::span<const DataBlock> data, Sigmoid sigmoid,
                    std::size_t* bad_block) {
  std::size_t unused = 0;
  std::size_t& at = bad_block != nullptr ? *bad_block : unused;
  at = data.size();
  if (data.empty()) {
    return Error{"no data: a psychometric fit needs at least 3 levels"};
  }
  std::set<double> levels;
  long long correct = 0, trials = 0;
  for (std::size_t i = 0; i < data.size(); ++i) {
    const DataBlock& b = data[i];
    at = i;
    if (!std::isfinite(b.level)) {
      return Error{fmt::format("block {}: level {} is not a finite number",
                               i + 1, b.level)};
    }
    if (b.n_total < 1) {
      return Error{fmt::format("block {}: n_total = {} must be at least 1",
                               i + 1, b.n_total)};
    }
    if (b.n_correct < 0) {
      return Error{fmt::format("block {}: n_correct = {} must be at least 0",
                               i + 1, b.n_correct)};
    }
    if (b.n_correct > b.n_total) {
      return Error{fmt::format("block {}: n_correct = {} exceeds n_total = {}",
                               i + 1, b.n_correct, b.n_total)};
    }
    if (sigmoid == Sigmoid::kWeibull && !(b.level > 0.0)) {
      return Error{fmt::format(
          "block {}: level {} must be positive for the Weibull, which uses "
          "(x / alpha)^beta",
          i + 1, b.level)};
    }
    levels.insert(b.level);
    correct += b.n_correct;
    trials += b.n_total;
  }
  at = data.size();
  if (levels.size() < 3) {
    return Error{fmt::format(
        "only {} distinct level{}: a psychometric fit needs at least 3",
        levels.size(), levels.size() == 1 ? "" : "s")};
  }
  if (correct == trials) {
    return Error{fmt::format(
        "all {} trials are correct (or 'yes'): the data do not constrain a "
        "psychometric function; test lower levels",
        trials)};
  }
  if (correct == 0) {
    return Error{fmt::format(
        "none of the {} trials is correct (or 'yes'): the data do not "
        "constrain a psychometric function; test higher levels",
        trials)};
  }
  return {};
}

Result<PsychometricFit> FitPsychometric(std::span<const DataBlock> data,
                                        const PsychometricOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  if (Status s = ValidateData(data, options.sigmoid); !s.ok()) return s.error();
  Fitter fitter(data, options);
  return MakeFit(fitter, fitter.FitFromScratch());
}

Result<PsychometricFit> RefitPsychometric(std::span<const DataBlock> data,
                                          const PsychometricOptions& options,
                                          const PsychometricParams& from) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  if (Status s = ValidateData(data, options.sigmoid); !s.ok()) return s.error();
  Fitter fitter(data, options);
  const Internal start = fitter.FromParams(from);
  return MakeFit(fitter,
                 fitter.RefitByScoring(start, fitter.FirstModel(start)));
}

std::array<std::array<double, 4>, 4> FisherInformation(
    std::span<const DataBlock> data, const PsychometricOptions& options,
    const PsychometricParams& params) {
  const LevelDerivatives d = DerivativesAt(data, options, params);
  std::array<std::array<double, 4>, 4> info{};
  for (std::size_t i = 0; i < data.size(); ++i) {
    const double weight = data[i].n_total / (d.yes[i] * d.no[i]);
    for (std::size_t j = 0; j < 4; ++j) {
      for (std::size_t k = 0; k < 4; ++k) {
        info[j][k] += weight * d.d_psi[i][j] * d.d_psi[i][k];
      }
    }
  }
  const bool fixed[4] = {false, false,
                         !(options.n_intervals == 1 && options.gamma_max > 0.0),
                         !(options.lambda_max > 0.0)};
  for (std::size_t j = 0; j < 4; ++j) {
    if (!fixed[j]) continue;
    for (std::size_t k = 0; k < 4; ++k) info[j][k] = info[k][j] = 0.0;
    info[j][j] = 1.0;
  }
  return info;
}

std::optional<std::array<std::array<double, 4>, 4>> ParameterCovariance(
    std::span<const DataBlock> data, const PsychometricOptions& options,
    const PsychometricParams& params) {
  const std::array<std::array<double, 4>, 4> info =
      FisherInformation(data, options, params);
  Eigen::Matrix4d fisher;
  for (int j = 0; j < 4; ++j) {
    for (int k = 0; k < 4; ++k) fisher(j, k) = info[j][k];
  }
  const Eigen::FullPivLU<Eigen::Matrix4d> lu(fisher);
  if (!lu.isInvertible()) return std::nullopt;
  const Eigen::Matrix4d inverse = lu.inverse();
  std::array<std::array<double, 4>, 4> covariance{};
  for (int j = 0; j < 4; ++j) {
    for (int k = 0; k < 4; ++k) covariance[j][k] = inverse(j, k);
  }
  return covariance;
}

std::array<double, 4> Score(std::span<const DataBlock> data,
                            const PsychometricOptions& options,
                            const PsychometricParams& params,
                            std::span<const int> n_correct) {
  const LevelDerivatives d = DerivativesAt(data, options, params);
  std::array<double, 4> score{};
  for (std::size_t i = 0; i < data.size(); ++i) {
    const double residual =
        (n_correct[i] - data[i].n_total * d.yes[i]) / (d.yes[i] * d.no[i]);
    for (std::size_t j = 0; j < 4; ++j) score[j] += residual * d.d_psi[i][j];
  }
  return score;
}

namespace {

// "a", "a and b", "a, b and c".
std::string JoinAnd(const std::vector<std::string>& items) {
  std::string text;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) text += i + 1 == items.size() ? " and " : ", ";
    text += items[i];
  }
  return text;
}

// The warnings about one estimate's bounds, one sentence per kind of
// problem, naming every bound it concerns ("the BCa and percentile bounds at
// 0.025 and 0.975 of the threshold at cut 0.5 are search limits: ...").
std::vector<std::string> BoundWarnings(const BootstrapEstimate& e,
                                       const std::vector<double>& conf,
                                       const char* what, bool bca_possible,
                                       int samples) {
  // Per bound level, which kinds are flagged, as "BCa and percentile".
  const auto phrase = [&](const auto& flagged) {
    std::vector<std::string> levels, kinds_at_level;
    for (std::size_t k = 0; k < conf.size(); ++k) {
      std::vector<std::string> kinds;
      for (const char* kind : {"BCa", "percentile"}) {
        if (flagged(kind, k)) kinds.push_back(kind);
      }
      if (kinds.empty()) continue;
      levels.push_back(fmt::format("{}", conf[k]));
      kinds_at_level.push_back(JoinAnd(kinds));
    }
    struct Phrase {
      std::string text;
      std::size_t bounds = 0;
      std::size_t levels = 0;
    } out;
    if (levels.empty()) return out;
    std::size_t bounds = 0;
    for (const std::string& k : kinds_at_level) {
      bounds += k.find(" and ") == std::string::npos ? 1 : 2;
    }
    out.bounds = bounds;
    out.levels = levels.size();
    const bool same_kinds = std::all_of(
        kinds_at_level.begin(), kinds_at_level.end(),
        [&](const std::string& k) { return k == kinds_at_level[0]; });
    if (same_kinds) {
      out.text = fmt::format("the {} bound{} at {}", kinds_at_level[0],
                             bounds > 1 ? "s" : "", JoinAnd(levels));
    } else {
      std::vector<std::string> parts;
      for (std::size_t i = 0; i < levels.size(); ++i) {
        parts.push_back(fmt::format(
            "{} bound{} at {}", kinds_at_level[i],
            kinds_at_level[i].find(" and ") == std::string::npos ? "" : "s",
            levels[i]));
      }
      out.text = "the " + JoinAnd(parts);
    }
    return out;
  };
  std::vector<std::string> warnings;
  const auto at_limit = phrase([&](const char* kind, std::size_t k) {
    return std::string(kind) == "BCa"
               ? bca_possible && e.bca_at_search_limit[k]
               : static_cast<bool>(e.percentile_at_search_limit[k]);
  });
  if (at_limit.bounds > 0) {
    const bool one = at_limit.bounds == 1;
    warnings.push_back(fmt::format(
        "{} of the {} at cut {} {}: bootstrap refits there stopped at the "
        "edge of the fit's search range, so the data do not bound the {} on "
        "{}",
        at_limit.text, what, e.cut,
        one ? "is a search limit" : "are search limits", what,
        at_limit.levels == 1 ? "that side" : "either side"));
  }
  const auto beyond = phrase([&](const char* kind, std::size_t k) {
    return std::string(kind) == "BCa" ? bca_possible && !std::isfinite(e.bca[k])
                                      : !std::isfinite(e.percentile[k]);
  });
  if (beyond.bounds > 0) {
    warnings.push_back(fmt::format(
        "{} of the {} at cut {} {} beyond the {} bootstrap samples (reported "
        "as null; more samples may help)",
        beyond.text, what, e.cut, beyond.bounds == 1 ? "lies" : "lie",
        samples));
  }
  return warnings;
}

}  // namespace

Result<PsychometricAnalysis> AnalyzePsychometric(
    std::span<const DataBlock> data, const PsychometricOptions& options) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  if (Status s = ValidateData(data, options.sigmoid); !s.ok()) return s.error();
  PsychometricAnalysis out;
  out.options = options;
  out.options.progress = nullptr;  // the caller's, which may not outlive out
  Fitter fitter(data, options);
  const Outcome best = fitter.FitFromScratch();
  out.fit = MakeFit(fitter, best);
  const PsychometricParams& fitted = out.fit.params;
  if (!out.fit.converged) {
    out.warnings.push_back(fmt::format(
        "the fit did not converge after {} likelihood evaluations; the "
        "estimates are unreliable",
        out.fit.evaluations));
  }
  for (std::size_t k = 0; k < 4; ++k) {
    if (out.fit.at_bound[k] != Bound::kNone) {
      out.warnings.push_back(
          BoundWarning(k, out.fit.at_bound[k], options, fitted));
    }
  }

  const std::optional<std::array<std::array<double, 4>, 4>> inverse =
      ParameterCovariance(data, options, fitted);
  const bool bca_possible = inverse.has_value();
  if (!bca_possible) {
    out.warnings.push_back(
        "the data do not determine every parameter (the Fisher information "
        "is singular at the fit, e.g. for a step between two neighbouring "
        "levels); BCa intervals are unavailable");
  }

  const std::size_t cuts = options.cuts.size();
  const std::size_t conf = options.conf.size();
  for (double cut : options.cuts) {
    BootstrapEstimate t, s;
    t.cut = s.cut = cut;
    t.value = Threshold(options, cut, fitted);
    s.value = Slope(options, cut, fitted);
    t.bca = t.percentile = s.bca = s.percentile =
        std::vector<double>(conf, kNaN);
    t.cpe = t.bias_z0 = t.acceleration = kNaN;
    s.cpe = s.bias_z0 = s.acceleration = kNaN;
    out.thresholds.push_back(std::move(t));
    out.slopes.push_back(std::move(s));
  }
  out.deviance_p = kNaN;
  const int samples = options.bootstrap_samples;
  out.bootstrap_samples = samples;
  if (samples == 0) return out;

  // Least-favourable directions cov * d(quantity)/d(theta) (Davison & Hinkley
  // 1997, p. 206-207), one per threshold and slope.
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();
  for (int j = 0; j < 4 && bca_possible; ++j) {
    for (int k = 0; k < 4; ++k) covariance(j, k) = (*inverse)[j][k];
  }
  std::vector<Eigen::Vector4d> directions;  // thresholds, then slopes
  for (std::size_t c = 0; c < cuts; ++c) {
    const std::array<double, 2> g = ThresholdGradient(
        options.sigmoid, options.cuts[c], fitted.alpha, fitted.beta);
    directions.push_back(covariance * Eigen::Vector4d(g[0], g[1], 0.0, 0.0));
  }
  for (std::size_t c = 0; c < cuts; ++c) {
    const std::array<double, 2> g = SlopeGradient(
        options.sigmoid, options.cuts[c], fitted.alpha, fitted.beta);
    directions.push_back(covariance * Eigen::Vector4d(g[0], g[1], 0.0, 0.0));
  }

  // What every simulated data set shares, at the fit: its log L and score
  // in the internal parameters are linear in its counts r_i
  // (Fitter::ModelInCounts), so the first, Fisher-scoring step of each
  // refit costs no exp() or log() over the levels; its BCa score (Davison &
  // Hinkley's ldot) is that score in the user parameters.
  const std::size_t levels = data.size();
  const CountModel at_counts = fitter.ModelInCounts(best.v);
  // The score in (alpha, beta, gamma, lambda) is J^T times the score in the
  // internal parameters, J = d(m, ln s, gamma, lambda) / d(alpha, beta,
  // gamma, lambda) at the fit; fixed parameters score 0.
  const Eigen::Matrix4d to_user = fitter.InternalJacobian(fitted);
  // Each simulated data set draws from a Boost mt19937_64 of its own,
  // seeded with (seed, its index), so the data sets do not depend on the
  // threads that refit them or on their order. A level of one trial is
  // correct when a 53-bit uniform integer is below ceil(psi 2^53) (a uniform
  // in [0, 1) below psi); other levels draw a Boost binomial.
  constexpr std::uint64_t kNotSingle =
      std::numeric_limits<std::uint64_t>::max();
  std::vector<std::uint64_t> below(levels, kNotSingle);
  std::vector<boost::random::binomial_distribution<int, double>> binomial;
  for (std::size_t i = 0; i < levels; ++i) {
    const double psi =
        std::clamp(Psi(options.sigmoid, fitted, data[i].level), 0.0, 1.0);
    binomial.emplace_back(data[i].n_total, psi);
    if (data[i].n_total == 1) {
      below[i] = static_cast<std::uint64_t>(std::ceil(std::ldexp(psi, 53)));
    }
  }
  const std::size_t count = static_cast<std::size_t>(samples);
  std::vector<std::vector<double>> values(2 * cuts, std::vector<double>(count));
  std::vector<std::vector<double>> scores(2 * cuts, std::vector<double>(count));
  std::vector<double> deviances(count);
  std::vector<char> refit_converged(count);
  // The refit's location or scale stopped at the search range.
  std::vector<char> refit_at_search_limit(count);
  std::atomic<std::size_t> next_sample{0};
  std::mutex progress_mutex;
  int done = 0;
  const auto refit_samples = [&](Fitter& worker) {
    for (std::size_t b = next_sample++; b < count; b = next_sample++) {
      std::seed_seq seeds{static_cast<std::uint32_t>(options.seed),
                          static_cast<std::uint32_t>(options.seed >> 32),
                          static_cast<std::uint32_t>(b),
                          static_cast<std::uint32_t>(b >> 32)};
      boost::random::mt19937_64 rng(seeds);
      const std::span<double> r = worker.Counts();
      LocalModel model = at_counts.base;
      // log L(saturated): 0 at a level of one trial.
      double saturated = 0.0;
      for (std::size_t i = 0; i < levels; ++i) {
        double correct;
        if (below[i] != kNotSingle) {
          // Indexed, not branched on: the branch would be a coin toss.
          constexpr double kBit[2] = {0.0, 1.0};
          correct = kBit[(rng() >> 11) < below[i] ? 1 : 0];
        } else {
          correct = binomial[i](rng);
          saturated += SaturatedTerm(correct, data[i].n_total);
        }
        r[i] = correct;
        const std::array<double, 5>& per = at_counts.per_correct[i];
        model.log_likelihood += correct * per[0];
        for (int j = 0; j < 4; ++j) model.gradient[j] += correct * per[j + 1];
      }
      const Eigen::Vector4d ldot = to_user.transpose() * model.gradient;
      const Outcome refit = worker.RefitByScoring(best.v, model);
      refit_converged[b] = refit.converged;
      const std::array<Bound, 4> bounds = worker.BoundsOf(refit.v);
      refit_at_search_limit[b] =
          bounds[0] != Bound::kNone || bounds[1] != Bound::kNone;
      const PsychometricParams p = worker.ToParams(refit.v);
      deviances[b] = 2.0 * (saturated - refit.log_likelihood);
      for (std::size_t c = 0; c < cuts; ++c) {
        values[c][b] = Threshold(options, options.cuts[c], p);
        values[cuts + c][b] = Slope(options, options.cuts[c], p);
      }
      for (std::size_t q = 0; q < 2 * cuts; ++q) {
        scores[q][b] = ldot.dot(directions[q]);
      }
      if (options.progress) {
        const std::lock_guard<std::mutex> lock(progress_mutex);
        options.progress(++done, samples);
      }
    }
  };
  // One refitting thread per core (or options.threads), each with a fitter
  // of its own; the first is this thread with `fitter`.
  const std::size_t threads = std::min<std::size_t>(
      count, options.threads > 0
                 ? static_cast<std::size_t>(options.threads)
                 : std::clamp(std::thread::hardware_concurrency(), 1u, 64u));
  PsychometricOptions single = options;
  single.threads = 1;
  std::vector<std::unique_ptr<Fitter>> fitters;
  std::vector<std::thread> helpers;
  for (std::size_t t = 1; t < threads; ++t) {
    fitters.push_back(std::make_unique<Fitter>(data, single));
    try {
      helpers.emplace_back(refit_samples, std::ref(*fitters.back()));
    } catch (const std::system_error&) {
      break;  // no more threads to be had: the others share the work
    }
  }
  refit_samples(fitter);
  for (std::thread& helper : helpers) helper.join();
  for (char converged : refit_converged) {
    out.bootstrap_not_converged += converged ? 0 : 1;
  }
  if (out.bootstrap_not_converged > 0) {
    out.warnings.push_back(fmt::format(
        "{} of {} bootstrap refits did not converge (kept in the intervals)",
        out.bootstrap_not_converged, samples));
  }
  std::size_t as_large = 0;
  for (double d : deviances) as_large += d >= out.fit.deviance;
  out.deviance_p = static_cast<double>(as_large + 1) / (samples + 1.0);

  for (std::size_t q = 0; q < 2 * cuts; ++q) {
    BootstrapEstimate& e = q < cuts ? out.thresholds[q] : out.slopes[q - cuts];
    const std::span<const double> bca_scores =
        bca_possible ? std::span<const double>(scores[q])
                     : std::span<const double>();
    BootstrapLimits limits =
        ComputeBootstrapLimits(values[q], bca_scores, e.value, options.conf);
    e.cpe = limits.cpe;
    e.bias_z0 = limits.bias_z0;
    e.acceleration = limits.acceleration;
    e.bca = std::move(limits.bca);
    e.percentile = std::move(limits.percentile);
    std::vector<std::pair<double, bool>> sorted(count);
    for (std::size_t b = 0; b < count; ++b) {
      sorted[b] = {values[q][b], refit_at_search_limit[b] != 0};
    }
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < conf; ++k) {
      e.bca_at_search_limit.push_back(FromSearchLimit(e.bca[k], sorted));
      e.percentile_at_search_limit.push_back(
          FromSearchLimit(e.percentile[k], sorted));
    }
    e.replicates = std::move(values[q]);
    if (bca_possible) e.scores = std::move(scores[q]);
    const char* what = q < cuts ? "threshold" : "slope";
    e.warnings = BoundWarnings(e, options.conf, what, bca_possible, samples);
    out.warnings.insert(out.warnings.end(), e.warnings.begin(),
                        e.warnings.end());
  }
  return out;
}

std::string PsychometricAnalysis::BriefReport() const {
  const PsychometricParams& p = fit.params;
  std::string text = fmt::format(
      "{} fit: alpha {:.6g}, beta {:.6g}, gamma {:.6g}, lambda {:.6g}; "
      "deviance {:.4g}",
      SigmoidName(options.sigmoid), p.alpha, p.beta, p.gamma, p.lambda,
      fit.deviance);
  if (bootstrap_samples > 0) {
    text += fmt::format(" (bootstrap p = {:.4g})", deviance_p);
  }
  if (!fit.converged) text += "; NOT CONVERGED";
  if (fit.AtAnyBound()) text += "; at a parameter bound";
  return text;
}

std::string PsychometricAnalysis::FullReport(bool with_warnings) const {
  const PsychometricParams& p = fit.params;
  std::string text = fmt::format(
      "model      psi = gamma + (1 - gamma - lambda) F, F {}, {}\n",
      SigmoidName(options.sigmoid),
      options.n_intervals == 1
          ? fmt::format("yes/no (gamma in [0, {}])", options.gamma_max)
          : fmt::format("{}-AFC (gamma = 1/{})", options.n_intervals,
                        options.n_intervals));
  const double values[4] = {p.alpha, p.beta, p.gamma, p.lambda};
  for (std::size_t k = 0; k < 4; ++k) {
    text += fmt::format(
        "{:<10} {:.6g}{}\n", kParamNames[k], values[k],
        fit.at_bound[k] == Bound::kNone
            ? ""
            : (fit.at_bound[k] == Bound::kLower ? "  (at lower bound)"
                                                : "  (at upper bound)"));
  }
  text += fmt::format("log L      {:.6f}\n", fit.log_likelihood);
  text += fmt::format("deviance   {:.6g}", fit.deviance);
  if (bootstrap_samples > 0) {
    text += fmt::format(" (bootstrap p = {:.4g}, {} samples)", deviance_p,
                        bootstrap_samples);
  }
  text += fmt::format("\nconverged  {} ({} evaluations)\n",
                      fit.converged ? "yes" : "NO", fit.evaluations);
  for (const auto* group : {&thresholds, &slopes}) {
    const bool is_threshold = group == &thresholds;
    for (const BootstrapEstimate& e : *group) {
      text += fmt::format("{} at cut {}: {:.6g}\n",
                          is_threshold ? "threshold" : "slope", e.cut, e.value);
      if (bootstrap_samples > 0) {
        text += "  BCa        " +
                FormatLimits(options.conf, e.bca, e.bca_at_search_limit) + "\n";
        text += "  percentile " +
                FormatLimits(options.conf, e.percentile,
                             e.percentile_at_search_limit) +
                "\n";
      }
    }
  }
  if (with_warnings) {
    for (const std::string& w : warnings) text += "warning: " + w + "\n";
  }
  return text;
}

}  // namespace burrlab::analysis
