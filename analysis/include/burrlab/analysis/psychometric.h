// Maximum-likelihood psychometric functions with parametric-bootstrap
// confidence intervals, following psignifit 2.5.6 (Wichmann & Hill 2001a,b):
//   psi(x) = gamma + (1 - gamma - lambda) F(x; alpha, beta)
// with F logistic, cumulative normal, Weibull or Gumbel; gamma = 1/n for
// n-AFC and free in [0, gamma_max] for yes/no; lambda free in
// [0, lambda_max]; thresholds F^-1(cut) and slopes dF/dx there; BCa (Efron
// 1987) and percentile intervals from refitted bootstrap data sets; the
// deviance and its bootstrap p-value. Formulas and conventions:
// analysis/README.md.
#ifndef BURRLAB_ANALYSIS_PSYCHOMETRIC_H_
#define BURRLAB_ANALYSIS_PSYCHOMETRIC_H_

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::analysis {

// The shape F of the psychometric function, parameterised as psignifit 2.5.6
// prints alpha and beta:
enum class Sigmoid {
  kLogistic,          // F = 1 / (1 + exp(-(x - alpha) / beta))
  kCumulativeNormal,  // F = Phi((x - alpha) / beta)
  kWeibull,           // F = 1 - exp(-(x / alpha)^beta), x > 0
  kGumbel,            // F = 1 - exp(-exp((x - alpha) / beta)) (log-Weibull)
};
// "logistic", "cumnorm", "weibull" or "gumbel".
std::string_view SigmoidName(Sigmoid sigmoid);
// The sigmoid named by SigmoidName; nullopt for another name.
std::optional<Sigmoid> SigmoidFromName(std::string_view name);

// F(x; alpha, beta) in [0, 1].
double SigmoidValue(Sigmoid sigmoid, double x, double alpha, double beta);
// dF/dx at x.
double SigmoidSlope(Sigmoid sigmoid, double x, double alpha, double beta);
// F^-1(cut) for cut in (0, 1): the threshold at that cut.
double SigmoidInverse(Sigmoid sigmoid, double cut, double alpha, double beta);
// d threshold / d(alpha, beta) at `cut` (for the BCa least-favourable
// direction).
std::array<double, 2> ThresholdGradient(Sigmoid sigmoid, double cut,
                                        double alpha, double beta);
// d slope / d(alpha, beta), slope = dF/dx at F^-1(cut).
std::array<double, 2> SlopeGradient(Sigmoid sigmoid, double cut, double alpha,
                                    double beta);

struct PsychometricParams {
  double alpha = 0.0;   // location (Weibull: scale, same unit as x)
  double beta = 1.0;    // spread (Weibull: shape exponent, dimensionless)
  double gamma = 0.5;   // guess rate, the lower asymptote
  double lambda = 0.0;  // lapse rate: the upper asymptote is 1 - lambda
};
// psi(x) = gamma + (1 - gamma - lambda) F(x; alpha, beta).
double Psi(Sigmoid sigmoid, const PsychometricParams& params, double x);

// One block of trials at one stimulus level.
struct DataBlock {
  double level = 0.0;  // stimulus level x (Weibull: > 0)
  int n_correct = 0;   // correct (n-AFC) or "yes" (yes/no) responses
  int n_total = 0;     // trials, >= 1
};

struct PsychometricOptions {
  Sigmoid sigmoid = Sigmoid::kLogistic;  // shape of F
  // n of an n-AFC task (gamma fixed at 1/n), or 1 for yes/no (gamma free).
  int n_intervals = 2;
  double lambda_max = 0.05;  // lambda in [0, lambda_max]; 0 fixes it at 0
  double gamma_max = 0.05;   // yes/no only: gamma in [0, gamma_max]
  // Cuts of F (not psi) at which thresholds and slopes are reported; with
  // gamma = 0.5, cut 0.5 is 75 % correct.
  std::vector<double> cuts = {0.2, 0.5, 0.8};
  // Cumulative probabilities of the reported interval bounds.
  std::vector<double> conf = {0.023, 0.159, 0.841, 0.977, 0.025, 0.975};
  int bootstrap_samples = 1999;  // refitted simulated data sets; 0: none
  // Simulated data set b draws from a Boost mt19937_64 seeded with
  // std::seed_seq{seed low 32 bits, seed high 32 bits, b low, b high}.
  std::uint64_t seed = 1;
  // Likelihood evaluations allowed per optimiser start (as Palamedes'
  // MaxFunEvals); a start that needs more is not converged.
  int max_evaluations = 2000;
  // Threads the fit's likelihood evaluations share the levels between
  // (4096 or more each) and the bootstrap shares its refits between (1 to
  // 64; 0: one per core). The results do not depend on it.
  int threads = 0;
  // Called after each bootstrap refit with (refits done, bootstrap_samples),
  // from the refitting threads one call at a time, `done` counting up; a
  // refit of a large data set costs about one pass over its levels.
  // Empty: not called.
  std::function<void(int done, int total)> progress;

  // Names the first bad field, its value and the rule it breaks.
  Status Validate() const;
};

// Whether a fitted parameter sits on a limit of its search range.
enum class Bound { kNone, kLower, kUpper };

struct PsychometricFit {
  PsychometricParams params;
  double log_likelihood = 0.0;  // sum r ln psi + (n - r) ln(1 - psi)
  double deviance = 0.0;        // 2 (log L(saturated) - log L(fit))
  bool converged = false;       // the optimiser met its tolerances
  int evaluations = 0;          // likelihood evaluations used
  // alpha, beta, gamma, lambda in that order. gamma is kNone when fixed
  // (n-AFC); lambda kNone when lambda_max = 0. alpha and beta are limited to
  // a wide search box around the data (see README), so kLower/kUpper there
  // means the data do not pin the parameter down.
  std::array<Bound, 4> at_bound = {Bound::kNone, Bound::kNone, Bound::kNone,
                                   Bound::kNone};
  bool AtAnyBound() const;
};

// A threshold or slope at one cut with its bootstrap intervals.
struct BootstrapEstimate {
  double cut = 0.0;
  double value = 0.0;  // from the fit to the data
  // Bounds at options.conf, in that order; NaN when no bootstrap was run or
  // the bound falls outside the bootstrap sample (then a warning says so).
  std::vector<double> bca;
  std::vector<double> percentile;
  // Per bound: it comes from a bootstrap refit whose location or scale
  // stopped at the edge of the fit's search range (the refit's own estimate
  // is then that edge, not a property of the data): the data do not bound
  // the estimate on that side, and reports say "search limit", not a number.
  std::vector<bool> bca_at_search_limit;
  std::vector<bool> percentile_at_search_limit;
  double cpe = 0.0;           // #(bootstrap values < value) / (R + 1)
  double bias_z0 = 0.0;       // Phi^-1(cpe)
  double acceleration = 0.0;  // Efron's a along the least-favourable direction
  // The R bootstrap values in the order they were drawn, and their scores
  // along the least-favourable direction (empty without BCa): enough to
  // recompute the limits with ComputeBootstrapLimits (bootstrap.h).
  std::vector<double> replicates;
  std::vector<double> scores;
  // What is wrong with these bounds (search limits, beyond the samples), one
  // sentence per kind; PsychometricAnalysis::warnings holds them too.
  std::vector<std::string> warnings;
};

struct PsychometricAnalysis {
  PsychometricOptions options;
  PsychometricFit fit;
  std::vector<BootstrapEstimate> thresholds;  // one per options.cuts
  std::vector<BootstrapEstimate> slopes;      // one per options.cuts
  int bootstrap_samples = 0;                  // R
  int bootstrap_not_converged = 0;  // refits that did not converge (kept)
  // (1 + #(bootstrap deviance >= deviance)) / (R + 1); NaN when R = 0.
  double deviance_p = 0.0;
  std::vector<std::string> warnings;  // one line each, for people

  // One line: parameters, deviance and its p-value.
  std::string BriefReport() const;
  // Parameters, bounds, thresholds and slopes with their intervals, and the
  // warnings unless `with_warnings` is false.
  std::string FullReport(bool with_warnings = true) const;
};

// Checks a data set for a fit: at least one block, finite levels, 1 <=
// n_total, 0 <= n_correct <= n_total, at least 3 distinct levels, levels > 0
// for the Weibull, and not every response correct (or every one wrong).
// Errors name the block (1-based) and its values; `bad_block`, when given,
// receives the 0-based index of the block at fault (data.size() when the
// problem is the data set as a whole).
Status ValidateData(std::span<const DataBlock> data, Sigmoid sigmoid,
                    std::size_t* bad_block = nullptr);

// The maximum-likelihood fit only.
Result<PsychometricFit> FitPsychometric(std::span<const DataBlock> data,
                                        const PsychometricOptions& options);

// The maximum-likelihood fit of `data` found from `from`, the parameters of
// a fit to similar data, as the bootstrap refits each simulated data set:
// Newton steps (the first by Fisher scoring), each a pass over the levels,
// and SLSQP from `from` when they fail. Far cheaper than FitPsychometric,
// which searches from scratch, and as good when the maximum is the one
// nearest `from`.
Result<PsychometricFit> RefitPsychometric(std::span<const DataBlock> data,
                                          const PsychometricOptions& options,
                                          const PsychometricParams& from);

// The fit, thresholds and slopes at options.cuts, and options.bootstrap_samples
// refitted parametric-bootstrap data sets for their intervals and the
// deviance p-value.
Result<PsychometricAnalysis> AnalyzePsychometric(
    std::span<const DataBlock> data, const PsychometricOptions& options);

// Expected Fisher information of the binomial likelihood at `params` in the
// user parameters (alpha, beta, gamma, lambda); rows and columns of fixed
// parameters (gamma for n-AFC, lambda when lambda_max = 0) are those of the
// identity, as psignifit 2.5.6 writes #FISHER.
std::array<std::array<double, 4>, 4> FisherInformation(
    std::span<const DataBlock> data, const PsychometricOptions& options,
    const PsychometricParams& params);

// The asymptotic covariance of (alpha, beta, gamma, lambda): the inverse of
// FisherInformation (fixed parameters get variance 1 and no covariance);
// nullopt when the information is singular.
std::optional<std::array<std::array<double, 4>, 4>> ParameterCovariance(
    std::span<const DataBlock> data, const PsychometricOptions& options,
    const PsychometricParams& params);

// d log L / d(alpha, beta, gamma, lambda) at `params` for the counts
// `n_correct` (one per block of `data`, whose own counts are ignored); 0 for
// fixed parameters (psignifit's #LDOT rows).
std::array<double, 4> Score(std::span<const DataBlock> data,
                            const PsychometricOptions& options,
                            const PsychometricParams& params,
                            std::span<const int> n_correct);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_PSYCHOMETRIC_H_
