// Virtual studies over a pool of rendered cues (see virtual_study.h).
#include "studies/virtual_study.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>

#include "burrlab/analysis/group_stats.h"
#include "burrlab/protocols/streams.h"
#include "burrlab/stimuli/interval.h"
#include "studies/session.h"

namespace burrlab::runner {
namespace {

using protocols::Method;
using protocols::StreamPurpose;
using protocols::TrialSpec;

// The observer stream of a virtual subject, apart from every session's.
constexpr std::uint64_t kPoolPurposeIndex = 1ull << 40;

}  // namespace

CuePool::CuePool(int samples, double radius_mm, std::uint64_t seed)
    : own_(std::make_unique<RenderingPool>(samples, seed, false)),
      renderings_(own_.get()),
      radius_mm_(radius_mm) {}

CuePool::CuePool(RenderingPool& shared, double radius_mm)
    : renderings_(&shared), radius_mm_(radius_mm) {}

Result<const std::vector<double>*> CuePool::Cues(
    const protocols::Protocol& protocol, const TrialSpec& trial,
    const stimuli::MaterialSet& set, double duration_s,
    const protocols::Exploration& e) {
  const stimuli::IntervalOptions o =
      IntervalOptionsFor(protocol, radius_mm_, trial, set, duration_s, 0);
  std::string key = StimulusKey(o, PooledExploration(e, o.task));
  auto it = cues_.find(key);
  if (it != cues_.end()) return &it->second;
  Result<std::vector<double>> cues = renderings_->Cues(o, e);
  if (!cues.ok()) {
    return Error{fmt::format("rendering {} ({}, {} s): {}", set.name,
                             stimuli::TaskName(o.task), duration_s,
                             cues.error().message)};
  }
  for (double& c : *cues) c = protocols::FeltCue(c);
  return &cues_.emplace(std::move(key), std::move(*cues)).first->second;
}

Status ValidateVirtualStudy(const VirtualStudyOptions& options) {
  if (options.subject_observers.empty() && options.subjects < 1) {
    return Error{
        fmt::format("subjects must be at least 1, got {}", options.subjects)};
  }
  for (const double spread :
       {options.spread_stiffness, options.spread_removal}) {
    if (!(spread >= 0.0) || !std::isfinite(spread)) {
      return Error{
          fmt::format("the Weber spread must be 0 or more, got {}", spread)};
    }
  }

  for (const protocols::ObserverParams& p : options.subject_observers) {
    if (Status st = p.Validate(); !st.ok()) return st;
  }
  return options.observer.Validate();
}

protocols::ObserverParams SubjectObserver(const VirtualStudyOptions& options,
                                          int s) {
  if (!options.subject_observers.empty()) {
    return options.subject_observers.at(static_cast<std::size_t>(s));
  }
  return protocols::DrawSubjectObserver(
      options.observer, {options.spread_stiffness, options.spread_removal},
      options.seed, s);
}

Result<std::vector<VirtualBlock>> RunVirtualStudy(
    const protocols::Protocol& protocol, const VirtualStudyOptions& options,
    CuePool& pool) {
  if (Status st = ValidateVirtualStudy(options); !st.ok()) return st.error();
  const int subjects = options.subject_observers.empty()
                           ? options.subjects
                           : static_cast<int>(options.subject_observers.size());
  std::vector<VirtualBlock> blocks;
  const auto block_of = [&](const TrialSpec& t) -> VirtualBlock& {
    for (VirtualBlock& b : blocks) {
      if (b.block == t.block) return b;
    }
    VirtualBlock b;
    b.block = t.block;
    b.method = t.method;
    b.trial_type = t.trial_type;
    b.correct.assign(static_cast<std::size_t>(subjects), 0);
    b.trials.assign(static_cast<std::size_t>(subjects), 0);
    blocks.push_back(std::move(b));
    return blocks.back();
  };
  const auto draw = [](const std::vector<double>& cues,
                       boost::random::mt19937& rng) {
    boost::random::uniform_int_distribution<std::size_t> pick(0,
                                                              cues.size() - 1);
    return cues[pick(rng)];
  };
  for (int s = 0; s < subjects; ++s) {
    const std::uint64_t subject_seed =
        protocols::SeedFor(options.seed, StreamPurpose::kSubjectSeed,
                           static_cast<std::uint64_t>(s));
    const protocols::ObserverParams params = SubjectObserver(options, s);
    const protocols::SimulatedObserver observer(params);
    Result<protocols::Engine> engine =
        protocols::Engine::Create(protocol, s, subject_seed);
    if (!engine.ok()) return engine.error();
    protocols::RememberedStandards standards;
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
          // A real reference: felt through its stand-in.
          Result<const protocols::ProtocolMaterial*> m =
              protocols::ReferenceStandIn(protocol, block);
          if (!m.ok()) return m.error();
          set = &(*m)->set;
          duration = protocols::ReferenceStandInDuration(trial);
        }
        Result<const std::vector<double>*> pooled =
            pool.Cues(protocol, trial, *set, duration, params.exploration);
        if (!pooled.ok()) return pooled.error();
        cues[i] = draw(**pooled, rng);
      }
      // A one-interval trial's standard is drawn from the pool once per
      // block.
      Result<protocols::TrialCues> trial_cues =
          standards.CuesFor(trial, cues, [&]() -> Result<double> {
            Result<stimuli::MaterialSet> standard =
                engine->MaterialAt(trial.standard_level.value_or(0.0));
            if (!standard.ok()) return standard.error();
            const double duration =
                trial.intervals.empty() ? 10.0 : trial.intervals[0].duration_s;
            Result<const std::vector<double>*> pooled = pool.Cues(
                protocol, trial, *standard, duration, params.exploration);
            if (!pooled.ok()) return pooled.error();
            return draw(**pooled, rng);
          });
      if (!trial_cues.ok()) return trial_cues.error();
      if (trial.method == Method::kSameDifferent &&
          params.rule != protocols::SameDifferentRule::kFixed) {
        // The block's two materials as felt: every rendering of each in the
        // pool (the population's familiarization).
        std::array<protocols::FeltMaterial, 2> felt;
        int m = 0;
        for (const std::string& id : {block.material_a, block.material_b}) {
          const protocols::ProtocolMaterial* material =
              protocol.FindMaterial(id);
          if (material == nullptr) {
            return Error{fmt::format("block \"{}\": material \"{}\" is missing",
                                     block.name, id)};
          }
          Result<const std::vector<double>*> pooled =
              pool.Cues(protocol, trial, material->set,
                        trial.intervals.at(0).duration_s, params.exploration);
          if (!pooled.ok()) return pooled.error();
          felt[static_cast<std::size_t>(m++)] =
              protocols::FeltMaterialOf(**pooled);
        }
        trial_cues->materials = felt;
      }
      Result<protocols::Response> response =
          observer.Decide(trial, *trial_cues, rng);
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
