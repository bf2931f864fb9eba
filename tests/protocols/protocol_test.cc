// The protocol model: axes against their closed forms, counterbalanced block
// orders, and the diagnostic format.
#include "burrlab/protocols/protocol.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace burrlab::protocols {
namespace {

Protocol TwoMaterials() {
  Protocol p;
  ProtocolMaterial soft;
  soft.id = "soft";
  soft.set.display_name = "soft";
  soft.set.material = {0.5, 0.3, 0.2, 0.5, 0.01};
  ProtocolMaterial hard;
  hard.id = "hard";
  hard.set.display_name = "hard";
  hard.set.material = {2.0, 0.1, 0.6, 0.25, 0.04};
  p.materials = {soft, hard};
  return p;
}

TEST(MaterialAtLevel, RatioIncrementAndValueAxesFollowTheirFormulas) {
  const Protocol p = TwoMaterials();
  Axis axis;
  axis.id = "ce";
  axis.parameter = MaterialParameter::kCE;
  axis.reference = "hard";
  axis.kind = AxisKind::kRatio;
  EXPECT_DOUBLE_EQ(MaterialAtLevel(p, axis, 1.5)->material.c_e_n_per_mm2, 3.0);
  EXPECT_DOUBLE_EQ(MaterialAtLevel(p, axis, 1.5)->material.alpha_per_s, 0.1);
  EXPECT_EQ(MaterialAtLevel(p, axis, 1.5)->name, "ce@1.5");
  axis.kind = AxisKind::kIncrement;
  EXPECT_DOUBLE_EQ(MaterialAtLevel(p, axis, 0.25)->material.c_e_n_per_mm2, 2.5);
  axis.kind = AxisKind::kValue;
  axis.parameter = MaterialParameter::kAlpha;
  EXPECT_DOUBLE_EQ(MaterialAtLevel(p, axis, 0.7)->material.alpha_per_s, 0.7);
  EXPECT_DOUBLE_EQ(MaterialAtLevel(p, axis, 0.7)->material.c_e_n_per_mm2, 2.0);
  EXPECT_EQ(MaterialAtLevel(p, axis, -1.0).error().message,
            "axis \"ce\" (value): level -1 is outside its domain (greater "
            "than 0)");
  axis.kind = AxisKind::kIncrement;
  EXPECT_EQ(MaterialAtLevel(p, axis, -1.0).error().message,
            "axis \"ce\" (increment): level -1 is outside its domain "
            "(greater than -1)");
}

TEST(MaterialAtLevel, LogInterpolationIsGeometricInEveryParameter) {
  const Protocol p = TwoMaterials();
  Axis axis;
  axis.id = "mix";
  axis.kind = AxisKind::kLogInterpolation;
  axis.from = "soft";
  axis.to = "hard";
  const sim::Material m = MaterialAtLevel(p, axis, 0.5)->material;
  EXPECT_NEAR(m.c_e_n_per_mm2, std::sqrt(0.5 * 2.0), 1e-12);
  EXPECT_NEAR(m.alpha_per_s, std::sqrt(0.3 * 0.1), 1e-12);
  EXPECT_NEAR(m.c_mu_n_per_mm2, std::sqrt(0.2 * 0.6), 1e-12);
  EXPECT_NEAR(m.mu, std::sqrt(0.5 * 0.25), 1e-12);
  EXPECT_NEAR(m.c_i_n_s_per_mm3, std::sqrt(0.01 * 0.04), 1e-12);
  EXPECT_DOUBLE_EQ(MaterialAtLevel(p, axis, 0.0)->material.c_e_n_per_mm2, 0.5);
  EXPECT_NEAR(MaterialAtLevel(p, axis, 1.0)->material.c_e_n_per_mm2, 2.0,
              1e-12);
  EXPECT_FALSE(MaterialAtLevel(p, axis, 1.2).ok());
}

TEST(MaterialAtLevel, RefusesParametersBeyondWhatMaterialsAccept) {
  // The exact text: 1e308 x c_e overflows, and a level past the largest
  // declarable c_e is refused like one outside the domain.
  const Protocol p = TwoMaterials();
  Axis axis;
  axis.id = "ce";
  axis.parameter = MaterialParameter::kCE;
  axis.reference = "hard";
  axis.kind = AxisKind::kRatio;
  EXPECT_EQ(MaterialAtLevel(p, axis, 1e308).error().message,
            "axis \"ce\" (ratio): level 1e+308 gives c_e = inf, outside (0, "
            "1000000] (the range [materials] accepts)");
  EXPECT_TRUE(MaterialAtLevel(p, axis, 5e5).ok());  // c_e = 1e6 exactly
  EXPECT_FALSE(MaterialAtLevel(p, axis, 5.000001e5).ok());
  axis.kind = AxisKind::kValue;
  EXPECT_EQ(MaterialAtLevel(p, axis, 2e6).error().message,
            "axis \"ce\" (value): level 2000000 gives c_e = 2000000, outside "
            "(0, 1000000] (the range [materials] accepts)");
}

TEST(AxisDomain, IsTheDomainWhereEveryMaterialCanBePresented) {
  // Each end gives a material MaterialAtLevel accepts; one step beyond the
  // upper end does not.
  const Protocol p = TwoMaterials();
  Axis axis;
  axis.id = "ce";
  axis.parameter = MaterialParameter::kCE;
  axis.reference = "hard";  // c_e = 2
  for (AxisKind kind :
       {AxisKind::kRatio, AxisKind::kIncrement, AxisKind::kValue}) {
    axis.kind = kind;
    const auto [lo, hi] = AxisDomain(p, axis);
    EXPECT_TRUE(MaterialAtLevel(p, axis, lo).ok()) << AxisKindName(kind);
    EXPECT_TRUE(MaterialAtLevel(p, axis, hi).ok()) << AxisKindName(kind);
    EXPECT_FALSE(MaterialAtLevel(p, axis, std::nextafter(hi, 2 * hi)).ok())
        << AxisKindName(kind);
  }
  axis.kind = AxisKind::kRatio;
  EXPECT_EQ(AxisDomain(p, axis), (std::pair(1e-9, 5e5)));
  axis.kind = AxisKind::kIncrement;
  EXPECT_DOUBLE_EQ(AxisDomain(p, axis).first, -1.0 + 1e-9);
  EXPECT_DOUBLE_EQ(AxisDomain(p, axis).second, 5e5 - 1.0);
  axis.kind = AxisKind::kLogInterpolation;
  EXPECT_EQ(AxisDomain(p, axis), (std::pair(0.0, 1.0)));
}

TEST(CheckSimulatedIntervals, NamesEveryReachedLevelThatCannotBeProbed) {
  // The exact text, against stimuli::IntervalOptions::Validate's bound: at
  // R = 2 mm and 0.3 mm voxels, 2 N needs c_e >= 2 / (0.9 x 4 x
  // (3.7 / 2)^(3/2)) = 0.2207 N/mm^2, i.e. a c_e ratio to bone (2.145) of
  // at least 0.103. The floor 0.05 is too soft; the ceiling and the standard
  // are fine. At R = 0.5 mm even twice bone's c_e holds only 1.6 N.
  const std::string text = R"toml(format = "burrlab-protocol/1"
[study]
name = "t"
[materials.bone]
builtin = "human_temporal_bone"
[axes.ce]
kind = "ratio"
parameter = "c_e_n_per_mm2"
reference = "bone"
[[blocks]]
method = "staircase"
task = "probe"
axis = "ce"
step_scale = "log10"
start_level = 1
floor = 0.05
ceiling = 2
max_trials = 30
)toml";
  const ParseOutcome outcome = ParseProtocol("p.toml", text);
  ASSERT_TRUE(outcome.protocol.has_value());
  const Protocol& p = *outcome.protocol;
  ASSERT_EQ(p.blocks[0].reach.size(), 3u);
  EXPECT_EQ(p.blocks[0].reach[0].what, "blocks[1]: the standard (level 1)");
  EXPECT_EQ(p.blocks[0].reach[1].what, "blocks[1].floor = 0.05");
  EXPECT_EQ(p.blocks[0].reach[2].what, "blocks[1].ceiling = 2");
  EXPECT_EQ(FormatDiagnostics("p.toml", text, CheckSimulatedIntervals(p, 2.0)),
            "p.toml:16:9: error: blocks[1].floor = 0.05: the simulated hand "
            "cannot probe it: probe_force_n = 2 N is more than material c_e = "
            "0.10725 N/mm^2 holds with radius_mm = 2 and voxel_mm = 0.3 (at "
            "most 0.972 N); lower [observer] probe_force_n or keep the levels "
            "where the material is stiffer\n"
            "floor = 0.05\n"
            "        ^\n");
  const std::vector<Diagnostic> small = CheckSimulatedIntervals(p, 0.5);
  ASSERT_EQ(small.size(), 3u);  // the standard (the block), floor, ceiling
  EXPECT_EQ(small[0].where.line, 10);
  EXPECT_EQ(small[1].where.line, 16);
  EXPECT_EQ(small[2].where.line, 17);
  // A radius no interval accepts is said once, without a place.
  EXPECT_EQ(FormatDiagnostics("p.toml", text, CheckSimulatedIntervals(p, 7.0)),
            "p.toml: error: interval: radius_mm must be in [0.5, 5], got 7\n");
}

TEST(BlockOrder, WilliamsSquareBalancesFirstOrderCarryOver) {
  for (int n : {2, 3, 4, 5, 6}) {
    Protocol p;
    p.blocks.resize(static_cast<std::size_t>(n));
    p.counterbalance = Counterbalance::kLatinSquare;
    const int rows = n % 2 == 0 ? n : 2 * n;
    std::set<std::pair<int, int>> pairs;
    int pair_count = 0;
    std::vector<std::vector<int>> position_counts(
        static_cast<std::size_t>(n),
        std::vector<int>(static_cast<std::size_t>(n)));
    for (int r = 0; r < rows; ++r) {
      const std::vector<int> order = BlockOrder(p, r);
      ASSERT_EQ(std::set<int>(order.begin(), order.end()).size(),
                static_cast<std::size_t>(n));
      for (int k = 0; k < n; ++k) {
        ++position_counts[static_cast<std::size_t>(order[k])]
                         [static_cast<std::size_t>(k)];
        if (k + 1 < n) {
          pairs.insert({order[k], order[k + 1]});
          ++pair_count;
        }
      }
      EXPECT_EQ(BlockOrder(p, r + rows), order);  // rows repeat
    }
    // Every ordered pair of distinct blocks follows directly equally often
    // (once for even n, twice over the 2n rows for odd n), and every block
    // holds every position equally often.
    EXPECT_EQ(pairs.size(), static_cast<std::size_t>(n * (n - 1))) << n;
    EXPECT_EQ(pair_count, rows * (n - 1)) << n;
    for (const auto& counts : position_counts) {
      for (int c : counts) EXPECT_EQ(c, rows / n) << n;
    }
  }
}

TEST(BlockOrder, ReverseAndNone) {
  Protocol p;
  p.blocks.resize(3);
  EXPECT_EQ(BlockOrder(p, 5), (std::vector<int>{0, 1, 2}));
  p.counterbalance = Counterbalance::kReverse;
  EXPECT_EQ(BlockOrder(p, 4), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(BlockOrder(p, 5), (std::vector<int>{2, 1, 0}));
}

TEST(FormatDiagnostic, CaretFollowsTabsAndColumnOne) {
  const std::string text = "a = 1\n\tb\t= x\n";
  EXPECT_EQ(FormatDiagnostic("f.toml", text, {{2, 4}, "bad"}),
            "f.toml:2:4: error: bad\n\tb\t= x\n\t \t^\n");
  EXPECT_EQ(FormatDiagnostic("f.toml", text, {{1, 1}, "first"}),
            "f.toml:1:1: error: first\na = 1\n^\n");
  EXPECT_EQ(FormatDiagnostic("f.toml", text, {{}, "whole file"}),
            "f.toml: error: whole file\n");
}

TEST(FormatDiagnostic, EscapesControlCharactersInMessageAndSourceLine) {
  const std::string text = "a = 1\nk\x1b]0;x\x07 = \"\xff\"\n";
  EXPECT_EQ(FormatDiagnostic("f.toml", text, {{2, 10}, "got \x1b[2J\x9b"}),
            "f.toml:2:10: error: got \\x1b[2J\\x9b\n"
            "k\\x1b]0;x\\x07 = \"\\xff\"\n"
            "               ^\n");
}

TEST(FormatDiagnostics, PrintsAHundredThenCountsTheRest) {
  const std::string text = "a = 1\nb = 2\n";
  std::vector<Diagnostic> all(kMaxPrintedDiagnostics + 2, {{2, 1}, "bad"});
  const std::string one = "f.toml:2:1: error: bad\nb = 2\n^\n";
  std::string expected;
  for (std::size_t i = 0; i < kMaxPrintedDiagnostics; ++i) expected += one;
  EXPECT_EQ(FormatDiagnostics("f.toml", text, all),
            expected + "f.toml: ... and 2 more errors\n");
  all.resize(kMaxPrintedDiagnostics + 1);
  EXPECT_EQ(FormatDiagnostics("f.toml", text, all),
            expected + "f.toml: ... and 1 more error\n");
  all.resize(2);
  all[0] = {{1, 3}, "first"};
  all[1] = {{}, "whole file"};
  EXPECT_EQ(
      FormatDiagnostics("f.toml", text, all),
      "f.toml:1:3: error: first\na = 1\n  ^\nf.toml: error: whole file\n");
}

}  // namespace
}  // namespace burrlab::protocols
