// Sessions: one subject runs a protocol. The engine plans trials, each
// interval is rendered by the simulator with a simulated hand (stimuli), the
// response comes from the simulated observer or a terminal prompt, and every
// completed trial is committed to the journal (one transaction, durable
// before the next trial starts). --resume replays the journaled responses
// through the engine, checks the random state matches the journal's, and goes
// on at the next trial; exports are rewritten at the end.
#ifndef BURRLAB_RUNNER_SESSION_H_
#define BURRLAB_RUNNER_SESSION_H_

#include <cstdint>
#include <filesystem>
#include <functional>
#include <istream>
#include <optional>
#include <ostream>
#include <string>

#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/observer.h"
#include "burrlab/protocols/protocol.h"
#include "burrlab/sim/result.h"
#include "burrlab/stimuli/interval.h"
#include "rendering_pool.h"

namespace burrlab::runner {

// The weakest cue an observer distinguishes from none: a drill interval too
// short to cut (the rate over its second half can come out 0 or negative)
// feels like 1 um/s; a probe that barely touches like 0.001 N/mm.
inline constexpr double kFeltCueFloor = 1e-3;

// The simulated-interval options of one interval of `trial` rendering `set`
// (burr radius, the protocol's observer forces and trace rate).
stimuli::IntervalOptions IntervalOptionsFor(const protocols::Protocol& p,
                                            double radius_mm,
                                            const protocols::TrialSpec& trial,
                                            const stimuli::MaterialSet& set,
                                            double duration_s,
                                            std::uint64_t seed);

// A protocol file read and parsed, with its text (for the journal's hash).
struct LoadedProtocol {
  std::string path;  // as given
  std::string text;
  protocols::Protocol protocol;
};

// Reads and parses a protocol file; the error holds every diagnostic
// formatted as `burrlab validate` prints them.
Result<LoadedProtocol> LoadProtocol(const std::string& path);
// The same for a protocol's text (e.g. one compiled in); `path` names it in
// diagnostics and the journal.
Result<LoadedProtocol> ParseLoadedProtocol(const std::string& path,
                                           std::string text);

// Prints LoadProtocol's error (a read error as one "burrlab: " line, parse
// errors as their diagnostics) and returns 1.
int ReportLoadError(std::ostream& err, const Error& error);

// Lowercase hex SHA-256 of `text` (the journal's protocol identity).
std::string Sha256Hex(std::string_view text);

// Who answers.
enum class Responder {
  kSimulated,  // the simulated observer
  kTerminal,   // a person typing answers at a prompt
};

struct SessionOptions {
  std::filesystem::path out_dir;
  std::string subject;     // BIDS label, letters and digits
  int subject_index = 0;   // counterbalancing row
  std::uint64_t seed = 1;  // master seed of this session
  bool resume = false;
  Responder responder = Responder::kSimulated;
  protocols::ObserverParams observer;  // for kSimulated
  double radius_mm = 2.0;              // burr radius of every interval
  std::istream* in = nullptr;          // kTerminal: answers
  std::ostream* prompt = nullptr;      // kTerminal: trial descriptions
  bool export_bids = true;             // write the BIDS files at the end
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
  std::optional<double> score;  // fraction correct over trials with an
                                // answer key, when any
};

// Runs (or resumes) one subject's session.
Result<SessionSummary> RunSession(const LoadedProtocol& loaded,
                                  const SessionOptions& options);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_SESSION_H_
