// Bounded BOBYQA keeping the best point evaluated (box_search.h).
#include "burrlab/analysis/box_search.h"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "nlopt_ptr.h"

namespace burrlab::analysis {
namespace {

struct BoxTracker {
  const std::function<double(std::span<const double>)>* objective;
  std::size_t dimension;
  BoxMinimum best;
};

double EvaluateTracked(unsigned, const double* x, double*, void* data) {
  BoxTracker& t = *static_cast<BoxTracker*>(data);
  const std::span<const double> point(x, t.dimension);
  const double value = (*t.objective)(point);
  if (value < t.best.value) {
    t.best.value = value;
    t.best.x.assign(point.begin(), point.end());
  }
  return std::isfinite(value) ? value : 1e300;
}

}  // namespace

BoxMinimum MinimiseInBox(
    const std::function<double(std::span<const double>)>& objective,
    const BoxSearch& search, std::vector<double> start) {
  const std::size_t n = start.size();
  for (std::size_t k = 0; k < n; ++k) {
    start[k] = std::clamp(start[k], search.lower[k], search.upper[k]);
  }
  BoxTracker tracker{
      &objective, n, {start, std::numeric_limits<double>::infinity()}};
  detail::NloptPtr opt(nlopt_create(NLOPT_LN_BOBYQA, static_cast<unsigned>(n)));
  nlopt_set_lower_bounds(opt.get(), search.lower.data());
  nlopt_set_upper_bounds(opt.get(), search.upper.data());
  nlopt_set_min_objective(opt.get(), EvaluateTracked, &tracker);
  nlopt_set_xtol_abs1(opt.get(), search.xtol_abs);
  if (search.ftol_rel > 0.0) nlopt_set_ftol_rel(opt.get(), search.ftol_rel);
  nlopt_set_maxeval(opt.get(), search.max_evaluations);
  nlopt_set_initial_step(opt.get(), search.initial_step.data());
  double value = 0.0;
  nlopt_optimize(opt.get(), start.data(), &value);  // any stop: the best seen
  return tracker.best;
}

}  // namespace burrlab::analysis
