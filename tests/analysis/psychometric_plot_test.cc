// The psychometric figure: what it draws and where.
#include "burrlab/analysis/psychometric_plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

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

}  // namespace
}  // namespace burrlab::analysis
