// Calibration of the base burr model (c_e, alpha) against measured steady
// penetration velocities (dissertation §8.6-8.7): least squares on log v
// through the steady-state surrogate (descent_surrogate.h), an identifiability
// check (SVD of the Jacobian of log v with respect to log c_e and log alpha,
// profile likelihood) and profile-likelihood intervals.
//
// With the model log v = log alpha + log R - g(log F - log c_e - 2 log R),
// g = log kappa of the surrogate, log alpha enters linearly: it is profiled in
// closed form and the fit is a bounded one-dimensional search over log c_e
// (a grid of starts, each local minimum refined by Brent's method).
#ifndef BURRLAB_ANALYSIS_MODEL_GAP_CALIBRATION_H_
#define BURRLAB_ANALYSIS_MODEL_GAP_CALIBRATION_H_

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/base/result.h"
#include "burrlab/sim/descent.h"

namespace burrlab::analysis {

struct CalibrationOptions {
  double radius_mm = 0.0;  // burr radius R, mm (required)
  // What the measured velocities are (sim/descent.h).
  sim::VelocityDefinition definition = sim::kDefaultVelocityDefinition;
  double confidence = 0.95;  // level of the profile-likelihood intervals
  // Search box for c_e (alpha, profiled in closed form, has none). The lower
  // end rises to where the largest force would push the burr through.
  double c_e_min_n_per_mm2 = 1e-3;
  double c_e_max_n_per_mm2 = 1e3;
  // Parametric-bootstrap replicates calibrating the profile threshold (0:
  // the F quantile alone) and their seed.
  int bootstrap_replicates = 200;
  std::uint64_t seed = 1;

  // Names the first bad field, its value and the rule broken.
  Status Validate() const;
};

// A closed interval [lo, hi].
using Interval = std::array<double, 2>;

// Another local minimum of the c_e profile whose RSS lies inside the
// confidence set: v(F) at the data's loads does not decide between it and the
// fit.
struct SecondMinimum {
  double c_e_n_per_mm2 = 0.0;
  double alpha_per_s = 0.0;
  double rss_log_v = 0.0;
  // Its own part of the confidence set when a ridge above the threshold
  // separates it from the fit's interval; nullopt when it lies inside that
  // interval.
  std::optional<Interval> c_e_ci;
};

struct CalibrationSummary {
  double c_e_n_per_mm2 = 0.0;  // best fit
  double alpha_per_s = 0.0;
  // Profile-likelihood intervals; nullopt when the profile does not close
  // inside the search box (the parameter is not identifiable from v(F)).
  std::optional<Interval> c_e_ci;
  std::optional<Interval> alpha_ci;
  // The best other minimum of the c_e profile inside the confidence set, when
  // the profile has one (only looked for where c_e_ci closes).
  std::optional<SecondMinimum> second_minimum;
  bool identifiable = false;    // c_e and alpha are determined separately
  std::string identifiability;  // one sentence for people
  // The combination alpha * c_e^exponent that v(F) determines best (exponent =
  // mean d log kappa / d log load at the fit), its value and interval.
  double combination_exponent = 0.0;
  double combination_value = 0.0;
  std::optional<Interval> combination_ci;
  std::array<double, 2> singular_values{};  // of the Jacobian, descending
  double condition_number = 0.0;            // singular_values[0] / [1]
  // Thresholds q of the profile statistic for c_e, alpha and the
  // combination (bootstrap-calibrated, at least the F_{1, n-2} quantile).
  std::array<double, 3> profile_quantiles{};
  double rss_log_v = 0.0;    // residual sum of squares
  double rmse_log_v = 0.0;   // sqrt(rss / runs)
  double sigma_log_v = 0.0;  // sqrt(rss / (runs - 2))
  int runs = 0;
  int force_levels = 0;
  std::vector<double> fitted_velocity_mm_s;  // per run, in file order
};

// Fits c_e and alpha to `data`. Errors: bad options, forces the surrogate
// cannot hold for any c_e in the box.
Result<CalibrationSummary> Calibrate(const MeasuredData& data,
                                     const CalibrationOptions& options);

// "alpha * c_e^-2.41" for an exponent.
std::string CombinationName(double exponent);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_MODEL_GAP_CALIBRATION_H_
