// Observer-population fits over virtual studies: moments by bisection, then
// maximum likelihood with profile intervals.
#include "studies/observer_fit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "burrlab/analysis/box_search.h"
#include "burrlab/analysis/published_scores.h"
#include "studies/parallel_for.h"

namespace burrlab::runner {
namespace {

struct Moments {
  double mean = 0.0;
  double sd = 0.0;
  std::vector<double> distribution;  // share of subjects scoring 0..trials
};

// Decimals of a number as written ("9.3": 1, "12": 0).
int DecimalsOf(std::string_view value) {
  const std::size_t dot = value.find('.');
  if (dot == std::string_view::npos) return 0;
  std::size_t digits = 0;
  while (dot + 1 + digits < value.size() &&
         std::isdigit(static_cast<unsigned char>(value[dot + 1 + digits]))) {
    ++digits;
  }
  return static_cast<int>(digits);
}

class PopulationFitter {
 public:
  PopulationFitter(const protocols::Protocol& protocol,
                   const ObserverFitOptions& options, CuePool& pool)
      : protocol_(protocol), options_(options), pool_(pool) {}

  // Mean and SD of the block's scores of a population (W, spread).
  Result<Moments> Evaluate(double weber, double spread) {
    weber = std::clamp(weber, kMinWeber, kMaxWeber);  // exp(ln W) rounding
    VirtualStudyOptions o;
    o.subjects = options_.virtual_subjects;
    o.seed = options_.seed;
    o.observer = options_.base;
    o.observer.weber_stiffness = weber;
    o.observer.weber_removal = weber;
    // Only the block is simulated, so only its cue's values matter.
    o.spread_stiffness = spread;
    o.spread_removal = spread;
    o.only_block = block_.empty() ? options_.block : block_;
    // Once the block is known, its trials are recorded and every later
    // population answers them again (RecordedBlock: exactly the same
    // studies, without the protocol engine); a block that adapts to the
    // answers is run afresh each time.
    Result<std::vector<VirtualBlock>> study = std::vector<VirtualBlock>{};
    if (record_.has_value()) {
      Result<VirtualBlock> b = record_->Answer(o);
      if (!b.ok()) return b.error();
      study->push_back(std::move(*b));
    } else if (!o.only_block.empty() && !record_failed_) {
      Result<RecordedBlock> r =
          RecordedBlock::Record(protocol_, o, pool_, &*study);
      if (r.ok()) {
        record_ = std::move(*r);
      } else {
        record_failed_ = true;
        study = RunVirtualStudy(protocol_, o, pool_);
      }
    } else {
      study = RunVirtualStudy(protocol_, o, pool_);
    }
    if (!study.ok()) return study.error();
    ++evaluations_;
    const VirtualBlock* block = nullptr;
    for (const VirtualBlock& b : *study) {
      if (options_.block.empty() || b.block == options_.block) {
        block = &b;
        break;
      }
    }
    if (block == nullptr) {
      std::string names;
      for (const VirtualBlock& b : *study) {
        names += (names.empty() ? "" : ", ") + b.block;
      }
      return Error{fmt::format(
          "the protocol has no scored block \"{}\" (scored blocks: {})",
          options_.block, names.empty() ? "none" : names)};
    }
    block_ = block->block;
    trials_ = block->trials.front();
    for (int t : block->trials) {
      if (t != trials_) {
        return Error{fmt::format(
            "block \"{}\" gives subjects different numbers of trials: a "
            "score out of a fixed n is needed",
            block_)};
      }
    }
    double sum = 0.0, sum2 = 0.0;
    for (int c : block->correct) {
      sum += c;
      sum2 += static_cast<double>(c) * c;
    }
    const double n = static_cast<double>(block->correct.size());
    Moments m;
    m.mean = sum / n;
    m.sd = n > 1 ? std::sqrt(std::max(0.0, (sum2 - sum * sum / n) / (n - 1)))
                 : 0.0;
    m.distribution.assign(static_cast<std::size_t>(trials_) + 1, 0.0);
    for (int c : block->correct) {
      m.distribution[static_cast<std::size_t>(c)] += 1.0 / n;
    }
    return m;
  }

  // The W of the highest mean score at `spread`, and that mean. The score
  // is not monotone in W: a very sharp observer (its criterion scales with
  // its own noise, §13.5.1's differencing rule) feels the variability between
  // renderings of one material and calls identical pairs "different", so
  // the mean rises from the smallest W to a peak and falls after it. A grid
  // over ln W, then golden-section steps around the best grid point.
  Result<std::pair<double, double>> Peak(double spread) {
    if (auto it = peaks_.find(spread); it != peaks_.end()) return it->second;
    constexpr int kGrid = 9;
    const double lo = std::log(kMinWeber), hi = std::log(kMaxWeber);
    const double step = (hi - lo) / (kGrid - 1);
    int best = 0;
    double best_mean = -1.0;
    for (int i = 0; i < kGrid; ++i) {
      Result<Moments> m = Evaluate(std::exp(lo + step * i), spread);
      if (!m.ok()) return m.error();
      if (m->mean > best_mean) {
        best_mean = m->mean;
        best = i;
      }
    }
    double a = lo + step * std::max(0, best - 1);
    double b = lo + step * std::min(kGrid - 1, best + 1);
    double at = lo + step * best;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int i = 0; i < 4 && b - a > 1e-3; ++i) {
      const double c = b - g * (b - a), d = a + g * (b - a);
      Result<Moments> mc = Evaluate(std::exp(c), spread);
      if (!mc.ok()) return mc.error();
      Result<Moments> md = Evaluate(std::exp(d), spread);
      if (!md.ok()) return md.error();
      if (mc->mean >= md->mean) {
        b = d;
        if (mc->mean > best_mean) {
          best_mean = mc->mean;
          at = c;
        }
      } else {
        a = c;
        if (md->mean > best_mean) {
          best_mean = md->mean;
          at = d;
        }
      }
    }
    const std::pair<double, double> peak{std::exp(at), best_mean};
    peaks_.emplace(spread, peak);
    return peak;
  }

  // The W above the peak whose mean score is `target` (the mean falls as W
  // grows there); the peak's W or the search limit when the target is out of
  // reach, with `*limit` set.
  Result<double> SolveWeber(double target, double spread, bool* limit) {
    Result<std::pair<double, double>> peak = Peak(spread);
    if (!peak.ok()) return peak.error();
    *limit = false;
    if (peak->second <= target) {
      *limit = true;
      return peak->first;
    }
    double lo = std::log(peak->first), hi = std::log(kMaxWeber);
    Result<Moments> at_hi = Evaluate(kMaxWeber, spread);
    if (!at_hi.ok()) return at_hi.error();
    if (at_hi->mean >= target) {
      *limit = true;
      return kMaxWeber;
    }
    for (int i = 0; i < 16; ++i) {
      const double mid = 0.5 * (lo + hi);
      Result<Moments> m = Evaluate(std::exp(mid), spread);
      if (!m.ok()) return m.error();
      (m->mean > target ? lo : hi) = mid;
    }
    return std::exp(0.5 * (lo + hi));
  }

  // ln P(n subjects of the population (e^ln_w, spread) report the observed
  // mean +- SEM to its rounding), from the virtual study's score
  // distribution with kPseudoSubjects spread evenly over the scores; -inf
  // where the publication is impossible.
  Result<double> LogLikelihood(double ln_w, double spread,
                               const ObservedGroup& observed) {
    const std::pair<double, double> key{ln_w, spread};
    if (auto it = log_likelihoods_.find(key); it != log_likelihoods_.end()) {
      return it->second;
    }
    Result<Moments> m = Evaluate(std::exp(ln_w), spread);
    if (!m.ok()) return m.error();
    // Nearby populations often answer exactly alike (common random numbers).
    if (auto it = by_distribution_.find(m->distribution);
        it != by_distribution_.end()) {
      log_likelihoods_.emplace(key, it->second);
      return it->second;
    }
    const double subjects = options_.virtual_subjects;
    const double scores = static_cast<double>(m->distribution.size());
    std::vector<double> p;
    double total = 0.0;
    for (double share : m->distribution) {
      p.push_back((share * subjects + kPseudoSubjects / scores) /
                  (subjects + kPseudoSubjects));
      total += p.back();
    }
    for (double& x : p) x /= total;  // exact sum for the check
    double ll = 0.0;
    if (!observed.scores.empty()) {
      // Each subject's score, independent draws from the distribution.
      for (int score : observed.scores) {
        const auto k = static_cast<std::size_t>(score);
        if (score < 0 || k >= p.size()) {
          return Error{fmt::format("a score of {} is outside 0 to {}", score,
                                   p.size() - 1)};
        }
        ll += std::log(p[k]);
      }
    } else {
      Result<double> probability = analysis::PublishedScoresProbability(
          p, {observed.mean, observed.sem, observed.n,
              std::min(observed.decimals, 6)});
      if (!probability.ok()) return probability.error();
      ll = *probability > 0.0 ? std::log(*probability)
                              : -std::numeric_limits<double>::infinity();
    }
    log_likelihoods_.emplace(key, ll);
    by_distribution_.emplace(m->distribution, ll);
    return ll;
  }

  const std::string& block() const { return block_; }
  int trials() const { return trials_; }
  int evaluations() const { return evaluations_; }

 private:
  const protocols::Protocol& protocol_;
  const ObserverFitOptions& options_;
  CuePool& pool_;
  std::string block_;
  int trials_ = 0;
  int evaluations_ = 0;
  std::map<double, std::pair<double, double>> peaks_;  // spread -> (W, mean)
  std::map<std::pair<double, double>, double> log_likelihoods_;
  std::map<std::vector<double>, double> by_distribution_;
  std::optional<RecordedBlock> record_;
  bool record_failed_ = false;
};

// Half the 95 % point of chi-square with one degree of freedom: a profile
// interval holds the values whose profile log likelihood is within it of the
// maximum.
constexpr double kProfileDrop = 0.5 * 3.841458820694124;

// The maximum-likelihood refinement of a moment fit: (ln W, spread)
// maximising LogLikelihood by BOBYQA from the moment fit, then each
// parameter's profile interval (the other re-maximised at every point).
class LikelihoodFit {
 public:
  LikelihoodFit(PopulationFitter& fitter, const ObservedGroup& observed,
                bool fit_spread)
      : fitter_(fitter), observed_(observed), fit_spread_(fit_spread) {}

  // Minus the log likelihood (+inf where impossible); the first error is
  // kept in error_ and every later call returns +inf.
  double Cost(double ln_w, double spread) {
    if (error_.has_value()) return kInf;
    Result<double> ll = fitter_.LogLikelihood(ln_w, spread, observed_);
    if (!ll.ok()) {
      error_ = ll.error();
      return kInf;
    }
    if (*ll > best_ll_) {
      best_ll_ = *ll;
      best_ = {ln_w, spread};
    }
    return -*ll;
  }

  // The maximum from the start; false with error() on an error.
  bool Maximise(double ln_w, double spread) {
    analysis::BoxSearch box;
    box.lower = {kLnMin, 0.0};
    box.upper = {kLnMax, fit_spread_ ? kMaxWeberSpread : 0.0};
    box.initial_step = {0.15, fit_spread_ ? 0.1 : 0.0};
    box.xtol_abs = 2e-3;
    box.max_evaluations = fit_spread_ ? 60 : 30;
    if (!fit_spread_) {
      box.lower.pop_back();
      box.upper.pop_back();
      box.initial_step.pop_back();
    }
    Cost(ln_w, spread);
    analysis::MinimiseInBox(
        [&](std::span<const double> x) {
          return Cost(x[0], fit_spread_ ? x[1] : 0.0);
        },
        box,
        fit_spread_ ? std::vector<double>{ln_w, spread}
                    : std::vector<double>{ln_w});
    return !error_.has_value();
  }

  // The profile log likelihood at ln W (spread re-maximised) or at a spread
  // (ln W re-maximised), starting the inner search at the best point.
  // Each inner search starts where the previous one of the same profile
  // ended (the profile is walked step by step); StartProfiles() resets that
  // to the best point.
  double ProfileAtWeber(double ln_w) {
    if (!fit_spread_) return -Cost(ln_w, 0.0);
    return -InnerMinimum([&](double s) { return Cost(ln_w, s); },
                         &spread_start_, 0.0, kMaxWeberSpread, 0.1);
  }
  double ProfileAtSpread(double spread) {
    return -InnerMinimum([&](double l) { return Cost(l, spread); },
                         &weber_start_, kLnMin, kLnMax, 0.15);
  }
  void StartProfiles() {
    weber_start_ = best_.first;
    spread_start_ = best_.second;
  }

  // One side of a profile interval: from `at` (the maximum) towards `limit`,
  // the point where `profile` falls kProfileDrop below `peak`: doubling steps
  // until it does, then bisection. False: it does not fall that far before
  // the limit (*bound is the limit).
  bool Bound(const std::function<double(double)>& profile, double at,
             double peak, double limit, double first_step, double* bound) {
    const double direction = limit > at ? 1.0 : -1.0;
    const auto toward_limit = [&](double x) {
      return direction > 0 ? std::min(x, limit) : std::max(x, limit);
    };
    // Outward: each step aims where a quadratic profile through the peak and
    // the last point would reach the drop (at least 1.5 times as far, at
    // most 4 times), until the drop is passed or the limit reached.
    double inside = at, inside_drop = 0.0;
    double x = toward_limit(at + direction * first_step);
    double outside = x, outside_drop = 0.0;
    bool passed = false;
    for (int i = 0; i < 10; ++i) {
      const double drop = peak - profile(x);
      if (drop > kProfileDrop) {
        outside = x;
        outside_drop = drop;
        passed = true;
        break;
      }
      inside = x;
      inside_drop = drop;
      if (x == limit) break;
      const double reach = std::abs(x - at);
      const double factor =
          drop > 1e-6
              ? std::clamp(std::sqrt(kProfileDrop / drop) * 1.1, 1.5, 4.0)
              : 4.0;
      x = toward_limit(at + direction * reach * factor);
    }
    if (!passed) {
      *bound = limit;
      return false;
    }
    // Inward: regula falsi on the drop (kept off the bracket's ends, so
    // neither end sticks), to within 0.05 of it.
    for (int j = 0; j < 6; ++j) {
      const double t =
          (kProfileDrop - inside_drop) / (outside_drop - inside_drop);
      const double mid = inside + std::clamp(t, 0.1, 0.9) * (outside - inside);
      const double drop = peak - profile(mid);
      if (std::abs(drop - kProfileDrop) < 0.05) {
        *bound = mid;
        return true;
      }
      if (drop > kProfileDrop) {
        outside = mid;
        outside_drop = drop;
      } else {
        inside = mid;
        inside_drop = drop;
      }
    }
    *bound = 0.5 * (inside + outside);
    return true;
  }

  const std::optional<Error>& error() const { return error_; }
  std::pair<double, double> best() const { return best_; }
  double best_log_likelihood() const { return best_ll_; }

  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static inline const double kLnMin = std::log(kMinWeber);
  static inline const double kLnMax = std::log(kMaxWeber);

 private:
  double InnerMinimum(const std::function<double(double)>& cost, double* start,
                      double lower, double upper, double step) {
    analysis::BoxSearch box;
    box.lower = {lower};
    box.upper = {upper};
    box.initial_step = {step};
    box.xtol_abs = 2e-3;
    box.max_evaluations = 12;
    const analysis::BoxMinimum m = analysis::MinimiseInBox(
        [&](std::span<const double> x) { return cost(x[0]); }, box, {*start});
    *start = m.x[0];
    return m.value;
  }

  PopulationFitter& fitter_;
  const ObservedGroup& observed_;
  bool fit_spread_;
  std::optional<Error> error_;
  double best_ll_ = -kInf;
  std::pair<double, double> best_{0.0, 0.0};
  double weber_start_ = 0.0, spread_start_ = 0.0;
};

// Moves `fit` (the moment fit) to the maximum of the likelihood and gives
// W and its spread their profile intervals, with a note for each bound that
// does not close inside the search range.
Status RefineByLikelihood(PopulationFitter& fitter,
                          const ObservedGroup& observed, bool fit_spread,
                          bool intervals, ObserverFit* fit) {
  LikelihoodFit ml(fitter, observed, fit_spread);
  if (!ml.Maximise(std::log(fit->weber), fit->weber_spread)) {
    return *ml.error();
  }
  if (!std::isfinite(ml.best_log_likelihood())) {
    return Error{fmt::format(
        "no population in the search range (W {} to {}, spread up to {}) "
        "makes {} subjects reporting {} +- {} possible",
        kMinWeber, kMaxWeber, fit_spread ? kMaxWeberSpread : 0.0, observed.n,
        observed.mean, observed.sem)};
  }
  if (!intervals) {
    const auto [ln_w, spread] = ml.best();
    fit->maximum_likelihood = true;
    fit->weber = fit->weber_low = fit->weber_high = std::exp(ln_w);
    fit->weber_spread = fit->spread_low = fit->spread_high = spread;
    return Status{};
  }
  // The profiles may find a higher likelihood than the search stopped at
  // (the likelihood is estimated by simulation, so its surface is rough on
  // a fine scale); the intervals are then taken again around it.
  double ln_w_low = 0.0, ln_w_high = 0.0, s_low = 0.0, s_high = 0.0;
  bool closed[4] = {};
  for (int pass = 0; pass < 2; ++pass) {
    const auto [ln_w, spread] = ml.best();
    const double peak = ml.best_log_likelihood();
    const auto at_weber = [&](double l) { return ml.ProfileAtWeber(l); };
    ml.StartProfiles();
    closed[0] =
        ml.Bound(at_weber, ln_w, peak, LikelihoodFit::kLnMin, 0.1, &ln_w_low);
    ml.StartProfiles();
    closed[1] =
        ml.Bound(at_weber, ln_w, peak, LikelihoodFit::kLnMax, 0.1, &ln_w_high);
    s_low = s_high = spread;
    if (fit_spread) {
      const auto at_spread = [&](double s) { return ml.ProfileAtSpread(s); };
      ml.StartProfiles();
      closed[2] = ml.Bound(at_spread, spread, peak, 0.0, 0.05, &s_low);
      ml.StartProfiles();
      closed[3] =
          ml.Bound(at_spread, spread, peak, kMaxWeberSpread, 0.05, &s_high);
    }
    if (ml.error().has_value()) return *ml.error();
    if (ml.best_log_likelihood() <= peak + 0.1) break;
  }
  const auto [ln_w, spread] = ml.best();
  fit->maximum_likelihood = true;
  fit->weber = std::exp(ln_w);
  fit->weber_spread = spread;
  fit->weber_low = std::exp(std::min(ln_w_low, ln_w));
  fit->weber_high = std::exp(std::max(ln_w_high, ln_w));
  fit->spread_low = std::min(s_low, spread);
  fit->spread_high = std::max(s_high, spread);
  const auto unidentified = [&](std::string_view what, std::string_view side,
                                double limit) {
    fit->notes.push_back(fmt::format(
        "{} is not identified {} the fit: the profile likelihood stays "
        "within {:.2f} of its maximum out to the search limit {} (the "
        "interval stops there)",
        what, side, kProfileDrop, limit));
  };
  if (!closed[0]) unidentified("W", "below", kMinWeber);
  if (!closed[1]) unidentified("W", "above", kMaxWeber);
  if (fit_spread && !closed[2]) {
    fit->notes.push_back(
        "the spread's interval reaches 0: subjects all alike are not "
        "rejected");
  }
  if (fit_spread && !closed[3]) {
    unidentified("the spread", "above", kMaxWeberSpread);
  }
  return Status{};
}

}  // namespace

ObservedGroup ObservedScores(std::vector<int> scores, std::string block) {
  ObservedGroup g;
  double sum = 0.0, sum2 = 0.0;
  for (int c : scores) {
    sum += c;
    sum2 += static_cast<double>(c) * c;
  }
  const double count = static_cast<double>(scores.size());
  g.n = static_cast<int>(scores.size());
  g.mean = count > 0.0 ? sum / count : 0.0;
  g.sem = count > 1.0 ? std::sqrt(std::max(0.0, (sum2 - sum * sum / count) /
                                                    (count - 1.0) / count))
                      : 0.0;
  g.decimals = 6;
  g.block = std::move(block);
  g.scores = std::move(scores);
  return g;
}

Result<ObservedGroup> ParseObservedGroup(std::string_view text) {
  ObservedGroup g;
  g.decimals = 0;
  bool mean = false, sem = false, n = false;
  const auto bad = [&] {
    return Error{fmt::format(
        "--observed must be [block=NAME,]mean=M,sem=S,n=N (M >= 0, S > 0, "
        "N >= 2) or [block=NAME,]scores=S1/S2/... (each subject's score, at "
        "least two), got '{}'",
        text)};
  };
  bool scores = false;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view item = text.substr(start, comma - start);
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos) return bad();
    const std::string_view key = item.substr(0, eq),
                           value = item.substr(eq + 1);
    if (key == "block") {
      if (value.empty() || !g.block.empty()) return bad();
      g.block = std::string(value);
      start = comma + 1;
      continue;
    }
    if (key == "scores") {
      if (scores) return bad();
      scores = true;
      std::size_t from = 0;
      while (from <= value.size()) {
        const std::size_t slash = std::min(value.find('/', from), value.size());
        int score = 0;
        const char* first = value.data() + from;
        const char* last = value.data() + slash;
        const auto [end, ec] = std::from_chars(first, last, score);
        if (ec != std::errc() || end != last || score < 0) return bad();
        g.scores.push_back(score);
        from = slash + 1;
      }
      start = comma + 1;
      continue;
    }
    double v = 0.0;
    const auto [end, ec] =
        std::from_chars(value.data(), value.data() + value.size(), v);
    if (ec != std::errc() || end != value.data() + value.size() ||
        !std::isfinite(v)) {
      return bad();
    }
    if (key == "mean") {
      g.mean = v;
      g.decimals = std::max(g.decimals, DecimalsOf(value));
      mean = true;
    } else if (key == "sem") {
      g.sem = v;
      g.decimals = std::max(g.decimals, DecimalsOf(value));
      sem = true;
    } else if (key == "n" && v == std::floor(v) && v >= 2 && v <= 1e6) {
      g.n = static_cast<int>(v);
      n = true;
    } else {
      return bad();
    }
    start = comma + 1;
  }
  if (scores) {
    if (mean || sem || n || g.scores.size() < 2) return bad();
    return ObservedScores(std::move(g.scores), g.block);
  }
  if (!mean || !sem || !n || g.mean < 0.0 || !(g.sem > 0.0)) return bad();
  return g;
}

Result<ObserverVariant> FindObserverVariant(std::string_view name) {
  std::string names;
  for (const ObserverVariant& v : kObserverVariants) {
    if (v.name == name) return v;
    names += (names.empty() ? "" : ", ") + std::string(v.name);
  }
  return Error{
      fmt::format("no observer variant \"{}\" (variants: {})", name, names)};
}

protocols::ObserverParams VariantObserver(const ObserverVariant& variant,
                                          protocols::ObserverParams base) {
  base.rule = variant.rule;
  const protocols::ExplorationSpreads spreads =
      variant.varied_exploration ? protocols::kVariedExploration
                                 : protocols::ExplorationSpreads{};
  base.exploration.force_spread = spreads.force;
  base.exploration.speed_spread = spreads.speed;
  base.exploration.subject_force_spread = spreads.subject_force;
  base.exploration.subject_speed_spread = spreads.subject_speed;
  return base;
}

Result<ObserverFit> FitObservers(const protocols::Protocol& protocol,
                                 const ObservedGroup& observed,
                                 const ObserverFitOptions& options,
                                 CuePool& pool) {
  if (options.virtual_subjects < 2) {
    return Error{fmt::format("virtual subjects must be at least 2, got {}",
                             options.virtual_subjects)};
  }
  ObserverFitOptions opts = options;
  if (!observed.block.empty()) {
    if (!opts.block.empty() && opts.block != observed.block) {
      return Error{fmt::format(
          "the observed result is of block \"{}\" but block \"{}\" was asked "
          "for",
          observed.block, opts.block)};
    }
    opts.block = observed.block;
  }
  if (!opts.block.empty()) {
    std::string names;
    bool found = false;
    for (const protocols::Block& b : protocol.blocks) {
      names += (names.empty() ? "" : ", ") + b.name;
      found = found || b.name == opts.block;
    }
    if (!found) {
      return Error{fmt::format("the protocol has no block \"{}\" (blocks: {})",
                               opts.block, names)};
    }
  }
  PopulationFitter fitter(protocol, opts, pool);
  // The block and its n, from one study.
  Result<Moments> probe = fitter.Evaluate(0.3, 0.0);
  if (!probe.ok()) return probe.error();
  ObserverFit fit;
  fit.block = fitter.block();
  fit.trials_per_subject = fitter.trials();
  for (const protocols::Block& b : protocol.blocks) {
    if (b.name == fit.block) fit.task = b.task;
  }
  for (int score : observed.scores) {
    if (score > fit.trials_per_subject) {
      return Error{fmt::format(
          "an observed score of {} is above the {} trials of block \"{}\"",
          score, fit.trials_per_subject, fit.block)};
    }
  }
  if (observed.mean > fit.trials_per_subject) {
    return Error{
        fmt::format("the observed mean {} is above the {} trials of "
                    "block \"{}\"",
                    observed.mean, fit.trials_per_subject, fit.block)};
  }
  fit.observed_sd = observed.sem * std::sqrt(static_cast<double>(observed.n));
  bool limit = false;
  Result<double> w = fitter.SolveWeber(observed.mean, 0.0, &limit);
  if (!w.ok()) return w.error();
  double spread = 0.0;
  if (options.fit_spread && !limit) {
    Result<Moments> m = fitter.Evaluate(*w, 0.0);
    if (!m.ok()) return m.error();
    if (m->sd >= fit.observed_sd) {
      fit.notes.push_back(fmt::format(
          "the observed SD {:.3g} is within the binomial SD {:.3g} of equal "
          "observers: no spread across subjects is needed",
          fit.observed_sd, m->sd));
    } else {
      // Only a start for the maximum likelihood: a coarser bisection.
      const int steps = options.maximum_likelihood ? 5 : 10;
      double lo = 0.0, hi = kMaxWeberSpread;
      for (int i = 0; i < steps; ++i) {
        const double mid = 0.5 * (lo + hi);
        bool l = false;
        Result<double> wm = fitter.SolveWeber(observed.mean, mid, &l);
        if (!wm.ok()) return wm.error();
        if (l) {  // so spread a population no W gives the mean: too wide
          hi = mid;
          continue;
        }
        Result<Moments> mm = fitter.Evaluate(*wm, mid);
        if (!mm.ok()) return mm.error();
        (mm->sd < fit.observed_sd ? lo : hi) = mid;
      }
      spread = lo;  // the widest spread known to reach the mean
      w = fitter.SolveWeber(observed.mean, spread, &limit);
      if (!w.ok()) return w.error();
      Result<Moments> reached = fitter.Evaluate(*w, spread);
      if (!reached.ok()) return reached.error();
      if (reached->sd < 0.9 * fit.observed_sd) {
        fit.notes.push_back(fmt::format(
            "the observed SD {:.3g} is out of reach: every spread up to 2 (SD "
            "of ln W) that still gives the mean gives a smaller SD; the "
            "spread stops at {:.3g} (SD {:.3g})",
            fit.observed_sd, spread, reached->sd));
      }
    }
  }
  if (limit) {
    Result<std::pair<double, double>> peak = fitter.Peak(spread);
    if (!peak.ok()) return peak.error();
    fit.notes.push_back(fmt::format(
        "the observed mean {} is out of reach: the highest mean any Weber "
        "fraction gives is {:.3g} (at W {:.3g}); the fit stops there",
        observed.mean, peak->second, peak->first));
  }
  fit.weber = *w;
  fit.weber_spread = spread;
  fit.spread_low = fit.spread_high = spread;
  if (options.maximum_likelihood) {
    if (Status s = RefineByLikelihood(fitter, observed, options.fit_spread,
                                      options.intervals, &fit);
        !s.ok()) {
      return s.error();
    }
  } else {
    const double z = 1.959963984540054;
    bool lo_limit = false, hi_limit = false;
    Result<double> high =  // a lower score needs a larger W
        fitter.SolveWeber(observed.mean - z * observed.sem, spread, &hi_limit);
    if (!high.ok()) return high.error();
    Result<double> low =
        fitter.SolveWeber(observed.mean + z * observed.sem, spread, &lo_limit);
    if (!low.ok()) return low.error();
    fit.weber_low = *low;
    fit.weber_high = *high;
    if (lo_limit || hi_limit) {
      fit.notes.push_back(
          "an interval bound is at the search limit: the observed mean +- "
          "1.96 SEM reaches scores no Weber fraction in range gives");
    }
  }
  Result<Moments> fitted = fitter.Evaluate(fit.weber, fit.weber_spread);
  if (!fitted.ok()) return fitted.error();
  fit.fitted_mean = fitted->mean;
  fit.fitted_sd = fitted->sd;
  // How likely the fitted population makes the publication itself.
  Result<double> ll =
      fitter.LogLikelihood(std::log(fit.weber), fit.weber_spread, observed);
  if (!ll.ok()) return ll.error();
  fit.log_likelihood = *ll;
  fit.published_probability = std::exp(*ll);
  fit.virtual_studies = fitter.evaluations();
  return fit;
}

Result<std::vector<ObserverFit>> FitObserverGroups(
    const protocols::Protocol& protocol,
    const std::vector<ObservedGroup>& observed,
    const ObserverFitOptions& options, CuePool& pool) {
  std::vector<Result<ObserverFit>> results(observed.size(),
                                           Error{"not fitted"});
  ParallelFor(
      static_cast<int>(observed.size()), options.jobs,
      [&](int i) {
        const std::size_t k = static_cast<std::size_t>(i);
        results[k] = FitObservers(protocol, observed[k], options, pool);
      },
      nullptr);
  std::vector<ObserverFit> fits;
  for (Result<ObserverFit>& r : results) {
    if (!r.ok()) return r.error();
    fits.push_back(std::move(*r));
  }
  return fits;
}

int FitsToCompare(std::span<const ObserverVariant> variants, int groups) {
  int fits = 0;
  for (const ObserverVariant& v : variants) {
    fits += groups * (v.lapse ? kLapseFitsPerGroup : 1);
  }
  return fits;
}

namespace {

// A variant's summary: its log likelihood, parameters, AIC and BIC over
// `subjects` observed subjects.
void Score(int groups, int subjects, VariantFit* v) {
  v->log_likelihood = 0.0;
  for (const ObserverFit& f : v->fits) v->log_likelihood += f.log_likelihood;
  v->parameters = groups * (v->fit_spread ? 2 : 1) + (v->variant.lapse ? 1 : 0);
  v->aic = 2.0 * v->parameters - 2.0 * v->log_likelihood;
  v->bic = v->parameters * std::log(static_cast<double>(subjects)) -
           2.0 * v->log_likelihood;
}

// The shared lapse of `v` (CompareObserverVariants): its profile over the
// lapse, each point every group fitted at its maximum, options.jobs fits at
// once; `done` is told of each fit. Fills v->fits, observer.lapse and the
// interval.
Status FitSharedLapse(const protocols::Protocol& protocol,
                      const std::vector<ObservedGroup>& observed,
                      const ObserverFitOptions& options, CuePool& pool,
                      const std::function<void()>& done, VariantFit* v) {
  const std::size_t groups = observed.size();
  ObserverFitOptions point = options;
  point.intervals = false;
  // The profile log likelihood at each lapse of `lapses`, all fits at once.
  std::map<double, double> profile;
  const auto evaluate = [&](const std::vector<double>& lapses) -> Status {
    std::vector<Result<ObserverFit>> results(lapses.size() * groups,
                                             Error{"not fitted"});
    ParallelFor(
        static_cast<int>(results.size()), options.jobs,
        [&](int i) {
          const std::size_t k = static_cast<std::size_t>(i);
          ObserverFitOptions o = point;
          o.base.lapse = lapses[k / groups];
          results[k] = FitObservers(protocol, observed[k % groups], o, pool);
        },
        [&](int) {
          if (done) done();
        });
    for (std::size_t l = 0; l < lapses.size(); ++l) {
      double sum = 0.0;
      for (std::size_t g = 0; g < groups; ++g) {
        Result<ObserverFit>& r = results[l * groups + g];
        if (!r.ok()) return r.error();
        sum += r->log_likelihood;
      }
      profile[lapses[l]] = sum;
    }
    return Status{};
  };
  const auto at = [&](double lapse) -> Result<double> {
    if (auto it = profile.find(lapse); it != profile.end()) return it->second;
    if (Status s = evaluate({lapse}); !s.ok()) return s.error();
    return profile.at(lapse);
  };
  const std::vector<double> grid(std::begin(kLapseGrid), std::end(kLapseGrid));
  if (Status s = evaluate(grid); !s.ok()) return s;
  std::size_t best = 0;
  for (std::size_t i = 1; i < grid.size(); ++i) {
    if (profile[grid[i]] > profile[grid[best]]) best = i;
  }
  // Golden-section steps between the best grid point's neighbours.
  double lo = grid[best > 0 ? best - 1 : 0];
  double hi = grid[std::min(best + 1, grid.size() - 1)];
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
  Result<double> fa = at(a);
  if (!fa.ok()) return fa.error();
  Result<double> fb = at(b);
  if (!fb.ok()) return fb.error();
  for (int step = 2; step < kLapseGoldenSteps; ++step) {
    if (*fa >= *fb) {  // the maximum is in [lo, b]
      hi = b;
      b = a;
      fb = fa;
      a = hi - ratio * (hi - lo);
      fa = at(a);
      if (!fa.ok()) return fa.error();
    } else {  // in [a, hi]
      lo = a;
      a = b;
      fa = fb;
      b = lo + ratio * (hi - lo);
      fb = at(b);
      if (!fb.ok()) return fb.error();
    }
  }
  double lapse = grid[best];
  for (const auto& [l, ll] : profile) {
    if (ll > profile[lapse]) lapse = l;
  }
  const double peak = profile[lapse];
  // Each end: bisection between the last lapse within 1.92 of the peak and
  // the first beyond it, going out from the fit; none beyond: the interval
  // runs to the grid's end.
  const auto end = [&](int direction, double* bound) -> Result<bool> {
    double inside = lapse;
    double outside = -1.0;
    for (const auto& [l, ll] : profile) {
      if ((l - lapse) * direction <= 0.0) continue;
      if (ll < peak - kProfileDrop) {
        if (outside < 0.0 || std::abs(l - lapse) < std::abs(outside - lapse))
          outside = l;
      }
    }
    if (outside < 0.0) {
      *bound = direction < 0 ? grid.front() : grid.back();
      return false;
    }
    for (const auto& [l, ll] : profile) {
      if ((l - lapse) * direction > 0.0 &&
          std::abs(l - lapse) < std::abs(outside - lapse) &&
          std::abs(l - lapse) > std::abs(inside - lapse)) {
        inside = l;
      }
    }
    for (int step = 0; step < kLapseBisections; ++step) {
      const double mid = 0.5 * (inside + outside);
      Result<double> f = at(mid);
      if (!f.ok()) return f.error();
      (*f < peak - kProfileDrop ? outside : inside) = mid;
    }
    *bound = 0.5 * (inside + outside);
    return true;
  };
  Result<bool> low_closed = end(-1, &v->lapse_low);
  if (!low_closed.ok()) return low_closed.error();
  Result<bool> high_closed = end(+1, &v->lapse_high);
  if (!high_closed.ok()) return high_closed.error();
  if (!*low_closed) {
    v->notes.push_back(
        "the lapse's interval reaches 0: observers that never lapse are not "
        "rejected");
  }
  if (!*high_closed) {
    v->notes.push_back(fmt::format(
        "the lapse is not identified above the fit: the profile likelihood "
        "stays within {:.2f} of its maximum out to {} (the interval stops "
        "there)",
        kProfileDrop, grid.back()));
  }
  // The blocks at the fitted lapse, with their intervals (at that lapse).
  ObserverFitOptions final_options = options;
  final_options.base.lapse = lapse;
  Result<std::vector<ObserverFit>> fits =
      FitObserverGroups(protocol, observed, final_options, pool);
  if (!fits.ok()) return fits.error();
  v->observer.lapse = lapse;
  v->fits = std::move(*fits);
  v->lapse_profile.assign(profile.begin(), profile.end());
  return Status{};
}

}  // namespace

Result<std::vector<VariantFit>> CompareObserverVariants(
    const protocols::Protocol& protocol,
    const std::vector<ObservedGroup>& observed,
    std::span<const ObserverVariant> variants,
    const ObserverFitOptions& options, CuePool& pool,
    const std::function<void(int, std::string_view)>& progress) {
  int subjects = 0;
  for (const ObservedGroup& g : observed) subjects += g.n;
  const std::size_t groups = observed.size();
  std::vector<ObserverFitOptions> variant_options;
  for (const ObserverVariant& variant : variants) {
    ObserverFitOptions o = options;
    o.base = VariantObserver(variant, options.base);
    o.fit_spread = variant.spread && options.fit_spread;
    variant_options.push_back(o);
  }
  // Every (variant, group) of a variant without a shared lapse is a fit of
  // its own: all at once.
  std::vector<std::size_t> plain;
  for (std::size_t i = 0; i < variants.size(); ++i) {
    if (!variants[i].lapse) plain.push_back(i);
  }
  std::vector<Result<ObserverFit>> results(variants.size() * groups,
                                           Error{"not fitted"});
  int finished = 0;
  ParallelFor(
      static_cast<int>(plain.size() * groups), options.jobs,
      [&](int i) {
        const std::size_t v = plain[static_cast<std::size_t>(i) / groups];
        const std::size_t g = static_cast<std::size_t>(i) % groups;
        results[v * groups + g] =
            FitObservers(protocol, observed[g], variant_options[v], pool);
      },
      [&](int i) {
        if (progress) {
          progress(++finished,
                   variants[plain[static_cast<std::size_t>(i) / groups]].name);
        }
      });
  std::vector<VariantFit> compared;
  for (std::size_t i = 0; i < variants.size(); ++i) {
    const ObserverFitOptions& o = variant_options[i];
    VariantFit v;
    v.variant = variants[i];
    v.observer = o.base;
    v.fit_spread = o.fit_spread;
    if (variants[i].lapse) {
      // Its profile's fits, then the rest of its count at once.
      const int allotted = static_cast<int>(groups) * kLapseFitsPerGroup;
      int used = 0;
      Status s = FitSharedLapse(
          protocol, observed, o, pool,
          [&] {
            if (used < allotted - 1) {
              ++used;
              if (progress) progress(++finished, v.variant.name);
            }
          },
          &v);
      if (!s.ok()) return s.error();
      finished += allotted - used;
      if (progress) progress(finished, v.variant.name);
    } else {
      for (std::size_t g = 0; g < groups; ++g) {
        Result<ObserverFit>& fit = results[i * groups + g];
        if (!fit.ok()) return fit.error();
        v.fits.push_back(std::move(*fit));
      }
    }
    Score(static_cast<int>(groups), subjects, &v);
    compared.push_back(std::move(v));
  }
  std::stable_sort(
      compared.begin(), compared.end(),
      [](const VariantFit& a, const VariantFit& b) { return a.aic < b.aic; });
  for (VariantFit& v : compared) {
    v.delta_aic = v.aic - compared.front().aic;
  }
  return compared;
}

Result<VirtualStudyOptions> PopulationOf(const std::vector<ObserverFit>& fits,
                                         const protocols::ObserverParams& base,
                                         std::vector<std::string>* notes) {
  VirtualStudyOptions v;
  v.observer = base;
  const ObserverFit* stiffness = nullptr;
  const ObserverFit* removal = nullptr;
  for (const ObserverFit& f : fits) {
    const ObserverFit*& slot =
        f.task == protocols::Task::kProbe ? stiffness : removal;
    if (slot != nullptr) {
      return Error{fmt::format(
          "blocks \"{}\" and \"{}\" both fit the {} cue: fit one block per "
          "task",
          slot->block, f.block,
          f.task == protocols::Task::kProbe ? "stiffness" : "removal")};
    }
    slot = &f;
  }
  if (stiffness == nullptr && removal == nullptr) {
    return Error{"no fitted block"};
  }
  if (stiffness == nullptr || removal == nullptr) {
    const ObserverFit& only = stiffness != nullptr ? *stiffness : *removal;
    if (notes != nullptr) {
      notes->push_back(fmt::format(
          "only the {} cue was fitted (block \"{}\"); the {} cue takes the "
          "same Weber fraction and spread",
          stiffness != nullptr ? "stiffness" : "removal", only.block,
          stiffness != nullptr ? "removal" : "stiffness"));
    }
    if (stiffness == nullptr) stiffness = &only;
    if (removal == nullptr) removal = &only;
  }
  v.observer.weber_stiffness = stiffness->weber;
  v.observer.weber_removal = removal->weber;
  v.spread_stiffness = stiffness->weber_spread;
  v.spread_removal = removal->weber_spread;
  return v;
}

}  // namespace burrlab::runner
