// Private to the model-gap layer: what the parts of the discover workflow
// share. The runs a fit uses and the models fitted to them
// (discover_model_fit.cc), the gap tests on a fit's residuals
// (discover_gap_tests.cc), the attribution of a gap to the effects of the
// library (discover_attribution.cc) and the report's text
// (discover_summary.cc); discover.cc runs them as the stages of Discover
// (discover.h).
//
// Every model is log v = ModelLogVelocity(F; c_e, alpha, R, effects) with
// unweighted least squares on log v.
#ifndef BURRLAB_ANALYSIS_SRC_MODEL_GAP_DISCOVER_INTERNAL_H_
#define BURRLAB_ANALYSIS_SRC_MODEL_GAP_DISCOVER_INTERNAL_H_

#include <Eigen/Dense>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/analysis/model_gap/trace_gap.h"
#include "burrlab/base/result.h"
#include "burrlab/sim/effects.h"

namespace burrlab::analysis::discover_internal {

// ---- Runs and models (discover_model_fit.cc) --------------------------------

// The runs a fit uses: log F, log v, level index, file line.
struct Runs {
  // What the velocities are; for the initial velocity, `transient` holds
  // each run's transient factor (SurrogateVelocityMmS), 1 when empty.
  sim::VelocityDefinition definition = sim::VelocityDefinition::kSettled;
  std::vector<double> transient;
  std::vector<double> force_n, ln_v;
  std::vector<int> level, line;
  int levels = 0;
  double radius_mm = 1.0;
  int size() const { return static_cast<int>(ln_v.size()); }
};

// Every run of `data`, in file order.
Runs MakeRuns(const MeasuredData& data, double radius_mm,
              sim::VelocityDefinition definition);

// Gross outliers: runs far from the other replicates of their level, one at a
// time (the largest first), against a robust scale of all runs. keep[i] is 0
// for a run left out.
std::vector<char> ScreenOutliers(const Runs& runs, double sigmas);

// The runs with keep[i], their levels renumbered.
Runs Subset(const Runs& runs, const std::vector<char>& keep);

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

// For the initial velocity: every run's transient factor at `p` with
// `active` (InitialTransientFactor); returns the largest change of their
// logs. Nothing for the settled velocity.
double RefreshTransient(Runs* runs, const std::vector<ActiveEffect>& active,
                        const Point& p);
// The base model's fit with every run's transient factor computed at each
// point searched (BOBYQA over log c_e and log alpha from `start`), for when
// the held-factor refits cycle: near full immersion the factor moves fast
// with c_e. Leaves runs->transient at the returned point's; `rss` receives
// its RSS.
Point FitBaseWithOwnTransient(Runs* runs, const Point& start, double* rss);

// The whole state of one model in the workflow.
struct Model {
  std::vector<ActiveEffect> active;
  Point point;
  double rss = 0.0;
};

// The strength of effect `k` (`e` = active[k]) at `p`.
double Strength(const ActiveEffect& e, const Point& p, std::size_t k);

// log v of every run at `p` (NaN where the model cannot reach it).
std::vector<double> Predict(const Runs& runs,
                            const std::vector<ActiveEffect>& active,
                            const Point& p);

// RSS over the runs with use[i] (all when `use` is empty).
double Rss(const Runs& runs, const std::vector<ActiveEffect>& active,
           const Point& p, const std::vector<char>& use);

// log alpha that best fits the other parameters when log alpha enters
// additively (exact without a power limit; a start otherwise).
double OffsetAlpha(const Runs& runs, const std::vector<ActiveEffect>& active,
                   Point p, const std::vector<char>& use);

// Bounded local fit (NLopt BOBYQA) from each start; the best.
// With `fixed` an index into `active`, that effect's strength stays at each
// start's value (a profile point).
Point FitFromStarts(const Runs& runs, const std::vector<ActiveEffect>& active,
                    const std::vector<Point>& starts,
                    const std::vector<char>& use, const Point& centre,
                    double* rss_out, std::optional<std::size_t> fixed = {});

// The u at which effect k changes log v by `target` at most (bisection; the
// upper bound when it never does).
double UForChange(const Runs& runs, const std::vector<ActiveEffect>& active,
                  const Point& p, std::size_t k, double target);

// Unit and range of an effect's strength for these data at the base fit: the
// strength scale where the effect starts to matter for this design.
ActiveEffect ScaleEffect(const sim::EffectSpec& spec, const Runs& runs,
                         double c_e, double alpha);

// Jacobian of the predictions with respect to (log c_e, log alpha, u...) by
// differences (forward for u at its lower bound).
Eigen::MatrixXd Jacobian(const Runs& runs,
                         const std::vector<ActiveEffect>& active,
                         const Point& p);

// An orthonormal basis of the column space of J (SVD, numerical rank).
Eigen::MatrixXd ColumnBasis(const Eigen::MatrixXd& j);

// P_perp x = x - U U^T x.
Eigen::VectorXd Project(const Eigen::MatrixXd& basis, const Eigen::VectorXd& x);

// AICc of a fit with `parameters` (and sigma) to n runs.
double Aicc(double rss, int n, int parameters);

// ---- Gap tests (discover_gap_tests.cc) --------------------------------------

// The omnibus gap tests' share of the gap family's level (the library's
// focused test has the rest).
inline constexpr double kOmnibusShare = 0.2;

// Pure error: within-level sum of squares of `values` and its dof.
void PureError(const Runs& runs, const std::vector<double>& values, double* ss,
               int* dof);

// P(F(d1, d2) > f); 1 when f is not positive.
double FUpper(double f, double d1, double d2);

// The family-wise verdict of the gap tests: Holm over the three omnibus
// tests (NaN ones left out) at a fifth of the level, and the library's
// focused test at four fifths (weighted Bonferroni, so the whole family stays
// at the level): the focused test carries the power against the library's
// shapes, the omnibus tests catch what lies outside it.
void CombineGapTests(GapTests* g, double level);

// The residual tests of `g` for a message: "lack of fit p = 0.031,
// curvature p = 0.014, runs p = 0.51; Holm p = 0.042".
std::string DescribeGap(const GapTests& g);

// The omnibus gap tests on the residuals of a fit with Jacobian `jacobian`
// (lack of fit, curvature, runs); the library's test is added by the caller.
GapTests RunGapTests(const Runs& runs, const std::vector<double>& fitted,
                     const Eigen::MatrixXd& jacobian, double level);

// The RMS shift of log v (orthogonal to the model, spread over the levels)
// the lack-of-fit test detects with probability 1/2.
double DetectableRms(const Runs& runs, int parameters, double sigma,
                     double level);

// ---- The fits, tests and attribution on one set of runs ---------------------

// One attribution round: every v(F) effect of the library not in the model,
// tested against it (library order).
struct AttributionRound {
  std::vector<EffectAttribution> effects;
  std::vector<Model> fits;                  // the model with each effect added
  std::vector<Eigen::VectorXd> signatures;  // each effect's P_perp s
};

// The workflow's view of one set of runs: it holds the runs and the options
// (both must outlive it) and the progress count's total. Its methods are
// defined with their parts: the fits in discover_model_fit.cc, Gap in
// discover_gap_tests.cc, Attribute in discover_attribution.cc.
class Workflow {
 public:
  Workflow(const Runs& runs, const DiscoverOptions& options)
      : runs_(runs), options_(options) {}

  const Runs& runs() const { return runs_; }
  const DiscoverOptions& options() const { return options_; }

  // The base fit on the runs with use[i] (all if empty), as calibration.h
  // does it: log alpha profiled in closed form (it enters additively), a
  // bounded search over log c_e (grid, then Brent's method around the best
  // grid point). Fails when every c_e in the box pushes the burr through.
  Result<Point> BaseFit(const std::vector<char>& use) const;

  // Fits `active` (the last one new) from `from` (the model without it) over
  // the runs with use[i].
  Model FitAugmented(const std::vector<ActiveEffect>& active, const Point& from,
                     const std::vector<char>& use) const;

  // Leave-one-force-level-out RMSE of log v for `model` (NaN with < 3
  // levels); each held-out level's own RMSE goes to `per_level` when given
  // (left empty when the result is NaN).
  double CrossValidate(const Model& model,
                       std::vector<double>* per_level = nullptr) const;

  // The report's numbers of a fitted model.
  ModelFit Describe(const Model& m) const;

  // The omnibus gap tests on the residuals of `m`.
  GapTests Gap(const Model& m) const;

  // Scores and augmented fits of every library effect not in `current`, the
  // likelihood ratios adjusted over them by single-step max-T; counts one
  // progress task per effect.
  AttributionRound Attribute(const Model& current, int* progress_done) const;

  void set_total_tasks(int total) { total_tasks_ = total; }

 private:
  const Runs& runs_;
  const DiscoverOptions& options_;
  int total_tasks_ = 1;
};

// ---- Alias sets (discover_attribution.cc) -----------------------------------

// The alias set of round.effects[best], the effect a step adds to `current`:
// it and the effects the design cannot separate from it given the effects
// already added (separation below options.alias_separation; or, among the
// `candidates`, projected signatures or fitted contributions with |cos| above
// options.alias_cosine, or AICc within 2).
std::vector<std::string> AliasSet(const Workflow& flow, const Model& current,
                                  const AttributionRound& round,
                                  std::size_t best,
                                  const std::vector<std::size_t>& candidates);

// ---- The report's text (discover_summary.cc) --------------------------------

// "a, b, c".
std::string Join(const std::vector<std::string>& items);

// " N run(s) far outside ... gross outliers." or "" without outliers.
std::string OutliersSentence(const DiscoverReport& report);

// Verdict absorbed: `effect` with the reference (report.reference_p and
// reference_effect_p, the augmented fit's parameter set).
std::string AbsorbedSummary(const DiscoverReport& report,
                            const EffectAttribution& effect);

// Verdict none: the gap p and what the design would have detected.
std::string NoGapSummary(const DiscoverReport& report);

// Verdict named or ambiguous (report.verdict set): the effects or alias sets
// added and the confirming numbers.
std::string ExplainedSummary(const DiscoverReport& report);

// Verdict unexplained, before the report drops the effects tried: what was
// tried and why it failed (`failure`, or the residual tests when it is "").
std::string UnexplainedSummary(const DiscoverReport& report,
                               const std::vector<std::string>& tried,
                               const std::string& failure);

// The trace stage found nothing: " The traces (N runs) show no ...".
std::string TraceGapNoneSentence(const TraceGapResult& gap);

// The trace stage named `named`: its parameter, test and trace RMSEs.
std::string TraceGapFinding(const TraceGapResult& gap,
                            const TraceEffectTest& named);

}  // namespace burrlab::analysis::discover_internal

#endif  // BURRLAB_ANALYSIS_SRC_MODEL_GAP_DISCOVER_INTERNAL_H_
