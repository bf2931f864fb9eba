// A shared pool of simulator renderings: each distinct stimulus (material,
// task, duration, burr and hand settings: everything an interval renders but
// its erosion seed) is rendered `renderings` times, once each, and every
// interval of that stimulus gets one of these renderings, picked by its
// erosion seed. Sessions of a simulated study then cost a few renderings per
// stimulus instead of one per interval (`burrlab study --renderings K`,
// `burrlab demo`); the pool keeps the simulator's variability between
// renderings of a stimulus and drops only the pairing of an interval with
// its own erosion seed. A rendering depends only on (pool seed, stimulus,
// index), never on which thread asked first, so results are the same for any
// number of jobs. Thread-safe.
#ifndef BURRLAB_RUNNER_STUDIES_RENDERING_POOL_H_
#define BURRLAB_RUNNER_STUDIES_RENDERING_POOL_H_

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/observer.h"
#include "burrlab/stimuli/interval.h"

namespace burrlab::runner {

// The most z-levels a pooled subject factor is held to either side of 1.
inline constexpr double kPooledSubjectLevel = 2.0;

// What a pool renders for a subject exploring with `e`: its typical force and
// speed factors held to the nearest of five levels, exp(z s) with z in {-2,
// ..., 2} and s the subject spread (a population then costs at most five
// sets of renderings per stimulus instead of one per subject; a factor is
// off by at most half a level, s / 2 in ln, for |z| <= 2.5); for a drill, no
// speed (a drill holds its force, so the pressing speed does nothing).
protocols::Exploration PooledExploration(const protocols::Exploration& e,
                                         stimuli::Task task);

// The bytes of everything `o` renders but its seed, and of `e` when it
// varies (a map key).
std::string StimulusKey(const stimuli::IntervalOptions& o,
                        const protocols::Exploration& e = {});

class RenderingPool {
 public:
  // `renderings` >= 1 per stimulus; `keep_traces` false drops the trace rows
  // (cue-only use).
  RenderingPool(int renderings, std::uint64_t seed, bool keep_traces = true);
  RenderingPool(const RenderingPool&) = delete;
  RenderingPool& operator=(const RenderingPool&) = delete;

  // The rendering of `o`'s stimulus with index o.seed mod renderings (a
  // copy; rendered on first use). With an exploration that varies, the
  // stimulus is `o` explored with PooledExploration(e), and each rendering is
  // protocols::ExploredInterval of `o` with its own draw (from the pool seed,
  // the stimulus and the index): the pool's renderings then sample the hand's
  // variability too, with as many draws as renderings.
  Result<stimuli::IntervalResult> Present(const stimuli::IntervalOptions& o,
                                          const protocols::Exploration& e = {});
  // The cues of all renderings of `o`'s stimulus, in index order.
  Result<std::vector<double>> Cues(const stimuli::IntervalOptions& o,
                                   const protocols::Exploration& e = {});

  int renderings() const { return renderings_; }
  std::uint64_t seed() const { return seed_; }
  // Simulator intervals rendered so far.
  int rendered() const;

 private:
  struct Slot {
    std::mutex mutex;
    bool done = false;
    Result<stimuli::IntervalResult> result = Error{"not rendered"};
  };
  struct Entry {
    std::vector<std::unique_ptr<Slot>> slots;
  };
  Entry& EntryFor(const std::string& key);
  Result<stimuli::IntervalResult> Render(const stimuli::IntervalOptions& o,
                                         const protocols::Exploration& e,
                                         const std::string& key, int index);
  const Result<stimuli::IntervalResult>& Get(const stimuli::IntervalOptions& o,
                                             const protocols::Exploration& e,
                                             const std::string& key, int index);

  int renderings_;
  std::uint64_t seed_;
  bool keep_traces_;
  mutable std::mutex mutex_;  // guards entries_ and rendered_
  std::map<std::string, std::unique_ptr<Entry>> entries_;
  int rendered_ = 0;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_RENDERING_POOL_H_
