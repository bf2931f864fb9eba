// Virtual studies: many simulated studies of one protocol, fast enough for
// power analysis and for fitting an observer population. Each subject's
// trials come from the protocol engine exactly as in `burrlab study` (same
// subject seeds, same trial order); each interval's cue is drawn from a pool
// of cues the simulator rendered for that stimulus (`cue_samples` erosion
// seeds per distinct material, task and duration, rendered once and reused:
// rendering_pool.h);
// the simulated observer answers. Nothing is journaled and no trace is kept.
// The pool keeps the simulator's own variability between renderings of one
// stimulus; what it drops is only the pairing of a cue with one particular
// erosion seed.
#ifndef BURRLAB_RUNNER_STUDIES_VIRTUAL_STUDY_H_
#define BURRLAB_RUNNER_STUDIES_VIRTUAL_STUDY_H_

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "burrlab/analysis/scores.h"
#include "burrlab/base/result.h"
#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/observer.h"
#include "burrlab/protocols/protocol.h"
#include "studies/rendering_pool.h"

namespace burrlab::runner {

// Cues of rendered intervals, cached by stimulus; the renderings come from
// a RenderingPool, its own or one shared with simulated sessions (then
// virtual and simulated studies feel the same renderings). Thread-safe.
class CuePool {
 public:
  // `samples` renderings per stimulus (erosion seeds derived from `seed`).
  CuePool(int samples, double radius_mm, std::uint64_t seed);
  // Cues of `shared`'s renderings (which must outlive this pool).
  CuePool(RenderingPool& shared, double radius_mm);

  // Renders (once) and returns the felt cues of `set` under the interval
  // options the protocol's sessions use for `trial`, explored with `e` (each
  // rendering with its own draw of the hand's force and speed:
  // RenderingPool::Present).
  Result<const std::vector<double>*> Cues(const protocols::Protocol& protocol,
                                          const protocols::TrialSpec& trial,
                                          const stimuli::MaterialSet& set,
                                          double duration_s,
                                          const protocols::Exploration& e = {});
  // Simulated intervals rendered so far.
  int rendered() const { return renderings_->rendered(); }
  double radius_mm() const { return radius_mm_; }

 private:
  std::unique_ptr<RenderingPool> own_;
  RenderingPool* renderings_;
  double radius_mm_;
  std::mutex mutex_;  // guards cues_ (whose values never move)
  std::map<std::string, std::vector<double>> cues_;
};

struct VirtualStudyOptions {
  int subjects = 20;
  std::uint64_t seed = 1;  // the study seed, as `burrlab study`
  // The population's typical observer. With a subject spread of force or
  // speed (its exploration), each subject explores with factors of its own,
  // felt through the pool's renderings at the nearest of five levels
  // (PooledExploration).
  protocols::ObserverParams observer;
  // Spread of each cue's Weber fraction across subjects (SD of ln W; 0: all
  // alike). Subject s draws one z ~ N(0, 1) and has W_stiffness x
  // exp(z spread_stiffness) and W_removal x exp(z spread_removal): one z for
  // both cues, so a keen prober is a keen driller (SubjectObserver).
  double spread_stiffness = 0.0;
  double spread_removal = 0.0;
  // Non-empty: the subjects' own observers (their number is the number of
  // subjects; `subjects` and the spreads are not used), e.g. the best
  // subjects of an earlier study.
  std::vector<protocols::ObserverParams> subject_observers;
  // Non-empty: only this block is simulated and scored; the other blocks'
  // trials are answered at once without rendering (they still run, so the
  // block sees the trials and seeds it has in a full study).
  std::string only_block;
};

// Correct answers per subject of one block with correct answers.
struct VirtualBlock {
  std::string block;
  protocols::Method method = protocols::Method::kSameDifferent;
  std::string trial_type;    // of its first trial (e.g. "2afc", "AB")
  std::vector<int> correct;  // per subject
  std::vector<int> trials;   // per subject
};

// Checks the options' numbers (subjects, spreads, observer).
Status ValidateVirtualStudy(const VirtualStudyOptions& options);

// The observer of subject `s` (0-based) of a study with `options`: its own
// entry of `subject_observers`, or the typical observer with the subject's
// draw of the spreads from the population stream of (seed, s)
// (protocols::DrawSubjectObserver). `burrlab
// study --weber-spread` draws its subjects the same way, so a real study and
// a virtual one of the same seed have the same observers.
protocols::ObserverParams SubjectObserver(const VirtualStudyOptions& options,
                                          int s);

// Runs one virtual study. Blocks without correct answers (adjustment,
// limits) are skipped; adjustment blocks are not simulated at all.
Result<std::vector<VirtualBlock>> RunVirtualStudy(
    const protocols::Protocol& protocol, const VirtualStudyOptions& options,
    CuePool& pool);

// One block of a virtual study recorded so that other populations can answer
// it again: every trial its subjects met, the cues each felt, and the
// observer stream as it stood before each decision. Answering it with
// another typical Weber fraction or spread gives exactly the block
// RunVirtualStudy gives for those options (the same subjects, trials, cues
// and noise draws: common random numbers), without running the protocol
// engine or drawing cues and noise again; an observer-population fit evaluates
// hundreds of populations of one design. Only blocks whose trials do not
// depend on the answers (same-different, two-interval, constant stimuli);
// limits, staircases and QUEST adapt.
class RecordedBlock {
 public:
  // Runs the study `options` (only_block names the block; a population, not
  // subject_observers) and records the block; the study's blocks into
  // `study` when not null.
  static Result<RecordedBlock> Record(const protocols::Protocol& protocol,
                                      const VirtualStudyOptions& options,
                                      CuePool& pool,
                                      std::vector<VirtualBlock>* study);
  // The block as RunVirtualStudy(protocol, options, pool) gives it; an error
  // when `options` differ from the recording's in anything but the typical
  // observer's Weber fractions and the spreads.
  Result<VirtualBlock> Answer(const VirtualStudyOptions& options) const;

 private:
  friend Result<std::vector<VirtualBlock>> RunRecordedStudy(
      const protocols::Protocol&, const VirtualStudyOptions&, CuePool&,
      RecordedBlock*);
  struct Decision {
    protocols::TrialSpec trial;
    std::vector<double> cues;   // TrialCues::cues
    protocols::TrialCues rest;  // its cues point at `cues` when answered
    protocols::SimulatedObserver::Noise noise;  // the decision's draws
  };
  std::string block_;
  VirtualStudyOptions options_;
  VirtualBlock shape_;  // the recorded study's block
  std::vector<Decision> decisions_;
  std::vector<std::size_t> subject_starts_;  // first decision of each subject
  std::vector<protocols::SubjectDraws> draws_;  // each subject's
};

// RunVirtualStudy, recording into `record` when not null (RecordedBlock).
Result<std::vector<VirtualBlock>> RunRecordedStudy(
    const protocols::Protocol& protocol, const VirtualStudyOptions& options,
    CuePool& pool, RecordedBlock* record);

// The outcome of many virtual studies for one block.
struct BlockPower {
  std::string block;
  std::string method;
  analysis::ChanceLevel chance;  // none: not tested (reason inside)
  int runs = 0;
  int t_significant = 0;         // one-sided t-test of proportions, p < alpha
  int binomial_significant = 0;  // exact binomial test of pooled answers
  std::vector<double> mean_scores;  // proportion correct of each study
  std::vector<double> mean_counts;  // mean correct answers of each study
};

// Runs `runs` virtual studies (study r seeded from `seed` and r) and tallies
// per scored block how often each test is significant at `alpha` against
// chance. `progress` (may be empty) gets the studies done.
Result<std::vector<BlockPower>> EstimatePower(
    const protocols::Protocol& protocol, VirtualStudyOptions options,
    std::uint64_t seed, int runs, double alpha, CuePool& pool,
    const std::function<void(int)>& progress);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_VIRTUAL_STUDY_H_
