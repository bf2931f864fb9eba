// What Discover answers on data from the independent truth: every mechanism
// variant at the strengths where its projected SNR reaches the targets, two
// porosity laws, a bump outside the library and the null, on the existing
// matrix's design (R = 1 mm, loads 0.5-1.5 of c_e R^2 in 6 levels, 4
// replicates, CV 10 %) for human temporal bone and PVC K70, with the
// material as the reference. Prints a Markdown table of verdict counts.
//
// The design is the same experiment on both materials in the model's own
// units (loads in c_e R^2, velocities in alpha R, noise on log v), so on the
// same seeds Discover gives the same answers; PVC runs seeds 1001 on, an
// independent replication.
//
// IndependentTruth.DiscoverRatesTable runs only with BURRLAB_SLOW_TESTS set:
// 20 seeds x 31 scenarios x 2 materials, about 1 CPU-s per Discover call,
// 20 minutes on one core of the release build (measured table: README.md
// here).
// Knobs: BURRLAB_TRUTH_SEEDS (default 20), BURRLAB_TRUTH_SNR (targets,
// default 4,6), BURRLAB_TRUTH_JOBS (threads sharing the seeds, default 1;
// the table is the same for any number), BURRLAB_TRUTH_FILTER (only the
// scenarios whose name contains one of its comma-separated parts; the null
// always runs),
// BURRLAB_TRUTH_MISSES (print each missed seed's verdict and summary).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "burrlab/analysis/model_gap/discover.h"
#include "burrlab/analysis/model_gap/discover_scenarios.h"
#include "burrlab/analysis/model_gap/measured_data.h"
#include "burrlab/sim/model.h"
#include "discover_fixtures.h"
#include "independent_truth/measured_csv.h"
#include "independent_truth/settled_descent.h"
#include "independent_truth/strength_at_snr.h"

namespace burrlab::analysis::independent_truth {
namespace {

// How one report answered a scenario whose truth hides `expected` (a library
// id, or "" when nothing should be named).
enum class Answer {
  kNamedRight,   // verdict named, the expected effect among those added
  kSetHoldsIt,   // named or ambiguous, the expected effect in an alias set
                 // (or added, in an ambiguous report)
  kOtherNamed,   // named or ambiguous without the expected effect
  kUnexplained,  // a gap the library does not explain
  kAbsorbed,     // an effect absorbed by c_e and alpha (reference check)
  kNone,         // no gap
};

bool Holds(const std::vector<std::string>& ids, const std::string& id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

Answer Classify(const DiscoverReport& r, const std::string& expected) {
  if (VerdictName(r.verdict) == "named" ||
      VerdictName(r.verdict) == "ambiguous") {
    if (expected.empty()) return Answer::kOtherNamed;
    if (VerdictName(r.verdict) == "named" && Holds(r.effects, expected)) {
      return Answer::kNamedRight;
    }
    bool in_set = Holds(r.effects, expected) || Holds(r.alias_set, expected);
    for (const std::vector<std::string>& set : r.alias_sets) {
      in_set = in_set || Holds(set, expected);
    }
    return in_set ? Answer::kSetHoldsIt : Answer::kOtherNamed;
  }
  if (VerdictName(r.verdict) == "unexplained") return Answer::kUnexplained;
  if (VerdictName(r.verdict) == "absorbed") return Answer::kAbsorbed;
  return Answer::kNone;
}

// The ids a named or ambiguous report sets out (every step's alias set).
std::vector<std::string> NamedIds(const DiscoverReport& r) {
  std::vector<std::string> ids;
  if (VerdictName(r.verdict) != "named" &&
      VerdictName(r.verdict) != "ambiguous")
    return ids;
  for (const std::vector<std::string>& set : r.alias_sets) {
    ids.insert(ids.end(), set.begin(), set.end());
  }
  if (ids.empty()) ids = r.alias_set;
  return ids;
}

DiscoverReport Report(Verdict verdict, std::vector<std::string> effects,
                      std::vector<std::vector<std::string>> sets) {
  DiscoverReport r;
  r.verdict = verdict;
  r.effects = std::move(effects);
  r.alias_sets = std::move(sets);
  if (!r.alias_sets.empty()) r.alias_set = r.alias_sets.front();
  return r;
}

TEST(IndependentTruthRates, ClassifiesReports) {
  const std::string power = "motor_power_limit";
  EXPECT_EQ(Classify(Report(Verdict::kNamed, {power}, {{power}}), power),
            Answer::kNamedRight);
  EXPECT_EQ(Classify(Report(Verdict::kAmbiguous, {"spindle_slowdown"},
                            {{"spindle_slowdown", power}}),
                     power),
            Answer::kSetHoldsIt);
  EXPECT_EQ(
      Classify(Report(Verdict::kAmbiguous, {power}, {{power, "x"}}), power),
      Answer::kSetHoldsIt);
  // A second step's set counts too.
  EXPECT_EQ(
      Classify(Report(Verdict::kAmbiguous, {"a", "b"}, {{"a"}, {"b", power}}),
               power),
      Answer::kSetHoldsIt);
  EXPECT_EQ(Classify(Report(Verdict::kNamed, {"a"}, {{"a"}}), power),
            Answer::kOtherNamed);
  EXPECT_EQ(Classify(Report(Verdict::kNamed, {"a"}, {{"a"}}), ""),
            Answer::kOtherNamed);
  EXPECT_EQ(Classify(Report(Verdict::kUnexplained, {}, {}), power),
            Answer::kUnexplained);
  EXPECT_EQ(Classify(Report(Verdict::kAbsorbed, {"porosity"}, {{"porosity"}}),
                     "porosity"),
            Answer::kAbsorbed);
  EXPECT_EQ(Classify(Report(Verdict::kNone, {}, {}), ""), Answer::kNone);
  EXPECT_EQ(
      NamedIds(Report(Verdict::kAmbiguous, {"a", "b"}, {{"a", "c"}, {"b"}})),
      (std::vector<std::string>{"a", "c", "b"}));
  EXPECT_TRUE(NamedIds(Report(Verdict::kAbsorbed, {"a"}, {{"a"}})).empty());
}

// Discover on one seed of the generator's data for `truth`, with the design's
// material as the reference, as the rates table runs it.
Result<DiscoverReport> DiscoverSeed(const Design& d,
                                    const std::vector<double>& truth,
                                    std::uint64_t seed) {
  const Result<MeasuredData> data = ParseMeasuredData(
      fmt::format("seed-{}.csv", seed), MeasuredCsv(d, truth, seed));
  if (!data.ok()) return data.error();
  DiscoverOptions options;
  options.radius_mm = d.radius_mm;
  options.definition = sim::VelocityDefinition::kSettled;  // the truth's
  sim::Material reference;
  reference.c_e_n_per_mm2 = d.c_e_n_per_mm2;
  reference.alpha_per_s = d.alpha_per_s;
  options.reference = reference;
  return Discover(*data, options);
}

// The held-out check on a kink. Truth: the independent generator's hard
// power cap (v falls as 1/demand once the motor's power runs out), bone at
// SNR 4, noise seed 1. A fit that leaves out the force level next to the
// kink cannot place it, and that one level's error rises more than the rest
// gain together: the leave-one-level-out RMSE of log v goes up, although the
// cap predicts most held-out levels better (4 of 6). Judged on the mean alone
// the cap was turned down and the report said `unexplained`; judged also level
// by level, the power limit is found (its family is one alias set with the
// other concave slowdowns on this design).
TEST(IndependentTruthRates, FindsAHardCapThatOneHeldOutLevelCannotPlace) {
  const Design d = BoneDesign();
#if defined(__SANITIZE_ADDRESS__)
  // The sanitizer build (11 s, nearly all of it the search, which runs there
  // in IndependentTruthSnr.FindsTheStrengthAtATarget) starts from the
  // strength the search finds, to 17 digits: the same truth.
  StrengthAtSnr cap;
  cap.strength = 14.371137050207222;
  cap.truth_mm_s = NoiseFreeVelocitiesMmS(
      d, TruthFor(d, Mechanism::kPowerCap, cap.strength));
  const Result<StrengthAtSnr> found = cap;
#else
  const Result<StrengthAtSnr> found =
      FindStrengthAtSnr(d, Mechanism::kPowerCap, 4.0);
#endif
  ASSERT_TRUE(found.ok()) << found.error().message;
  const Result<DiscoverReport> report = DiscoverSeed(d, found->truth_mm_s, 1);
  ASSERT_TRUE(report.ok()) << report.error().message;
  const Answer answer = Classify(*report, "motor_power_limit");
  EXPECT_TRUE(answer == Answer::kNamedRight || answer == Answer::kSetHoldsIt)
      << VerdictName(report->verdict) << ": " << report->summary;
  ASSERT_EQ(report->effects.size(), 1u) << report->summary;
  const ModelFit& before = report->baseline;
  const ModelFit& after = report->augmented;
  EXPECT_GT(after.cv_rmse_log_v, before.cv_rmse_log_v);
  ASSERT_EQ(before.cv_level_rmse_log_v.size(), 6u);
  ASSERT_EQ(after.cv_level_rmse_log_v.size(), 6u);
  int better = 0;
  for (std::size_t i = 0; i < 6; ++i) {
    better += after.cv_level_rmse_log_v[i] < before.cv_level_rmse_log_v[i];
  }
  EXPECT_GE(better, 4);
  // One held-out level carries the rise: its error grows by more than half.
  double worst_ratio = 0.0;
  for (std::size_t i = 0; i < 6; ++i) {
    worst_ratio = std::max(worst_ratio, after.cv_level_rmse_log_v[i] /
                                            before.cv_level_rmse_log_v[i]);
  }
  EXPECT_GT(worst_ratio, 1.5);
}

// One scenario's seeds.
struct Tally {
  std::map<Answer, int> answers;
  std::map<std::string, int> first_effects;  // effects[0] of named/ambiguous
  int porosity_named = 0;   // seeds with porosity in an alias set
  ScenarioOutcome outcome;  // for NamedBeyond against the null
};

struct SeedResult {
  std::optional<Error> error;
  DiscoverReport report;
};

Tally RunSeeds(const Design& d, const std::vector<double>& truth,
               const std::string& expected, std::uint64_t first_seed, int seeds,
               int jobs) {
  std::vector<SeedResult> results(static_cast<std::size_t>(seeds));
  std::atomic<int> next{0};
  const auto work = [&] {
    for (int k = next++; k < seeds; k = next++) {
      SeedResult& slot = results[static_cast<std::size_t>(k)];
      const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(k);
      Result<DiscoverReport> report = DiscoverSeed(d, truth, seed);
      if (!report.ok()) {
        slot.error = report.error();
        continue;
      }
      slot.report = std::move(*report);
    }
  };
  std::vector<std::thread> workers;
  for (int j = 1; j < std::min(jobs, seeds); ++j) workers.emplace_back(work);
  work();
  for (std::thread& t : workers) t.join();
  Tally tally;
  for (int k = 0; k < seeds; ++k) {
    const SeedResult& s = results[static_cast<std::size_t>(k)];
    EXPECT_FALSE(s.error.has_value()) << s.error->message;
    if (s.error) continue;
    const DiscoverReport& r = s.report;
    const Answer answer = Classify(r, expected);
    ++tally.answers[answer];
    const std::vector<std::string> named = NamedIds(r);
    if (!named.empty() && !r.effects.empty())
      ++tally.first_effects[r.effects[0]];
    tally.porosity_named += Holds(named, "porosity");
    ScenarioOutcome& o = tally.outcome;
    o.per_seed.push_back(
        {first_seed + static_cast<std::uint64_t>(k), r.verdict, named});
    ++o.seeds;
    ++o.verdicts[r.verdict];
    o.named_physical += !named.empty();
    const bool hit = answer == Answer::kNamedRight ||
                     answer == Answer::kSetHoldsIt ||
                     (answer == Answer::kAbsorbed && !r.effects.empty() &&
                      r.effects[0] == expected);
    if (!hit && !expected.empty() &&
        std::getenv("BURRLAB_TRUTH_MISSES") != nullptr) {
      std::fprintf(stderr, "  miss, seed %llu (%s): %s\n",
                   static_cast<unsigned long long>(o.per_seed.back().seed),
                   std::string(VerdictName(r.verdict)).c_str(),
                   r.summary.c_str());
    }
    if (hit) {
      ++o.hits;
      o.mean_cv_before += r.baseline.cv_rmse_log_v;
      o.mean_cv_after += r.augmented.cv_rmse_log_v;
      o.cv_shrank += r.augmented.cv_rmse_log_v < r.baseline.cv_rmse_log_v;
    }
  }
  if (tally.outcome.hits > 0) {
    tally.outcome.mean_cv_before /= tally.outcome.hits;
    tally.outcome.mean_cv_after /= tally.outcome.hits;
  }
  return tally;
}

int EnvInt(const char* name, int fallback) {
  const char* text = std::getenv(name);
  return text != nullptr ? std::max(1, std::atoi(text)) : fallback;
}

std::vector<double> EnvTargets() {
  const char* text = std::getenv("BURRLAB_TRUTH_SNR");
  std::vector<double> targets;
  std::stringstream in(text != nullptr ? text : "4,6");
  for (std::string item; std::getline(in, item, ',');) {
    targets.push_back(std::stod(item));
  }
  return targets;
}

struct Scenario {
  std::string name;
  Mechanism mechanism = Mechanism::kNone;
  double target = 0.0;  // 0: a fixed strength
  double strength = 0.0;
  double snr_averaged = 0.0, snr_free = 0.0;
  std::string expected;
  bool control = false;
};

std::string Count(const Tally& t, Answer a) {
  const auto it = t.answers.find(a);
  return std::to_string(it == t.answers.end() ? 0 : it->second);
}

std::string FirstEffects(const Tally& t) {
  std::vector<std::pair<int, std::string>> sorted;
  for (const auto& [id, n] : t.first_effects) sorted.push_back({-n, id});
  std::sort(sorted.begin(), sorted.end());
  std::string text;
  for (const auto& [n, id] : sorted) {
    text += fmt::format("{}{} {}", text.empty() ? "" : ", ", id, -n);
  }
  return text.empty() ? "—" : text;
}

TEST(IndependentTruth, DiscoverRatesTable) {
  if (!analysis::testing::Slow()) {
    GTEST_SKIP() << "set BURRLAB_SLOW_TESTS=1 (about 20 CPU-minutes)";
  }
  const int seeds = EnvInt("BURRLAB_TRUTH_SEEDS", 20);
  const int jobs = EnvInt("BURRLAB_TRUTH_JOBS", 1);
  const std::vector<double> targets = EnvTargets();
  const char* filter_text = std::getenv("BURRLAB_TRUTH_FILTER");
  std::vector<std::string> filter;
  std::stringstream filter_in(filter_text != nullptr ? filter_text : "");
  for (std::string part; std::getline(filter_in, part, ',');) {
    if (!part.empty()) filter.push_back(part);
  }
  const auto wanted = [&filter](const std::string& name) {
    return filter.empty() ||
           std::any_of(filter.begin(), filter.end(), [&](const auto& part) {
             return name.find(part) != std::string::npos;
           });
  };
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&start] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                         start)
        .count();
  };
  std::string table = fmt::format(
      "truth: independent (settled_descent.h), R = 1 mm, loads 0.5-1.5 of "
      "c_e R^2 (6 levels), 4 replicates, CV 0.1, {} seeds per scenario "
      "(bone from 1, PVC from 1001), Discover with the material as "
      "reference; SNR = noise-averaged "
      "(noise-free)\n\n"
      "| material | scenario | strength | SNR | named right | set holds it | "
      "other named | unexplained | absorbed | none | hit rate | held-out "
      "RMSE log v (hits) | first effect named (seeds) | named beyond the "
      "null |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
      seeds);
  for (const Design& d : {BoneDesign(), PvcDesign()}) {
    std::vector<Scenario> scenarios;
    scenarios.push_back(
        {"null (base model)", Mechanism::kNone, 0.0, 0.0, 0.0, 0.0, "", true});
    for (double target : targets) {
      for (const MechanismInfo& info : Mechanisms()) {
        if (!info.physical && info.mechanism != Mechanism::kLogBump) continue;
        scenarios.push_back({std::string(info.name), info.mechanism, target,
                             0.0, 0.0, 0.0, std::string(info.library_id),
                             !info.physical});
      }
    }
    for (Mechanism m :
         {Mechanism::kPorositySquare, Mechanism::kPorosityPower15}) {
      scenarios.push_back({std::string(InfoOf(m).name) + " 0.2", m, 0.0, 0.2,
                           0.0, 0.0, "porosity", true});
    }
    std::optional<Tally> null;
    for (Scenario& s : scenarios) {
      if (s.mechanism != Mechanism::kNone && !wanted(s.name)) {
        continue;
      }
      std::vector<double> truth;
      if (s.target > 0.0) {
        const Result<StrengthAtSnr> found =
            FindStrengthAtSnr(d, s.mechanism, s.target);
        if (!found.ok()) {
          std::fprintf(stderr, "%s %s at SNR %g: %s\n", d.material_name.c_str(),
                       s.name.c_str(), s.target, found.error().message.c_str());
          table += fmt::format("| {} | {} | — | {} | {} |\n", d.material_name,
                               s.name, s.target, found.error().message);
          continue;
        }
        s.strength = found->strength;
        truth = found->truth_mm_s;
        s.snr_averaged = found->snr_noise_averaged;
        s.snr_free = found->snr_noise_free;
      } else {
        truth = NoiseFreeVelocitiesMmS(d, TruthFor(d, s.mechanism, s.strength));
        SnrOptions free;
        free.definition = SnrDefinition::kNoiseFree;
        s.snr_averaged = ProjectedSnr(d, truth).value();
        s.snr_free = ProjectedSnr(d, truth, free).value();
      }
      const std::uint64_t first_seed = d.material_name == "pvc_k70" ? 1001 : 1;
      const Tally t = RunSeeds(d, truth, s.expected, first_seed, seeds, jobs);
      if (s.mechanism == Mechanism::kNone) null = t;
      if (s.expected == "porosity") {
        EXPECT_EQ(t.porosity_named, 0) << d.material_name << " " << s.name;
      }
      const ScenarioOutcome& o = t.outcome;
      const std::string hit_rate =
          s.expected.empty()
              ? "—"
              : fmt::format("{:.2f}", static_cast<double>(o.hits) / o.seeds);
      const std::string rmse =
          o.hits > 0 ? fmt::format("{:.3f} → {:.3f}", o.mean_cv_before,
                                   o.mean_cv_after)
                     : "—";
      const std::string beyond =
          s.control && s.mechanism != Mechanism::kNone && null
              ? std::to_string(NamedBeyond(o, null->outcome).size())
              : "—";
      const std::string strength =
          s.mechanism == Mechanism::kNone ? "—"
          : s.target > 0.0
              ? fmt::format("{:.4g} (SNR {:g})", s.strength, s.target)
              : fmt::format("{:.4g}", s.strength);
      const std::string row = fmt::format(
          "| {} | {} | {} | {:.2f} ({:.2f}) | {} | {} | {} | {} | {} | {} | {} "
          "| {} | {} | {} |\n",
          d.material_name, s.name, strength, s.snr_averaged, s.snr_free,
          s.expected.empty() ? "—" : Count(t, Answer::kNamedRight),
          s.expected.empty() ? "—" : Count(t, Answer::kSetHoldsIt),
          Count(t, Answer::kOtherNamed), Count(t, Answer::kUnexplained),
          Count(t, Answer::kAbsorbed), Count(t, Answer::kNone), hit_rate, rmse,
          FirstEffects(t), beyond);
      table += row;
      std::fprintf(stderr, "[%7.0f s] %s", seconds(), row.c_str());
    }
  }
  std::printf("\n%s\ntook %.0f s wall (%d seeds, %d job(s))\n", table.c_str(),
              seconds(), seeds, jobs);
}

}  // namespace
}  // namespace burrlab::analysis::independent_truth
