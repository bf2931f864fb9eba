// The protocol engine with scripted responses: balanced designs, staircase
// tracks against hand-computed sequences, QUEST against the library (itself
// matched to Psychtoolbox), limits thresholds, adjustment paths and replay.
#include "burrlab/protocols/engine.h"

#include <gtest/gtest.h>

#include <boost/random/uniform_01.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

namespace burrlab::protocols {
namespace {

stimuli::MaterialSet Material(std::string name, double c_e) {
  stimuli::MaterialSet set;
  set.name = name;
  set.display_name = name;
  set.material.c_e_n_per_mm2 = c_e;
  set.material.alpha_per_s = 0.1;
  set.material.c_mu_n_per_mm2 = 0.3;
  set.material.mu = 0.5;
  set.material.c_i_n_s_per_mm3 = 0.005;
  return set;
}

// A protocol with materials "soft" and "hard", a ratio axis on c_e of
// "hard", and no blocks.
Protocol BaseProtocol() {
  Protocol p;
  p.format = std::string(kProtocolFormat);
  p.study_name = "test";
  p.materials.push_back({"soft", "", Material("soft", 0.5), {}});
  p.materials.push_back({"hard", "", Material("hard", 2.0), {}});
  Axis axis;
  axis.id = "ce";
  axis.kind = AxisKind::kRatio;
  axis.parameter = MaterialParameter::kCE;
  axis.reference = "hard";
  p.axes.push_back(axis);
  return p;
}

Block SameDifferentBlock(std::string name, int trials) {
  Block b;
  b.name = std::move(name);
  b.method = Method::kSameDifferent;
  b.material_a = "soft";
  b.material_b = "hard";
  b.same_different.n_trials = trials;
  b.interval_s = {20.0, 20.0};
  return b;
}

Block StaircaseBlock(int n_down, double start, double step) {
  Block b;
  b.name = "stairs";
  b.method = Method::kStaircase;
  b.axis = "ce";
  b.standard_level = 1.0;
  StaircaseOptions o;
  o.n_down = n_down;
  o.n_up = 1;
  o.step_down = step;
  o.step_up = step;
  o.start_level = start;
  o.floor_level = 1.0;
  o.max_trials = 12;
  b.staircases = {o};
  b.threshold_reversals = 2;
  return b;
}

// Runs the engine to the end with a response function; returns the specs.
template <typename F>
std::vector<TrialSpec> RunAll(Engine& engine, F respond) {
  std::vector<TrialSpec> specs;
  while (!engine.finished()) {
    specs.push_back(engine.current());
    Result<Outcome> out = engine.Respond(respond(engine.current()));
    EXPECT_TRUE(out.ok()) << out.error().message;
    if (!out.ok()) break;
  }
  return specs;
}

Response Correct(const TrialSpec& t) {
  return ScriptedResponse(t, "1").value();
}

TEST(Engine, SameDifferentBlocksHoldThreeOfEachPairInSeedDependentOrder) {
  Protocol p = BaseProtocol();
  p.blocks = {SameDifferentBlock("probe", 12), SameDifferentBlock("drill", 12)};
  p.blocks[1].task = Task::kDrill;
  std::set<std::string> orders;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Result<Engine> engine = Engine::Create(p, 0, seed);
    ASSERT_TRUE(engine.ok()) << engine.error().message;
    std::vector<TrialSpec> specs = RunAll(*engine, Correct);
    ASSERT_EQ(specs.size(), 24u);
    std::string order;
    for (int block = 0; block < 2; ++block) {
      std::map<std::string, int> counts;
      for (int i = 0; i < 12; ++i) {
        const TrialSpec& t = specs[block * 12 + i];
        EXPECT_EQ(t.trial_index, block * 12 + i);
        EXPECT_EQ(t.trial_in_block, i);
        EXPECT_EQ(t.task, block == 0 ? Task::kProbe : Task::kDrill);
        ++counts[t.trial_type];
        order += t.trial_type;
        ASSERT_EQ(t.intervals.size(), 2u);
        const std::string expected_ids =
            std::string(t.trial_type[0] == 'A' ? "soft" : "hard") + "|" +
            (t.trial_type[1] == 'A' ? "soft" : "hard");
        EXPECT_EQ(t.intervals[0].material_id + "|" + t.intervals[1].material_id,
                  expected_ids);
        EXPECT_EQ(t.intervals[0].duration_s, 20.0);
        EXPECT_EQ(t.correct_answer,
                  t.trial_type[0] == t.trial_type[1] ? "same" : "different");
      }
      EXPECT_EQ(counts, (std::map<std::string, int>{
                            {"AA", 3}, {"AB", 3}, {"BA", 3}, {"BB", 3}}));
    }
    orders.insert(order);
  }
  EXPECT_GE(orders.size(), 19u);  // 20 seeds, practically all different
}

TEST(Engine, SameSeedAndResponsesGiveTheSameTrialsAndRandomState) {
  Protocol p = BaseProtocol();
  p.blocks = {SameDifferentBlock("probe", 8), StaircaseBlock(2, 2.0, 0.25)};
  Result<Engine> a = Engine::Create(p, 0, 77);
  Result<Engine> b = Engine::Create(p, 0, 77);
  ASSERT_TRUE(a.ok() && b.ok());
  int k = 0;
  while (!a->finished()) {
    ASSERT_FALSE(b->finished());
    EXPECT_EQ(a->current().trial_type, b->current().trial_type);
    EXPECT_EQ(a->current().correct_answer, b->current().correct_answer);
    const std::string token = (k++ % 3 == 0) ? "0" : "1";
    ASSERT_TRUE(a->Respond(ScriptedResponse(a->current(), token).value()).ok());
    ASSERT_TRUE(b->Respond(ScriptedResponse(b->current(), token).value()).ok());
    EXPECT_EQ(a->RngState(), b->RngState());
  }
  EXPECT_TRUE(b->finished());
}

TEST(Engine, StaircaseFollowsTheHandComputedTwoDownOneUpTrack) {
  Protocol p = BaseProtocol();
  p.blocks = {StaircaseBlock(2, 2.0, 0.25)};
  Result<Engine> engine = Engine::Create(p, 0, 5);
  ASSERT_TRUE(engine.ok());
  // Responses and the levels the 2-down/1-up rule gives (step 0.25, floor 1):
  // 2.0 c, 2.0 c -> down 1.75 c, 1.75 w -> up (reversal at 1.75) 2.0 c,
  // 2.0 c -> down (reversal at 2.0) 1.75 c, 1.75 c -> 1.5 c, 1.5 c -> 1.25,
  // 1.25 c, 1.25 c -> 1.0, 1.0 c, 1.0 c -> floor 1.0.
  const std::string script = "111011111111";
  const std::vector<double> levels = {2.0,  2.0,  1.75, 1.75, 2.0,  2.0,
                                      1.75, 1.75, 1.5,  1.5,  1.25, 1.25};
  const std::vector<bool> reversals = {false, false, false, true,
                                       false, true,  false, false,
                                       false, false, false, false};
  for (std::size_t i = 0; i < script.size(); ++i) {
    ASSERT_FALSE(engine->finished()) << i;
    const TrialSpec& t = engine->current();
    EXPECT_DOUBLE_EQ(*t.level, levels[i]) << "trial " << i;
    ASSERT_EQ(t.intervals.size(), 2u);
    // The comparison interval holds the level, the standard ratio 1.
    const int cmp = t.correct_answer == "1" ? 0 : 1;
    EXPECT_EQ(t.intervals[cmp].role, "comparison");
    EXPECT_DOUBLE_EQ(*t.intervals[cmp].level, levels[i]);
    EXPECT_DOUBLE_EQ(t.intervals[cmp].material->material.c_e_n_per_mm2,
                     2.0 * levels[i]);
    EXPECT_DOUBLE_EQ(*t.intervals[1 - cmp].level, 1.0);
    Result<Outcome> out =
        engine->Respond(ScriptedResponse(t, std::string(1, script[i])).value());
    ASSERT_TRUE(out.ok()) << out.error().message;
    EXPECT_EQ(*out->reversal, reversals[i]) << "trial " << i;
    EXPECT_EQ(*out->correct, script[i] == '1');
    if (i >= 5) {
      EXPECT_DOUBLE_EQ(*out->estimate, (1.75 + 2.0) / 2);
    } else {
      EXPECT_FALSE(out->estimate.has_value());
    }
  }
  EXPECT_TRUE(engine->finished());  // max_trials 12
}

TEST(Engine, InterleavedStaircasesDrawTheirOrderFromTheOrderStream) {
  Protocol p = BaseProtocol();
  Block b = StaircaseBlock(3, 2.0, 0.25);
  b.staircases.push_back(b.staircases[0]);
  b.staircases[1].start_level = 3.0;
  b.staircases[0].max_trials = 5;
  b.staircases[1].max_trials = 7;
  p.blocks = {b};
  Result<Engine> engine = Engine::Create(p, 0, 11);
  ASSERT_TRUE(engine.ok());
  std::map<int, int> per_staircase;
  std::string ids;
  std::vector<TrialSpec> specs = RunAll(*engine, Correct);
  for (const TrialSpec& t : specs) {
    ++per_staircase[*t.staircase_id];
    ids += std::to_string(*t.staircase_id);
  }
  EXPECT_EQ(per_staircase, (std::map<int, int>{{0, 5}, {1, 7}}));
  EXPECT_NE(ids, "000001111111");  // interleaved, not sequential
}

TEST(Engine, QuestPlacesTrialsAtThePosteriorQuantileOfTheLibrary) {
  Protocol p = BaseProtocol();
  Block b;
  b.name = "quest";
  b.method = Method::kQuest;
  b.axis = "ce";
  b.standard_level = 1.0;
  b.quest.t_guess = std::log10(1.5);
  b.quest.t_guess_sd = 0.5;
  b.quest.p_threshold = 0.82;
  b.quest_trials = 15;
  p.blocks = {b};
  Result<Engine> engine = Engine::Create(p, 0, 3);
  ASSERT_TRUE(engine.ok());
  Result<Quest> quest = Quest::Create(b.quest);
  ASSERT_TRUE(quest.ok());
  const std::string script = "110111011101111";
  for (std::size_t i = 0; i < script.size(); ++i) {
    const TrialSpec t = engine->current();  // Respond replaces current()
    const double x = quest->Quantile().value();
    // Placed at 10^x rounded to 12 significant digits (levels.h).
    EXPECT_NEAR(*t.level, std::pow(10.0, x), 5e-12 * *t.level) << i;
    const bool r = script[i] == '1';
    Result<Outcome> out =
        engine->Respond(ScriptedResponse(t, std::string(1, script[i])).value());
    ASSERT_TRUE(out.ok());
    ASSERT_TRUE(quest->Update(std::log10(*t.level), r).ok());
    EXPECT_NEAR(*out->estimate, std::pow(10.0, quest->Mean()), 1e-12);
  }
  EXPECT_TRUE(engine->finished());
}

TEST(Engine, QuestPlacementsAreClampedToTheAxisDomainAndTheBlockBounds) {
  // tGuess = 308 places the first trial near 10^308; it is presented at the
  // highest level whose c_e a material may have (1e6 / hard's 2 = 5e5), and
  // at the block's ceiling when there is one. The update then uses the level
  // presented.
  Protocol p = BaseProtocol();
  Block b;
  b.name = "quest";
  b.method = Method::kQuest;
  b.axis = "ce";
  b.standard_level = 1.0;
  b.quest.t_guess = 308.0;
  b.quest.t_guess_sd = 0.5;
  b.quest_trials = 2;
  p.blocks = {b};
  Result<Engine> engine = Engine::Create(p, 0, 3);
  ASSERT_TRUE(engine.ok());
  EXPECT_EQ(*engine->current().level, 5e5);
  Result<Outcome> out =
      engine->Respond(ScriptedResponse(engine->current(), "0").value());
  ASSERT_TRUE(out.ok());
  const nlohmann::json extra = nlohmann::json::parse(out->extra);
  EXPECT_EQ(extra["placement_clamped"], true);
  EXPECT_DOUBLE_EQ(extra["intensity_log10"].get<double>(), std::log10(5e5));
  p.blocks[0].quest_ceiling_level = 3.0;
  p.blocks[0].quest.t_guess = -308.0;
  p.blocks[0].quest_floor_level = 0.25;
  engine = Engine::Create(p, 0, 3);
  ASSERT_TRUE(engine.ok());
  EXPECT_EQ(*engine->current().level, 0.25);
  p.blocks[0].quest.t_guess = 308.0;
  engine = Engine::Create(p, 0, 3);
  ASSERT_TRUE(engine.ok());
  EXPECT_EQ(*engine->current().level, 3.0);
}

TEST(Engine, LimitsEstimateIsTheMeanOfHandComputedTransitions) {
  Protocol p = BaseProtocol();
  Block b;
  b.name = "limits";
  b.method = Method::kLimits;
  b.axis = "ce";
  b.standard_level = 1.0;
  b.limits.first_direction = SeriesDirection::kAscending;
  b.limits.n_series = 2;
  b.limits.step = 0.1;
  b.limits.ascending_start = 1.0;
  b.limits.descending_start = 2.0;
  b.limits.floor_level = 1.0;
  b.limits.ceiling_level = 2.0;
  p.blocks = {b};
  Result<Engine> engine = Engine::Create(p, 0, 1);
  ASSERT_TRUE(engine.ok());
  // Ascending 1.0 no, 1.1 no, 1.2 no, 1.3 yes -> transition 1.25.
  // Descending 2.0 yes, 1.9 yes, 1.8 no -> transition 1.85.
  const std::vector<std::string> answers = {"no",  "no",  "no", "yes",
                                            "yes", "yes", "no"};
  const std::vector<double> levels = {1.0, 1.1, 1.2, 1.3, 2.0, 1.9, 1.8};
  std::optional<double> estimate;
  for (std::size_t i = 0; i < answers.size(); ++i) {
    ASSERT_FALSE(engine->finished());
    const TrialSpec& t = engine->current();
    EXPECT_NEAR(*t.level, levels[i], 1e-12);
    EXPECT_EQ(t.trial_type, i < 4 ? "ascending" : "descending");
    Result<Outcome> out = engine->Respond({answers[i], 1.0});
    ASSERT_TRUE(out.ok()) << out.error().message;
    estimate = out->estimate;
  }
  EXPECT_TRUE(engine->finished());
  ASSERT_TRUE(estimate.has_value());
  EXPECT_NEAR(*estimate, (1.25 + 1.85) / 2, 1e-12);
}

TEST(Engine, AdjustmentRecordsThePathAndTheFinalLevel) {
  Protocol p = BaseProtocol();
  Block b;
  b.name = "adjust";
  b.method = Method::kAdjustment;
  b.axis = "ce";
  b.standard_level = 1.0;
  b.adjustment.start_level = 2.0;
  b.adjustment.step = 0.1;
  b.adjustment.floor_level = 0.5;
  b.adjustment.ceiling_level = 3.0;
  b.adjustment_repetitions = 2;
  p.blocks = {b};
  Result<Engine> engine = Engine::Create(p, 0, 1);
  ASSERT_TRUE(engine.ok());
  EXPECT_NEAR(engine->PreviewAdjustment("---+").value(), 1.8, 1e-12);
  // The comparison a station presents after a step: planned as the trial's
  // own comparison, at the level reached.
  Result<PlannedInterval> after = engine->AdjustedComparison("---+");
  ASSERT_TRUE(after.ok()) << after.error().message;
  const PlannedInterval& planned = engine->current().intervals[1];
  EXPECT_EQ(after->role, planned.role);
  EXPECT_EQ(after->material_id, "ce@1.8");
  EXPECT_EQ(after->duration_s, planned.duration_s);
  EXPECT_NEAR(*after->level, 1.8, 1e-12);
  EXPECT_EQ(after->material->material.c_e_n_per_mm2,
            engine->MaterialAt(*after->level)->material.c_e_n_per_mm2);
  Result<Outcome> out = engine->Respond({"----+=", 4.0});
  ASSERT_TRUE(out.ok()) << out.error().message;
  EXPECT_NEAR(*out->presented_level, 1.7, 1e-12);
  EXPECT_NE(out->extra.find("\"steps\":5"), std::string::npos) << out->extra;
  out = engine->Respond({"++=", 2.0});
  ASSERT_TRUE(out.ok());
  EXPECT_NEAR(*out->presented_level, 2.2, 1e-12);
  const auto extra = nlohmann::json::parse(out->extra);
  EXPECT_NEAR(extra["mean_final_level"].get<double>(), (1.7 + 2.2) / 2, 1e-12);
  EXPECT_EQ(extra["path"].size(), 3u);
  EXPECT_TRUE(engine->finished());
}

TEST(Engine, RefusesAnswersThatAreNotOptions) {
  Protocol p = BaseProtocol();
  p.blocks = {SameDifferentBlock("probe", 4), StaircaseBlock(2, 2.0, 0.25)};
  Result<Engine> engine = Engine::Create(p, 0, 1);
  ASSERT_TRUE(engine.ok());
  Result<Outcome> out = engine->Respond({"maybe", 1.0});
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.error().message,
            "trial 0 (block \"probe\"): answer \"maybe\" is not one of same, "
            "different");
  for (int i = 0; i < 4; ++i) ASSERT_TRUE(engine->Respond({"", {}}).ok());
  out = engine->Respond({"", {}});
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.error().message,
            "trial 4 (block \"stairs\", staircase) needs an answer: the next "
            "level depends on it");
  out = engine->Respond({"1", -1.0});
  ASSERT_FALSE(out.ok());
  EXPECT_EQ(out.error().message, "response time must be 0 s or more, got -1");
}

TEST(Engine, CounterbalancedBlockOrderFollowsTheSubjectIndex) {
  Protocol p = BaseProtocol();
  p.blocks = {SameDifferentBlock("one", 4), SameDifferentBlock("two", 4)};
  p.counterbalance = Counterbalance::kReverse;
  Result<Engine> even = Engine::Create(p, 0, 1);
  Result<Engine> odd = Engine::Create(p, 1, 1);
  ASSERT_TRUE(even.ok() && odd.ok());
  EXPECT_EQ(even->current().block, "one");
  EXPECT_EQ(odd->current().block, "two");
  EXPECT_EQ(odd->block_order(), (std::vector<int>{1, 0}));
}

// What a runner shows around each trial comes with the trial: the study's
// instructions before the first, a block's before its first, a rest break
// every break_every trials within a block and between blocks, and the
// block's pacing and practice flag on every trial.
TEST(Engine, TrialsCarryInstructionsBreaksAndPacingOfTheirBlock) {
  Protocol p = BaseProtocol();
  p.instructions = "Feel each pair and say whether it is the same.";
  p.breaks_between_blocks = true;
  p.blocks = {SameDifferentBlock("familiarize", 4),
              SameDifferentBlock("main", 8)};
  p.blocks[0].practice = true;
  p.blocks[0].feedback = true;
  p.blocks[0].instructions = "Practice: you will be told if you are right.";
  p.blocks[0].isi_s = 1.5;
  p.blocks[0].iti_s = 2.0;
  p.blocks[1].instructions = "Now the scored trials.";
  p.blocks[1].break_every = 3;
  p.blocks[1].response_deadline_s = 4.0;
  Result<Engine> engine = Engine::Create(p, 0, 5);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  const std::vector<TrialSpec> specs = RunAll(*engine, Correct);
  ASSERT_EQ(specs.size(), 12u);
  std::string breaks;
  for (const TrialSpec& t : specs) breaks += t.break_before ? 'B' : '.';
  // Block 2 starts with a break (between blocks), then one after its 3rd
  // and 6th trials; none after its last.
  EXPECT_EQ(breaks, "....B..B..B.");
  EXPECT_EQ(specs[0].study_instructions, p.instructions);
  EXPECT_EQ(specs[0].block_instructions, p.blocks[0].instructions);
  EXPECT_EQ(specs[4].block_instructions, p.blocks[1].instructions);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const TrialSpec& t = specs[i];
    if (i > 0) {
      EXPECT_EQ(t.study_instructions, "") << i;
    }
    if (i != 0 && i != 4) {
      EXPECT_EQ(t.block_instructions, "") << i;
    }
    const bool practice = i < 4;
    EXPECT_EQ(t.practice, practice) << i;
    EXPECT_EQ(t.feedback, practice) << i;
    EXPECT_EQ(t.isi_s, practice ? 1.5 : 0.0) << i;
    EXPECT_EQ(t.iti_s, practice ? 2.0 : 0.0) << i;
    EXPECT_EQ(t.response_deadline_s,
              practice ? std::nullopt : std::optional<double>(4.0))
        << i;
  }
}

// Pacing never draws from a random stream: the same seed gives the same
// trials with or without it.
TEST(Engine, PacingKeysLeaveTheTrialsAndRandomStateAlone) {
  Protocol plain = BaseProtocol();
  plain.blocks = {SameDifferentBlock("probe", 8), StaircaseBlock(2, 2.0, 0.25)};
  Protocol paced = plain;
  paced.breaks_between_blocks = true;
  for (Block& b : paced.blocks) {
    b.practice = true;
    b.isi_s = 0.5;
    b.iti_s = 1.0;
    b.break_every = 2;
    b.response_deadline_s = 3.0;
  }
  Result<Engine> a = Engine::Create(plain, 0, 31);
  Result<Engine> b = Engine::Create(paced, 0, 31);
  ASSERT_TRUE(a.ok() && b.ok());
  int k = 0;
  while (!a->finished()) {
    ASSERT_FALSE(b->finished());
    EXPECT_EQ(a->current().trial_type, b->current().trial_type);
    EXPECT_EQ(a->current().level, b->current().level);
    const std::string token = (k++ % 3 == 0) ? "0" : "1";
    Result<Outcome> oa =
        a->Respond(ScriptedResponse(a->current(), token).value());
    Result<Outcome> ob =
        b->Respond(ScriptedResponse(b->current(), token).value());
    ASSERT_TRUE(oa.ok() && ob.ok());
    EXPECT_EQ(oa->correct, ob->correct);
    EXPECT_EQ(oa->extra, ob->extra);
    EXPECT_EQ(a->RngState(), b->RngState());
  }
  EXPECT_TRUE(b->finished());
}

// An answer after the deadline is taken like any other and marked late; no
// deadline, or no response time, leaves `late` unknown.
TEST(Engine, AnswersAfterTheDeadlineAreKeptAndMarkedLate) {
  Protocol p = BaseProtocol();
  p.blocks = {SameDifferentBlock("timed", 4), SameDifferentBlock("free", 4)};
  p.blocks[0].response_deadline_s = 2.0;
  Result<Engine> engine = Engine::Create(p, 0, 3);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  const auto answer = [&](std::optional<double> rt) {
    Response r = Correct(engine->current());
    r.response_time_s = rt;
    Result<Outcome> out = engine->Respond(r);
    EXPECT_TRUE(out.ok()) << out.error().message;
    return out.ok() ? *out : Outcome{};
  };
  EXPECT_EQ(answer(1.5).late, false);
  EXPECT_EQ(answer(2.0).late, false);  // at the deadline is in time
  const Outcome late = answer(2.5);
  EXPECT_EQ(late.late, true);
  EXPECT_EQ(late.correct, true);  // still scored
  EXPECT_EQ(answer(std::nullopt).late, std::nullopt);
  EXPECT_EQ(answer(9.0).late, std::nullopt);  // block "free": no deadline
}

// Constant stimuli at the standard's level have no correct answer: such a
// trial gets no feedback even in a feedback block.
TEST(Engine, ATrialWithoutACorrectAnswerGetsNoFeedback) {
  Protocol p = BaseProtocol();
  Block b;
  b.name = "levels";
  b.method = Method::kConstantStimuli;
  b.axis = "ce";
  b.standard_level = 1.0;
  b.constant_stimuli.levels = {1.0, 1.5};
  b.constant_stimuli.repetitions = 2;
  b.constant_stimuli.response = ResponseMode::kTwoInterval;
  b.interval_s = {1.0, 1.0};
  b.practice = true;
  b.feedback = true;
  p.blocks = {b};
  Result<Engine> engine = Engine::Create(p, 0, 9);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  int with = 0, without = 0;
  const auto first = [](const TrialSpec&) { return Response{"1", {}}; };
  for (const TrialSpec& t : RunAll(*engine, first)) {
    EXPECT_EQ(t.feedback, !t.correct_answer.empty()) << t.trial_index;
    (t.feedback ? with : without) += 1;
  }
  EXPECT_EQ(with, 2);
  EXPECT_EQ(without, 2);
}

TEST(ScriptedResponse, MapsOneAndZeroToRightAndWrongAnswers) {
  TrialSpec t;
  t.trial_index = 3;
  t.method = Method::kSameDifferent;
  t.response_options = {"same", "different"};
  t.correct_answer = "different";
  EXPECT_EQ(ScriptedResponse(t, "1")->answer, "different");
  EXPECT_EQ(ScriptedResponse(t, "0")->answer, "same");
  EXPECT_EQ(ScriptedResponse(t, "same")->answer, "same");
  t.method = Method::kLimits;
  t.response_options = {"yes", "no"};
  t.correct_answer.clear();
  EXPECT_EQ(ScriptedResponse(t, "1")->answer, "yes");
  t.method = Method::kAdjustment;
  Result<Response> bad = ScriptedResponse(t, "1");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message,
            "trial 3 is an adjustment: script it as a path of '+' and '-' "
            "steps ending in '=' (e.g. ++-=), not \"1\"");
}

}  // namespace
}  // namespace burrlab::protocols
