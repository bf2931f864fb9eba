// Simulated studies (see study.h).
#include "studies/study.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <thread>

#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/streams.h"
#include "burrlab/results_schema/bids_export.h"
#include "burrlab/results_schema/dataset_files.h"
#include "burrlab/results_schema/dataset_layout.h"
#include "burrlab/results_schema/journal.h"
#include "burrlab/results_schema/participants.h"
#include "studies/participant_rows.h"

namespace burrlab::runner {

int SimulatedStudyResult::failed() const {
  return static_cast<int>(
      std::count_if(failures.begin(), failures.end(),
                    [](const std::string& f) { return !f.empty(); }));
}

std::vector<std::string> SubjectLabels(int n) {
  const int width = std::max(2, static_cast<int>(std::to_string(n).size()));
  std::vector<std::string> labels;
  for (int i = 0; i < n; ++i) {
    labels.push_back(fmt::format("{:0{}}", i + 1, width));
  }
  return labels;
}

Status CheckNoSubjectExists(const SimulatedStudyOptions& options) {
  if (options.resume) return {};
  for (const std::string& label : options.labels) {
    std::error_code ec;
    if (std::filesystem::exists(results_schema::JournalPath(
                                    options.out_dir, label, options.session),
                                ec)) {
      return Error{fmt::format(
          "{} already exists in {}; use --resume to continue the study",
          results_schema::SessionName(label, options.session),
          options.out_dir.string())};
    }
  }
  return {};
}

Result<int> PrerenderProtocol(const protocols::Protocol& protocol,
                              RenderingPool& pool, double radius_mm, int jobs,
                              int plan_subjects,
                              const std::function<void(int, int)>& progress) {
  std::map<std::string, stimuli::IntervalOptions> stimuli;
  for (int s = 0; s < std::max(1, plan_subjects); ++s) {
    Result<protocols::Engine> engine = protocols::Engine::Create(
        protocol, s,
        protocols::SeedFor(1, protocols::StreamPurpose::kSubjectSeed,
                           static_cast<std::uint64_t>(s)));
    if (!engine.ok()) return engine.error();
    while (!engine->finished()) {
      const protocols::TrialSpec trial = engine->current();
      for (const protocols::PlannedInterval& iv : trial.intervals) {
        if (!iv.material.has_value()) continue;
        stimuli::IntervalOptions o = IntervalOptionsFor(
            protocol, radius_mm, trial, *iv.material, iv.duration_s, 0);
        stimuli.emplace(StimulusKey(o), o);
      }
      protocols::Response answer;
      answer.answer = trial.correct_answer.empty()
                          ? trial.response_options.front()
                          : trial.correct_answer;
      Result<protocols::Outcome> outcome = engine->Respond(answer);
      if (!outcome.ok()) return outcome.error();
    }
  }
  std::vector<stimuli::IntervalOptions> work;
  for (const auto& [key, o] : stimuli) {
    for (int k = 0; k < pool.renderings(); ++k) {
      work.push_back(o);
      work.back().seed = static_cast<std::uint64_t>(k);  // picks rendering k
    }
  }
  const int total = static_cast<int>(work.size());
  std::atomic<int> next{0};
  std::mutex mutex;
  int done = 0;
  std::string failure;
  auto worker = [&]() {
    for (;;) {
      const int i = next.fetch_add(1);
      if (i >= total) return;
      Result<stimuli::IntervalResult> r =
          pool.Present(work[static_cast<std::size_t>(i)]);
      std::lock_guard<std::mutex> lock(mutex);
      if (!r.ok() && failure.empty()) failure = r.error().message;
      if (progress) progress(++done, total);
    }
  };
  std::vector<std::thread> threads;
  for (int j = 0; j < std::min(std::max(1, jobs), std::max(1, total)); ++j) {
    threads.emplace_back(worker);
  }
  for (std::thread& t : threads) t.join();
  if (!failure.empty()) return Error{"rendering a stimulus: " + failure};
  return static_cast<int>(stimuli.size());
}

SimulatedStudyResult RunSimulatedStudy(const protocols::LoadedProtocol& loaded,
                                       const SimulatedStudyOptions& options) {
  const int n = static_cast<int>(options.labels.size());
  SimulatedStudyResult result;
  result.failures.resize(options.labels.size());
  result.scores.resize(options.labels.size());
  // What the exports would refuse at the end is refused before any session.
  Status dataset = CheckDatasetOptions(options.authors, {});
  if (dataset.ok()) {
    dataset = results_schema::CheckParticipantsFiles(options.out_dir);
  }
  if (!dataset.ok()) {
    for (std::string& failure : result.failures) {
      failure = dataset.error().message;
    }
    return result;
  }
  std::mutex mutex;
  std::atomic<int> next{0};
  int done = 0;
  auto worker = [&]() {
    for (;;) {
      const int i = next.fetch_add(1);
      if (i >= n) return;
      const std::size_t k = static_cast<std::size_t>(i);
      SessionOptions session;
      session.out_dir = options.out_dir;
      session.subject = options.labels[k];
      session.session = options.session;
      session.authors = options.authors;
      session.subject_index = i;
      session.seed = protocols::SeedFor(options.seed,
                                        protocols::StreamPurpose::kSubjectSeed,
                                        static_cast<std::uint64_t>(i));
      session.observer = options.observers.at(k);
      session.radius_mm = options.radius_mm;
      session.export_bids = false;
      session.renderings = options.renderings;
      std::error_code ec;
      session.resume =
          options.resume &&
          std::filesystem::exists(
              results_schema::JournalPath(options.out_dir, session.subject,
                                          session.session),
              ec);
      Result<SessionSummary> summary = RunSession(loaded, session);
      std::lock_guard<std::mutex> lock(mutex);
      if (!summary.ok()) {
        result.failures[k] = summary.error().message;
      } else {
        result.scores[k] = summary->score;
      }
      if (options.progress) options.progress(++done, session.subject);
    }
  };
  std::vector<std::thread> threads;
  for (int j = 0; j < std::min(std::max(1, options.jobs), n); ++j) {
    threads.emplace_back(worker);
  }
  for (std::thread& t : threads) t.join();
  std::vector<results_schema::ParticipantRow> participants;
  for (std::size_t i = 0; i < options.labels.size(); ++i) {
    if (!result.failures[i].empty()) continue;
    if (Status s =
            results_schema::ExportBids(options.out_dir, options.labels[i],
                                       {options.session, options.authors});
        !s.ok()) {
      result.failures[i] = "export failed: " + s.error().message;
      continue;
    }
    participants.push_back(
        {options.labels[i], ObserverParticipantValues(options.observers[i])});
  }
  if (participants.empty()) return result;
  dataset = results_schema::WriteDatasetSource(options.out_dir,
                                               DatasetSourceOf(loaded));
  if (dataset.ok()) {
    dataset = results_schema::UpdateParticipants(options.out_dir, participants,
                                                 ObserverParticipantColumns());
  }
  if (!dataset.ok()) {
    for (std::string& failure : result.failures) {
      if (failure.empty()) {
        failure = "export failed: " + dataset.error().message;
      }
    }
  }
  return result;
}

}  // namespace burrlab::runner
