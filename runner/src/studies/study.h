// Simulated studies: many simulated subjects run one protocol, each in its
// own session (journal, traces, BIDS exports), in parallel. `burrlab study`
// and `burrlab demo` run them.
#ifndef BURRLAB_RUNNER_STUDIES_STUDY_H_
#define BURRLAB_RUNNER_STUDIES_STUDY_H_

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "burrlab/protocols/observer.h"
#include "burrlab/stimuli/interval.h"
#include "studies/rendering_pool.h"
#include "studies/session.h"

namespace burrlab::runner {

struct SimulatedStudyOptions {
  std::filesystem::path out_dir;
  // BIDS labels of the subjects, in order; subject i gets counterbalancing
  // row i and the master seed SeedFor(seed, kSubjectSeed, i).
  std::vector<std::string> labels;
  std::vector<protocols::ObserverParams> observers;  // one per subject
  // BIDS session label of every subject's session (DIR/sub-<label>/
  // ses-<session>/); empty: none.
  std::string session;
  // The dataset's authors (dataset_description.json); none: left out.
  std::vector<std::string> authors;
  std::uint64_t seed = 1;  // the study seed
  int jobs = 1;            // parallel sessions
  double radius_mm = stimuli::kDefaultBurrRadiusMm;
  bool resume = false;  // continue subjects whose journal exists
  RenderingPool* renderings = nullptr;  // shared renderings; null: afresh
  // Called (under a lock) after each subject with (subjects done, label).
  std::function<void(int, const std::string&)> progress;
};

struct SimulatedStudyResult {
  // Per subject, in label order: the error of a failed session or export
  // (empty when it ran), and its fraction correct.
  std::vector<std::string> failures;
  std::vector<std::optional<double>> scores;
  int failed() const;
};

// Labels "01", "02", ... for n subjects (at least two digits).
std::vector<std::string> SubjectLabels(int n);

// Refuses (error naming the first) when a subject's journal (of
// options.session) exists and `resume` is off: nothing is ever overwritten.
Status CheckNoSubjectExists(const SimulatedStudyOptions& options);

// Renders every stimulus a protocol's simulated intervals use (those of the
// first `plan_subjects` subjects' plans, answered correctly) into `pool`, all
// of its renderings, on `jobs` threads; `progress` (may be empty) gets
// (renderings done, of total). Returns the number of distinct stimuli.
Result<int> PrerenderProtocol(const protocols::Protocol& protocol,
                              RenderingPool& pool, double radius_mm, int jobs,
                              int plan_subjects,
                              const std::function<void(int, int)>& progress);

// Runs every subject's session, then writes the BIDS exports, the dataset's
// README and protocol copy, and participants.tsv with every subject's
// observer parameters (a failure there is each exported subject's
// "export failed: ...").
SimulatedStudyResult RunSimulatedStudy(const protocols::LoadedProtocol& loaded,
                                       const SimulatedStudyOptions& options);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_STUDY_H_
