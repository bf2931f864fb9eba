// The effect library: ids, validation, and each effect's change to the
// simulator step (the steady-state numbers are checked against the
// surrogate in tests/analysis/descent_surrogate_test.cc).
#include "burrlab/sim/effects.h"

#include <gtest/gtest.h>

#include <cstdint>

#include "burrlab/sim/step.h"

namespace burrlab::sim {
namespace {

TEST(Effects, DefaultIsNullAndSetEffectChangesOneParameter) {
  Effects effects;
  EXPECT_TRUE(effects.IsNull());
  ASSERT_TRUE(SetEffect("cutting_threshold", 0.5, &effects).ok());
  EXPECT_EQ(effects.cutting_threshold_n, 0.5);
  EXPECT_FALSE(effects.IsNull());
  ASSERT_TRUE(SetEffect("cutting_threshold", 0.0, &effects).ok());
  EXPECT_TRUE(effects.IsNull());
}

TEST(Effects, NamesUnknownIdsAndBadValues) {
  Effects effects;
  EXPECT_EQ(SetEffect("porosity", 0.1, &effects).error().message,
            "unknown effect 'porosity'; known effects: motor_power_limit, "
            "cutting_threshold");
  EXPECT_EQ(SetEffect("motor_power_limit", 0.0, &effects).error().message,
            "motor_power_limit must be a positive removal rate in mm^3/s (inf "
            "for none), got 0");
  EXPECT_TRUE(effects.IsNull());  // unchanged after an error
  Model model;
  model.effects.cutting_threshold_n = -1.0;
  EXPECT_EQ(model.Validate().error().message,
            "cutting_threshold must be a finite force of at least 0 N, got -1");
}

// Material removed by a spinning burr held a quarter of its radius deep in a
// solid half-space for 200 steps.
double RemovedMm3(const Effects& effects) {
  constexpr int kN = 32;
  constexpr double kVoxelMm = 0.2;
  Volume volume = Volume::Create(kN, kN, kN, kVoxelMm).value();
  for (int k = 0; k < kN / 2; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i) volume.Set(i, j, k, kSolidOccupancy);
  Model model;
  model.radius_mm = 1.0;
  model.material.alpha_per_s = 0.3;
  model.effects = effects;
  State state = State::Create(model, std::move(volume), 3).value();
  Input input;
  const double surface_mm = kN / 2 * kVoxelMm;
  input.position_mm = {kN * kVoxelMm / 2, kN * kVoxelMm / 2, surface_mm + 0.75};
  input.spindle_rad_s = {0.0, 0.0, 2094.0};
  Output out;
  for (int step = 0; step < 200; ++step) Step(model, state, input, &out);
  return state.counters().removed_mm3;
}

TEST(Effects, CuttingThresholdStopsErosionBelowTheForce) {
  const double free_mm3 = RemovedMm3({});
  ASSERT_GT(free_mm3, 0.0);
  Effects above;
  above.cutting_threshold_n = 1e6;  // far above the elastic force
  EXPECT_EQ(RemovedMm3(above), 0.0);
}

TEST(Effects, MotorPowerLimitCapsTheRemovalRate) {
  const double free_mm3 = RemovedMm3({});
  Effects limited;
  // A tenth of the free rate over the 0.2 s run.
  limited.max_removal_mm3_per_s = 0.1 * free_mm3 / 0.2;
  const double removed = RemovedMm3(limited);
  // The load filter (0.1 s) lets the first steps run free, then the rate
  // holds at the cap.
  EXPECT_LT(removed, 0.5 * free_mm3);
  EXPECT_GT(removed, 0.1 * free_mm3);
}

}  // namespace
}  // namespace burrlab::sim
