#include "studies/fit_recovery.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "burrlab/protocols/streams.h"
#include "studies/parallel_for.h"

namespace burrlab::runner {

ObservedGroup PublishedResult(const std::vector<int>& correct,
                              const std::string& block, int decimals) {
  ObservedGroup g = ObservedScores(correct, block);
  const double unit = std::pow(10.0, -decimals);
  g.mean = std::round(g.mean / unit) * unit;
  g.sem = std::max(unit, std::round(g.sem / unit) * unit);
  g.decimals = decimals;
  g.scores.clear();  // only the mean and SEM are published
  return g;
}

Result<Recovery> CheckRecovery(const protocols::Protocol& protocol,
                               const ObservedGroup& observed,
                               const ObserverFit& truth,
                               const ObserverFitOptions& fit_options,
                               CuePool& fit_pool,
                               const RecoveryOptions& options,
                               const std::function<void(int)>& progress) {
  if (options.studies < 1) {
    return Error{fmt::format("recovery: studies must be at least 1, got {}",
                             options.studies)};
  }
  if (options.renderings < 1) {
    return Error{fmt::format("recovery: renderings must be at least 1, got {}",
                             options.renderings)};
  }
  Result<VirtualStudyOptions> population =
      PopulationOf({truth}, fit_options.base, nullptr);
  if (!population.ok()) return population.error();
  const std::size_t n = static_cast<std::size_t>(options.studies);
  std::vector<Result<ObserverFit>> fits(n, Error{"not fitted"});
  using protocols::SeedFor;
  using protocols::StreamPurpose;
  ParallelFor(
      options.studies, fit_options.jobs,
      [&](int i) {
        const auto k = static_cast<std::uint64_t>(i);
        // The published study: its own subjects and renderings.
        CuePool published_pool(
            options.renderings, fit_pool.radius_mm(),
            SeedFor(options.seed, StreamPurpose::kErosion, k, 1));
        VirtualStudyOptions study = *population;
        study.subjects = observed.n;
        study.seed = SeedFor(options.seed, StreamPurpose::kPopulation, k, 1);
        study.only_block = truth.block;
        Result<std::vector<VirtualBlock>> result =
            RunVirtualStudy(protocol, study, published_pool);
        if (!result.ok()) {
          fits[static_cast<std::size_t>(i)] = result.error();
          return;
        }
        const VirtualBlock* block = nullptr;
        for (const VirtualBlock& b : *result) {
          if (b.block == truth.block) block = &b;
        }
        if (block == nullptr) {
          fits[static_cast<std::size_t>(i)] =
              Error{fmt::format("block \"{}\" was not scored", truth.block)};
          return;
        }
        // Published as the observed result is: each subject's score, or the
        // rounded mean and SEM.
        const ObservedGroup published =
            observed.scores.empty()
                ? PublishedResult(block->correct, truth.block,
                                  observed.decimals)
                : ObservedScores(block->correct, truth.block);
        // Fitted back as the observed result was, with a seed of its own.
        ObserverFitOptions o = fit_options;
        o.block = truth.block;
        o.seed = SeedFor(options.seed, StreamPurpose::kPopulation, k, 2);
        fits[static_cast<std::size_t>(i)] =
            FitObservers(protocol, published, o, fit_pool);
      },
      [&, done = 0](int) mutable {
        if (progress) progress(++done);
      });
  Recovery r;
  r.block = truth.block;
  r.weber = truth.weber;
  r.spread = truth.weber_spread;
  r.fit_spread = fit_options.fit_spread;
  r.studies = options.studies;
  for (std::size_t i = 0; i < n; ++i) {
    if (!fits[i].ok()) {
      return Error{fmt::format("recovery, study {}: {}", i + 1,
                               fits[i].error().message)};
    }
    const ObserverFit& f = *fits[i];
    const bool w = f.weber_low <= r.weber && r.weber <= f.weber_high;
    const bool s = !r.fit_spread ||
                   (f.spread_low <= r.spread && r.spread <= f.spread_high);
    r.weber_covered += w ? 1 : 0;
    r.spread_covered += s ? 1 : 0;
    r.both_covered += w && s ? 1 : 0;
    r.weber_at_limit +=
        f.weber_low <= kMinWeber || f.weber_high >= kMaxWeber ? 1 : 0;
    r.spread_at_limit +=
        r.fit_spread && f.spread_high >= kMaxWeberSpread ? 1 : 0;
    r.fits.push_back(f);
  }
  return r;
}

}  // namespace burrlab::runner
