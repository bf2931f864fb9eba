// The attribution of a gap to the effects of the library: each effect's
// projected signature, identifiability index and projected score test, its
// augmented fit and likelihood ratio, the single-step max-T adjustment over
// the effects, and the alias set of the effect a step adds.
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
#include <optional>
#include <span>
#include <string>
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

// The other shapes of a family are fitted when its first shape's likelihood
// ratio has p below this.
constexpr double kShapeGate = 0.1;

}  // namespace

AttributionRound Workflow::Attribute(const Model& current,
                                     int* progress_done) const {
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
  AttributionRound round;
  const double c_e = std::exp(current.point.ln_c_e);
  const double alpha = std::exp(current.point.ln_alpha);
  // One candidate per family: each of its variants (shapes) is scored and
  // fitted, and the best fit speaks for the family.
  const std::span<const sim::EffectSpec> library = sim::EffectLibrary();
  // Each family's test is its first shape's (and that of a shape on the
  // other side of its null, which the first cannot stand in for): whether
  // there is a gap, and which families explain it, is decided on these alone
  // (a search over shapes would raise the null's false names); the other
  // shapes then compete to describe the gap the family explains.
  struct Tested {
    double lr = 0.0;
    Eigen::VectorXd signature;
    bool testable = false;
    std::size_t family = 0;  // index into round.effects
  };
  std::vector<Tested> tested;
  for (const sim::EffectSpec& head : library) {
    if (head.trace_only) continue;           // v(F) cannot see it (trace_gap.h)
    if (head.Family() != head.id) continue;  // a variant: with its family
    bool used = false;
    for (const ActiveEffect& a : current.active) {
      used |= a.spec->Family() == head.id;
    }
    if (used) continue;
    if (options_.progress) {
      options_.progress((*progress_done)++, total_tasks_,
                        fmt::format("attributing: {}", head.id));
    }
    struct Variant {
      EffectAttribution e;
      Model fit;
      Eigen::VectorXd signature;
    };
    std::vector<Variant> variants;
    for (const sim::EffectSpec& spec : library) {
      if (spec.Family() != head.id) continue;
      // The other shapes only where the first shows something (likelihood
      // ratio p < kShapeGate): a family that explains nothing in its first
      // shape is not searched further, which keeps the null's false names
      // and the cost where they were.
      if (&spec != &head && !spec.own_test &&
          !(variants.front().e.lr_p < kShapeGate)) {
        continue;
      }
      Variant var;
      EffectAttribution& e = var.e;
      e.id = head.id;
      e.variant = spec.id;
      e.shape = spec.shape;
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
      Eigen::VectorXd sig(n);
      for (int i = 0; i < n; ++i) {
        sig(i) = std::isfinite(y1[i]) ? (y1[i] - y0[i]) / u_small : 0.0;
      }
      const Eigen::VectorXd s_perp = Project(basis, sig);
      const double norm = sig.norm();
      e.identifiability = norm > 0.0 ? s_perp.norm() / norm : 0.0;
      e.absorbed = e.identifiability < options_.absorbed_index;
      var.signature = s_perp;
      if (!e.absorbed && sigma > 0.0) {
        e.score_z = s_perp.dot(r) / (sigma * s_perp.norm());
        e.score_p = boost::math::cdf(boost::math::complement(
            boost::math::students_t_distribution<>(dof), e.score_z));
      }
      Model& fit = var.fit;
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
      variants.push_back(std::move(var));
    }
    // The best-fitting shape speaks for the family (the first on ties and
    // when all are absorbed); the others that fit alike leave it open.
    std::size_t best = 0;
    for (std::size_t v = 1; v < variants.size(); ++v) {
      if (variants[v].fit.rss < variants[best].fit.rss) best = v;
    }
    // The first shape, and each shape tested in its own right (the other
    // side of the family's null).
    for (std::size_t v = 0; v < variants.size(); ++v) {
      const sim::EffectSpec* spec = sim::FindEffect(variants[v].e.variant);
      if (v > 0 && !(spec != nullptr && spec->own_test)) continue;
      tested.push_back(
          {variants[v].e.lr, variants[v].signature,
           !variants[v].e.absorbed && variants[v].signature.norm() > 0.0,
           round.effects.size()});
    }
    Variant chosen = variants[best];
    for (std::size_t v = 0; v < variants.size(); ++v) {
      if (v == best || chosen.e.absorbed) continue;
      if (variants[v].e.aicc - chosen.e.aicc < 2.0) {
        chosen.e.shape_determined = false;
        chosen.e.alike_shapes.push_back(std::string(variants[v].e.shape));
      }
    }
    round.signatures.push_back(chosen.signature);
    round.fits.push_back(std::move(chosen.fit));
    round.effects.push_back(std::move(chosen.e));
  }
  // Family-wise: max-T over the testable families' first shapes (and the
  // shapes tested in their own right), correlated through their projected
  // signatures; a family's p is the smallest of its entries'.
  std::vector<std::size_t> testable;
  for (std::size_t i = 0; i < tested.size(); ++i) {
    if (tested[i].testable) testable.push_back(i);
  }
  const int m = static_cast<int>(testable.size());
  Eigen::MatrixXd corr(m, m);
  std::vector<double> lr(m);
  for (int a = 0; a < m; ++a) {
    const Eigen::VectorXd& sa = tested[testable[a]].signature;
    lr[a] = tested[testable[a]].lr;
    for (int b = 0; b < m; ++b) {
      const Eigen::VectorXd& sb = tested[testable[b]].signature;
      corr(a, b) = sa.dot(sb) / (sa.norm() * sb.norm());
    }
  }
  const std::vector<double> adjusted =
      MaxTAdjusted(lr, corr, pure_error ? dof : 0);
  for (EffectAttribution& e : round.effects) e.lr_p_adjusted = 1.0;
  for (int a = 0; a < m; ++a) {
    double& family_p = round.effects[tested[testable[a]].family].lr_p_adjusted;
    family_p = std::min(family_p, adjusted[a]);
  }
  return round;
}

std::vector<std::string> AliasSet(const Workflow& flow, const Model& current,
                                  const AttributionRound& round,
                                  std::size_t best,
                                  const std::vector<std::size_t>& candidates) {
  const Runs& runs = flow.runs();
  const DiscoverOptions& options = flow.options();
  const int n = runs.size();
  const std::vector<Model>& fits = round.fits;
  const std::vector<Eigen::VectorXd>& sigs = round.signatures;
  // Their local signatures may be nearly parallel, or their fitted
  // contributions (augmented minus current predictions, projected off the
  // current Jacobian: for a capped effect such as the power limit the local
  // signature sits at the top force only) are.
  std::vector<std::string> alias = {round.effects[best].id};
  const std::vector<double> y_now =
      Predict(runs, current.active, current.point);
  const Eigen::MatrixXd basis =
      ColumnBasis(Jacobian(runs, current.active, current.point));
  const auto contribution = [&](std::size_t k) {
    const std::vector<double> y = Predict(runs, fits[k].active, fits[k].point);
    Eigen::VectorXd d(n);
    for (int i = 0; i < n; ++i) {
      d(i) = std::isfinite(y[i]) ? y[i] - y_now[i] : 0.0;
    }
    return Eigen::VectorXd(Project(basis, d));
  };
  const Eigen::VectorXd c_best = contribution(best);
  // Separation: what a test between the best and effect j could see. The
  // other effect, fitted (with its own c_e and alpha, and the effects already
  // added) to a model's noise-free predictions, leaves a remainder; over the
  // noise variance it is the noncentrality of a test between the two on this
  // design were the best the truth; below options.alias_separation the design
  // would not tell them apart. (The reverse, the best fitted to j's model, was
  // tried: it did not change the second set of the two-effect test's seed 6.)
  double sigma2 = 0.0;
  {
    std::vector<double> residual(n);
    for (int i = 0; i < n; ++i) residual[i] = runs.ln_v[i] - y_now[i];
    double ss_pe = 0.0;
    int dof_pe = 0;
    PureError(runs, residual, &ss_pe, &dof_pe);
    sigma2 = dof_pe >= 2 && ss_pe > 0.0 ? ss_pe / dof_pe
                                        : fits[best].rss / std::max(1, n - 3);
  }
  // The current model (base plus the effects already added) refitted to
  // `target`'s predictions, then with `spec` added: the remainder over
  // sigma^2.
  struct Pseudo {
    Runs runs;
    std::optional<Model> current;
  };
  const auto make_pseudo = [&](const Model& target) {
    Pseudo ps{runs, std::nullopt};
    ps.runs.ln_v = target.active.empty()
                       ? y_now
                       : Predict(runs, target.active, target.point);
    const Workflow flow_t(ps.runs, options);
    const Result<Point> b = flow_t.BaseFit({});
    if (b.ok()) {
      ps.current = current.active.empty()
                       ? Model{{}, *b, Rss(ps.runs, {}, *b, {})}
                       : flow_t.FitAugmented(current.active, *b, {});
    }
    return ps;
  };
  const auto remainder = [&](const Pseudo& ps, const sim::EffectSpec& spec) {
    if (!ps.current || !(sigma2 > 0.0)) return kInf;
    const Workflow flow_t(ps.runs, options);
    std::vector<ActiveEffect> active = ps.current->active;
    active.push_back(ScaleEffect(spec, ps.runs,
                                 std::exp(ps.current->point.ln_c_e),
                                 std::exp(ps.current->point.ln_alpha)));
    const Model m = flow_t.FitAugmented(active, ps.current->point, {});
    return std::min(m.rss, ps.current->rss) / sigma2;
  };
  const Pseudo as_best = make_pseudo(fits[best]);
  const auto separation = [&](std::size_t j) {
    return remainder(as_best, *fits[j].active.back().spec);
  };
  for (std::size_t j = 0; j < round.effects.size(); ++j) {
    if (j == best || round.effects[j].absorbed) continue;
    if (separation(j) < options.alias_separation) {
      alias.push_back(round.effects[j].id);
      continue;
    }
    if (std::find(candidates.begin(), candidates.end(), j) ==
        candidates.end()) {
      continue;
    }
    const double denom = sigs[best].norm() * sigs[j].norm();
    const Eigen::VectorXd c_j = contribution(j);
    const double fitted_denom = c_best.norm() * c_j.norm();
    const double cosine = std::max(
        denom > 0.0 ? std::abs(sigs[best].dot(sigs[j])) / denom : 0.0,
        fitted_denom > 0.0 ? std::abs(c_best.dot(c_j)) / fitted_denom : 0.0);
    if (cosine > options.alias_cosine ||
        round.effects[j].aicc - round.effects[best].aicc < 2.0) {
      alias.push_back(round.effects[j].id);
    }
  }
  return alias;
}

}  // namespace burrlab::analysis::discover_internal
