// Private: the base model's fit to initial velocities with every run's
// transient factor computed at each point searched, shared by calibrate and
// discover. Near full immersion the held-factor refits cycle (the factor
// moves fast with c_e and alpha: PVC K70 at 3 N, R = 2 mm, 1.42 at c_e 0.45,
// alpha 0.3, 1.03 at c_e 0.6), and the RSS with each point's own factors has
// a narrow basin next to the full-immersion bound beside a long, nearly flat
// valley toward larger c_e, on which a local search can stop. So the profile
// over log c_e is scanned from the bound up before the local search.
#ifndef BURRLAB_ANALYSIS_SRC_MODEL_GAP_OWN_FACTOR_FIT_H_
#define BURRLAB_ANALYSIS_SRC_MODEL_GAP_OWN_FACTOR_FIT_H_

#include <array>
#include <functional>

namespace burrlab::analysis::detail {

struct OwnFactorProblem {
  // log alpha that fits best at log c_e = l with the factors held now.
  std::function<double(double l)> held_alpha;
  // The RSS at (log c_e, log alpha) with the factors computed there; they
  // stay held until the next call.
  std::function<double(double l, double a)> own_rss;
  // The full-immersion bound of log c_e (the largest force's), and the box.
  double l_bound = 0.0;
  double l_lower = 0.0, l_upper = 0.0;
};

struct OwnFactorMinimum {
  double l = 0.0, a = 0.0;
  double rss = 0.0;  // +inf when no point searched was finite
};

// The best of: BOBYQA over (log c_e, log alpha) from `start`; the scan of
// log c_e from the bound up (alpha from held_alpha under the factors of the
// scan's previous point, from the top down where the factors move slowly);
// BOBYQA from the scan's best point when that fits better than the first
// search. Leaves the factors of the last point evaluated held.
OwnFactorMinimum FitWithOwnFactors(const OwnFactorProblem& problem,
                                   std::array<double, 2> start);

}  // namespace burrlab::analysis::detail

#endif  // BURRLAB_ANALYSIS_SRC_MODEL_GAP_OWN_FACTOR_FIT_H_
