// The attribution of a gap to the effects of the library: each effect's
// projected signature, identifiability index and projected score test, its
// augmented fit and likelihood ratio, and the single-step max-T adjustment
// over the effects.
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/random/chi_squared_distribution.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <cstddef>
#include <vector>

#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/sim/effects.h"
#include "model_gap/discover_internal.h"
#include "non_finite.h"

namespace burrlab::analysis::discover_internal {

using detail::kInf;

namespace {

// p of the likelihood ratio for one parameter on its null boundary: the
// 50:50 mixture of chi^2_0 and chi^2_1 (Self & Liang 1987).
double ChiBarP(double lr) {
  if (!(lr > 0.0)) return 1.0;
  return 0.5 * boost::math::cdf(boost::math::complement(
                   boost::math::chi_squared_distribution<>(1.0), lr));
}

// Single-step max-T adjusted p-values (Westfall & Young 1993) of one-sided
// likelihood-ratio tests whose signed roots are jointly normal under the null
// with correlation `corr` (the cosines of the effects' projected signatures):
// p_k = P(max_j max(z_j, 0) / s >= sqrt(LR_k)), z ~ N(0, corr), s = 1 or,
// when the statistics share a variance estimate with `dof` > 0 degrees of
// freedom, s^2 ~ chi^2_dof / dof (multivariate t), by Monte Carlo
// with a fixed seed so a report is reproducible. Near-aliased effects test
// nearly the same thing, so this is much less conservative than Holm. An
// LR of 0 gets 1.
std::vector<double> MaxTAdjusted(const std::vector<double>& lr,
                                 const Eigen::MatrixXd& corr, int dof) {
  const int m = static_cast<int>(lr.size());
  std::vector<double> adjusted(m, 1.0);
  if (m == 0) return adjusted;
  // A factor L with L L^T = corr; the eigen-decomposition tolerates a
  // rank-deficient (exactly aliased) matrix.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(corr);
  const Eigen::VectorXd values = eig.eigenvalues().cwiseMax(0.0);
  const Eigen::MatrixXd factor =
      eig.eigenvectors() * values.cwiseSqrt().asDiagonal();
  constexpr int kDraws = 20000;
  boost::random::mt19937_64 engine(20261124);
  boost::random::normal_distribution<double> normal;
  boost::random::chi_squared_distribution<double> chi2(dof > 0 ? dof : 1);
  std::vector<int> exceed(m, 0);
  std::vector<double> roots(m);
  for (int k = 0; k < m; ++k) roots[k] = std::sqrt(std::max(lr[k], 0.0));
  Eigen::VectorXd e(m);
  for (int d = 0; d < kDraws; ++d) {
    for (int k = 0; k < m; ++k) e(k) = normal(engine);
    const Eigen::VectorXd z = factor * e;
    const double scale = dof > 0 ? std::sqrt(chi2(engine) / dof) : 1.0;
    const double top = std::max(0.0, z.maxCoeff()) / scale;
    for (int k = 0; k < m; ++k) exceed[k] += top >= roots[k];
  }
  for (int k = 0; k < m; ++k) {
    adjusted[k] = roots[k] > 0.0 ? (exceed[k] + 1.0) / (kDraws + 1.0) : 1.0;
  }
  return adjusted;
}

}  // namespace

std::vector<EffectAttribution> Workflow::Attribute(
    const Model& current, std::vector<Model>* fits,
    std::vector<Eigen::VectorXd>* sigs, int* progress_done) const {
  const int n = runs_.size();
  const std::vector<double> y0 = Predict(runs_, current.active, current.point);
  Eigen::VectorXd r(n);
  for (int i = 0; i < n; ++i) r(i) = runs_.ln_v[i] - y0[i];
  const Eigen::MatrixXd basis =
      ColumnBasis(Jacobian(runs_, current.active, current.point));
  // Noise scale: pure error when the replicates give it.
  std::vector<double> residual(r.data(), r.data() + n);
  double ss_pe = 0.0;
  int dof_pe = 0;
  PureError(runs_, residual, &ss_pe, &dof_pe);
  const int p = 2 + static_cast<int>(current.active.size());
  double sigma = 0.0;
  int dof = 0;
  const bool pure_error = dof_pe >= 2 && ss_pe > 0.0;
  if (pure_error) {
    sigma = std::sqrt(ss_pe / dof_pe);
    dof = dof_pe;
  } else {
    dof = std::max(1, n - p);
    sigma = std::sqrt(current.rss / dof);
  }
  std::vector<EffectAttribution> out;
  fits->clear();
  sigs->clear();
  const double c_e = std::exp(current.point.ln_c_e);
  const double alpha = std::exp(current.point.ln_alpha);
  for (const sim::EffectSpec& spec : sim::EffectLibrary()) {
    if (spec.trace_only) continue;  // v(F) cannot see it (trace_gap.h)
    bool used = false;
    for (const ActiveEffect& a : current.active) used |= a.spec == &spec;
    if (used) continue;
    if (options_.progress) {
      options_.progress((*progress_done)++, total_tasks_,
                        fmt::format("attributing: {}", spec.id));
    }
    EffectAttribution e;
    e.id = spec.id;
    std::vector<ActiveEffect> active = current.active;
    active.push_back(ScaleEffect(spec, runs_, c_e, alpha));
    const std::size_t k = active.size() - 1;
    Point at = current.point;
    at.u.push_back(0.0);
    // Signature: the change of the fit per unit u at a small strength
    // (2 % at most), a secant for effects with a kink such as the cap.
    const double u_small = UForChange(runs_, active, at, k, 0.02);
    Point moved = at;
    moved.u[k] = u_small;
    const std::vector<double> y1 = Predict(runs_, active, moved);
    Eigen::VectorXd s(n);
    for (int i = 0; i < n; ++i) {
      s(i) = std::isfinite(y1[i]) ? (y1[i] - y0[i]) / u_small : 0.0;
    }
    const Eigen::VectorXd s_perp = Project(basis, s);
    const double norm = s.norm();
    e.identifiability = norm > 0.0 ? s_perp.norm() / norm : 0.0;
    e.absorbed = e.identifiability < options_.absorbed_index;
    sigs->push_back(s_perp);
    if (!e.absorbed && sigma > 0.0) {
      e.score_z = s_perp.dot(r) / (sigma * s_perp.norm());
      e.score_p = boost::math::cdf(boost::math::complement(
          boost::math::students_t_distribution<>(dof), e.score_z));
    }
    Model fit;
    if (!e.absorbed) {
      fit = FitAugmented(active, current.point, {});
      if (fit.rss > current.rss) {  // never worse than the nested model
        fit.point = at;
        fit.rss = current.rss;
      }
      if (pure_error) {
        // The likelihood ratio with the variance held at the replicates'
        // pure-error estimate, which no model touches: the drop in RSS
        // over sigma^2, F(1, dof) on the boundary's 50:50 mixture. (With
        // the variance profiled out, n ln(RSS_0 / RSS_1) gives away about
        // a fifth of the signal at these sizes.)
        e.lr = std::max(current.rss - fit.rss, 0.0) / (sigma * sigma);
        e.lr_p = e.lr > 0.0 ? 0.5 * FUpper(e.lr, 1.0, dof) : 1.0;
      } else {
        e.lr = n * std::log(current.rss / std::max(fit.rss, 1e-300));
        e.lr_p = ChiBarP(e.lr);
      }
      e.aicc = Aicc(fit.rss, n, 2 + static_cast<int>(active.size()));
      e.value =
          sim::ParameterAtStrength(spec, Strength(active[k], fit.point, k));
    } else {
      fit.active = active;
      fit.point = at;
      fit.rss = current.rss;
      e.aicc = kInf;
      e.value = spec.null_value;
    }
    fits->push_back(fit);
    out.push_back(e);
  }
  // Family-wise: max-T over the testable effects, correlated through
  // their projected signatures.
  std::vector<std::size_t> testable;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!out[i].absorbed && (*sigs)[i].norm() > 0.0) testable.push_back(i);
  }
  const int m = static_cast<int>(testable.size());
  Eigen::MatrixXd corr(m, m);
  std::vector<double> lr(m);
  for (int a = 0; a < m; ++a) {
    const Eigen::VectorXd& sa = (*sigs)[testable[a]];
    lr[a] = out[testable[a]].lr;
    for (int b = 0; b < m; ++b) {
      const Eigen::VectorXd& sb = (*sigs)[testable[b]];
      corr(a, b) = sa.dot(sb) / (sa.norm() * sb.norm());
    }
  }
  const std::vector<double> adjusted =
      MaxTAdjusted(lr, corr, pure_error ? dof : 0);
  for (EffectAttribution& e : out) e.lr_p_adjusted = 1.0;
  for (int a = 0; a < m; ++a) out[testable[a]].lr_p_adjusted = adjusted[a];
  return out;
}

}  // namespace burrlab::analysis::discover_internal
