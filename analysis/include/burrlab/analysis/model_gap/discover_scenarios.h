// Hidden-effect scenarios for testing the model-gap workflow honestly, on data
// it did not fit: "measured" data from the synthetic measurement generator (the
// full rig, or the surrogate for a fast tier) with an effect hidden at a chosen
// projected signal-to-noise ratio, optional distortions outside the library (a
// smooth bump in log v, gross outliers), written as CSV and parsed back, so
// Discover sees only what a user's file would give it. Used by
// tests/analysis/model_gap/discover_test.cc and by `burrlab discover-matrix`.
#ifndef BURRLAB_ANALYSIS_MODEL_GAP_DISCOVER_SCENARIOS_H_
#define BURRLAB_ANALYSIS_MODEL_GAP_DISCOVER_SCENARIOS_H_

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/base/result.h"
#include "burrlab/sim/descent.h"
#include "burrlab/sim/effects.h"
#include "burrlab/sim/model.h"

namespace burrlab::analysis {

struct ScenarioDesign {
  std::string material_name = "human_temporal_bone";
  sim::Material material;  // the truth's base parameters
  double radius_mm = 1.0;
  // Force levels as loads F / (c_e R^2).
  std::vector<double> loads = {0.5, 0.7, 0.9, 1.1, 1.3, 1.5};
  int replicates = 4;
  double noise_cv = 0.1;
  // The truth: the full descent rig (voxel R/12, 5 ms), or the continuum
  // surrogate itself (fast tier).
  bool full_rig = true;
  // The matrix measures the settled velocity, whichever the tools' default:
  // the surrogate tier's truths are the steady-state surrogate's, and its
  // published rates are of that quantity.
  static constexpr sim::VelocityDefinition kDefinition =
      sim::VelocityDefinition::kSettled;

  std::vector<double> ForcesN() const;
  // The noise's standard deviation of log v, sqrt(ln(1 + cv^2)).
  double SigmaLogV() const;
};

// Distortions outside the library's physics and noise model.
struct Distortion {
  // A Gaussian bump of this height in log v, centred at the middle of the
  // log-force range, width a sixth of it.
  double bump_log_v = 0.0;
  // Each run is a gross outlier with this probability: v times or divided by
  // outlier_factor (equally likely).
  double outlier_fraction = 0.0;
  double outlier_factor = 3.0;
};

// The projected signal-to-noise ratio of `effects` in the design: sqrt of
// the noncentrality lambda of the truth against the base model as this
// design's noise shows it, lambda = E[RSS_base - RSS_truth] / sigma^2 + 2
// over 48 fixed noise draws (RSS_base: the base model (c_e, alpha) fitted as
// Discover fits it; + 2 for its fitted parameters, so a linear base model
// gives exactly the noise-free ||P_perp delta||^2 / sigma^2). The noise-free
// distance alone overstates what any test can see where the base model is
// curved (c_e at the end of its range, v(F) a power law): there an oracle
// knowing the true effect passed its 5 % test in only 80 % of seeds at a
// noise-free "SNR 4".
Result<double> ProjectedSnr(const ScenarioDesign& design,
                            const sim::Effects& effects);

// Effect `id` at the strength where ProjectedSnr reaches `target` (bisection
// on the strength); an error when it never does in the effect's range.
Result<sim::Effects> EffectAtSnr(const ScenarioDesign& design,
                                 const std::string& id, double target);

// The noise-free truth per force level (the rig or the surrogate); the rig
// runs `jobs` force levels at once (the result does not depend on it).
Result<std::vector<double>> TruthVelocitiesMmS(const ScenarioDesign& design,
                                               const sim::Effects& effects,
                                               int jobs = 1);

// The CSV a user would have for one seed.
std::string ScenarioCsv(const ScenarioDesign& design,
                        const std::vector<double>& truth_mm_s,
                        const Distortion& distortion, std::uint64_t seed);

// One seed's report, as the scenario tally saw it.
struct SeedOutcome {
  std::uint64_t seed = 0;
  Verdict verdict = Verdict::kNone;
  std::vector<std::string> named;  // every alias set's ids (named/ambiguous)
};

struct ScenarioOutcome {
  int seeds = 0;
  std::vector<SeedOutcome> per_seed;  // in seed order
  std::map<Verdict, int> verdicts;    // count per verdict
  int hits = 0;  // expected id named, or in the alias set (named/ambiguous)
  int named_physical = 0;   // verdict named or ambiguous (any effect)
  int cv_shrank = 0;        // held-out RMSE after < before, among hits
  int held_out_better = 0;  // PredictsHeldOutBetter(after, before), hits
  double mean_cv_before = 0.0, mean_cv_after = 0.0;  // over the hits
};

// Runs Discover on `seeds` seeds from `first_seed`; `expected_id` empty for
// scenarios where no effect should be named. `jobs` threads share the seeds;
// the outcome is the same for any `jobs`.
Result<ScenarioOutcome> RunScenario(const ScenarioDesign& design,
                                    const std::vector<double>& truth_mm_s,
                                    const Distortion& distortion,
                                    const std::string& expected_id,
                                    std::uint64_t first_seed, int seeds,
                                    const DiscoverOptions& options,
                                    int jobs = 1);

// Seeds where `scenario` names or sets out a physical effect while
// `control`, run on the same seeds (the same noise draws), does not: what
// the scenario adds beyond the control's own chance shapes. Porosity only
// rescales c_e and the outlier distortion is drawn on top of the null's
// noise, so against the null control both should add none. Seeds missing
// from `control` count as named beyond it.
std::vector<std::uint64_t> NamedBeyond(const ScenarioOutcome& scenario,
                                       const ScenarioOutcome& control);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_MODEL_GAP_DISCOVER_SCENARIOS_H_
