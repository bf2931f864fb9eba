// The effect library: ids, validation, and each effect's change to the
// simulator step (the steady-state numbers are checked against the
// surrogate in tests/analysis/model_gap/descent_surrogate_test.cc).
#include "burrlab/sim/effects.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string_view>
#include <vector>

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

// The shapes of sim/effects.h against their closed forms.
TEST(Effects, ShapesFollowTheirClosedForms) {
  Effects fx;
  EXPECT_EQ(ErosionRateScale(fx, 3.0, 0.1), 1.0);
  // Hard threshold: 1 - F0 / F above F0, nothing below.
  fx.cutting_threshold_n = 1.0;
  EXPECT_DOUBLE_EQ(ErosionRateScale(fx, 4.0, 0.1), 0.75);
  EXPECT_EQ(ErosionRateScale(fx, 0.9, 0.1), 0.0);
  // Soft: w ln(1 + exp((F - F0) / w)) / F with w = 0.5 F0; at F = F0 that is
  // 0.5 ln 2, and far above F0 it approaches the hard threshold.
  ASSERT_TRUE(SetEffect("cutting_threshold_soft", 1.0, &fx).ok());
  EXPECT_NEAR(ErosionRateScale(fx, 1.0, 0.1), 0.5 * std::log(2.0), 1e-12);
  EXPECT_NEAR(ErosionRateScale(fx, 20.0, 0.1), 0.95, 1e-6);
  EXPECT_GT(ErosionRateScale(fx, 0.5, 0.1), 0.0);
  // Spindle: linear 1 - F / F_s, exponential exp(-F / F_s).
  Effects spindle;
  ASSERT_TRUE(SetEffect("spindle_slowdown", 4.0, &spindle).ok());
  EXPECT_DOUBLE_EQ(ErosionRateScale(spindle, 1.0, 0.1), 0.75);
  ASSERT_TRUE(SetEffect("spindle_slowdown_exponential", 4.0, &spindle).ok());
  EXPECT_DOUBLE_EQ(ErosionRateScale(spindle, 1.0, 0.1), std::exp(-0.25));
  // Friction wear: 1 + k F^p / alpha.
  Effects wear;
  ASSERT_TRUE(SetEffect("friction_erosion", 0.2, &wear).ok());
  EXPECT_DOUBLE_EQ(ErosionRateScale(wear, 3.0, 0.1), 1.0 + 0.2 * 3.0 / 0.1);
  ASSERT_TRUE(SetEffect("friction_erosion_quadratic", 0.2, &wear).ok());
  EXPECT_DOUBLE_EQ(ErosionRateScale(wear, 3.0, 0.1), 1.0 + 0.2 * 9.0 / 0.1);
  // Power limit: the hard cap min(1, Q_max / Q); the droop with k = 1.5,
  // (1 + (Q / Q_max)^1.5)^(-1/1.5): 2^(-2/3) at Q = Q_max, below 1 well under
  // the limit, and towards the cap far above it.
  Effects power;
  ASSERT_TRUE(SetEffect("motor_power_limit", 2.0, &power).ok());
  EXPECT_EQ(PowerLimitScale(power, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(PowerLimitScale(power, 8.0), 0.25);
  ASSERT_TRUE(SetEffect("motor_power_limit_droop", 2.0, &power).ok());
  EXPECT_NEAR(PowerLimitScale(power, 2.0), std::pow(2.0, -2.0 / 3.0), 1e-12);
  EXPECT_LT(PowerLimitScale(power, 1.0), 0.95);
  EXPECT_NEAR(PowerLimitScale(power, 200.0) * 200.0 / 2.0, 1.0, 1e-3);
  // Setting the first shape again restores it.
  ASSERT_TRUE(SetEffect("motor_power_limit", 2.0, &power).ok());
  EXPECT_EQ(PowerLimitScale(power, 1.0), 1.0);
}

TEST(Effects, NamesUnknownIdsAndBadValues) {
  Effects effects;
  EXPECT_EQ(SetEffect("porosty", 0.1, &effects).error().message,
            "unknown effect 'porosty'; known effects: motor_power_limit, "
            "motor_power_limit_droop, spindle_slowdown, "
            "spindle_slowdown_exponential, cutting_threshold, "
            "cutting_threshold_soft, viscous_resistance, "
            "viscous_resistance_sqrt, friction_erosion, "
            "friction_erosion_quadratic, contact_exponent, "
            "contact_exponent_stiff, porosity, "
            "load_cell_lag, arm_compliance");
  EXPECT_EQ(SetEffect("motor_power_limit", 0.0, &effects).error().message,
            "motor_power_limit must be a positive removal rate in mm^3/s (inf "
            "for none), got 0");
  EXPECT_EQ(SetEffect("contact_exponent", 0.5, &effects).error().message,
            "contact_exponent must lie in [1, 2] (Hertz 1.5), got 0.5");
  EXPECT_EQ(SetEffect("porosity", 1.0, &effects).error().message,
            "porosity must lie in [0, 1), got 1");
  EXPECT_EQ(SetEffect("load_cell_lag", -0.1, &effects).error().message,
            "load_cell_lag must be a time constant in [0, 10] s, got -0.1");
  EXPECT_EQ(SetEffect("arm_compliance", 1e9, &effects).error().message,
            "arm_compliance must be a compliance in [0, 100] mm/N, got "
            "1000000000");
  EXPECT_EQ(SetEffect("spindle_slowdown", -2.0, &effects).error().message,
            "spindle_slowdown must be a positive stall force in N (inf for "
            "none), got -2");
  EXPECT_TRUE(effects.IsNull());  // unchanged after an error
  Model model;
  model.effects.cutting_threshold_n = -1.0;
  EXPECT_EQ(model.Validate().error().message,
            "cutting_threshold must be a finite force of at least 0 N, got -1");
}

TEST(Effects, EveryEffectHasOneParameterWithANullStrengthOfZero) {
  for (const EffectSpec& spec : EffectLibrary()) {
    EXPECT_EQ(ParameterAtStrength(spec, 0.0), spec.null_value) << spec.id;
    EXPECT_EQ(StrengthOfParameter(spec, spec.null_value), 0.0) << spec.id;
    const double value = ParameterAtStrength(spec, 0.25);
    EXPECT_NEAR(StrengthOfParameter(spec, value), 0.25, 1e-15) << spec.id;
    Effects effects;
    ASSERT_TRUE(SetEffect(spec.id, value, &effects).ok()) << spec.id;
    EXPECT_FALSE(effects.IsNull()) << spec.id;
    EXPECT_EQ(FindEffect(spec.id), &spec);
  }
  EXPECT_EQ(FindEffect("load_cell"), nullptr);
}

TEST(Effects, OnlyTheMeasurementChainEffectsAreTraceOnly) {
  std::vector<std::string_view> trace_only;
  for (const EffectSpec& spec : EffectLibrary()) {
    if (spec.trace_only) trace_only.push_back(spec.id);
  }
  EXPECT_EQ(trace_only,
            (std::vector<std::string_view>{"load_cell_lag", "arm_compliance"}));
}

// The elastic force of a burr held at depth h = R/2 in a solid half-space.
double ElasticForceN(const Effects& effects) {
  constexpr int kN = 32;
  constexpr double kVoxelMm = 0.2;
  Volume volume = Volume::Create(kN, kN, kN, kVoxelMm).value();
  for (int k = 0; k < kN / 2; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i) volume.Set(i, j, k, kSolidOccupancy);
  Model model;
  model.radius_mm = 1.0;
  model.effects = effects;
  const MomentOctree octree = MomentOctree::Build(volume);
  Input input;
  input.position_mm = {kN * kVoxelMm / 2, kN * kVoxelMm / 2,
                       kN / 2 * kVoxelMm + 0.5};
  const Output out = EvaluateForce(model, volume, octree, input);
  return out.elastic_n.z;
}

TEST(Effects, PorosityAndContactExponentChangeTheElasticForceOfEq73) {
  const double hertz = ElasticForceN({});
  ASSERT_GT(hertz, 0.0);
  Effects porous;
  porous.porosity = 0.2;  // c_e (1 - 0.2)^2
  EXPECT_NEAR(ElasticForceN(porous) / hertz, 0.64, 1e-12);
  // F = c_e R^2 (h/R)^n: the ratio to Hertz is (h/R)^(n - 3/2), h/R from the
  // Hertz force itself.
  const double depth_ratio = std::pow(hertz / (2.145 * 1.0), 2.0 / 3.0);
  Effects plastic;
  plastic.contact_exponent = 1.1;
  EXPECT_NEAR(ElasticForceN(plastic) / hertz, std::pow(depth_ratio, -0.4),
              1e-9);
}

TEST(Effects, ViscousResistanceAddsTheImpactForceOfEq714) {
  constexpr int kN = 32;
  constexpr double kVoxelMm = 0.2;
  Volume volume = Volume::Create(kN, kN, kN, kVoxelMm).value();
  for (int k = 0; k < kN / 2; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i) volume.Set(i, j, k, kSolidOccupancy);
  Model model;
  model.radius_mm = 1.0;
  model.effects.impact_c_i_n_s_per_mm3 = 3.0;
  const MomentOctree octree = MomentOctree::Build(volume);
  Input input;
  input.position_mm = {kN * kVoxelMm / 2, kN * kVoxelMm / 2,
                       kN / 2 * kVoxelMm + 0.5};
  input.velocity_mm_s = {0.0, 0.0, -0.2};  // descending
  const Output out = EvaluateForce(model, volume, octree, input);
  // F_i = -c_i R^2 (h/R) V.
  EXPECT_NEAR(out.impact_n.z, 3.0 * (out.h_mm / 1.0) * 0.2, 1e-12);
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

TEST(Effects, SpindleSlowdownAndFrictionErosionScaleTheErosionRate) {
  const double free_mm3 = RemovedMm3({});
  Effects stalled;
  stalled.stall_force_n = 1e-6;  // far below the elastic force: no cutting
  EXPECT_EQ(RemovedMm3(stalled), 0.0);
  Effects slowed;
  slowed.stall_force_n = 1e6;  // barely slowed
  EXPECT_GT(RemovedMm3(slowed), 0.9 * free_mm3);
  Effects wear;
  // alpha 0.3 + 3/(N s) x 0.27 N (h = R/4): 3.7 times the rate.
  wear.friction_erosion_per_n_s = 3.0;
  EXPECT_GT(RemovedMm3(wear), 2.0 * free_mm3);
}

}  // namespace
}  // namespace burrlab::sim
