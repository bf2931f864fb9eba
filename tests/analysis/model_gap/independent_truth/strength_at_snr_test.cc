// The projected SNR of the independent truth's mechanisms and the strength
// at a target (strength_at_snr.h).
#include "independent_truth/strength_at_snr.h"

#include <gtest/gtest.h>

#include <vector>

namespace burrlab::analysis::independent_truth {
namespace {

SnrOptions NoiseFree() {
  SnrOptions o;
  o.definition = SnrDefinition::kNoiseFree;
  return o;
}

// The base model and a porous sample (c_e (1 - phi)^2: a pure rescale of c_e)
// are fitted by the base model: no SNR, under either definition (the
// noise-averaged one of the base model is ~0 up to its 48 draws' sampling
// error; measured 0).
TEST(IndependentTruthSnr, BaseModelAndPorosityHaveNone) {
  const Design d = BoneDesign();
  for (const Truth& t : {TruthFor(d, Mechanism::kNone, 0.0),
                         TruthFor(d, Mechanism::kPorositySquare, 0.2)}) {
    const std::vector<double> v = NoiseFreeVelocitiesMmS(d, t);
    EXPECT_LT(ProjectedSnr(d, v, NoiseFree()).value(), 0.01);
    EXPECT_LT(ProjectedSnr(d, v).value(), 1.0);
  }
}

TEST(IndependentTruthSnr, FindsTheStrengthAtATarget) {
  const Design d = BoneDesign();
  const StrengthAtSnr found =
      FindStrengthAtSnr(d, Mechanism::kSpindleExponential, 4.0).value();
  EXPECT_GE(found.snr, 4.0);
  EXPECT_LT(found.snr, 4.02);
  EXPECT_EQ(found.snr, found.snr_noise_averaged);
  const std::vector<double> weaker = NoiseFreeVelocitiesMmS(
      d, TruthFor(d, Mechanism::kSpindleExponential, 0.99 * found.strength));
  EXPECT_LT(ProjectedSnr(d, weaker).value(), 4.0);
  // The noise-free definition on PVC, a load offset.
  const Design pvc = PvcDesign();
  const StrengthAtSnr offset =
      FindStrengthAtSnr(pvc, Mechanism::kThresholdOffset, 6.0, NoiseFree())
          .value();
  EXPECT_GE(offset.snr, 6.0);
  EXPECT_LT(offset.snr, 6.03);
  EXPECT_EQ(offset.snr, offset.snr_noise_free);
  EXPECT_LT(offset.strength, pvc.ForcesN().front());
}

// The softest contact law allowed (n = 1) does not reach SNR 1000.
TEST(IndependentTruthSnr, SaysWhenATargetIsOutOfReach) {
  const Result<StrengthAtSnr> found = FindStrengthAtSnr(
      BoneDesign(), Mechanism::kContactSofter, 1000.0, NoiseFree());
  ASSERT_FALSE(found.ok());
  EXPECT_NE(found.error().message.find("contact_softer reaches a projected SNR "
                                       "of only"),
            std::string::npos)
      << found.error().message;
}

}  // namespace
}  // namespace burrlab::analysis::independent_truth
