// Observer-population fits by bisection over virtual studies.
#include "observer_fit.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <optional>

namespace burrlab::runner {
namespace {

struct Moments {
  double mean = 0.0;
  double sd = 0.0;
};

class Fitter {
 public:
  Fitter(const protocols::Protocol& protocol, const ObserverFitOptions& options,
         CuePool& pool)
      : protocol_(protocol), options_(options), pool_(pool) {}

  // Mean and SD of the block's scores of a population (W, spread).
  Result<Moments> Evaluate(double weber, double spread) {
    VirtualStudyOptions o;
    o.subjects = options_.virtual_subjects;
    o.seed = options_.seed;
    o.observer = options_.base;
    o.observer.weber_stiffness = weber;
    o.observer.weber_removal = weber;
    o.weber_log_sd = spread;
    o.only_block = block_.empty() ? options_.block : block_;
    Result<std::vector<VirtualBlock>> study =
        RunVirtualStudy(protocol_, o, pool_);
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
    return m;
  }

  // The W whose mean score is `target` (mean falls as W grows); the search
  // limit when the target is out of reach, with `*limit` set.
  Result<double> SolveWeber(double target, double spread, bool* limit) {
    double lo = std::log(kMinWeber), hi = std::log(kMaxWeber);
    Result<Moments> at_lo = Evaluate(kMinWeber, spread);
    if (!at_lo.ok()) return at_lo.error();
    *limit = false;
    if (at_lo->mean <= target) {
      *limit = true;
      return kMinWeber;
    }
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
};

}  // namespace

Result<ObservedGroup> ParseObservedGroup(std::string_view text) {
  ObservedGroup g;
  bool mean = false, sem = false, n = false;
  const auto bad = [&] {
    return Error{fmt::format(
        "--observed must be mean=M,sem=S,n=N (M >= 0, S > 0, N >= 2), got "
        "'{}'",
        text)};
  };
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view item = text.substr(start, comma - start);
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos) return bad();
    const std::string_view key = item.substr(0, eq),
                           value = item.substr(eq + 1);
    double v = 0.0;
    const auto [end, ec] =
        std::from_chars(value.data(), value.data() + value.size(), v);
    if (ec != std::errc() || end != value.data() + value.size() ||
        !std::isfinite(v)) {
      return bad();
    }
    if (key == "mean") {
      g.mean = v;
      mean = true;
    } else if (key == "sem") {
      g.sem = v;
      sem = true;
    } else if (key == "n" && v == std::floor(v) && v >= 2 && v <= 1e6) {
      g.n = static_cast<int>(v);
      n = true;
    } else {
      return bad();
    }
    start = comma + 1;
  }
  if (!mean || !sem || !n || g.mean < 0.0 || !(g.sem > 0.0)) return bad();
  return g;
}

Result<ObserverFit> FitObservers(const protocols::Protocol& protocol,
                                 const ObservedGroup& observed,
                                 const ObserverFitOptions& options,
                                 CuePool& pool) {
  if (options.virtual_subjects < 2) {
    return Error{fmt::format("virtual subjects must be at least 2, got {}",
                             options.virtual_subjects)};
  }
  Fitter fitter(protocol, options, pool);
  // The block and its n, from one study.
  Result<Moments> probe = fitter.Evaluate(0.3, 0.0);
  if (!probe.ok()) return probe.error();
  ObserverFit fit;
  fit.block = fitter.block();
  fit.trials_per_subject = fitter.trials();
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
      double lo = 0.0, hi = 2.0;
      for (int i = 0; i < 10; ++i) {
        const double mid = 0.5 * (lo + hi);
        bool l = false;
        Result<double> wm = fitter.SolveWeber(observed.mean, mid, &l);
        if (!wm.ok()) return wm.error();
        Result<Moments> mm = fitter.Evaluate(*wm, mid);
        if (!mm.ok()) return mm.error();
        (mm->sd < fit.observed_sd ? lo : hi) = mid;
      }
      spread = 0.5 * (lo + hi);
      w = fitter.SolveWeber(observed.mean, spread, &limit);
      if (!w.ok()) return w.error();
    }
  }
  if (limit) {
    fit.notes.push_back(fmt::format(
        "the observed mean {} is out of reach of Weber fractions {} to {}: "
        "the fit stops at the limit",
        observed.mean, kMinWeber, kMaxWeber));
  }
  fit.weber = *w;
  fit.weber_spread = spread;
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
  Result<Moments> fitted = fitter.Evaluate(fit.weber, spread);
  if (!fitted.ok()) return fitted.error();
  fit.fitted_mean = fitted->mean;
  fit.fitted_sd = fitted->sd;
  fit.virtual_studies = fitter.evaluations();
  return fit;
}

}  // namespace burrlab::runner
