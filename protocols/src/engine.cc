// The protocol engine: per-block state machines over the method libraries,
// trial specs and response handling.
#include "burrlab/protocols/engine.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/random/uniform_int_distribution.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>
#include <variant>

#include "burrlab/protocols/streams.h"

namespace burrlab::protocols {
namespace {

using Json = nlohmann::ordered_json;

// "1" or "2" for an interval number.
std::string IntervalToken(int interval) { return std::to_string(interval); }

// Default question per method and design.
std::string DefaultQuestion(const Block& block) {
  if (!block.question.empty()) return block.question;
  switch (block.method) {
    case Method::kSameDifferent:
      return "Did the two intervals feel the same or different?";
    case Method::kTwoInterval:
      return block.design == TwoIntervalDesign::kReference
                 ? "Which interval felt more like the reference?"
                 : "Which interval felt harder?";
    case Method::kConstantStimuli:
      return block.constant_stimuli.response == ResponseMode::kYesNo
                 ? "Did it feel harder than the standard?"
                 : "Which interval felt harder?";
    case Method::kLimits:
      return "Did the second interval feel different from the first?";
    case Method::kAdjustment:
      return "Adjust the second interval until it feels like the first.";
    case Method::kStaircase:
    case Method::kQuest:
      return block.adaptive_response == AdaptiveResponse::kYesNo
                 ? "Did it feel harder than the standard?"
                 : "Which interval felt harder?";
  }
  return {};
}

// Duration of interval i of a block (interval_s may be empty: 10 s each).
double IntervalDuration(const Block& block, std::size_t i) {
  if (block.interval_s.empty()) return 10.0;
  if (block.interval_s.size() == 1) return block.interval_s[0];
  return i < block.interval_s.size() ? block.interval_s[i]
                                     : block.interval_s.back();
}

}  // namespace

struct Engine::Impl {
  // Per-block method state. Nested here rather than in the anonymous
  // namespace: a member of Engine::Impl (external linkage) must not have a type
  // with internal linkage (-Wsubobject-linkage, which GCC raises when this file
  // is compiled as part of a unity source).
  struct SameDifferentState {
    std::vector<SameDifferentTrial> plan;
  };
  struct TwoIntervalState {
    std::vector<TwoIntervalTrial> plan;
  };
  struct ReferenceState {
    std::vector<ReferenceTrial> plan;
  };
  struct ConstantState {
    std::vector<ConstantStimuliTrial> plan;
  };
  struct LimitsState {
    MethodOfLimits limits;
  };
  struct AdjustmentState {
    std::vector<Adjustment> done;       // finished adjustments
    std::optional<Adjustment> current;  // the running one
  };
  struct StaircaseState {
    InterleavedStaircases staircases;
    int current = 0;              // staircase of the current trial
    int comparison_interval = 1;  // 2AFC: interval of the comparison
    int trials = 0;
  };
  struct QuestState {
    Quest quest;
    int trials = 0;
    double intensity_log10 = 0.0;  // placement of the current trial
    double level = 0.0;            // level presented (clamped to the axis)
    bool clamped = false;
    int comparison_interval = 1;
  };

  using BlockState =
      std::variant<std::monostate, SameDifferentState, TwoIntervalState,
                   ReferenceState, ConstantState, LimitsState, AdjustmentState,
                   StaircaseState, QuestState>;

  const Protocol* protocol = nullptr;
  std::uint64_t master_seed = 0;
  std::vector<int> order;
  boost::random::mt19937 order_rng;
  boost::random::mt19937 jitter_rng;
  int position = 0;  // index into order
  int trial_index = 0;
  int trial_in_block = 0;
  BlockState state;
  TrialSpec spec;
  bool finished = false;

  const Block& block() const { return protocol->blocks[order[position]]; }

  Status StartBlock();
  Status PlanTrial();  // fills spec for the current block state
  Status Advance();    // after a response: next trial or next block
  Result<PlannedInterval> MaterialInterval(const std::string& role,
                                           const std::string& id,
                                           std::size_t i) const;
  Result<PlannedInterval> AxisInterval(const std::string& role, double level,
                                       std::size_t i) const;
  bool BlockDone() const;
};

Result<PlannedInterval> Engine::Impl::MaterialInterval(const std::string& role,
                                                       const std::string& id,
                                                       std::size_t i) const {
  const ProtocolMaterial* m = protocol->FindMaterial(id);
  if (m == nullptr) {
    return Error{
        fmt::format("block \"{}\": unknown material \"{}\"", block().name, id)};
  }
  PlannedInterval interval;
  interval.role = role;
  interval.material_id = id;
  interval.material = m->set;
  interval.duration_s = IntervalDuration(block(), i);
  return interval;
}

Result<PlannedInterval> Engine::Impl::AxisInterval(const std::string& role,
                                                   double level,
                                                   std::size_t i) const {
  const Axis* axis = protocol->FindAxis(block().axis);
  if (axis == nullptr) {
    return Error{fmt::format("block \"{}\": unknown axis \"{}\"", block().name,
                             block().axis)};
  }
  Result<stimuli::MaterialSet> set = MaterialAtLevel(*protocol, *axis, level);
  if (!set.ok()) return set.error();
  PlannedInterval interval;
  interval.role = role;
  // '+' would split the exported interval_materials cell: "1e+20" -> "1e20".
  std::string id = fmt::format("{}@{:.8g}", axis->id, level);
  std::erase(id, '+');
  interval.material_id = std::move(id);
  interval.material = std::move(set.value());
  interval.duration_s = IntervalDuration(block(), i);
  interval.level = level;
  return interval;
}

bool Engine::Impl::BlockDone() const {
  const Block& b = block();
  return std::visit(
      [&](const auto& s) -> bool {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, std::monostate>) {
          return true;
        } else if constexpr (std::is_same_v<S, LimitsState>) {
          return s.limits.finished();
        } else if constexpr (std::is_same_v<S, AdjustmentState>) {
          return static_cast<int>(s.done.size()) >= b.adjustment_repetitions;
        } else if constexpr (std::is_same_v<S, StaircaseState>) {
          return s.staircases.finished();
        } else if constexpr (std::is_same_v<S, QuestState>) {
          return s.trials >= b.quest_trials;
        } else {
          return trial_in_block >= static_cast<int>(s.plan.size());
        }
      },
      state);
}

Status Engine::Impl::StartBlock() {
  const Block& b = block();
  trial_in_block = 0;
  switch (b.method) {
    case Method::kSameDifferent: {
      auto plan = PlanSameDifferent(b.same_different, order_rng);
      if (!plan.ok()) return plan.error();
      state = SameDifferentState{std::move(plan.value())};
      break;
    }
    case Method::kTwoInterval:
      if (b.design == TwoIntervalDesign::kReference) {
        auto plan = PlanReferenceDesign(b.reference, order_rng);
        if (!plan.ok()) return plan.error();
        state = ReferenceState{std::move(plan.value())};
      } else {
        auto plan = PlanTwoInterval(b.two_interval, order_rng);
        if (!plan.ok()) return plan.error();
        state = TwoIntervalState{std::move(plan.value())};
      }
      break;
    case Method::kConstantStimuli: {
      auto plan = PlanConstantStimuli(b.constant_stimuli, order_rng);
      if (!plan.ok()) return plan.error();
      state = ConstantState{std::move(plan.value())};
      break;
    }
    case Method::kLimits: {
      auto limits = MethodOfLimits::Create(b.limits, jitter_rng);
      if (!limits.ok()) return limits.error();
      state = LimitsState{std::move(limits.value())};
      break;
    }
    case Method::kAdjustment:
      state = AdjustmentState{};
      break;
    case Method::kStaircase: {
      auto staircases = InterleavedStaircases::Create(b.staircases);
      if (!staircases.ok()) return staircases.error();
      state = StaircaseState{std::move(staircases.value())};
      break;
    }
    case Method::kQuest: {
      auto quest = Quest::Create(b.quest);
      if (!quest.ok()) return quest.error();
      state = QuestState{std::move(quest.value())};
      break;
    }
  }
  return {};
}

Status Engine::Impl::PlanTrial() {
  const Block& b = block();
  TrialSpec t;
  t.trial_index = trial_index;
  t.block_index = order[position];
  t.block_position = position;
  t.trial_in_block = trial_in_block;
  t.block = b.name;
  t.method = b.method;
  t.task = b.task;
  t.question = DefaultQuestion(b);
  t.practice = b.practice;
  t.feedback = b.feedback;
  t.isi_s = b.isi_s;
  t.iti_s = b.iti_s;
  t.response_deadline_s = b.response_deadline_s;
  if (trial_index == 0) t.study_instructions = protocol->instructions;
  if (trial_in_block == 0) {
    t.block_instructions = b.instructions;
    t.break_before = position > 0 && protocol->breaks_between_blocks;
  } else if (b.break_every.has_value()) {
    t.break_before = trial_in_block % *b.break_every == 0;
  }
  const Axis* axis = b.axis.empty() ? nullptr : protocol->FindAxis(b.axis);
  if (axis != nullptr) {
    t.stim_unit = AxisUnit(*axis);
    t.standard_level = b.standard_level;
  }

  // Appends the interval or returns its error.
  auto add = [&t](Result<PlannedInterval> interval) -> Status {
    if (!interval.ok()) return interval.error();
    t.intervals.push_back(std::move(interval.value()));
    return {};
  };
  // 2AFC standard/comparison in the given order; the correct answer is the
  // interval with the higher level (none when equal).
  auto two_afc = [&](double level, int comparison_interval) -> Status {
    const double standard = b.standard_level;
    for (int i = 1; i <= 2; ++i) {
      const bool is_comparison = i == comparison_interval;
      Status s = add(AxisInterval(is_comparison ? "comparison" : "standard",
                                  is_comparison ? level : standard,
                                  static_cast<std::size_t>(i - 1)));
      if (!s.ok()) return s;
    }
    t.response_options = {"1", "2"};
    if (level > standard) t.correct_answer = IntervalToken(comparison_interval);
    if (level < standard) {
      t.correct_answer = IntervalToken(3 - comparison_interval);
    }
    return {};
  };
  // One interval at the level; "yes" is correct above the standard.
  auto yes_no = [&](double level) -> Status {
    Status s = add(AxisInterval("stimulus", level, 0));
    if (!s.ok()) return s;
    t.response_options = {"yes", "no"};
    if (level > b.standard_level) t.correct_answer = "yes";
    if (level < b.standard_level) t.correct_answer = "no";
    return {};
  };

  Status status = std::visit(
      [&](auto& s) -> Status {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, std::monostate>) {
          return Error{"engine: no block is running"};
        } else if constexpr (std::is_same_v<S, SameDifferentState>) {
          const SameDifferentTrial& p = s.plan[trial_in_block];
          t.trial_type = std::string(PairName(p.pair));
          for (std::size_t i = 0; i < 2; ++i) {
            const bool a = p.intervals[i] == MaterialLabel::kA;
            Status st = add(MaterialInterval(
                a ? "A" : "B", a ? b.material_a : b.material_b, i));
            if (!st.ok()) return st;
          }
          t.response_options = {"same", "different"};
          t.correct_answer =
              std::string(SameDifferentAnswerName(p.correct_answer));
          return {};
        } else if constexpr (std::is_same_v<S, TwoIntervalState>) {
          const TwoIntervalTrial& p = s.plan[trial_in_block];
          t.trial_type = p.comparison_interval == 1 ? "BA" : "AB";
          for (std::size_t i = 0; i < 2; ++i) {
            const bool a = p.intervals[i] == MaterialLabel::kA;
            Status st =
                add(MaterialInterval(a ? "standard" : "comparison",
                                     a ? b.material_a : b.material_b, i));
            if (!st.ok()) return st;
          }
          t.response_options = {"1", "2"};
          t.correct_answer = IntervalToken(p.comparison_interval);
          return {};
        } else if constexpr (std::is_same_v<S, ReferenceState>) {
          const ReferenceTrial& p = s.plan[trial_in_block];
          t.trial_type = std::string("R") +
                         std::string(MaterialLabelName(p.comparisons[0])) +
                         std::string(MaterialLabelName(p.comparisons[1]));
          if (b.reference_material.empty()) {
            PlannedInterval ref;
            ref.role = "reference";
            ref.material_id = "real";
            ref.duration_s = IntervalDuration(b, 0);
            t.intervals.push_back(std::move(ref));
          } else {
            Status st =
                add(MaterialInterval("reference", b.reference_material, 0));
            if (!st.ok()) return st;
          }
          for (std::size_t i = 0; i < 2; ++i) {
            const bool a = p.comparisons[i] == MaterialLabel::kA;
            Status st = add(MaterialInterval(
                a ? "A" : "B", a ? b.material_a : b.material_b, i + 1));
            if (!st.ok()) return st;
          }
          t.response_options = {"2", "3"};
          t.correct_answer = IntervalToken(p.correct_interval);
          return {};
        } else if constexpr (std::is_same_v<S, ConstantState>) {
          const ConstantStimuliTrial& p = s.plan[trial_in_block];
          t.level = p.level;
          if (p.comparison_interval.has_value()) {
            t.trial_type = "2afc";
            return two_afc(p.level, *p.comparison_interval);
          }
          t.trial_type = "yesno";
          return yes_no(p.level);
        } else if constexpr (std::is_same_v<S, LimitsState>) {
          const double level = s.limits.level();
          t.level = level;
          t.trial_type = std::string(SeriesDirectionName(
              s.limits.series()[s.limits.series_index()].direction));
          Status st = add(AxisInterval("standard", b.standard_level, 0));
          if (!st.ok()) return st;
          st = add(AxisInterval("comparison", level, 1));
          if (!st.ok()) return st;
          t.response_options = {"yes", "no"};
          return {};
        } else if constexpr (std::is_same_v<S, AdjustmentState>) {
          if (!s.current.has_value()) {
            auto adjustment = Adjustment::Create(b.adjustment, jitter_rng);
            if (!adjustment.ok()) return adjustment.error();
            s.current = std::move(adjustment.value());
          }
          const double level = s.current->level();
          t.level = level;
          t.trial_type = "adjustment";
          Status st = add(AxisInterval("standard", b.standard_level, 0));
          if (!st.ok()) return st;
          st = add(AxisInterval("comparison", level, 1));
          if (!st.ok()) return st;
          t.response_options = {"+", "-", "="};
          return {};
        } else if constexpr (std::is_same_v<S, StaircaseState>) {
          Result<int> next = s.staircases.NextIndex(order_rng);
          if (!next.ok()) return next.error();
          s.current = next.value();
          t.staircase_id = s.current;
          const double level = s.staircases.staircase(s.current).level();
          t.level = level;
          if (b.adaptive_response == AdaptiveResponse::kYesNo) {
            t.trial_type = "yesno";
            Status st = yes_no(level);
            t.correct_answer = "yes";
            return st;
          }
          boost::random::uniform_int_distribution<int> pick(1, 2);
          s.comparison_interval = pick(order_rng);
          t.trial_type = "2afc";
          return two_afc(level, s.comparison_interval);
        } else if constexpr (std::is_same_v<S, QuestState>) {
          Result<double> x = s.quest.Quantile();
          if (!x.ok()) return x.error();
          s.intensity_log10 = x.value();
          // Within the axis's domain and the block's floor and ceiling.
          auto [lo, hi] = AxisDomain(*protocol, *axis);
          lo = std::max(lo, b.quest_floor_level);
          hi = std::max(lo, std::min(hi, b.quest_ceiling_level));
          // Rounded like every level (levels.h): QUEST has no step.
          const double raw =
              RoundSignificant(std::pow(10.0, s.intensity_log10));
          s.level = std::clamp(raw, lo, hi);
          s.clamped = s.level != raw;
          t.level = s.level;
          if (b.adaptive_response == AdaptiveResponse::kYesNo) {
            t.trial_type = "yesno";
            Status st = yes_no(s.level);
            t.correct_answer = "yes";
            return st;
          }
          boost::random::uniform_int_distribution<int> pick(1, 2);
          s.comparison_interval = pick(order_rng);
          t.trial_type = "2afc";
          return two_afc(s.level, s.comparison_interval);
        }
      },
      state);
  if (!status.ok()) return status;
  // A trial at the standard's level has no correct answer to tell.
  if (t.correct_answer.empty()) t.feedback = false;
  spec = std::move(t);
  return {};
}

Status Engine::Impl::Advance() {
  ++trial_index;
  ++trial_in_block;
  while (BlockDone()) {
    ++position;
    if (position >= static_cast<int>(order.size())) {
      finished = true;
      return {};
    }
    Status s = StartBlock();
    if (!s.ok()) return s;
  }
  return PlanTrial();
}

Engine::Engine(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;
Engine::~Engine() = default;

Result<Engine> Engine::Create(const Protocol& protocol, int subject_index,
                              std::uint64_t master_seed) {
  if (subject_index < 0) {
    return Error{
        fmt::format("subject index must be 0 or more, got {}", subject_index)};
  }
  if (protocol.blocks.empty()) return Error{"the protocol has no blocks"};
  auto impl = std::make_unique<Impl>();
  impl->protocol = &protocol;
  impl->master_seed = master_seed;
  impl->order = BlockOrder(protocol, subject_index);
  impl->order_rng = StreamFor(master_seed, StreamPurpose::kTrialOrder);
  impl->jitter_rng = StreamFor(master_seed, StreamPurpose::kLevelJitter);
  Status s = impl->StartBlock();
  if (!s.ok()) return s.error();
  while (impl->BlockDone()) {  // a block without trials (not valid, but safe)
    if (++impl->position >= static_cast<int>(impl->order.size())) {
      impl->finished = true;
      return Engine(std::move(impl));
    }
    s = impl->StartBlock();
    if (!s.ok()) return s.error();
  }
  s = impl->PlanTrial();
  if (!s.ok()) return s.error();
  return Engine(std::move(impl));
}

bool Engine::finished() const { return impl_->finished; }
const TrialSpec& Engine::current() const { return impl_->spec; }
const std::vector<int>& Engine::block_order() const { return impl_->order; }
const Protocol& Engine::protocol() const { return *impl_->protocol; }
std::uint64_t Engine::master_seed() const { return impl_->master_seed; }

std::string Engine::RngState() const {
  std::ostringstream text;
  text << "order " << impl_->order_rng << " jitter " << impl_->jitter_rng;
  return text.str();
}

Result<double> Engine::PreviewAdjustment(std::string_view path) const {
  const auto* s = std::get_if<Impl::AdjustmentState>(&impl_->state);
  if (impl_->finished || s == nullptr || !s->current.has_value()) {
    return Error{"the current trial is not an adjustment"};
  }
  Adjustment copy = *s->current;
  for (char c : path) {
    if (c != '+' && c != '-') {
      return Error{fmt::format(
          "adjustment path \"{}\" may hold only '+' and '-' steps", path)};
    }
    Status st = copy.Step(c == '+' ? 1 : -1);
    if (!st.ok()) return st.error();
  }
  return copy.level();
}

Result<PlannedInterval> Engine::AdjustedComparison(
    std::string_view path) const {
  Result<double> level = PreviewAdjustment(path);
  if (!level.ok()) return level.error();
  return impl_->AxisInterval("comparison", *level, 1);
}

Result<stimuli::MaterialSet> Engine::MaterialAt(double level) const {
  const Axis* axis = impl_->protocol->FindAxis(impl_->block().axis);
  if (impl_->finished || axis == nullptr) {
    return Error{"the current block has no stimulus axis"};
  }
  return MaterialAtLevel(*impl_->protocol, *axis, level);
}

Result<Outcome> Engine::Respond(const Response& response) {
  if (impl_->finished) return Error{"the session has finished"};
  Impl& im = *impl_;
  const TrialSpec& t = im.spec;
  const Block& b = im.block();
  const std::string& answer = response.answer;
  if (response.response_time_s.has_value() &&
      !(std::isfinite(*response.response_time_s) &&
        *response.response_time_s >= 0.0)) {
    return Error{fmt::format("response time must be 0 s or more, got {}",
                             *response.response_time_s)};
  }
  const bool adaptive =
      b.method == Method::kLimits || b.method == Method::kAdjustment ||
      b.method == Method::kStaircase || b.method == Method::kQuest;
  if (answer.empty() && adaptive) {
    return Error{fmt::format(
        "trial {} (block \"{}\", {}) needs an answer: the next level depends "
        "on it",
        t.trial_index, t.block, MethodName(b.method))};
  }
  if (!answer.empty() && b.method != Method::kAdjustment &&
      std::find(t.response_options.begin(), t.response_options.end(), answer) ==
          t.response_options.end()) {
    std::string options;
    for (const std::string& o : t.response_options) {
      options += (options.empty() ? "" : ", ") + o;
    }
    return Error{
        fmt::format("trial {} (block \"{}\"): answer \"{}\" is not one of {}",
                    t.trial_index, t.block, answer, options)};
  }

  Outcome out;
  if (b.response_deadline_s.has_value() &&
      response.response_time_s.has_value()) {
    out.late = *response.response_time_s > *b.response_deadline_s;
  }
  Json extra = Json::object();
  if (!answer.empty() && !t.correct_answer.empty()) {
    out.correct = answer == t.correct_answer;
  } else if (answer.empty() && !t.correct_answer.empty()) {
    out.correct = false;  // a missed answer counts as wrong
  }

  Status status = std::visit(
      [&](auto& s) -> Status {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Impl::LimitsState>) {
          Result<LimitsTrial> r = s.limits.Update(answer == "yes");
          if (!r.ok()) return r.error();
          extra["series"] = r->series;
          extra["ends_series"] = r->ends_series;
          extra["transition"] = r->transition;
          if (r->ends_series) {
            const auto& tl = s.limits.series()[r->series].transition_level;
            extra["transition_level"] =
                tl.has_value() ? Json(*tl) : Json(nullptr);
          }
          if (Result<double> th = s.limits.Threshold(); th.ok()) {
            out.estimate = th.value();
          }
          return {};
        } else if constexpr (std::is_same_v<S, Impl::AdjustmentState>) {
          if (answer.empty() || answer.back() != '=') {
            return Error{fmt::format(
                "trial {} (block \"{}\"): an adjustment answer is a path of "
                "'+' and '-' steps ending in '=', got \"{}\"",
                t.trial_index, t.block, answer)};
          }
          Adjustment copy = *s.current;
          for (std::size_t i = 0; i + 1 < answer.size(); ++i) {
            const char c = answer[i];
            if (c != '+' && c != '-') {
              return Error{fmt::format(
                  "trial {} (block \"{}\"): an adjustment answer is a path "
                  "of '+' and '-' steps ending in '=', got \"{}\"",
                  t.trial_index, t.block, answer)};
            }
            Status st = copy.Step(c == '+' ? 1 : -1);
            if (!st.ok()) return st;
          }
          Result<double> final_level = copy.Finish();
          if (!final_level.ok()) return final_level.error();
          out.presented_level = final_level.value();
          extra["start_level"] = copy.start_level();
          extra["jitter_steps"] = copy.jitter_steps();
          extra["final_level"] = final_level.value();
          extra["steps"] = copy.steps_taken();
          extra["path"] = copy.path();
          s.done.push_back(std::move(copy));
          s.current.reset();
          double sum = 0.0;
          for (const Adjustment& a : s.done) sum += *a.final_level();
          // The method's estimate: the mean adjusted level so far.
          out.estimate = sum / static_cast<double>(s.done.size());
          extra["mean_final_level"] = *out.estimate;
          return {};
        } else if constexpr (std::is_same_v<S, Impl::StaircaseState>) {
          Result<StaircaseTrial> r =
              s.staircases.Update(s.current, out.correct.value_or(false));
          if (!r.ok()) return r.error();
          ++s.trials;
          out.reversal = r->reversal;
          out.step_size = r->step_size;
          extra["move"] = std::string(MoveName(r->move));
          extra["clamped"] = r->clamped;
          extra["staircase_trial"] = r->index;
          const Staircase& sc = s.staircases.staircase(s.current);
          extra["next_level"] = sc.level();
          extra["reversals"] = static_cast<int>(sc.reversals().size());
          // How the estimate is formed, so analyses of the exported files
          // can recompute it (burrlab analyze thresholds).
          extra["threshold_reversals"] = b.threshold_reversals;
          extra["step_scale"] =
              std::string(StepScaleName(sc.options().step_scale));
          if (Result<double> th = sc.Threshold(b.threshold_reversals);
              th.ok()) {
            out.estimate = th.value();
          }
          return {};
        } else if constexpr (std::is_same_v<S, Impl::QuestState>) {
          const bool r1 = b.adaptive_response == AdaptiveResponse::kYesNo
                              ? answer == "yes"
                              : out.correct.value_or(false);
          Result<QuestUpdateReport> r = s.quest.Update(std::log10(s.level), r1);
          if (!r.ok()) return r.error();
          ++s.trials;
          const double mean = s.quest.Mean();
          out.estimate = std::pow(10.0, mean);
          extra["intensity_log10"] = std::log10(s.level);
          extra["placement_log10"] = s.intensity_log10;
          extra["placement_clamped"] = s.clamped;
          extra["posterior_mean_log10"] = mean;
          extra["posterior_sd_log10"] = s.quest.Sd();
          return {};
        } else if constexpr (std::is_same_v<S, Impl::TwoIntervalState> ||
                             std::is_same_v<S, Impl::ConstantState>) {
          if constexpr (std::is_same_v<S, Impl::ConstantState>) {
            const ConstantStimuliTrial& p = s.plan[im.trial_in_block];
            extra["level_index"] = p.level_index;
            extra["repetition"] = p.repetition;
            if (p.comparison_interval.has_value()) {
              extra["comparison_interval"] = *p.comparison_interval;
            }
          } else {
            extra["comparison_interval"] =
                s.plan[im.trial_in_block].comparison_interval;
          }
          return {};
        } else {
          return {};
        }
      },
      im.state);
  if (!status.ok()) return status.error();
  if (const auto* s = std::get_if<Impl::StaircaseState>(&im.state)) {
    extra["comparison_interval"] =
        b.adaptive_response == AdaptiveResponse::k2Afc
            ? Json(s->comparison_interval)
            : Json(nullptr);
  }
  if (const auto* s = std::get_if<Impl::QuestState>(&im.state)) {
    extra["comparison_interval"] =
        b.adaptive_response == AdaptiveResponse::k2Afc
            ? Json(s->comparison_interval)
            : Json(nullptr);
  }
  out.extra = extra.dump();
  Status advanced = im.Advance();
  if (!advanced.ok()) return advanced.error();
  return out;
}

Result<Response> ScriptedResponse(const TrialSpec& trial,
                                  std::string_view token) {
  Response r;
  if (trial.method == Method::kAdjustment) {
    if (token == "1" || token == "0") {
      return Error{fmt::format(
          "trial {} is an adjustment: script it as a path of '+' and '-' "
          "steps ending in '=' (e.g. ++-=), not \"{}\"",
          trial.trial_index, token)};
    }
    r.answer = std::string(token);
    return r;
  }
  if (token != "1" && token != "0") {
    r.answer = std::string(token);
    return r;
  }
  const bool right = token == "1";
  if (trial.correct_answer.empty()) {
    if (std::find(trial.response_options.begin(), trial.response_options.end(),
                  "yes") == trial.response_options.end()) {
      return Error{fmt::format(
          "trial {} has no correct answer: script one of its answers instead "
          "of \"{}\"",
          trial.trial_index, token)};
    }
    r.answer = right ? "yes" : "no";
    return r;
  }
  if (right) {
    r.answer = trial.correct_answer;
    return r;
  }
  for (const std::string& option : trial.response_options) {
    if (option != trial.correct_answer) {
      r.answer = option;
      return r;
    }
  }
  return Error{"no wrong answer exists"};
}

}  // namespace burrlab::protocols
