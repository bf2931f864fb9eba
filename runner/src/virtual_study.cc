// Virtual studies over a pool of rendered cues (see virtual_study.h).
#include "virtual_study.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>

#include "burrlab/stimuli/interval.h"
#include "session.h"

namespace burrlab::runner {
namespace {

using protocols::Method;
using protocols::StreamPurpose;
using protocols::TrialSpec;

// Erosion seeds of the pool, apart from every session's streams.
constexpr std::uint64_t kPoolPurposeIndex = 1ull << 40;

// One stimulus of the pool: what the simulator renders.
std::string StimulusKey(const stimuli::IntervalOptions& o) {
  return fmt::format(
      "{}|{}|{}|{}|{}|{}|{}|{}|{}|{}|{}", o.material.c_e_n_per_mm2,
      o.material.alpha_per_s, o.material.c_mu_n_per_mm2, o.material.mu,
      o.material.c_i_n_s_per_mm3, static_cast<int>(o.task), o.duration_s,
      o.radius_mm, o.probe_force_n, o.drill_force_n, o.press_period_s);
}

}  // namespace

CuePool::CuePool(int samples, double radius_mm, std::uint64_t seed)
    : samples_(std::max(1, samples)), radius_mm_(radius_mm), seed_(seed) {}

Result<const std::vector<double>*> CuePool::Cues(
    const protocols::Protocol& protocol, const TrialSpec& trial,
    const stimuli::MaterialSet& set, double duration_s) {
  stimuli::IntervalOptions o =
      IntervalOptionsFor(protocol, radius_mm_, trial, set, duration_s, 0);
  const std::string key = StimulusKey(o);
  auto it = cues_.find(key);
  if (it != cues_.end()) return &it->second;
  std::vector<double> cues;
  for (int k = 0; k < samples_; ++k) {
    o.seed = protocols::SeedFor(seed_, StreamPurpose::kErosion,
                                kPoolPurposeIndex + cues_.size(),
                                static_cast<std::uint64_t>(k));
    Result<stimuli::IntervalResult> r = stimuli::PresentSimulatedInterval(o);
    if (!r.ok()) {
      return Error{fmt::format("rendering {} ({}, {} s): {}", set.name,
                               stimuli::TaskName(o.task), duration_s,
                               r.error().message)};
    }
    cues.push_back(std::max(r->cue, kFeltCueFloor));
    ++rendered_;
  }
  return &cues_.emplace(key, std::move(cues)).first->second;
}

Result<std::vector<VirtualBlock>> RunVirtualStudy(
    const protocols::Protocol& protocol, const VirtualStudyOptions& options,
    CuePool& pool) {
  if (options.subjects < 1) {
    return Error{
        fmt::format("subjects must be at least 1, got {}", options.subjects)};
  }
  if (!(options.weber_log_sd >= 0.0) || !std::isfinite(options.weber_log_sd)) {
    return Error{fmt::format("the Weber spread must be 0 or more, got {}",
                             options.weber_log_sd)};
  }
  std::vector<VirtualBlock> blocks;
  const auto block_of = [&](const TrialSpec& t) -> VirtualBlock& {
    for (VirtualBlock& b : blocks) {
      if (b.block == t.block) return b;
    }
    VirtualBlock b;
    b.block = t.block;
    b.method = t.method;
    b.trial_type = t.trial_type;
    b.correct.assign(static_cast<std::size_t>(options.subjects), 0);
    b.trials.assign(static_cast<std::size_t>(options.subjects), 0);
    blocks.push_back(std::move(b));
    return blocks.back();
  };
  const auto draw = [](const std::vector<double>& cues,
                       boost::random::mt19937& rng) {
    boost::random::uniform_int_distribution<std::size_t> pick(0,
                                                              cues.size() - 1);
    return cues[pick(rng)];
  };
  for (int s = 0; s < options.subjects; ++s) {
    const std::uint64_t subject_seed =
        protocols::SeedFor(options.seed, StreamPurpose::kSubjectSeed,
                           static_cast<std::uint64_t>(s));
    protocols::ObserverParams params = options.observer;
    if (options.weber_log_sd > 0.0) {
      boost::random::mt19937 population =
          protocols::StreamFor(options.seed, StreamPurpose::kPopulation,
                               static_cast<std::uint64_t>(s));
      boost::random::normal_distribution<double> z(0.0, options.weber_log_sd);
      const double factor = std::exp(z(population));
      params.weber_stiffness *= factor;
      params.weber_removal *= factor;
    }
    const protocols::SimulatedObserver observer(params);
    Result<protocols::Engine> engine =
        protocols::Engine::Create(protocol, s, subject_seed);
    if (!engine.ok()) return engine.error();
    std::map<int, double> standard_cues;
    while (!engine->finished()) {
      const TrialSpec trial = engine->current();
      if (trial.method == Method::kAdjustment) {
        return Error{fmt::format(
            "block \"{}\": adjustment blocks cannot be simulated virtually "
            "(no correct answer to score); leave them out of a power "
            "analysis",
            trial.block)};
      }
      boost::random::mt19937 rng =
          protocols::StreamFor(subject_seed, StreamPurpose::kObserver,
                               static_cast<std::uint64_t>(trial.trial_index));
      std::vector<double> cues(trial.intervals.size(), 0.0);
      const protocols::Block& block = protocol.blocks[trial.block_index];
      for (std::size_t i = 0; i < trial.intervals.size(); ++i) {
        const protocols::PlannedInterval& iv = trial.intervals[i];
        const stimuli::MaterialSet* set =
            iv.material.has_value() ? &*iv.material : nullptr;
        double duration = iv.duration_s;
        if (set == nullptr) {
          // A real reference: felt through the material modelled on it.
          const std::string& id =
              block.reference.matching_material == protocols::MaterialLabel::kA
                  ? block.material_a
                  : block.material_b;
          const protocols::ProtocolMaterial* m = protocol.FindMaterial(id);
          if (m == nullptr)
            return Error{"reference stand-in material is missing"};
          set = &m->set;
          duration =
              trial.intervals.size() > 1 ? trial.intervals[1].duration_s : 10.0;
        }
        Result<const std::vector<double>*> pooled =
            pool.Cues(protocol, trial, *set, duration);
        if (!pooled.ok()) return pooled.error();
        cues[i] = draw(**pooled, rng);
      }
      protocols::TrialCues trial_cues;
      trial_cues.cues = cues;
      if (trial.intervals.size() == 1) {
        auto it = standard_cues.find(trial.block_index);
        if (it == standard_cues.end()) {
          Result<stimuli::MaterialSet> standard =
              engine->MaterialAt(trial.standard_level.value_or(0.0));
          if (!standard.ok()) return standard.error();
          const double duration =
              trial.intervals.empty() ? 10.0 : trial.intervals[0].duration_s;
          Result<const std::vector<double>*> pooled =
              pool.Cues(protocol, trial, *standard, duration);
          if (!pooled.ok()) return pooled.error();
          it = standard_cues.emplace(trial.block_index, draw(**pooled, rng))
                   .first;
        }
        trial_cues.standard_cue = it->second;
      }
      Result<protocols::Response> response =
          observer.Decide(trial, trial_cues, rng);
      if (!response.ok()) return response.error();
      Result<protocols::Outcome> outcome = engine->Respond(*response);
      if (!outcome.ok()) return outcome.error();
      if (outcome->correct.has_value()) {
        VirtualBlock& b = block_of(trial);
        b.correct[static_cast<std::size_t>(s)] += *outcome->correct ? 1 : 0;
        b.trials[static_cast<std::size_t>(s)] += 1;
      }
    }
  }
  return blocks;
}

}  // namespace burrlab::runner
