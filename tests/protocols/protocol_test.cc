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
