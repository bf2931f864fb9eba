// Virtual studies over a pool of rendered cues (see virtual_study.h).
#include "virtual_study.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>

#include "burrlab/analysis/group_stats.h"
#include "burrlab/stimuli/interval.h"
#include "session.h"

namespace burrlab::runner {
namespace {

using protocols::Method;
using protocols::StreamPurpose;
using protocols::TrialSpec;

// Erosion seeds of the pool, apart from every session's streams.
constexpr std::uint64_t kPoolPurposeIndex = 1ull << 40;

// One stimulus of the pool: what the simulator renders, as the bytes of its
// numbers (no formatting on the per-trial path).
std::string StimulusKey(const stimuli::IntervalOptions& o) {
  const double values[] = {o.material.c_e_n_per_mm2,
                           o.material.alpha_per_s,
                           o.material.c_mu_n_per_mm2,
                           o.material.mu,
                           o.material.c_i_n_s_per_mm3,
                           static_cast<double>(o.task),
                           o.duration_s,
                           o.radius_mm,
                           o.probe_force_n,
                           o.drill_force_n,
                           o.press_period_s};
  return std::string(reinterpret_cast<const char*>(values), sizeof values);
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
    // One observer stream per subject (seeding a Mersenne twister per trial,
    // as sessions do, would be most of the cost here).
    boost::random::mt19937 rng = protocols::StreamFor(
        subject_seed, StreamPurpose::kObserver, kPoolPurposeIndex);
    while (!engine->finished()) {
      const TrialSpec trial = engine->current();
      if (trial.method == Method::kAdjustment) {
        return Error{fmt::format(
            "block \"{}\": adjustment blocks cannot be simulated virtually "
            "(no correct answer to score); leave them out of a power "
            "analysis",
            trial.block)};
      }
      if (!options.only_block.empty() && trial.block != options.only_block) {
        protocols::Response skip;
        skip.answer = trial.correct_answer.empty()
                          ? trial.response_options.front()
                          : trial.correct_answer;
        Result<protocols::Outcome> outcome = engine->Respond(skip);
        if (!outcome.ok()) return outcome.error();
        continue;
      }
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

Result<std::vector<BlockPower>> EstimatePower(
    const protocols::Protocol& protocol, VirtualStudyOptions options,
    std::uint64_t seed, int runs, double alpha, CuePool& pool,
    const std::function<void(int)>& progress) {
  std::vector<BlockPower> tallies;
  for (int r = 0; r < runs; ++r) {
    options.seed =
        protocols::SeedFor(seed, StreamPurpose::kPopulation, 1ull << 40,
                           static_cast<std::uint64_t>(r));
    Result<std::vector<VirtualBlock>> study =
        RunVirtualStudy(protocol, options, pool);
    if (!study.ok()) return study.error();
    for (const VirtualBlock& b : *study) {
      auto it =
          std::find_if(tallies.begin(), tallies.end(),
                       [&](const BlockPower& t) { return t.block == b.block; });
      if (it == tallies.end()) {
        BlockPower t;
        t.block = b.block;
        t.method = std::string(protocols::MethodName(b.method));
        t.chance = analysis::ChanceOf(t.method, b.trial_type);
        tallies.push_back(t);
        it = tallies.end() - 1;
      }
      ++it->runs;
      std::vector<double> proportions;
      int correct = 0, trials = 0;
      for (std::size_t s = 0; s < b.correct.size(); ++s) {
        proportions.push_back(static_cast<double>(b.correct[s]) / b.trials[s]);
        correct += b.correct[s];
        trials += b.trials[s];
      }
      it->mean_scores.push_back(static_cast<double>(correct) / trials);
      it->mean_counts.push_back(static_cast<double>(correct) /
                                static_cast<double>(b.correct.size()));
      if (!it->chance.p) continue;
      if (Result<analysis::TTestResult> t =
              analysis::OneSampleTTest(proportions, *it->chance.p);
          t.ok()) {
        it->t_significant += t->p_greater < alpha ? 1 : 0;
      } else {
        // All proportions equal: significant when above chance.
        it->t_significant += proportions[0] > *it->chance.p ? 1 : 0;
      }
      if (Result<analysis::BinomialTestResult> t =
              analysis::ExactBinomialTest(correct, trials, *it->chance.p);
          t.ok()) {
        it->binomial_significant += t->p_greater < alpha ? 1 : 0;
      }
    }
    if (progress) progress(r + 1);
  }
  if (tallies.empty()) {
    return Error{"the protocol has no block with correct answers to test"};
  }
  return tallies;
}

}  // namespace burrlab::runner
