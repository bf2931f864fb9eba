// The shared rendering pool (see rendering_pool.h).
#include "studies/rendering_pool.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "burrlab/protocols/streams.h"

namespace burrlab::runner {
namespace {

// Erosion seeds of pooled renderings, apart from every session's streams
// (sessions index their erosion streams by trial and interval, far below).
constexpr std::uint64_t kPoolStreamBase = 1ull << 41;

// FNV-1a of the key: a stimulus's renderings get seeds from its own bytes,
// not from the order stimuli were first asked for.
std::uint64_t Fnv1a(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

protocols::Exploration PooledExploration(const protocols::Exploration& e,
                                         stimuli::Task task) {
  protocols::Exploration pooled = e;
  auto level = [](double factor, double spread) {
    if (!(spread > 0.0)) return factor;
    const double z = std::clamp(std::round(std::log(factor) / spread),
                                -kPooledSubjectLevel, kPooledSubjectLevel);
    return std::exp(z * spread);
  };
  pooled.force_factor = level(e.force_factor, e.subject_force_spread);
  pooled.speed_factor = level(e.speed_factor, e.subject_speed_spread);
  if (task == stimuli::Task::kDrill) {
    // A drill holds its force: how fast the hand would press does nothing.
    pooled.speed_factor = 1.0;
    pooled.speed_spread = 0.0;
  }
  return pooled;
}

std::string StimulusKey(const stimuli::IntervalOptions& o,
                        const protocols::Exploration& e) {
  const double values[] = {o.material.c_e_n_per_mm2,
                           o.material.alpha_per_s,
                           o.material.c_mu_n_per_mm2,
                           o.material.mu,
                           o.material.c_i_n_s_per_mm3,
                           static_cast<double>(o.task),
                           o.duration_s,
                           o.radius_mm,
                           o.spindle_rad_s,
                           o.probe_force_n,
                           o.press_period_s,
                           o.drill_force_n,
                           o.voxel_mm,
                           static_cast<double>(o.trace_hz)};
  std::string key(reinterpret_cast<const char*>(values), sizeof values);
  if (e.Varies()) {
    const double exploration[] = {e.force_factor, e.speed_factor,
                                  e.force_spread, e.speed_spread};
    key.append(reinterpret_cast<const char*>(exploration), sizeof exploration);
  }
  return key;
}

RenderingPool::RenderingPool(int renderings, std::uint64_t seed,
                             bool keep_traces)
    : renderings_(std::max(1, renderings)),
      seed_(seed),
      keep_traces_(keep_traces) {}

int RenderingPool::rendered() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rendered_;
}

RenderingPool::Entry& RenderingPool::EntryFor(const std::string& key) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::unique_ptr<Entry>& entry = entries_[key];
  if (entry == nullptr) {
    entry = std::make_unique<Entry>();
    for (int k = 0; k < renderings_; ++k) {
      entry->slots.push_back(std::make_unique<Slot>());
    }
  }
  return *entry;
}

Result<stimuli::IntervalResult> RenderingPool::Render(
    const stimuli::IntervalOptions& o, const protocols::Exploration& e,
    const std::string& key, int index) {
  const std::uint64_t stimulus = kPoolStreamBase + (Fnv1a(key) >> 24);
  stimuli::IntervalOptions r = o;
  if (e.Varies()) {
    boost::random::mt19937 stream =
        protocols::StreamFor(seed_, protocols::StreamPurpose::kExploration,
                             stimulus, static_cast<std::uint64_t>(index));
    r = protocols::ExploredInterval(o, e, stream);
  }
  r.seed = protocols::SeedFor(seed_, protocols::StreamPurpose::kErosion,
                              stimulus, static_cast<std::uint64_t>(index));
  Result<stimuli::IntervalResult> result = stimuli::PresentSimulatedInterval(r);
  if (result.ok() && !keep_traces_) result->rows.clear();
  std::lock_guard<std::mutex> lock(mutex_);
  ++rendered_;
  return result;
}

const Result<stimuli::IntervalResult>& RenderingPool::Get(
    const stimuli::IntervalOptions& o, const protocols::Exploration& e,
    const std::string& key, int index) {
  Slot& slot = *EntryFor(key).slots[static_cast<std::size_t>(index)];
  std::lock_guard<std::mutex> lock(slot.mutex);
  if (!slot.done) {
    slot.result = Render(o, e, key, index);
    slot.done = true;
  }
  return slot.result;
}

Result<stimuli::IntervalResult> RenderingPool::Present(
    const stimuli::IntervalOptions& o, const protocols::Exploration& e) {
  const protocols::Exploration pooled = PooledExploration(e, o.task);
  const std::string key = StimulusKey(o, pooled);
  const int index =
      static_cast<int>(o.seed % static_cast<std::uint64_t>(renderings_));
  return Get(o, pooled, key, index);
}

Result<std::vector<double>> RenderingPool::Cues(
    const stimuli::IntervalOptions& o, const protocols::Exploration& e) {
  const protocols::Exploration pooled = PooledExploration(e, o.task);
  const std::string key = StimulusKey(o, pooled);
  std::vector<double> cues;
  for (int k = 0; k < renderings_; ++k) {
    const Result<stimuli::IntervalResult>& r = Get(o, pooled, key, k);
    if (!r.ok()) return r.error();
    cues.push_back(r->cue);
  }
  return cues;
}

}  // namespace burrlab::runner
