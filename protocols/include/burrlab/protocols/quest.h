// QUEST (Watson & Pelli 1983): Bayesian adaptive threshold estimation with a
// Weibull psychometric function in log10 intensity units. Trials are placed at
// a posterior quantile (Pelli 1987) and threshold is reported as the posterior
// mean. Parameters, grid and tables behave like Psychtoolbox-3's QuestCreate,
// QuestUpdate, QuestQuantile, QuestMean, QuestSd, QuestMode and QuestP; the
// tests replay traces recorded with them in Octave
// (tests/protocols/fixtures/quest/).
#ifndef BURRLAB_PROTOCOLS_QUEST_H_
#define BURRLAB_PROTOCOLS_QUEST_H_

#include <optional>
#include <span>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::protocols {

// Parameters of one QUEST track, named as QuestCreate's arguments. The
// psychometric function is
//   p(x) = delta*gamma + (1 - delta)*(1 - (1 - gamma)*exp(-10^(beta*(x + e))))
// with x = intensity - threshold in log10 units and e chosen so that
// p(0) = p_threshold.
struct QuestOptions {
  double t_guess = 0.0;       // prior threshold guess (tGuess), log10 units
  double t_guess_sd = 2.0;    // prior standard deviation (tGuessSd), log10
  double p_threshold = 0.82;  // response-1 probability at threshold
  double beta = 3.5;          // Weibull steepness
  double delta = 0.01;        // fraction of trials answered blindly (lapses)
  double gamma = 0.5;         // response-1 probability at intensity -inf
  double grain = 0.01;        // step of the threshold table, log10 units
  double range = 5.0;         // width of the table centred on t_guess, log10
                              // units (QuestCreate without range uses 500
                              // steps, the same only when grain = 0.01)
  bool normalize_pdf = true;  // rescale the posterior to sum 1 after updates
  bool update_pdf = true;     // false: Update only records the trial
  std::optional<double> quantile_order;  // placement quantile; unset: the
                                         // optimum QuestCreate computes
  int reserve_trials = 1000;  // history capacity reserved at creation, so
                              // Update does not allocate before this many

  // Names the first bad field, its value and the rule it breaks.
  Status Validate() const;
};

// What Update did with one trial's intensity.
struct QuestUpdateReport {
  bool clamped = false;        // intensity beyond the table; the likelihood
                               // was taken at the nearest table edge
  double table_intensity = 0;  // intensity the likelihood was evaluated at
};

// One recorded trial, as given to Update (intensity not clamped).
struct QuestTrial {
  double intensity = 0.0;  // tested intensity, log10 units
  bool response = false;   // true: correct / "yes" (PTB response 1)
};

// One QUEST track: a posterior over threshold on a grid t_guess + x[j].
class Quest {
 public:
  // Builds the prior, the psychometric tables and the placement quantile.
  static Result<Quest> Create(const QuestOptions& options);

  // Adds one trial; NaN intensity is an error, +-inf is clamped like PTB.
  Result<QuestUpdateReport> Update(double intensity, bool response);

  // Intensity for the next trial: the posterior quantile_order() quantile.
  Result<double> Quantile() const;
  // The posterior quantile of the given order in [0, 1] (as QuestQuantile:
  // linear in the cumulative sum, about grain/2 below the continuous one).
  Result<double> Quantile(double order) const;
  // Posterior mean of threshold (the recommended estimate); NaN if all zero.
  double Mean() const;
  // Posterior standard deviation of threshold; NaN if the posterior is zero.
  double Sd() const;
  // Posterior mode (the first grid point of highest density).
  double Mode() const;
  // Response-1 probability at x = intensity - threshold (log10 units).
  double P(double x) const;

  // Quantile order used by Quantile(): the option or Pelli's optimum.
  double quantile_order() const { return quantile_order_; }
  // Offset e in the Weibull that puts p_threshold at threshold (PTB
  // q.xThreshold).
  double x_threshold() const { return x_threshold_; }
  // Lowest intensity whose likelihood the tables hold exactly.
  double intensity_min() const;
  // Highest intensity whose likelihood the tables hold exactly.
  double intensity_max() const;
  // Number of trials given to Update.
  int trial_count() const { return static_cast<int>(trials_.size()); }
  // Every trial given to Update, in order.
  std::span<const QuestTrial> trials() const { return trials_; }
  // Posterior (normalised when normalize_pdf) at thresholds t_guess + x()[j].
  std::span<const double> pdf() const { return pdf_; }
  // Threshold grid relative to t_guess: (j - dim/2) * grain.
  std::span<const double> x() const { return x_; }
  // The options the track was created with.
  const QuestOptions& options() const { return options_; }

 private:
  explicit Quest(const QuestOptions& options) : options_(options) {}

  QuestOptions options_;
  int half_dim_ = 0;                // dim/2: the grid has 2*half_dim_+1 points
  std::vector<double> x_;           // threshold offsets, size dim+1
  std::vector<double> pdf_;         // posterior, size dim+1
  std::vector<double> x2_;          // intensity - threshold, size 2*dim+1
  std::vector<double> p1_;          // P(response 1 | x2_), size 2*dim+1
  std::vector<double> p0_;          // 1 - p1_
  double x_threshold_ = 0.0;        // see x_threshold()
  double quantile_order_ = 0.0;     // see quantile_order()
  std::vector<QuestTrial> trials_;  // history, reserved reserve_trials
};

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_QUEST_H_
