// The gap tests of the discover workflow on a fit's residuals: lack of fit
// against the replicates' pure error, curvature in log F projected off the
// model, runs of residual signs ordered by force, their family-wise
// combination with the library's focused test, and the smallest change the
// design detects.
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/non_central_f.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/statistics/runs_test.hpp>
#include <cmath>
#include <exception>
#include <numeric>
#include <string>
#include <vector>

#include "burrlab/analysis/model_gap/discover.h"
#include "model_gap/discover_internal.h"
#include "non_finite.h"

namespace burrlab::analysis::discover_internal {

using detail::kNaN;

namespace {

// Holm-adjusted p-values (NaN entries stay NaN and do not count).
std::vector<double> Holm(const std::vector<double>& p) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!std::isnan(p[i])) order.push_back(i);
  }
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return p[a] < p[b]; });
  std::vector<double> adjusted(p.size(), kNaN);
  const double m = static_cast<double>(order.size());
  double running = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    running = std::max(
        running, std::min(1.0, (m - static_cast<double>(k)) * p[order[k]]));
    adjusted[order[k]] = running;
  }
  return adjusted;
}

}  // namespace

void PureError(const Runs& runs, const std::vector<double>& values, double* ss,
               int* dof) {
  std::vector<double> sum(runs.levels, 0.0);
  std::vector<int> count(runs.levels, 0);
  for (int i = 0; i < runs.size(); ++i) {
    sum[runs.level[i]] += values[i];
    ++count[runs.level[i]];
  }
  *ss = 0.0;
  for (int i = 0; i < runs.size(); ++i) {
    const double d = values[i] - sum[runs.level[i]] / count[runs.level[i]];
    *ss += d * d;
  }
  *dof = runs.size() - runs.levels;
}

double FUpper(double f, double d1, double d2) {
  if (!(f > 0.0)) return 1.0;
  return boost::math::cdf(
      boost::math::complement(boost::math::fisher_f_distribution<>(d1, d2), f));
}

void CombineGapTests(GapTests* g, double level) {
  const std::vector<double> adjusted =
      Holm({g->lack_of_fit_p, g->curvature_p, g->runs_p});
  double omnibus = 1.0;
  for (double a : adjusted) {
    if (!std::isnan(a)) omnibus = std::min(omnibus, a);
  }
  g->holm_min_p = std::isnan(g->library_p)
                      ? omnibus
                      : std::min({1.0, omnibus / kOmnibusShare,
                                  g->library_p / (1.0 - kOmnibusShare)});
  g->detected = g->holm_min_p < level;
}

std::string DescribeGap(const GapTests& g) {
  std::string text;
  const auto add = [&](const char* name, double p) {
    if (std::isnan(p)) return;
    text += fmt::format("{}{} p = {:.2g}", text.empty() ? "" : ", ", name, p);
  };
  add("lack of fit", g.lack_of_fit_p);
  add("curvature", g.curvature_p);
  add("runs", g.runs_p);
  return fmt::format("{}; Holm p = {:.3g}", text, g.holm_min_p);
}

GapTests RunGapTests(const Runs& runs, const std::vector<double>& fitted,
                     const Eigen::MatrixXd& jacobian, double level) {
  const int n = runs.size();
  const int p = static_cast<int>(jacobian.cols());
  GapTests g;
  Eigen::VectorXd r(n);
  std::vector<double> residual(n);
  for (int i = 0; i < n; ++i) residual[i] = r(i) = runs.ln_v[i] - fitted[i];
  const double rss = r.squaredNorm();
  double ss_pe = 0.0;
  int dof_pe = 0;
  PureError(runs, residual, &ss_pe, &dof_pe);
  // Lack of fit (pure error from the replicates).
  const int dof_lof = runs.levels - p;
  g.lack_of_fit_p = kNaN;
  if (dof_pe >= 1 && dof_lof >= 1 && ss_pe > 0.0) {
    g.lack_of_fit_p =
        FUpper(((rss - ss_pe) / dof_lof) / (ss_pe / dof_pe), dof_lof, dof_pe);
  }
  // Curvature: x^2 and x^3 of the standardised log force, projected off the
  // model's Jacobian; an F test of their fit to the residuals.
  g.curvature_p = kNaN;
  const int q = std::min(2, runs.levels - p);
  if (q >= 1) {
    double mean = 0.0, var = 0.0;
    for (int i = 0; i < n; ++i) mean += std::log(runs.force_n[i]) / n;
    for (int i = 0; i < n; ++i) {
      var += std::pow(std::log(runs.force_n[i]) - mean, 2) / n;
    }
    const double sd = var > 0.0 ? std::sqrt(var) : 1.0;
    Eigen::MatrixXd extra(n, q);
    for (int i = 0; i < n; ++i) {
      const double x = (std::log(runs.force_n[i]) - mean) / sd;
      extra(i, 0) = x * x;
      if (q > 1) extra(i, 1) = x * x * x;
    }
    const Eigen::MatrixXd basis = ColumnBasis(jacobian);
    for (int c = 0; c < q; ++c) extra.col(c) = Project(basis, extra.col(c));
    const Eigen::MatrixXd extra_basis = ColumnBasis(extra);
    const int rank = static_cast<int>(extra_basis.cols());
    if (rank >= 1) {
      const double ss_q = (extra_basis.transpose() * r).squaredNorm();
      double sigma2 = 0.0;
      int dof = 0;
      if (dof_pe >= 2 && ss_pe > 0.0) {
        sigma2 = ss_pe / dof_pe;
        dof = dof_pe;
      } else {
        dof = n - p - rank;
        sigma2 = dof > 0 ? (rss - ss_q) / dof : 0.0;
      }
      if (dof >= 1 && sigma2 > 0.0) {
        g.curvature_p = FUpper((ss_q / rank) / sigma2, rank, dof);
      }
    }
  }
  // Runs of residual signs ordered by force (too few runs: a trend).
  g.runs_p = kNaN;
  if (n >= 6) {
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return runs.force_n[a] < runs.force_n[b];
    });
    std::vector<double> sorted;
    for (int i : order) sorted.push_back(residual[i]);
    try {
      const auto [z, two_sided] =
          boost::math::statistics::runs_above_and_below_threshold(sorted, 0.0);
      (void)two_sided;
      if (std::isfinite(z)) {
        g.runs_p = boost::math::cdf(boost::math::normal_distribution<>(), z);
      }
    } catch (const std::exception&) {
      g.runs_p = kNaN;
    }
  }
  g.library_p = kNaN;
  CombineGapTests(&g, level);
  return g;
}

double DetectableRms(const Runs& runs, int parameters, double sigma,
                     double level) {
  const int d1 = runs.levels - parameters, d2 = runs.size() - runs.levels;
  if (d1 < 1 || d2 < 1 || !(sigma > 0.0)) return kNaN;
  const double critical = boost::math::quantile(
      boost::math::fisher_f_distribution<>(d1, d2), 1.0 - level);
  const auto power = [&](double lambda) {
    return boost::math::cdf(boost::math::complement(
        boost::math::non_central_f_distribution<>(d1, d2, lambda), critical));
  };
  double lo = 0.0, hi = 1.0;
  while (power(hi) < 0.5 && hi < 1e6) hi *= 2.0;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (power(mid) < 0.5 ? lo : hi) = mid;
  }
  // lambda = sum_i delta_i^2 / sigma^2 = n rms^2 / sigma^2.
  return sigma * std::sqrt(0.5 * (lo + hi) / runs.size());
}

GapTests Workflow::Gap(const Model& m) const {
  return RunGapTests(runs_, Predict(runs_, m.active, m.point),
                     Jacobian(runs_, m.active, m.point), options_.test_level);
}

}  // namespace burrlab::analysis::discover_internal
