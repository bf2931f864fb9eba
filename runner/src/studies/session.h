// Sessions: one subject runs a protocol. The engine plans trials, each
// interval is rendered by the simulator with a simulated hand (stimuli) and
// the response comes from the simulated observer or a terminal prompt, or a
// person at a station (LiveStation) feels the intervals through a haptic
// device and answers in the subject window; every
// completed trial is committed to the journal (one transaction, durable
// before the next trial starts). --resume replays the journaled responses
// through the engine, checks the random state matches the journal's, and goes
// on at the next trial; exports are rewritten at the end.
#ifndef BURRLAB_RUNNER_STUDIES_SESSION_H_
#define BURRLAB_RUNNER_STUDIES_SESSION_H_

#include <cstdint>
#include <filesystem>
#include <functional>
#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/observer.h"
#include "burrlab/protocols/protocol.h"
#include "burrlab/protocols/protocol_file.h"
#include "burrlab/results_schema/dataset_files.h"
#include "burrlab/results_schema/participants.h"
#include "burrlab/results_schema/records.h"
#include "burrlab/stimuli/interval.h"
#include "common/loop_counters.h"
#include "studies/rendering_pool.h"

namespace burrlab::runner {

// The simulated-interval options of one interval of `trial` rendering `set`
// (burr radius, the protocol's observer forces and trace rate).
stimuli::IntervalOptions IntervalOptionsFor(const protocols::Protocol& p,
                                            double radius_mm,
                                            const protocols::TrialSpec& trial,
                                            const stimuli::MaterialSet& set,
                                            double duration_s,
                                            std::uint64_t seed);

// The protocol loader lives in protocols (protocol_file.h); these names keep
// the runner's tests unchanged.
using protocols::LoadedProtocol;
using protocols::LoadProtocol;
using protocols::ParseLoadedProtocol;

// Refuses a protocol when a simulated interval with burr radius radius_mm
// cannot render a stimulus one of its blocks can reach
// (protocols::CheckSimulatedIntervals): the error holds the diagnostics as
// `burrlab validate` prints them. Runs that render simulated intervals check
// this before they write anything.
Status CheckRenderable(const protocols::LoadedProtocol& loaded,
                       double radius_mm);

// Prints protocols::LoadProtocol's error (a read error as one "burrlab: " line,
// parse errors as their diagnostics) and returns 1.
int ReportLoadError(std::ostream& err, const Error& error);

// Lowercase hex SHA-256 of `text` (the journal's protocol identity).
std::string Sha256Hex(std::string_view text);

// Who answers.
enum class Responder {
  kSimulated,  // the simulated observer
  kTerminal,   // a person typing answers at a prompt
  kStation,    // a person at a station (SessionOptions::station)
};

// What one interval of a live trial left behind: the haptic loop's timing and
// counters, and what the simulator rendered. Stored in the trial's `extra`
// ("intervals").
struct LiveIntervalRecord {
  int interval_index = 0;  // 0-based within the trial
  double rate_hz = 1000.0;
  LoopCounters counters;
  LoopStats stats;
  double max_force_n = 0.0;    // the loop's clamp (station and device)
  double c_e_n_per_mm2 = 0.0;  // the elastic constant rendered
  // The material's c_e when the stiffness limit lowered it (else none).
  std::optional<double> c_e_limited_from_n_per_mm2;
};

// One trial as a person at a station did it.
struct LiveTrial {
  // The answer; none when the session stops here (stop_reason says why and
  // the trial is not recorded).
  std::optional<protocols::Response> response;
  std::string stop_reason;
  // The traces of the simulated intervals; start_time_s counts from the
  // trial's start.
  std::vector<results_schema::TraceSamples> traces;
  std::vector<LiveIntervalRecord> intervals;  // one per simulated interval
  double duration_s = 0.0;        // from the trial's start to the answer
  int aborted_presentations = 0;  // times the trial was cut short and shown
                                  // again (a device fault, a pause)
};

// Adjustment trials: the comparison at the level that `path` ('+' and '-'
// steps from the trial's start) reaches, or none when the block allows no
// more steps (max_steps).
using AdjustedComparison =
    std::function<Result<std::optional<protocols::PlannedInterval>>(
        std::string_view path)>;

// A subject station: presents trials to a person and brings back answers.
class LiveStation {
 public:
  virtual ~LiveStation() = default;
  // Presents `trial` (after trials_done completed trials) until the subject
  // answers or the session stops; an error is a failure of the station.
  // `adjusted` gives an adjustment trial's comparison after each step.
  virtual Result<LiveTrial> PresentTrial(
      const protocols::TrialSpec& trial, int trials_done,
      const AdjustedComparison& adjusted) = 0;
  // After the trial's answer is saved: feedback (when the trial gives it;
  // `correct` is the engine's verdict) and the gap after the answer. Returns
  // why the session stops there (the window was closed, the experimenter
  // aborted), or empty to go on.
  virtual std::string AfterAnswer(const protocols::TrialSpec& trial,
                                  std::optional<bool> correct) {
    (void)trial;
    (void)correct;
    return {};
  }
  // Shows that the session ran to its end.
  virtual void Finish() = 0;
};

struct SessionOptions {
  std::filesystem::path out_dir;
  std::string subject;  // BIDS label, letters and digits
  // BIDS session label (letters and digits), e.g. "2" for the subject's
  // second visit: the journal and files go to DIR/sub-<subject>/ses-<session>/
  // and --resume continues that session; empty: DIR/sub-<subject>/.
  std::string session;
  // The dataset's authors, one name each (dataset_description.json).
  std::vector<std::string> authors;
  // What the experimenter records of the subject (participants.tsv, e.g.
  // age, group); a simulated subject's row also gets its observer's
  // parameters (participant_rows.h).
  std::vector<results_schema::ParticipantValue> participant;
  int subject_index = 0;   // counterbalancing row
  std::uint64_t seed = 1;  // master seed of this session
  bool resume = false;
  Responder responder = Responder::kSimulated;
  protocols::ObserverParams observer;  // for kSimulated
  double radius_mm =
      stimuli::kDefaultBurrRadiusMm;  // burr radius of every interval
  std::istream* in = nullptr;         // kTerminal: answers
  std::ostream* prompt = nullptr;     // kTerminal: trial descriptions
  // kTerminal: false when the answers come from a pipe or a file, not a
  // person at a terminal; their response times are then not recorded (n/a),
  // and instructions and rest breaks are printed without waiting for Enter
  // (which would take an answer).
  bool answers_timed = true;
  LiveStation* station = nullptr;  // kStation: the station
  // kStation: the device backend ("mouse", "hid", ...) and the SHA-256 of the
  // station file (empty when none); recorded in the journal's setup. (A
  // simulated device's script stands for the person and may change.)
  std::string device;
  std::string station_file_sha256;
  bool export_bids = true;  // write the BIDS files at the end
  // Non-null: intervals come from this shared pool of renderings (picked by
  // each interval's erosion seed) instead of being rendered afresh; trials
  // record the pool's size in their `extra` ("rendering_pool").
  RenderingPool* renderings = nullptr;
  // Tests only: caps the journal's size so a write fails (SQLITE_FULL); 0 =
  // no cap.
  std::int64_t journal_limit_bytes_for_testing = 0;
  // Called after each committed trial with (trials done, label); may be
  // empty.
  std::function<void(int, const std::string&)> on_trial;
};

struct SessionSummary {
  int trials_run = 0;           // trials run now
  int trials_resumed = 0;       // trials found in the journal
  int trials_total = 0;         // trials in the journal at the end
  bool finished = false;        // the protocol ran to its end
  std::string stop_reason;      // why it stopped early (kStation), if it did
  std::optional<double> score;  // fraction correct over scored trials
                                // (with an answer key, not practice)
};

// What shapes a session's results besides its protocol and seed, as the
// journal records it and --resume checks it: radius_mm, voxel_mm,
// subject_index, responder ("typed", "station" or "simulated" with every
// observer parameter), device, station_file_sha256 and renderings ("fresh" or
// the shared pool's size); "none" where not used.
std::vector<results_schema::SetupField> SessionSetup(
    const SessionOptions& options);

// The number of trials `protocol` presents for this subject and seed (the
// station's "Trial k of N", the journal's planned trials); 0 when that is not
// known ahead (limits, adjustment, staircase and QUEST blocks depend on the
// answers).
int PlannedTrials(const protocols::Protocol& protocol, int subject_index,
                  std::uint64_t seed);

// OK when every author can be listed (results_schema::ValidateAuthor) and
// every value can be a participants.tsv cell of the session's row: a column
// checked by results_schema::CheckParticipantColumn, not an observer_*
// column (burrlab's), each column once.
Status CheckDatasetOptions(
    const std::vector<std::string>& authors,
    const std::vector<results_schema::ParticipantValue>& values);

// What a dataset's README and code/ say of `loaded` (dataset_files.h).
results_schema::DatasetSource DatasetSourceOf(
    const protocols::LoadedProtocol& loaded);

// The participants.tsv row of a session: options.participant, then a
// simulated observer's parameters.
results_schema::ParticipantRow SessionParticipantRow(
    const SessionOptions& options);

// Writes a session's exports (results_schema::ExportBids with its session
// and authors), the dataset's README and protocol copy, and merges its
// subject's row into participants.tsv.
Status ExportSession(const protocols::LoadedProtocol& loaded,
                     const SessionOptions& options);

// Runs (or resumes) one subject's session. The session's lock is held from
// the journal's opening to the end of the export; a --resume of a journal
// with no trial starts it again with the protocol and set-up given now. The
// journal records the planned trials when it opens and the session's
// completion when the protocol has run to its end, before the export (which
// marks a session that stopped early as incomplete).
Result<SessionSummary> RunSession(const protocols::LoadedProtocol& loaded,
                                  const SessionOptions& options);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STUDIES_SESSION_H_
