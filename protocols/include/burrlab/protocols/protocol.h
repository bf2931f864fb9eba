// Protocol files (format "burrlab-protocol/1", TOML; the author's guide is
// protocols/README.md): the parsed, validated model of a study, and the
// diagnostics `burrlab validate` prints. Parsing checks everything it can
// without running the study (types, ranges, unknown keys, unknown materials,
// designs that cannot be balanced, staircases that can never stop, levels a
// block can reach whose material cannot be presented) and reports every
// problem it finds, each with its place in the file; CheckSimulatedIntervals
// adds what depends on the run's burr.
#ifndef BURRLAB_PROTOCOLS_PROTOCOL_H_
#define BURRLAB_PROTOCOLS_PROTOCOL_H_

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "burrlab/base/result.h"
#include "burrlab/protocols/adjustment.h"
#include "burrlab/protocols/constant_stimuli.h"
#include "burrlab/protocols/limits.h"
#include "burrlab/protocols/quest.h"
#include "burrlab/protocols/same_different.h"
#include "burrlab/protocols/staircase.h"
#include "burrlab/protocols/two_interval.h"
#include "burrlab/stimuli/interval.h"
#include "burrlab/stimuli/materials.h"

namespace burrlab::protocols {

// Format id every protocol file starts with (`format = "..."`).
inline constexpr std::string_view kProtocolFormat = "burrlab-protocol/1";
// Largest protocol file read (bytes); larger files are refused unread.
inline constexpr std::uint64_t kMaxProtocolBytes = 1 << 20;

// A place in a protocol file: 1-based line and column; 0 when unknown (then
// the diagnostic names the file only).
struct SourceLocation {
  int line = 0;
  int column = 0;
};

// An error stops the file from being used; a note says what reads but should
// change (an old spelling).
enum class Severity { kError, kNote };

// One problem found in a protocol file.
struct Diagnostic {
  SourceLocation where;  // the offending key or value
  std::string message;   // one line: what is wrong and what is accepted
  Severity severity = Severity::kError;
};

// "path:line:col: error: message" ("note:" for a note), then the source line
// and a caret under the column, each line ending in '\n'. Without a location:
// "path: error: message\n". `text` is the whole file. Control characters and
// bytes that are not UTF-8 in the message and the source line are escaped
// (\x1b; see burrlab/base/printable.h), except the source line's tabs, which
// the caret line copies so that it lines up.
std::string FormatDiagnostic(std::string_view path, std::string_view text,
                             const Diagnostic& diagnostic);

// Most diagnostics FormatDiagnostics prints; the rest are only counted.
inline constexpr std::size_t kMaxPrintedDiagnostics = 100;

// The first kMaxPrintedDiagnostics diagnostics as FormatDiagnostic formats
// them, then "path: ... and N more errors\n" when there are more. Time and
// output are linear in the text and the number of diagnostics.
std::string FormatDiagnostics(std::string_view path, std::string_view text,
                              std::span<const Diagnostic> diagnostics);

// What the subject does in every interval of a block (probe or drill).
using stimuli::Task;
using stimuli::TaskName;

// A material parameter an axis varies (names as in sim::Material).
enum class MaterialParameter {
  kCE,     // "c_e": elastic coefficient c_e, N/mm^2 (eq. 6.12/7.3)
  kAlpha,  // "alpha": erosion rate alpha, 1/s (eq. 7.12)
  kCMu,    // "c_mu": friction coefficient c_mu, N/mm^2 (eq. 6.23)
  kMu,     // "mu": Coulomb friction coefficient mu
  kCI,     // "c_i": impact coefficient c_i, N s/mm^3 (eq. 7.14)
};
// "c_e", "alpha", "c_mu", "mu" or "c_i".
std::string_view MaterialParameterName(MaterialParameter parameter);
// The parameter's value in `material`.
double GetParameter(const sim::Material& material, MaterialParameter parameter);
// `material` with the parameter set to `value`.
sim::Material WithParameter(sim::Material material, MaterialParameter parameter,
                            double value);

// Largest value of a material parameter, in its unit: what [materials]
// accepts, and what a level on an axis may give.
inline constexpr double kMaxMaterialParameter = 1e6;

// A material a block may present, as declared under [materials.<id>].
struct ProtocolMaterial {
  std::string id;            // the key after "materials.", e.g. "bone"
  std::string builtin;       // built-in name when declared with builtin = ...
  stimuli::MaterialSet set;  // resolved parameters (built-in or inline)
  SourceLocation where;      // the [materials.<id>] table
};

// How an axis turns a level into a material.
enum class AxisKind {
  kRatio,      // parameter = reference's parameter x level (level > 0)
  kIncrement,  // parameter = reference's parameter x (1 + level) (level > -1)
  kValue,      // parameter = level (level > 0, in the parameter's unit)
  kLogInterpolation,  // every parameter = from^(1 - level) x to^level
                      // (level in [0, 1]: 0 is `from`, 1 is `to`)
};
// "ratio", "increment", "value" or "log_interpolation".
std::string_view AxisKindName(AxisKind kind);

// A stimulus axis declared under [axes.<id>].
struct Axis {
  std::string id;  // the key after "axes."
  AxisKind kind = AxisKind::kRatio;
  MaterialParameter parameter = MaterialParameter::kCE;  // not for
                                                         // log_interpolation
  std::string reference;  // material id (ratio, increment, value)
  std::string from;       // material id (log_interpolation)
  std::string to;         // material id (log_interpolation)
  SourceLocation where;   // the [axes.<id>] table
};
// Unit of an axis's levels: "ratio", "fraction", "t" (log_interpolation) or
// the parameter's unit for kValue ("N/mm^2", "1/s", "1", "N s/mm^3").
std::string AxisUnit(const Axis& axis);

enum class Method {
  kSameDifferent,    // "same_different"
  kTwoInterval,      // "two_interval" (design "2afc" or "reference")
  kConstantStimuli,  // "constant_stimuli"
  kLimits,           // "limits"
  kAdjustment,       // "adjustment"
  kStaircase,        // "staircase"
  kQuest,            // "quest"
};
// The method's name in protocol files and results, e.g. "same_different".
std::string_view MethodName(Method method);

// How a two_interval block is laid out.
enum class TwoIntervalDesign {
  k2Afc,       // "2afc": standard and comparison in random order
  kReference,  // "reference": reference, then A and B (§13.5.2)
};

// Response mode of a staircase or QUEST block.
enum class AdaptiveResponse {
  k2Afc,   // "2afc": standard and comparison, which one is "more"
  kYesNo,  // "yesno": one interval at the level; "yes" counts as correct
};

// A stimulus a block can present at an end of its range, as the parser found
// it: a material the block names, or the material at its standard or at the
// lowest or highest level it can reach on its axis.
struct ReachedStimulus {
  std::string what;      // for messages, e.g. "blocks[1].floor = 0.01" or
                         // "blocks[1]: 25 steps of 0.1 down from start_level
                         // 0.5 reach level -2"
  SourceLocation where;  // the key (or table) it comes from
  std::optional<double> level;  // on the block's axis; none: a material the
                                // block names
  stimuli::MaterialSet set;     // the material presented
};

// One block of trials ([[blocks]]).
struct Block {
  std::string name;  // unique within the protocol; default "block<k>"
  Method method = Method::kSameDifferent;
  Task task = Task::kProbe;
  std::string instructions;        // shown before the block; may be empty
  std::string question;            // shown after the intervals; method default
  std::vector<double> interval_s;  // duration of each interval, s (> 0; a
                                   // real reference interval is 0 =
                                   // subject-paced)
  SourceLocation where;            // the [[blocks]] table

  // How the block is paced and what the subject is told (§13.5.1: the
  // subjects had a familiarization phase before the scored trials).
  bool practice = false;  // familiarization: recorded, never scored
  bool feedback = false;  // "correct"/"wrong" after each answer (default:
                          // practice, where the design has a correct answer)
  double isi_s = 0.0;     // blank gap between a trial's intervals, s
  double iti_s = 0.0;     // gap after the answer before the next trial, s
  // Answers later than this (s from the question) are recorded and marked
  // late; none: no deadline.
  std::optional<double> response_deadline_s;
  // A rest break after every N trials of the block; none: no breaks.
  std::optional<int> break_every;

  // same_different, two_interval: the two materials (ids in [materials]).
  std::string material_a;  // same_different "a"; 2afc "standard"; ref. "a"
  std::string material_b;  // same_different "b"; 2afc "comparison"; ref. "b"
  SameDifferentOptions same_different;
  TwoIntervalDesign design = TwoIntervalDesign::k2Afc;
  TwoIntervalOptions two_interval;
  ReferenceDesignOptions reference;
  std::string reference_material;     // reference design: simulated reference
                                      // id, or empty for a real sample
  std::string reference_description;  // reference design: what the real
                                      // sample is (shown to experimenter)

  // Axis methods (constant_stimuli, limits, adjustment, staircase, quest).
  std::string axis;             // id in [axes]
  double standard_level = 0.0;  // level of the standard interval
  ConstantStimuliOptions constant_stimuli;
  LimitsOptions limits;
  AdjustmentOptions adjustment;
  int adjustment_repetitions = 1;            // adjustments in the block
  std::vector<StaircaseOptions> staircases;  // one, or several interleaved
  int threshold_reversals = 6;  // staircase estimate: mean of the last k
  AdaptiveResponse adaptive_response = AdaptiveResponse::k2Afc;
  QuestOptions quest;  // intensities are log10(level)
  int quest_trials = 40;
  // QUEST placements, 10^intensity rounded to 12 significant digits
  // (levels.h), are clamped to [floor, ceiling] (and to AxisDomain).
  double quest_floor_level = -std::numeric_limits<double>::infinity();
  double quest_ceiling_level = std::numeric_limits<double>::infinity();

  // Every material the block names and, on its axis, the standard and the
  // lowest and highest levels it can reach (staircases and adjustments
  // without a floor or ceiling: as far as their steps can go), each giving a
  // material within kMaxMaterialParameter. CheckSimulatedIntervals checks
  // them against the run's burr.
  std::vector<ReachedStimulus> reach;
};

// Why a block's trials cannot be given feedback (the design has no correct
// answer, or one that only repeats the answer), or empty when they can.
std::string NoFeedbackReason(const Block& block);

// Counterbalancing of block order across subjects.
enum class Counterbalance {
  kNone,         // "none": blocks in file order for everyone
  kLatinSquare,  // "latin_square": row (subject_index mod n) of a balanced
                 // Latin square (Williams design for an even n)
  kReverse,      // "reverse": odd subject indices run the blocks in reverse
};

// How a same-different observer decides whether a trial's two intervals
// differ (Macmillan & Creelman 2005, "Detection theory: a user's guide",
// ch. 9). Percepts are psi = ln(cue) + sigma eps; the cue of a material varies
// itself from one rendering to the next (erosion is stochastic), so across
// trials a material's percepts have variance s^2 + sigma^2, with s^2 the
// variance of its ln cue over renderings: the variability the observer
// experiences.
enum class SameDifferentRule {
  // "fixed": "different" when |psi1 - psi2| > criterion x sigma x sqrt(2), a
  // criterion set against the internal noise alone. Where the renderings
  // vary, a keen observer (small sigma) calls identical pairs "different", so
  // its score is not monotone in sigma.
  kFixed,
  // "differencing": the differencing observer, deciding on D = psi1 - psi2
  // alone with the optimal criterion for the total variability it
  // experienced: "different" when D is likelier under a different pair, D ~
  // N(+-(mu_a - mu_b), v_a + v_b), than under a same pair, D ~ N(0, 2 v_a) or
  // N(0, 2 v_b), each with probability one half (v = s^2 + sigma^2).
  kDifferencing,
  // "likelihood": the independent-observation (likelihood-ratio) observer,
  // deciding on both percepts: "different" when (psi1, psi2) is likelier
  // under the pairs (a, b) and (b, a) than under (a, a) and (b, b), each
  // material's percepts N(mu, v).
  kLikelihood,
};
// The rules' names in protocol files, specs and participants.tsv, in
// SameDifferentRule order.
inline constexpr std::string_view kSameDifferentRuleNames[] = {
    "fixed", "differencing", "likelihood"};

// Exploration that varies ([observer]; SD of ln, 0: none): the simulated
// hand's force (probe_force_n, drill_force_n) and pressing speed (1 /
// press_period_s) from one interval of a subject to the next (force, speed),
// and each subject's typical force and speed from one simulated subject to
// the next (subject_force, subject_speed).
struct ExplorationSpreads {
  double force = 0.0;
  double speed = 0.0;
  double subject_force = 0.0;
  double subject_speed = 0.0;
};
// kVariedExploration, the spreads of `exploration = "varied"`, from the
// surgeons of the dissertation's end-user tests (§12.3), whose average forces
// per session were 0.7-1.3 N (expert) and 0.8-1.1 N (trainees) and average tool
// speeds 8-12 (expert) and 10-17 (trainees), each range read as the mean +- 2
// SD of a log-normal: force from one interval to the next ln(1.3 / 0.7) / 4 =
// 0.15, speed ln(12 / 8) / 4 to ln(17 / 10) / 4, 0.12; between subjects,
// the ranges' centres differ by 5 % in force (1.0 and 0.95 N) and by a factor
// 1.35 in speed (10 and 13.5), an SD of ln of 0.05 and 0.15.
inline constexpr ExplorationSpreads kVariedExploration{0.15, 0.12, 0.05, 0.15};

// Defaults for the simulated observer ([observer]); `burrlab run --observer
// simulated:weber=W,lapse=L` overrides them.
struct ObserverDefaults {
  double weber_stiffness = 0.20;  // log-normal sigma of the probing cue
  double weber_removal = 0.30;    // log-normal sigma of the drilling cue
  double lapse = 0.02;            // probability of a random response
  double criterion = 1.0;         // same-different (rule fixed) and limits:
                           // "different" when the percepts differ by more
                           // than criterion x sigma x sqrt(2)
  SameDifferentRule rule = SameDifferentRule::kFixed;
  double bias = 0.0;  // same-different, differencing and likelihood rules:
                      // ln of the prior odds of "same" the observer assumes
  double probe_force_n = 2.0;      // peak force of each probing press
  double drill_force_n = 3.0;      // force held while drilling
  ExplorationSpreads exploration;  // none: every interval alike
};

// A parsed, validated protocol.
struct Protocol {
  std::string format;  // kProtocolFormat
  std::string study_name;
  std::string description;
  std::string instructions;                 // shown once at the start
  bool breaks_between_blocks = false;       // a rest break before every block
                                            // but the first
  int trace_hz = 1000;                      // trace sampling rate; divides 1000
  std::vector<ProtocolMaterial> materials;  // in file order
  std::vector<Axis> axes;                   // in file order
  std::vector<Block> blocks;                // in file order, at least one
  Counterbalance counterbalance = Counterbalance::kNone;
  ObserverDefaults observer;

  // The material with this id, or null.
  const ProtocolMaterial* FindMaterial(std::string_view id) const;
  // The axis with this id, or null.
  const Axis* FindAxis(std::string_view id) const;
};

// What parsing produced: the protocol when there were no errors, and every
// diagnostic in file order (line, then column).
struct ParseOutcome {
  std::optional<Protocol> protocol;
  std::vector<Diagnostic> diagnostics;  // errors, in file order
  std::vector<Diagnostic> notes;        // notes, in file order
};

// Parses and validates protocol text; `path` names the file in messages.
ParseOutcome ParseProtocol(std::string_view path, std::string_view text);

// The material an axis gives at `level` (checked against the axis's domain,
// and every parameter within [0, kMaxMaterialParameter] with c_e > 0: an
// error names the axis, the level and the rule).
Result<stimuli::MaterialSet> MaterialAtLevel(const Protocol& protocol,
                                             const Axis& axis, double level);

// The closed range of levels the engine may present on `axis` (it clamps
// QUEST placements to it): the axis's domain, 1e-9 inside an open end, and
// the levels whose parameter stays within kMaxMaterialParameter; at most
// [1e-9, 1e9].
std::pair<double, double> AxisDomain(const Protocol& protocol,
                                     const Axis& axis);

// The options of a simulated interval of a `task` block rendering `material`
// for duration_s with burr radius radius_mm: the protocol's [observer] forces
// and trace rate, one press a second (or one over a shorter interval), seed 1.
stimuli::IntervalOptions SimulatedIntervalOptions(const Protocol& protocol,
                                                  double radius_mm, Task task,
                                                  const sim::Material& material,
                                                  double duration_s);

// What a simulated interval with burr radius radius_mm would refuse among
// the stimuli every block can reach (Block::reach; stimuli::
// IntervalOptions::Validate): a probe the material cannot hold, or a radius
// outside [0.5, 5] mm (one diagnostic without a place). Empty when all of
// them render. `burrlab validate` checks this at --radius-mm, and every run
// that renders simulated intervals checks it before its first trial.
std::vector<Diagnostic> CheckSimulatedIntervals(const Protocol& protocol,
                                                double radius_mm);

// Block order for subject `subject_index` (0-based) under the protocol's
// counterbalancing: indices into protocol.blocks.
std::vector<int> BlockOrder(const Protocol& protocol, int subject_index);

}  // namespace burrlab::protocols

#endif  // BURRLAB_PROTOCOLS_PROTOCOL_H_
