// The simulated hand's exploration that varies ([observer] exploration,
// force_spread, speed_spread; protocols::ExploredInterval) on the full
// simulator: the cue a subject feels varies with the force it presses with as
// contact mechanics says it must, rendered sessions draw every interval's
// force from their own stream (the same seed, the same forces), and virtual
// studies' pools sample the hand's variability with their renderings.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "../results_schema/temp_dir.h"
#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/observer.h"
#include "burrlab/protocols/streams.h"
#include "burrlab/results_schema/journal.h"
#include "burrlab/stimuli/interval.h"
#include "burrlab/stimuli/materials.h"
#include "example_protocol.h"
#include "read_file.h"
#include "studies/rendering_pool.h"
#include "studies/study.h"
#include "studies/virtual_study.h"

namespace burrlab::runner {
namespace {

namespace rs = results_schema;
using protocols::Exploration;
using protocols::StreamPurpose;

// Slope of the least-squares line of y on x.
double Slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(y.size());
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
  }
  return sxy / sxx;
}

// Kind of truth: a closed form of contact mechanics, not the code under test.
// A probe's felt stiffness is its peak force over the indentation there; for
// Hertzian contact F = c_e R^2 (h / R)^(3/2) (eq. 6.12) that is F / h =
// c_e^(2/3) R^(1/3) F^(1/3). So a hand whose force varies by an SD of ln F
// of s feels the stiffness vary by s / 3, and the log-log slope of felt
// stiffness on force is 1/3, on soft PVC and on hard bone alike. Probing
// erodes nothing, so all the cue's variability is the hand's.
TEST(Exploration, ProbingStiffnessVariesAsTheCubeRootOfTheHandsForce) {
  Exploration e;
  e.force_spread = 0.15;
  for (const char* name : {"pvc_k70", "human_temporal_bone"}) {
    stimuli::IntervalOptions nominal;
    nominal.material = stimuli::LoadBuiltinMaterial(name).value().material;
    nominal.task = stimuli::Task::kProbe;
    nominal.duration_s = 3.0;  // three presses
    boost::random::mt19937 stream =
        protocols::StreamFor(4, StreamPurpose::kExploration);
    std::vector<double> ln_force, ln_cue;
    for (int i = 0; i < 12; ++i) {
      const stimuli::IntervalOptions o =
          protocols::ExploredInterval(nominal, e, stream);
      Result<stimuli::IntervalResult> r = stimuli::PresentSimulatedInterval(o);
      ASSERT_TRUE(r.ok()) << r.error().message;
      ln_force.push_back(std::log(o.probe_force_n));
      ln_cue.push_back(std::log(r->cue));
    }
    const double slope = Slope(ln_force, ln_cue);
    RecordProperty(std::string(name) + "_slope", std::to_string(slope));
    EXPECT_NEAR(slope, 1.0 / 3.0, 0.02) << name;
    // Nothing but the force moves the cue: the line explains it all.
    const double a = ln_cue[0] - slope * ln_force[0];
    for (std::size_t i = 0; i < ln_cue.size(); ++i) {
      EXPECT_NEAR(ln_cue[i], a + slope * ln_force[i], 0.01) << name << i;
    }
  }
}

constexpr char kDrillProtocol[] = R"(format = "burrlab-protocol/1"
[study]
name = "explore"
[recording]
trace_hz = 100
[materials.pvc]
builtin = "pvc_k70"
[materials.bone]
builtin = "human_temporal_bone"
[observer]
exploration = "varied"
[[blocks]]
name = "drill"
method = "same_different"
task = "drill"
a = "pvc"
b = "bone"
trials = 8
interval_s = 2
)";

// Every drill interval's held force (the trace's target_force_n) is the
// protocol's 3 N x the subject's factor x exp(force_spread z), z the first
// draw of the session's exploration stream of (trial, interval): written out
// here from the documented draw, not through ExploredInterval. Rendering
// afresh and through a pool of 2 renderings: the pool's intervals of one
// stimulus take one of its renderings' forces. The same seed gives the same
// forces and answers.
TEST(Exploration, RenderedSessionsDrawTheHandsForceForEveryInterval) {
  Result<protocols::LoadedProtocol> loaded =
      protocols::ParseLoadedProtocol("explore.toml", kDrillProtocol);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  const protocols::ObserverParams typical =
      protocols::ObserverParamsFrom(loaded->protocol.observer);
  ASSERT_EQ(typical.exploration.force_spread, 0.15);
  std::vector<std::string> first_answers;
  for (int run = 0; run < 3; ++run) {
    const bool pooled = run == 2;
    rs::TempDir dir;
    RenderingPool pool(2, 9);
    SimulatedStudyOptions study;
    study.out_dir = dir.path() / "study";
    study.labels = {"01", "02"};
    study.seed = 5;
    for (int s = 0; s < 2; ++s) {
      study.observers.push_back(
          protocols::DrawSubjectObserver(typical, {}, study.seed, s));
    }
    // The subjects press differently (subject_force_spread 0.05).
    ASSERT_NE(study.observers[0].exploration.force_factor,
              study.observers[1].exploration.force_factor);
    study.renderings = pooled ? &pool : nullptr;
    const SimulatedStudyResult r = RunSimulatedStudy(*loaded, study);
    ASSERT_EQ(r.failed(), 0) << r.failures[0] << r.failures[1];
    std::vector<std::string> answers;
    for (int s = 0; s < 2; ++s) {
      const protocols::Exploration& e = study.observers[s].exploration;
      const std::uint64_t session_seed =
          protocols::SeedFor(study.seed, StreamPurpose::kSubjectSeed,
                             static_cast<std::uint64_t>(s));
      Result<rs::Journal> journal =
          rs::Journal::Open(study.out_dir, study.labels[s]);
      ASSERT_TRUE(journal.ok()) << journal.error().message;
      Result<std::vector<rs::TrialRecord>> trials = journal->Trials();
      ASSERT_TRUE(trials.ok());
      ASSERT_EQ(trials->size(), 8u);
      std::set<double> forces;
      std::vector<double> ln_force;
      for (const rs::TrialRecord& t : *trials) {
        answers.push_back(t.response);
        Result<std::vector<rs::TraceSamples>> traces =
            journal->Traces(t.trial_index);
        ASSERT_TRUE(traces.ok());
        ASSERT_EQ(traces->size(), 2u);
        for (const rs::TraceSamples& trace : *traces) {
          const auto column = std::find(trace.columns.begin(),
                                        trace.columns.end(), "target_force_n");
          ASSERT_NE(column, trace.columns.end());
          const std::size_t c =
              static_cast<std::size_t>(column - trace.columns.begin());
          const double held = trace.rows.front()[c];
          for (const std::vector<double>& row : trace.rows) {
            ASSERT_EQ(row[c], held);  // held for the whole interval
          }
          forces.insert(held);
          ln_force.push_back(std::log(held / 3.0));
          if (!pooled) {
            boost::random::mt19937 stream = protocols::StreamFor(
                session_seed, StreamPurpose::kExploration,
                static_cast<std::uint64_t>(t.trial_index),
                static_cast<std::uint64_t>(trace.interval_index));
            boost::random::normal_distribution<double> unit(0.0, 1.0);
            EXPECT_DOUBLE_EQ(
                held, 3.0 * e.force_factor * std::exp(0.15 * unit(stream)));
          }
        }
      }
      if (pooled) {
        // Two materials, two renderings each.
        EXPECT_LE(forces.size(), 4u);
      } else {
        EXPECT_EQ(forces.size(), 16u);
        double mean = 0.0, ss = 0.0;
        for (double l : ln_force) mean += l / 16.0;
        for (double l : ln_force) ss += (l - mean) * (l - mean);
        // 16 draws of SD 0.15 (the chi-square's 99.9 % range is 0.07-0.24).
        EXPECT_GT(std::sqrt(ss / 15.0), 0.07);
        EXPECT_LT(std::sqrt(ss / 15.0), 0.24);
      }
    }
    if (run == 0) first_answers = answers;
    if (run == 1) {
      EXPECT_EQ(answers, first_answers);
    }
    // participants.tsv says how each subject explored.
    const std::string table = ReadFile(study.out_dir / "participants.tsv");
    EXPECT_NE(
        table.find(fmt::format("\tfixed\t0\t{}\t{}\t0.15\t0.12\t",
                               study.observers[1].exploration.force_factor,
                               study.observers[1].exploration.speed_factor)),
        std::string::npos)
        << table;
  }
}

// A virtual study's pool renders each stimulus with a draw of the hand per
// rendering, so the observer's familiarization (FeltMaterialOf the pool's
// cues) holds the hand's variability: felt probing stiffness varies by about
// force_spread / 3 (the Hertz slope above) where without exploration it does
// not vary at all.
TEST(Exploration, VirtualStudiesPoolsSampleTheHandsVariability) {
  const protocols::Protocol protocol =
      ExampleProtocol("same_different_pvc_vs_bone.toml");
  Result<protocols::Engine> engine = protocols::Engine::Create(protocol, 0, 1);
  ASSERT_TRUE(engine.ok());
  const protocols::TrialSpec trial = engine->current();
  ASSERT_EQ(trial.task, protocols::Task::kProbe);
  const protocols::ProtocolMaterial* bone = protocol.FindMaterial("bone");
  ASSERT_NE(bone, nullptr);
  CuePool pool(12, 2.0, 21);
  Exploration e;
  e.force_spread = 0.3;
  Result<const std::vector<double>*> fixed =
      pool.Cues(protocol, trial, bone->set, 5.0);
  ASSERT_TRUE(fixed.ok()) << fixed.error().message;
  Result<const std::vector<double>*> varied =
      pool.Cues(protocol, trial, bone->set, 5.0, e);
  ASSERT_TRUE(varied.ok()) << varied.error().message;
  // Identical renderings (to the rounding of their logs).
  EXPECT_LT(protocols::FeltMaterialOf(**fixed).var_ln_cue, 1e-20);
  const double sd = std::sqrt(protocols::FeltMaterialOf(**varied).var_ln_cue);
  // 12 draws: the sample SD of ln F lies within 0.55-1.45 of 0.3 (99.9 %).
  EXPECT_GT(sd, 0.55 * 0.3 / 3.0);
  EXPECT_LT(sd, 1.45 * 0.3 / 3.0);
  EXPECT_EQ(pool.rendered(), 24);
}

}  // namespace
}  // namespace burrlab::runner
