// The shared rendering pool: which rendering an interval gets, and that
// results do not depend on the order or thread that asked. That a simulated
// study sharing renderings is reproducible for any number of jobs (`burrlab
// study --renderings`) is in cli/study_renderings_test.cc.
#include "studies/rendering_pool.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <thread>

#include "burrlab/stimuli/materials.h"

namespace burrlab::runner {
namespace {

stimuli::IntervalOptions ShortProbe(const char* material) {
  stimuli::IntervalOptions o;
  Result<stimuli::MaterialSet> set = stimuli::LoadBuiltinMaterial(material);
  EXPECT_TRUE(set.ok());
  o.material = set->material;
  o.task = stimuli::Task::kProbe;
  o.duration_s = 2.0;
  o.trace_hz = 100;
  return o;
}

TEST(RenderingPool, TheIntervalSeedPicksOneOfKRenderingsOfItsStimulus) {
  RenderingPool pool(3, 7);
  stimuli::IntervalOptions o = ShortProbe("pvc_k70");
  std::vector<stimuli::IntervalResult> first;
  for (std::uint64_t seed = 0; seed < 3; ++seed) {
    o.seed = seed;
    Result<stimuli::IntervalResult> r = pool.Present(o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->rows.size(), 200u);  // 2 s at 100 Hz, traces kept
    first.push_back(*r);
  }
  EXPECT_EQ(pool.rendered(), 3);
  // Seeds 3..8 reuse renderings 0..2: nothing more is rendered.
  for (std::uint64_t seed = 3; seed < 9; ++seed) {
    o.seed = seed;
    Result<stimuli::IntervalResult> r = pool.Present(o);
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r->rows, first[seed % 3].rows) << seed;
    EXPECT_EQ(r->cue, first[seed % 3].cue);
  }
  EXPECT_EQ(pool.rendered(), 3);
  // The renderings differ (own erosion seeds) and Cues lists them in order.
  Result<std::vector<double>> cues = pool.Cues(o);
  ASSERT_TRUE(cues.ok());
  ASSERT_EQ(cues->size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ((*cues)[k], first[k].cue);
  // Another stimulus is rendered on its own.
  o = ShortProbe("human_temporal_bone");
  ASSERT_TRUE(pool.Present(o).ok());
  EXPECT_EQ(pool.rendered(), 4);
}

TEST(RenderingPool, RenderingsDependOnTheStimulusNotOnWhoAskedFirst) {
  const stimuli::IntervalOptions a = ShortProbe("pvc_k70");
  const stimuli::IntervalOptions b = ShortProbe("human_temporal_bone");
  RenderingPool forward(2, 5, false), backward(2, 5, false);
  Result<std::vector<double>> fa = forward.Cues(a), fb = forward.Cues(b);
  Result<std::vector<double>> bb = backward.Cues(b), ba = backward.Cues(a);
  ASSERT_TRUE(fa.ok() && fb.ok() && ba.ok() && bb.ok());
  EXPECT_EQ(*fa, *ba);
  EXPECT_EQ(*fb, *bb);
  EXPECT_NE(*fa, *fb);
  // Without traces the rows are dropped; the cue stays.
  Result<stimuli::IntervalResult> r = forward.Present(a);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->rows.empty());
  // Threads asking for the same stimulus at once get one rendering each.
  RenderingPool shared(2, 5);
  std::vector<std::thread> threads;
  std::vector<double> seen(8);
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&, t] {
      stimuli::IntervalOptions o = a;
      o.seed = static_cast<std::uint64_t>(t);
      Result<stimuli::IntervalResult> x = shared.Present(o);
      seen[static_cast<std::size_t>(t)] = x.ok() ? x->cue : -1.0;
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(shared.rendered(), 2);
  for (int t = 0; t < 8; ++t) EXPECT_EQ(seen[t], (*fa)[t % 2]) << t;
}

// A subject's typical factors are felt at the nearest of five levels e^(z s),
// z = -2 ... 2; the interval spreads are kept; a drill drops the speed.
TEST(RenderingPool, PooledSubjectsExploreAtFiveLevels) {
  protocols::Exploration e;
  e.subject_force_spread = 0.05;
  e.subject_speed_spread = 0.15;
  e.force_spread = 0.15;
  e.speed_spread = 0.12;
  std::set<double> force_levels, speed_levels;
  for (double z = -4.0; z <= 4.0; z += 0.01) {
    e.force_factor = std::exp(z * 0.05);
    e.speed_factor = std::exp(z * 0.15);
    const protocols::Exploration p =
        PooledExploration(e, stimuli::Task::kProbe);
    const double zq = std::clamp(std::round(z), -2.0, 2.0);
    ASSERT_NEAR(p.force_factor, std::exp(zq * 0.05), 1e-12) << z;
    ASSERT_NEAR(p.speed_factor, std::exp(zq * 0.15), 1e-12) << z;
    EXPECT_EQ(p.force_spread, 0.15);
    EXPECT_EQ(p.speed_spread, 0.12);
    force_levels.insert(p.force_factor);
    speed_levels.insert(p.speed_factor);
    const protocols::Exploration d =
        PooledExploration(e, stimuli::Task::kDrill);
    EXPECT_EQ(d.force_factor, p.force_factor);
    EXPECT_EQ(d.speed_factor, 1.0);
    EXPECT_EQ(d.speed_spread, 0.0);
  }
  EXPECT_EQ(force_levels.size(), 5u);
  EXPECT_EQ(speed_levels.size(), 5u);
  // Without subject spreads the factors are kept as they are.
  protocols::Exploration own;
  own.force_factor = 1.3;
  EXPECT_EQ(PooledExploration(own, stimuli::Task::kProbe).force_factor, 1.3);
}

}  // namespace
}  // namespace burrlab::runner
