// A bounded derivative-free minimisation (NLopt's BOBYQA, Powell 2009) that
// returns the best point it evaluated. BOBYQA can stop above its own best
// evaluation on a kinked or noisy objective (a power limit's RSS, a refreshed
// transient factor, a likelihood estimated by simulation), so every search
// that uses it keeps the best point seen rather than trusting the stopping
// point.
#ifndef BURRLAB_ANALYSIS_BOX_SEARCH_H_
#define BURRLAB_ANALYSIS_BOX_SEARCH_H_

#include <functional>
#include <span>
#include <vector>

namespace burrlab::analysis {

struct BoxSearch {
  std::vector<double> lower, upper;  // the box; equal bounds fix a coordinate
  std::vector<double> initial_step;
  double xtol_abs = 1e-6;  // on every coordinate
  double ftol_rel = 0.0;   // 0: not used
  int max_evaluations = 300;
};

struct BoxMinimum {
  std::vector<double> x;  // the best point evaluated (the start if none)
  double value = 0.0;     // the objective there (+inf if never finite)
};

// Minimises `objective` over the box from `start` (clamped into it). A value
// that is not finite counts as worse than any finite one.
BoxMinimum MinimiseInBox(
    const std::function<double(std::span<const double>)>& objective,
    const BoxSearch& search, std::vector<double> start);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_BOX_SEARCH_H_
