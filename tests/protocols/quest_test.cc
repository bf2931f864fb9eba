// Tests of burrlab::protocols::Quest: replays of Psychtoolbox-3 traces
// (tests/protocols/fixtures/quest/, made by make_quest_fixtures.m in Octave),
// option validation, posterior normalisation, a simulated observer and
// reproducibility.
#include "burrlab/protocols/quest.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_01.hpp>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace burrlab::protocols {
namespace {

// Fixture values are log10 intensities of order 1 (one is 6e-18), so the
// comparison is absolute: |burrlab - Psychtoolbox| <= 1e-6.
constexpr double kPtbTolerance = 1e-6;

// One row of a fixture: the trial, then the estimates after its update.
struct TraceRow {
  int trial = 0;
  double intensity = 0.0;
  bool response = false;
  double quantile = 0.0;
  double mean = 0.0;
  double sd = 0.0;
  double mode = 0.0;
};

// A parsed quest_<case>.csv.
struct Trace {
  std::map<std::string, double> params;            // "# params:" key=value
  std::map<std::string, double> prior;             // "# prior:" key=value
  std::vector<std::pair<double, double>> quest_p;  // "# quest_p:" x:p
  std::vector<TraceRow> rows;
};

double ParseDouble(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);  // accepts Inf and -Inf
  EXPECT_EQ(*end, '\0') << "not a number: '" << s << "'";
  return v;
}

// Splits "key=value key=value" after the label into a map.
std::map<std::string, double> ParseKeyValues(const std::string& text) {
  std::map<std::string, double> out;
  std::istringstream in(text);
  std::string item;
  while (in >> item) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) continue;
    out[item.substr(0, eq)] = ParseDouble(item.substr(eq + 1));
  }
  return out;
}

std::string FixturePath(const std::string& name) {
  return std::string(BURRLAB_SOURCE_DIR) +
         "/tests/protocols/fixtures/quest/quest_" + name + ".csv";
}

Trace LoadTrace(const std::string& name) {
  Trace trace;
  std::ifstream file(FixturePath(name));
  EXPECT_TRUE(file.good()) << "cannot open " << FixturePath(name);
  std::string line;
  bool header_seen = false;
  while (std::getline(file, line)) {
    if (line.rfind("# params:", 0) == 0) {
      trace.params = ParseKeyValues(line.substr(9));
    } else if (line.rfind("# prior:", 0) == 0) {
      trace.prior = ParseKeyValues(line.substr(8));
    } else if (line.rfind("# quest_p:", 0) == 0) {
      std::istringstream in(line.substr(10));
      std::string pair;
      while (in >> pair) {
        const auto colon = pair.find(':');
        trace.quest_p.emplace_back(ParseDouble(pair.substr(0, colon)),
                                   ParseDouble(pair.substr(colon + 1)));
      }
    } else if (line.empty() || line[0] == '#') {
      continue;
    } else if (!header_seen) {
      EXPECT_EQ(line,
                "trial,intensity,response,quantile_after,mean_after,sd_after,"
                "mode_after");
      header_seen = true;
    } else {
      std::vector<std::string> cells;
      std::istringstream in(line);
      std::string cell;
      while (std::getline(in, cell, ',')) cells.push_back(cell);
      EXPECT_EQ(cells.size(), 7u) << line;
      if (cells.size() != 7) continue;
      TraceRow row;
      row.trial = std::atoi(cells[0].c_str());
      row.intensity = ParseDouble(cells[1]);
      row.response = cells[2] == "1";
      row.quantile = ParseDouble(cells[3]);
      row.mean = ParseDouble(cells[4]);
      row.sd = ParseDouble(cells[5]);
      row.mode = ParseDouble(cells[6]);
      trace.rows.push_back(row);
    }
  }
  return trace;
}

QuestOptions OptionsFrom(const Trace& trace) {
  const auto& p = trace.params;
  QuestOptions o;
  o.t_guess = p.at("t_guess");
  o.t_guess_sd = p.at("t_guess_sd");
  o.p_threshold = p.at("p_threshold");
  o.beta = p.at("beta");
  o.delta = p.at("delta");
  o.gamma = p.at("gamma");
  o.grain = p.at("grain");
  o.range = p.at("range");
  o.normalize_pdf = p.at("normalize_pdf") != 0.0;
  return o;
}

// Largest |burrlab - Psychtoolbox| seen in one replay.
struct MaxDiff {
  double value = 0.0;
  void Add(double ours, double theirs) {
    value = std::max(value, std::abs(ours - theirs));
  }
};

double QuantileOrDie(const Quest& quest) {
  Result<double> q = quest.Quantile();
  EXPECT_TRUE(q.ok()) << q.error().message;
  return q.ok() ? *q : std::numeric_limits<double>::quiet_NaN();
}

class QuestPsychtoolbox : public ::testing::TestWithParam<std::string> {};

TEST_P(QuestPsychtoolbox, ReplaysOctaveTraceWithin1e6) {
  const Trace trace = LoadTrace(GetParam());
  ASSERT_EQ(trace.rows.size(), 40u);
  ASSERT_EQ(trace.quest_p.size(), 8u);
  Result<Quest> created = Quest::Create(OptionsFrom(trace));
  ASSERT_TRUE(created.ok()) << created.error().message;
  Quest& quest = *created;
  MaxDiff diff;

  // Tables and the prior.
  EXPECT_NEAR(quest.quantile_order(), trace.prior.at("quantile_order"),
              kPtbTolerance);
  EXPECT_NEAR(quest.x_threshold(), trace.prior.at("x_threshold"),
              kPtbTolerance);
  diff.Add(quest.quantile_order(), trace.prior.at("quantile_order"));
  diff.Add(quest.x_threshold(), trace.prior.at("x_threshold"));
  for (const auto& [x, p] : trace.quest_p) {
    EXPECT_NEAR(quest.P(x), p, kPtbTolerance) << "QuestP at x = " << x;
    diff.Add(quest.P(x), p);
  }
  double placed = QuantileOrDie(quest);
  EXPECT_NEAR(placed, trace.prior.at("quantile"), kPtbTolerance);
  EXPECT_NEAR(quest.Mean(), trace.prior.at("mean"), kPtbTolerance);
  EXPECT_NEAR(quest.Sd(), trace.prior.at("sd"), kPtbTolerance);
  EXPECT_NEAR(quest.Mode(), trace.prior.at("mode"), kPtbTolerance);
  diff.Add(placed, trace.prior.at("quantile"));

  // Psychtoolbox warned "out of range" for exactly these scripted trials.
  const std::set<int> expected_clamped = GetParam() == "clamped"
                                             ? std::set<int>{4, 9, 14, 19, 29}
                                             : std::set<int>{};
  double previous_quantile = trace.prior.at("quantile");
  for (const TraceRow& row : trace.rows) {
    SCOPED_TRACE("trial " + std::to_string(row.trial));
    // Trials not scripted by the fixture were placed at QuestQuantile.
    if (row.intensity == previous_quantile) {
      EXPECT_NEAR(placed, row.intensity, kPtbTolerance);
    }
    Result<QuestUpdateReport> report =
        quest.Update(row.intensity, row.response);
    ASSERT_TRUE(report.ok()) << report.error().message;
    EXPECT_EQ(report->clamped, expected_clamped.count(row.trial) == 1);
    placed = QuantileOrDie(quest);
    EXPECT_NEAR(placed, row.quantile, kPtbTolerance);
    EXPECT_NEAR(quest.Mean(), row.mean, kPtbTolerance);
    EXPECT_NEAR(quest.Sd(), row.sd, kPtbTolerance);
    EXPECT_NEAR(quest.Mode(), row.mode, kPtbTolerance);
    diff.Add(placed, row.quantile);
    diff.Add(quest.Mean(), row.mean);
    diff.Add(quest.Sd(), row.sd);
    diff.Add(quest.Mode(), row.mode);
    previous_quantile = row.quantile;
  }

  // The history holds what was given, unclamped (PTB q.intensity).
  ASSERT_EQ(quest.trial_count(), 40);
  for (std::size_t k = 0; k < trace.rows.size(); ++k) {
    EXPECT_EQ(quest.trials()[k].intensity, trace.rows[k].intensity);
    EXPECT_EQ(quest.trials()[k].response, trace.rows[k].response);
  }
  std::cout << "[ quest    ] " << GetParam()
            << ": max |burrlab - Psychtoolbox| = " << diff.value << "\n";
}

// Test names carry the fixture's case name.
std::string CaseName(const ::testing::TestParamInfo<std::string>& param) {
  return "case_" + param.param;
}

INSTANTIATE_TEST_SUITE_P(QuestTraces, QuestPsychtoolbox,
                         ::testing::Values("2afc", "yesno",
                                           "4afc_beta2_grain002",
                                           "unnormalized", "clamped"),
                         CaseName);

std::string ValidateMessage(const QuestOptions& options) {
  const Status status = options.Validate();
  return status.ok() ? "ok" : status.error().message;
}

TEST(QuestOptions, DefaultsAreValid) {
  EXPECT_EQ(ValidateMessage(QuestOptions{}), "ok");
}

TEST(QuestOptions, ValidateNamesFieldRuleAndValue) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  QuestOptions o;
  o.beta = 0;
  EXPECT_EQ(ValidateMessage(o), "quest: beta must be positive, got 0");
  o = {};
  o.beta = inf;
  EXPECT_EQ(ValidateMessage(o), "quest: beta must be finite, got inf");
  o = {};
  o.t_guess = nan;
  EXPECT_EQ(ValidateMessage(o), "quest: t_guess must be finite, got nan");
  o = {};
  o.t_guess_sd = -1;
  EXPECT_EQ(ValidateMessage(o), "quest: t_guess_sd must be positive, got -1");
  o = {};
  o.delta = 1;
  EXPECT_EQ(ValidateMessage(o), "quest: delta must be in [0, 1), got 1");
  o = {};
  o.gamma = -0.1;
  EXPECT_EQ(ValidateMessage(o), "quest: gamma must be in [0, 1), got -0.1");
  o = {};
  o.p_threshold = 1.0;
  EXPECT_EQ(ValidateMessage(o), "quest: p_threshold must be in (0, 1), got 1");
  o = {};
  o.p_threshold = 0.4;
  EXPECT_EQ(ValidateMessage(o),
            "quest: p_threshold must be above gamma = 0.5, got 0.4");
  o = {};
  o.p_threshold = 0.999;
  EXPECT_EQ(ValidateMessage(o),
            "quest: p_threshold must be below the ceiling delta*gamma + 1 - "
            "delta = 0.995, got 0.999");
  o = {};
  o.grain = 0;
  EXPECT_EQ(ValidateMessage(o), "quest: grain must be positive, got 0");
  o = {};
  o.range = -5;
  EXPECT_EQ(ValidateMessage(o), "quest: range must be positive, got -5");
  o = {};
  o.range = 10000;
  o.grain = 0.001;
  EXPECT_EQ(ValidateMessage(o),
            "quest: range/grain must be at most 1000000 table steps, got "
            "10000000 (range 10000, grain 0.001)");
  o = {};
  o.quantile_order = 1.5;
  EXPECT_EQ(ValidateMessage(o),
            "quest: quantile_order must be in [0, 1], got 1.5");
  o = {};
  o.reserve_trials = -1;
  EXPECT_EQ(ValidateMessage(o),
            "quest: reserve_trials must be zero or positive, got -1");
}

TEST(QuestCreate, ReturnsTheValidationError) {
  QuestOptions o;
  o.beta = 0;
  Result<Quest> q = Quest::Create(o);
  ASSERT_FALSE(q.ok());
  EXPECT_EQ(q.error().message, "quest: beta must be positive, got 0");
}

TEST(QuestCreate, RangeTooNarrowForThresholdIsAnError) {
  // Over +-0.02 log units a beta = 3.5 Weibull spans only about 0.78..0.84.
  QuestOptions o;
  o.range = 0.02;
  o.p_threshold = 0.9;
  Result<Quest> q = Quest::Create(o);
  ASSERT_FALSE(q.ok());
  EXPECT_EQ(q.error().message,
            "quest: the psychometric function spans [0.7837, 0.8421] over "
            "the table and misses p_threshold = 0.9; increase range or beta");
}

TEST(QuestCreate, TableSpansRangeAroundGuess) {
  QuestOptions o;
  o.t_guess = -1.0;
  Result<Quest> q = Quest::Create(o);
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(q->x().size(), 501u);
  EXPECT_EQ(q->pdf().size(), 501u);
  EXPECT_DOUBLE_EQ(q->intensity_min(), -3.5);
  EXPECT_DOUBLE_EQ(q->intensity_max(), 1.5);
  // Threshold is where the function reaches p_threshold.
  EXPECT_NEAR(q->P(0.0), o.p_threshold, 1e-4);
}

TEST(QuestUpdate, NanIntensityIsAnErrorAndNotRecorded) {
  Result<Quest> q = Quest::Create(QuestOptions{});
  ASSERT_TRUE(q.ok());
  Result<QuestUpdateReport> r =
      q->Update(std::numeric_limits<double>::quiet_NaN(), true);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, "quest: intensity of trial 1 is NaN");
  EXPECT_EQ(q->trial_count(), 0);
}

TEST(QuestUpdate, ReportsClampingBeyondTheTable) {
  Result<Quest> q = Quest::Create(QuestOptions{});  // table -2.5 .. 2.5
  ASSERT_TRUE(q.ok());
  Result<QuestUpdateReport> edge = q->Update(2.5, true);
  ASSERT_TRUE(edge.ok());
  EXPECT_FALSE(edge->clamped);
  Result<QuestUpdateReport> above = q->Update(2.6, true);
  ASSERT_TRUE(above.ok());
  EXPECT_TRUE(above->clamped);
  EXPECT_DOUBLE_EQ(above->table_intensity, 2.5);
  // log10(0): a zero-contrast trial is legitimate and sits at the bottom.
  Result<QuestUpdateReport> zero =
      q->Update(-std::numeric_limits<double>::infinity(), false);
  ASSERT_TRUE(zero.ok());
  EXPECT_TRUE(zero->clamped);
  EXPECT_DOUBLE_EQ(zero->table_intensity, -2.5);
  EXPECT_EQ(q->trial_count(), 3);
  EXPECT_EQ(q->trials()[2].intensity, -std::numeric_limits<double>::infinity());
}

TEST(QuestUpdate, WithoutUpdatePdfOnlyRecords) {
  QuestOptions o;
  o.update_pdf = false;
  Result<Quest> q = Quest::Create(o);
  ASSERT_TRUE(q.ok());
  const std::vector<double> prior(q->pdf().begin(), q->pdf().end());
  ASSERT_TRUE(q->Update(0.3, true).ok());
  EXPECT_EQ(std::vector<double>(q->pdf().begin(), q->pdf().end()), prior);
  EXPECT_EQ(q->trial_count(), 1);
}

TEST(QuestQuantile, OrderOutsideZeroOneIsAnError) {
  Result<Quest> q = Quest::Create(QuestOptions{});
  ASSERT_TRUE(q.ok());
  Result<double> t = q->Quantile(1.5);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.error().message,
            "quest: quantile order must be in [0, 1], got 1.5");
}

TEST(QuestQuantile, MedianOfSymmetricPriorIsHalfAGrainLow) {
  Result<Quest> q = Quest::Create(QuestOptions{});
  ASSERT_TRUE(q.ok());
  // The prior is symmetric around t_guess = 0, but like QuestQuantile the
  // cumulative sum at x[j] includes pdf[j], which puts the median of a
  // symmetric posterior half a grain low.
  Result<double> median = q->Quantile(0.5);
  ASSERT_TRUE(median.ok());
  EXPECT_NEAR(*median, -0.005, 1e-12);
}

TEST(QuestQuantile, OptionOverridesPelliOrder) {
  QuestOptions o;
  o.quantile_order = 0.5;
  Result<Quest> q = Quest::Create(o);
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(q->quantile_order(), 0.5);
  // 2AFC (gamma 0.5, delta 0.01): Pelli's order is about 0.59.
  Result<Quest> pelli = Quest::Create(QuestOptions{});
  ASSERT_TRUE(pelli.ok());
  EXPECT_NEAR(pelli->quantile_order(), 0.5898, 1e-4);
}

// Scripted responses of a seeded observer, as (intensity, response) pairs
// produced by running `quest` itself.
std::vector<QuestTrial> RunObserver(Quest& quest, double true_threshold,
                                    int trials, unsigned seed) {
  boost::random::mt19937 rng(seed);
  boost::random::uniform_01<double> uniform;
  for (int k = 0; k < trials; ++k) {
    Result<double> t = quest.Quantile();
    EXPECT_TRUE(t.ok());
    const bool response = uniform(rng) < quest.P(*t - true_threshold);
    EXPECT_TRUE(quest.Update(*t, response).ok());
  }
  return {quest.trials().begin(), quest.trials().end()};
}

TEST(QuestPosterior, SumsToOneAfterEveryUpdate) {
  Result<Quest> q = Quest::Create(QuestOptions{});
  ASSERT_TRUE(q.ok());
  boost::random::mt19937 rng(7);
  boost::random::uniform_01<double> uniform;
  for (int k = 0; k < 200; ++k) {
    const double t = *q->Quantile();
    ASSERT_TRUE(q->Update(t, uniform(rng) < q->P(t + 0.4)).ok());
    double sum = 0.0;
    for (double p : q->pdf()) sum += p;
    ASSERT_NEAR(sum, 1.0, 1e-12) << "after trial " << k + 1;
  }
}

TEST(QuestPosterior, UnnormalizedGivesTheSameEstimates) {
  QuestOptions raw_options;
  raw_options.normalize_pdf = false;
  Result<Quest> normalized = Quest::Create(QuestOptions{});
  Result<Quest> raw = Quest::Create(raw_options);
  ASSERT_TRUE(normalized.ok() && raw.ok());
  const std::vector<QuestTrial> trials = RunObserver(*normalized, -0.6, 60, 11);
  double raw_sum = 0.0;
  for (const QuestTrial& t : trials) {
    ASSERT_TRUE(raw->Update(t.intensity, t.response).ok());
  }
  for (double p : raw->pdf()) raw_sum += p;
  EXPECT_LT(raw_sum, 1e-6);  // the product of 60 likelihoods, not rescaled
  EXPECT_NEAR(*raw->Quantile(), *normalized->Quantile(), 1e-9);
  EXPECT_NEAR(raw->Mean(), normalized->Mean(), 1e-9);
  EXPECT_NEAR(raw->Sd(), normalized->Sd(), 1e-9);
  EXPECT_EQ(raw->Mode(), normalized->Mode());
}

TEST(QuestObserver, MeanConvergesToTrueThreshold) {
  // 2AFC observer whose Weibull (log10 units) is QUEST's own, threshold -1.3;
  // prior guess -1 with sd 2. 400 seeded runs of 64 trials.
  constexpr double kTrue = -1.3;
  constexpr int kRuns = 400;
  QuestOptions o;
  o.t_guess = -1.0;
  o.t_guess_sd = 2.0;
  double sum_error = 0.0;
  double sum_squared_error = 0.0;
  int within_02 = 0;
  for (int run = 0; run < kRuns; ++run) {
    Result<Quest> q = Quest::Create(o);
    ASSERT_TRUE(q.ok());
    RunObserver(*q, kTrue, 64, 1000u + static_cast<unsigned>(run));
    const double error = q->Mean() - kTrue;
    sum_error += error;
    sum_squared_error += error * error;
    if (std::abs(error) < 0.2) ++within_02;
  }
  const double bias = sum_error / kRuns;
  const double rms = std::sqrt(sum_squared_error / kRuns);
  std::cout << "[ quest    ] bias " << bias << ", rms error " << rms
            << ", within 0.2: " << within_02 << "/" << kRuns << "\n";
  EXPECT_LT(std::abs(bias), 0.015);
  EXPECT_LT(rms, 0.06);
  EXPECT_GE(within_02, kRuns * 97 / 100);
}

TEST(QuestObserver, PosteriorSdMatchesErrorWhenThresholdsFollowThePrior) {
  // Bayesian calibration: with true thresholds drawn from QUEST's own prior
  // the mean squared error of the posterior mean equals the mean posterior
  // variance (up to Monte-Carlo error and the table's truncation).
  constexpr int kRuns = 400;
  QuestOptions o;
  o.t_guess = 0.0;
  o.t_guess_sd = 0.5;
  boost::random::mt19937 rng(2024);
  boost::random::normal_distribution<double> prior(o.t_guess, o.t_guess_sd);
  double sum_squared_error = 0.0;
  double sum_variance = 0.0;
  for (int run = 0; run < kRuns; ++run) {
    const double true_threshold = prior(rng);
    Result<Quest> q = Quest::Create(o);
    ASSERT_TRUE(q.ok());
    RunObserver(*q, true_threshold, 40, 5000u + static_cast<unsigned>(run));
    const double error = q->Mean() - true_threshold;
    sum_squared_error += error * error;
    sum_variance += q->Sd() * q->Sd();
  }
  const double ratio = sum_squared_error / sum_variance;
  std::cout << "[ quest    ] mse / mean posterior variance = " << ratio << "\n";
  EXPECT_GT(ratio, 0.8);
  EXPECT_LT(ratio, 1.25);
}

TEST(QuestReplay, SameResponsesGiveIdenticalTrace) {
  // A seeded observer run, with the placement and estimate of every trial.
  Result<Quest> first = Quest::Create(QuestOptions{});
  ASSERT_TRUE(first.ok());
  boost::random::mt19937 rng(99);
  boost::random::uniform_01<double> uniform;
  std::vector<double> placed, means, sds;
  for (int k = 0; k < 80; ++k) {
    const double t = *first->Quantile();
    ASSERT_TRUE(first->Update(t, uniform(rng) < first->P(t - 0.4)).ok());
    placed.push_back(t);
    means.push_back(first->Mean());
    sds.push_back(first->Sd());
  }
  // Replaying the recorded trials reproduces every number bit for bit.
  Result<Quest> replay = Quest::Create(QuestOptions{});
  ASSERT_TRUE(replay.ok());
  std::vector<double> replay_placed, replay_means, replay_sds;
  for (const QuestTrial& t : first->trials()) {
    replay_placed.push_back(*replay->Quantile());
    ASSERT_TRUE(replay->Update(t.intensity, t.response).ok());
    replay_means.push_back(replay->Mean());
    replay_sds.push_back(replay->Sd());
  }
  EXPECT_EQ(replay_placed, placed);
  EXPECT_EQ(replay_means, means);
  EXPECT_EQ(replay_sds, sds);
  EXPECT_EQ(std::vector<double>(replay->pdf().begin(), replay->pdf().end()),
            std::vector<double>(first->pdf().begin(), first->pdf().end()));
  // The same seed asks the same questions and gets the same answers.
  Result<Quest> again = Quest::Create(QuestOptions{});
  ASSERT_TRUE(again.ok());
  const std::vector<QuestTrial> repeat = RunObserver(*again, 0.4, 80, 99);
  ASSERT_EQ(repeat.size(), 80u);
  for (std::size_t k = 0; k < repeat.size(); ++k) {
    EXPECT_EQ(repeat[k].intensity, first->trials()[k].intensity);
    EXPECT_EQ(repeat[k].response, first->trials()[k].response);
  }
}

}  // namespace
}  // namespace burrlab::protocols
