// The protocol engine: runs a parsed protocol for one subject as a sequence of
// trials. It yields the next trial (its intervals, each a material and a
// duration, the question, the answers offered and the correct one) and
// consumes the subject's response (staircase step, QUEST update, limits
// series, adjustment path). No devices, no clocks, no I/O: the same protocol,
// subject index, master seed and responses give the same trials, so a session
// is resumed by replaying its journaled responses.
//
// Randomness: one Boost.Random stream per purpose (streams.h: trial order,
// level jitter), so drawing more for one purpose never shifts another.
#ifndef BURRLAB_PROTOCOLS_ENGINE_H_
#define BURRLAB_PROTOCOLS_ENGINE_H_

#include <boost/random/mersenne_twister.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/protocol.h"

namespace burrlab::protocols {

// One interval of a planned trial.
struct PlannedInterval {
  std::string role;         // "A", "B", "standard", "comparison",
                            // "reference" or "stimulus"
  std::string material_id;  // protocol material id or "<axis>@<level>"
  std::optional<stimuli::MaterialSet> material;  // none: a real sample
                                                 // outside the computer
  double duration_s = 0.0;      // 0: subject-paced (real reference)
  std::optional<double> level;  // axis level, for axis methods
};

// A trial as the engine plans it, before the response.
struct TrialSpec {
  int trial_index = 0;     // 0-based over the whole session
  int block_index = 0;     // index into Protocol::blocks
  int block_position = 0;  // 0-based position in this subject's block order
  int trial_in_block = 0;  // 0-based within the block
  std::string block;       // block name
  Method method = Method::kSameDifferent;
  Task task = Task::kProbe;
  std::string trial_type;       // "AB", "2afc", "ascending", "staircase", ...
  std::optional<double> level;  // the varied level; none for A/B designs
  std::string stim_unit;        // unit of level; empty when none
  std::optional<double> standard_level;  // axis methods: the standard's level
  std::vector<PlannedInterval> intervals;
  std::string question;
  std::vector<std::string> response_options;  // tokens the subject may give
  std::string correct_answer;                 // empty when the design has none
  std::optional<int> staircase_id;            // interleaved staircase, 0-based

  // Pacing, from the block (Block's keys of the same names): what a runner
  // shows around the trial, so that it need not work it out.
  bool practice = false;  // familiarization (§13.5.1): recorded, not scored
  bool feedback = false;  // say "correct"/"wrong" after the answer (never
                          // when correct_answer is empty)
  double isi_s = 0.0;     // blank gap between intervals, s
  double iti_s = 0.0;     // gap after the answer, before the next trial, s
  std::optional<double> response_deadline_s;  // later answers are late
  // Before the trial, in this order: the study's instructions (the
  // session's first trial), a rest break (ended by a key press), the
  // block's instructions (the block's first trial). Empty or false: none.
  std::string study_instructions;
  bool break_before = false;
  std::string block_instructions;
};

// What the subject answered.
struct Response {
  std::string answer;  // one of the response options; empty: missed (only
                       // for non-adaptive methods); adjustment: the path,
                       // '+' and '-' steps ending in '='
  std::optional<double> response_time_s;  // s from the prompt; none: unknown
};

// What the engine made of a response.
struct Outcome {
  std::optional<bool> correct;      // none when there is no correct answer
  std::optional<bool> reversal;     // staircases
  std::optional<double> step_size;  // staircases: size of the move made
  std::optional<double> estimate;   // adaptive methods: threshold estimate
                                    // in level units, once there is one
  std::optional<double> presented_level;  // adjustment: the final level
  // The answer came after the block's response_deadline_s; none when the
  // block has no deadline or the response time is unknown.
  std::optional<bool> late;
  std::string extra = "{}";  // JSON object with method-specific fields
};

// The trial sequence of one subject.
class Engine {
 public:
  // The engine at the first trial of the first block of this subject's
  // block order; `protocol` must outlive it.
  static Result<Engine> Create(const Protocol& protocol, int subject_index,
                               std::uint64_t master_seed);
  Engine(Engine&&) noexcept;
  Engine& operator=(Engine&&) noexcept;
  ~Engine();

  // True once every block is done.
  bool finished() const;
  // The trial awaiting a response (only when !finished()).
  const TrialSpec& current() const;
  // Records the response to current() and plans the next trial. An error
  // (nothing changes) for an answer that is not an option, a missed answer
  // in an adaptive block, or a call once finished().
  Result<Outcome> Respond(const Response& response);
  // Adjustment trials: the comparison level after applying `path` ('+'/'-'
  // steps, without the final '=') to the current trial's start level.
  Result<double> PreviewAdjustment(std::string_view path) const;
  // Adjustment trials: the comparison interval (material, id, duration,
  // level) at the level `path` reaches, planned as the trial's own
  // comparison is; an error past the block's max_steps.
  Result<PlannedInterval> AdjustedComparison(std::string_view path) const;
  // The comparison material at an adjustment level (for presenting it).
  Result<stimuli::MaterialSet> MaterialAt(double level) const;
  // Serialized state of the trial-order and jitter streams (opaque text,
  // stored in TrialRecord::rng_state and compared on resume).
  std::string RngState() const;
  // Indices into Protocol::blocks in this subject's order.
  const std::vector<int>& block_order() const;
  // The protocol being run.
  const Protocol& protocol() const;
  // The master seed.
  std::uint64_t master_seed() const;

 private:
  struct Impl;
  explicit Engine(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The response a script token stands for: "1" is the correct answer (or
// "yes" where there is none), "0" a wrong one (or "no"); any other token is
// the answer itself (e.g. an adjustment path "++-=").
Result<Response> ScriptedResponse(const TrialSpec& trial,
                                  std::string_view token);

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_ENGINE_H_
