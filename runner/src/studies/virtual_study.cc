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
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = cues_.find(key);
    if (it != cues_.end()) return &it->second;
  }
  // Rendered outside the lock (the rendering pool renders each once, for
  // whichever thread asks first); the first to store its cues keeps them.
  Result<std::vector<double>> cues = renderings_->Cues(o, e);
  if (!cues.ok()) {
    return Error{fmt::format("rendering {} ({}, {} s): {}", set.name,
                             stimuli::TaskName(o.task), duration_s,
                             cues.error().message)};
  }
  for (double& c : *cues) c = protocols::FeltCue(c);
  std::lock_guard<std::mutex> lock(mutex_);
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

// RunVirtualStudy; with `record`, every decision of block record->block_ is
// kept in it.
Result<std::vector<VirtualBlock>> RunRecordedStudy(
    const protocols::Protocol& protocol, const VirtualStudyOptions& options,
    CuePool& pool, RecordedBlock* record) {
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
    if (record != nullptr) {
      record->subject_starts_.push_back(record->decisions_.size());
    }
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
      if (record != nullptr && trial.block == record->block_) {
        if (trial.method == Method::kLimits ||
            trial.method == Method::kStaircase ||
            trial.method == Method::kQuest) {
          return Error{fmt::format(
              "block \"{}\" ({}) adapts its trials to the answers: it cannot "
              "be answered again by other observers",
              trial.block, protocols::MethodName(trial.method))};
        }
      }
      // Decide's draws, taken apart so that a recording keeps them.
      const protocols::SimulatedObserver::Noise noise =
          observer.DrawNoise(trial, rng);
      if (record != nullptr && trial.block == record->block_) {
        protocols::TrialCues rest = *trial_cues;
        rest.cues = {};
        record->decisions_.push_back(
            {trial,
             std::vector<double>(trial_cues->cues.begin(),
                                 trial_cues->cues.end()),
             rest, noise});
      }
      Result<protocols::Response> response =
          observer.DecideWith(trial, *trial_cues, noise);
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

Result<std::vector<VirtualBlock>> RunVirtualStudy(
    const protocols::Protocol& protocol, const VirtualStudyOptions& options,
    CuePool& pool) {
  return RunRecordedStudy(protocol, options, pool, nullptr);
}

Result<RecordedBlock> RecordedBlock::Record(const protocols::Protocol& protocol,
                                            const VirtualStudyOptions& options,
                                            CuePool& pool,
                                            std::vector<VirtualBlock>* study) {
  if (options.only_block.empty()) {
    return Error{
        "recording a virtual study needs the block to record (only_block)"};
  }
  if (!options.subject_observers.empty()) {
    return Error{
        "recording a virtual study needs a population (no subject_observers)"};
  }
  RecordedBlock record;
  record.block_ = options.only_block;
  record.options_ = options;
  Result<std::vector<VirtualBlock>> blocks =
      RunRecordedStudy(protocol, options, pool, &record);
  if (!blocks.ok()) return blocks.error();
  for (const VirtualBlock& b : *blocks) {
    if (b.block == record.block_) record.shape_ = b;
  }
  if (record.shape_.block.empty()) {
    return Error{
        fmt::format("the protocol has no scored block \"{}\"", record.block_)};
  }
  const bool explores =
      options.observer.exploration.subject_force_spread > 0.0 ||
      options.observer.exploration.subject_speed_spread > 0.0;
  for (int s = 0; s < options.subjects; ++s) {
    record.draws_.push_back(protocols::DrawSubject(options.seed, s, explores));
  }
  if (study != nullptr) *study = std::move(*blocks);
  return record;
}

Result<VirtualBlock> RecordedBlock::Answer(
    const VirtualStudyOptions& options) const {
  // Everything but the typical Weber fractions and the spreads must be as
  // recorded: the same subjects, trials, cues and observer streams.
  VirtualStudyOptions same = options;
  same.observer.weber_stiffness = options_.observer.weber_stiffness;
  same.observer.weber_removal = options_.observer.weber_removal;
  same.spread_stiffness = options_.spread_stiffness;
  same.spread_removal = options_.spread_removal;
  const protocols::ObserverParams& a = same.observer;
  const protocols::ObserverParams& b = options_.observer;
  const protocols::Exploration& ea = a.exploration;
  const protocols::Exploration& eb = b.exploration;
  const bool observer_as_recorded =
      a.lapse == b.lapse && a.criterion == b.criterion && a.rule == b.rule &&
      a.bias == b.bias && a.rt_median_s == b.rt_median_s &&
      a.rt_log_sd == b.rt_log_sd && a.match_tolerance == b.match_tolerance &&
      a.answers == b.answers && ea.force_factor == eb.force_factor &&
      ea.speed_factor == eb.speed_factor &&
      ea.force_spread == eb.force_spread &&
      ea.speed_spread == eb.speed_spread &&
      ea.subject_force_spread == eb.subject_force_spread &&
      ea.subject_speed_spread == eb.subject_speed_spread;
  if (!observer_as_recorded || same.subjects != options_.subjects ||
      same.seed != options_.seed || same.only_block != options_.only_block ||
      !same.subject_observers.empty()) {
    return Error{
        "a recorded virtual study can be answered again only with other Weber "
        "fractions and spreads"};
  }
  if (Status st = ValidateVirtualStudy(options); !st.ok()) return st.error();
  VirtualBlock block = shape_;
  std::fill(block.correct.begin(), block.correct.end(), 0);
  std::fill(block.trials.begin(), block.trials.end(), 0);
  for (int s = 0; s < options.subjects; ++s) {
    const auto su = static_cast<std::size_t>(s);
    const protocols::ObserverParams params = protocols::ApplySubjectDraws(
        options.observer, {options.spread_stiffness, options.spread_removal},
        draws_[su]);
    const protocols::SimulatedObserver observer(params);
    const std::size_t end = su + 1 < subject_starts_.size()
                                ? subject_starts_[su + 1]
                                : decisions_.size();
    for (std::size_t i = subject_starts_[su]; i < end; ++i) {
      const Decision& d = decisions_[i];
      protocols::TrialCues cues = d.rest;
      cues.cues = d.cues;
      Result<protocols::Response> response =
          observer.DecideWith(d.trial, cues, d.noise);
      if (!response.ok()) return response.error();
      // As the engine scores a trial with a correct answer (a trial without
      // one is not counted).
      if (d.trial.correct_answer.empty()) continue;
      block.correct[su] += response->answer == d.trial.correct_answer ? 1 : 0;
      block.trials[su] += 1;
    }
  }
  return block;
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
