// The psychometric figure: what it draws and where.
#include "burrlab/analysis/psychometric_plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "golden.h"

namespace burrlab::analysis {
namespace {

TEST(MakePsychometricPlot, DrawsDataCurveAndThresholdBars) {
  const std::vector<DataBlock> fixed = {{1.0, 21, 40}, {2.0, 24, 40},
                                        {3.0, 29, 40}, {4.0, 35, 40},
                                        {5.0, 9, 10},  {6.0, 40, 40}};
  PsychometricOptions o;
  o.bootstrap_samples = 199;
  Result<PsychometricAnalysis> a = AnalyzePsychometric(fixed, o);
  ASSERT_TRUE(a.ok()) << a.error().message;
  const LinePlot plot = MakePsychometricPlot(fixed, *a, "level (N/mm^2)");
  ASSERT_EQ(plot.series.size(), 4u);
  const Series& curve = plot.series[0];
  const Series& points = plot.series[1];
  const Series& bars = plot.series[2];
  EXPECT_EQ(plot.x_label, "level (N/mm^2)");
  EXPECT_EQ(plot.y_label, "proportion correct");
  // Markers: proportions, the smaller block drawn smaller (area ~ trials).
  EXPECT_DOUBLE_EQ(points.y[4], 0.9);
  EXPECT_NEAR(points.marker_px[4] / points.marker_px[0], 0.5, 1e-12);
  // The curve is psi of the fit.
  EXPECT_NEAR(curve.y[150], Psi(o.sigmoid, a->fit.params, curve.x[150]), 1e-15);
  // One bar per threshold, at the height psi reaches there, around it.
  ASSERT_EQ(bars.x.size(), 9u);
  EXPECT_TRUE(std::isnan(bars.x[2]));
  EXPECT_LT(bars.x[3], a->thresholds[1].value);
  EXPECT_GT(bars.x[4], a->thresholds[1].value);
  EXPECT_DOUBLE_EQ(bars.y[3],
                   Psi(o.sigmoid, a->fit.params, a->thresholds[1].value));
  EXPECT_TRUE(RenderPlot(plot).ok());
}

const std::vector<DataBlock> kGoldenBlocks = {{1.0, 21, 40}, {2.0, 24, 40},
                                              {3.0, 29, 40}, {4.0, 35, 40},
                                              {5.0, 9, 10},  {6.0, 40, 40}};

TEST(MakePsychometricPlot, DataHaveWilsonIntervalsAndChanceIsALine) {
  PsychometricOptions o;
  o.bootstrap_samples = 0;
  Result<PsychometricAnalysis> a = AnalyzePsychometric(kGoldenBlocks, o);
  ASSERT_TRUE(a.ok()) << a.error().message;
  const LinePlot plot = MakePsychometricPlot(kGoldenBlocks, *a, "level (N)");
  const Series& points = plot.series[1];
  ASSERT_EQ(points.y_low.size(), kGoldenBlocks.size());
  // 21 of 40: Wilson's 95 % interval (p + z^2/2n -+ z sqrt(p(1-p)/n +
  // z^2/4n^2)) / (1 + z^2/n), z = 1.95996: [0.374974, 0.670645].
  EXPECT_NEAR(points.y_low[0], 0.374974, 1e-6);
  EXPECT_NEAR(points.y_high[0], 0.670645, 1e-6);
  // 40 of 40: [n / (n + z^2), 1] = [0.912378, 1].
  EXPECT_NEAR(points.y_low[5], 0.912378, 1e-6);
  EXPECT_DOUBLE_EQ(points.y_high[5], 1.0);
  // Chance (gamma = 0.5) as a horizontal line; each threshold a vertical one.
  ASSERT_EQ(plot.reference_lines.size(), 4u);
  EXPECT_TRUE(plot.reference_lines[0].vertical);
  EXPECT_DOUBLE_EQ(plot.reference_lines[1].value, a->thresholds[1].value);
  EXPECT_FALSE(plot.reference_lines[3].vertical);
  EXPECT_DOUBLE_EQ(plot.reference_lines[3].value, 0.5);
  EXPECT_EQ(plot.reference_lines[3].label, "chance 50 %");
}

TEST(GoldenPlot, PsychometricFitWithErrorBarsReferenceLinesAndLegend) {
  PsychometricOptions o;
  o.bootstrap_samples = 199;
  Result<PsychometricAnalysis> a = AnalyzePsychometric(kGoldenBlocks, o);
  ASSERT_TRUE(a.ok()) << a.error().message;
  EXPECT_EQ(testing::CompareWithGolden(
                MakePsychometricPlot(kGoldenBlocks, *a, "level (N/mm^2)"),
                "psychometric"),
            "");
}

}  // namespace
}  // namespace burrlab::analysis
