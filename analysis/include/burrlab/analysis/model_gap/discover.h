// The model-gap workflow (analysis/README.md, "Finding what the model misses"):
// given measured steady velocities v(F), fit the base model (c_e, alpha),
// detect a gap (lack of fit against the replicates' pure error, residual
// structure against force), attribute it to an effect of the library
// (sim/effects.h) by projected score tests, identifiability indices, alias sets
// and likelihood-ratio tests with Holm's family-wise correction, augment the
// model one effect at a time (at most two) and confirm (boundary-aware
// likelihood ratio, AICc, leave-one-force-level-out cross-validation, residual
// tests re-run), and say what was found: a named effect, an ambiguous set, a
// gap outside the library, an effect absorbed by a base parameter, or none.
//
// Every model is log v = log SurrogateVelocityMmS(F; c_e, alpha, R, effects)
// under the options' velocity definition (descent_surrogate.h) with unweighted
// least squares on log v (log-normal run-to-run scatter), so the Gaussian
// profile likelihood gives LR = n log(RSS_0 / RSS_1).
#ifndef BURRLAB_ANALYSIS_MODEL_GAP_DISCOVER_H_
#define BURRLAB_ANALYSIS_MODEL_GAP_DISCOVER_H_

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/analysis/model_gap/trace_gap.h"
#include "burrlab/base/result.h"
#include "burrlab/sim/descent.h"
#include "burrlab/sim/model.h"

namespace burrlab::analysis {

struct DiscoverOptions {
  double radius_mm = 0.0;  // burr radius R, mm (required)
  // What the measured velocities are (sim/descent.h). For the initial
  // velocity the rig's transient factor of each run is refreshed at the base
  // fit until it settles and held through the effects' fits.
  sim::VelocityDefinition definition = sim::kDefaultVelocityDefinition;
  double test_level = 0.05;  // family-wise level of each family of tests
  int max_effects = 2;       // effects added at most, one at a time
  // |cos| of two projected signatures above which the design cannot tell the
  // effects apart (an alias set).
  double alias_cosine = 0.95;
  // An effect is also in the alias set when, fitted to the best model's
  // noise-free predictions, what it cannot reproduce is below this many
  // noise variances: a test between the two on this design would have less
  // than 80 % power at 5 % (noncentrality (1.645 + 0.842)^2 = 6.2).
  double alias_separation = 6.2;
  // Identifiability index ||P_perp s|| / ||s|| below which an effect is
  // absorbed by c_e and alpha (not testable from v(F)).
  double absorbed_index = 0.01;
  // Reference material (e.g. the built-in set the material column names):
  // lets an absorbed effect be reported when the data reject the reference
  // and reference + effect fits as well as free c_e and alpha.
  std::optional<sim::Material> reference;
  // Relative change of v an absorbed effect must make to be reported (the
  // rig's discretisation alone shifts v by about 2 %).
  double absorbed_margin = 0.1;
  // A run whose log v lies more than this many robust standard deviations
  // from the other replicates of its level is a gross outlier and is left
  // out (needs 3 or more replicates at the level).
  double outlier_sigmas = 5.0;
  // Time traces of the runs (trace_data.h): the trace-only effects, which
  // v(F) cannot see, are tested on them (trace_gap.h).
  std::optional<TraceData> traces;
  // Called with (done, total, what runs now) as the work proceeds.
  std::function<void(int, int, std::string_view)> progress;

  // Names the first bad field, its value and the rule broken.
  Status Validate() const;
};

// A fitted model: base parameters, the added effects and the fit's numbers.
struct ModelFit {
  double c_e_n_per_mm2 = 0.0;
  double alpha_per_s = 0.0;
  std::vector<std::string> effects;   // ids, in the order added
  std::vector<double> effect_values;  // their parameters (sim/effects.h units)
  std::vector<double> strengths;      // the same as strengths >= 0
  int parameters = 2;                 // c_e, alpha and one per effect
  double rss_log_v = 0.0;
  double rmse_log_v = 0.0;  // sqrt(rss / runs)
  double aicc = 0.0;        // n log(rss/n) + 2k + 2k(k+1)/(n-k-1), k = p + 1
  // Leave-one-force-level-out RMSE of log v (NaN with fewer than 3 levels).
  double cv_rmse_log_v = 0.0;
  // The same for each held-out level alone, lowest force first (empty with
  // fewer than 3 levels).
  std::vector<double> cv_level_rmse_log_v;
  std::vector<double> fitted_log_v;  // per run used, in file order
};

// The gap tests on one fit's residuals; NaN where a test does not apply.
struct GapTests {
  double lack_of_fit_p = 0.0;  // F test of level means against pure error
  double curvature_p = 0.0;    // quadratic + cubic in log F, projected
  double runs_p = 0.0;         // Wald-Wolfowitz runs of residual signs by F
  // The library's focused test: the smallest max-T adjusted likelihood-ratio
  // p of the effects (more powerful than the omnibus tests against a gap of
  // the library's shapes); NaN after augmentation.
  double library_p = 0.0;
  // The family's adjusted p: Holm over the three omnibus tests, weighted
  // Bonferroni with the library's test (omnibus 1/5 of the level, library
  // 4/5); the omnibus Holm p alone at the whole level when library_p is NaN
  // (after augmentation: the augmented model must pass the residual tests
  // at the full level, so a shape outside the library is not forced onto an
  // effect).
  double holm_min_p = 0.0;
  bool detected = false;  // holm_min_p < test_level
};

// One effect of the library against the current model.
struct EffectAttribution {
  std::string id;  // the effect family (the id of its first library entry)
  // The family's variant that fits best (sim/effects.h: each family lists
  // its shapes), its shape's name (empty for a family of one), and whether
  // the data fix the shape: every other variant's AICc is at least 2 worse.
  // `undetermined_shapes` names the variants that fit alike.
  std::string variant;
  std::string shape;
  bool shape_determined = true;
  std::vector<std::string> alike_shapes;
  double identifiability = 0.0;  // ||P_perp s|| / ||s||
  double score_z = 0.0;          // projected score, allowed side positive
  double score_p = 1.0;          // one-sided
  double lr = 0.0;               // likelihood ratio of the augmented fit
  double lr_p = 1.0;             // 50:50 chi-bar-squared mixture
  // Family-wise adjusted over the testable effects (single-step max-T, the
  // signed roots' correlation from the projected signatures).
  double lr_p_adjusted = 1.0;
  double aicc = 0.0;      // of the augmented fit
  double value = 0.0;     // fitted parameter
  bool absorbed = false;  // identifiability < absorbed_index
};

// What discovery concluded about the gap between the base model and the data.
enum class Verdict {
  kNone,         // no gap the tests can see: the base model explains the data
  kNamed,        // a gap, and the effect(s) added close it
  kAmbiguous,    // a gap closed by an effect the design cannot tell from
                 // others (its alias set)
  kUnexplained,  // a gap no effect in the library closes
  kAbsorbed,     // the effect is absorbed by the base model's own parameters
};
// "none", "named", "ambiguous", "unexplained" or "absorbed" (as reports,
// JSON and Markdown spell it).
std::string_view VerdictName(Verdict verdict);

struct DiscoverReport {
  Verdict verdict = Verdict::kNone;
  // What the velocities were (DiscoverOptions::definition).
  sim::VelocityDefinition velocity_definition = sim::kDefaultVelocityDefinition;
  std::vector<std::string> effects;    // added, in order (empty: none)
  std::vector<std::string> alias_set;  // cannot be told from effects[0]
  // One per added effect: alias_sets[k] holds effects[k] and the effects
  // the design cannot tell from it once effects[0..k-1] are in the model
  // (alias_sets[0] == alias_set).
  std::vector<std::vector<std::string>> alias_sets;
  ModelFit baseline;
  ModelFit augmented;  // = baseline when nothing was added
  GapTests gap_before, gap_after;
  // Attribution rounds (one per effect step), each over the library.
  std::vector<std::vector<EffectAttribution>> rounds;
  // The confirming tests of the last step tried.
  double lr_p = 1.0;        // augmented against the model before the step
  double delta_aicc = 0.0;  // AICc(augmented) - AICc(before); < 0 is better
  double delta_aicc_runner_up = 0.0;  // AICc(runner-up) - AICc(best)
  // Reference check (absorbed effects): p of the reference against the free
  // base fit, and of reference + effect against it; NaN without reference.
  double reference_p = 0.0;
  double reference_effect_p = 0.0;
  std::vector<int> outlier_lines;  // runs left out (file lines)
  // A paragraph for people: what was found and why.
  std::string summary;
  // The smallest RMS change of log v the lack-of-fit test detects with
  // probability 1/2 in this design (an equal shift of all level means
  // orthogonal to the base model): what "none" rules out.
  double detectable_rms_log_v = 0.0;
  // The trace-gap test, when traces were given.
  std::optional<TraceGapResult> trace_gap;
};

// Runs the workflow on `data`. Errors: bad options, data the base fit cannot
// use (see calibration.h).
Result<DiscoverReport> Discover(const MeasuredData& data,
                                const DiscoverOptions& options);

// Discover's held-out check: whether `after` predicts force levels it was not
// fitted to better than `before` — its leave-one-level-out RMSE of log v is
// lower, or it predicts more than half of the held-out levels better (a kink
// such as a hard power cap: the fit that leaves out the level next to it
// cannot place it, and that one level can lose more than all the others
// gain). A NaN error (fewer than 3 levels) passes.
bool PredictsHeldOutBetter(const ModelFit& after, const ModelFit& before);

// The residual sum of squares of log v of the base model (c_e, alpha) fitted
// to `data` exactly as Discover fits it.
Result<double> BaseModelRss(const MeasuredData& data, double radius_mm);

// log v of the surrogate with the given effects (NaN when v is 0 or inf).
double ModelLogVelocity(
    double force_n, double c_e_n_per_mm2, double alpha_per_s, double radius_mm,
    const sim::Effects& effects,
    sim::VelocityDefinition definition = sim::kDefaultVelocityDefinition,
    double transient_factor = 1.0);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_MODEL_GAP_DISCOVER_H_
