// Line plots: tick choice, where data lands in the image, PNG output and
// errors.
#include "burrlab/analysis/plot.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace burrlab::analysis {
namespace {

TEST(NiceTicks, StepsOfOneTwoOrFiveTimesAPowerOfTenCoverTheRange) {
  EXPECT_EQ(NiceTicks(0.0, 19.3), (std::vector<double>{0, 5, 10, 15, 20}));
  const std::vector<double> ticks = NiceTicks(3.0, 6.0);
  ASSERT_EQ(ticks.size(), 7u);
  EXPECT_DOUBLE_EQ(ticks.front(), 3.0);
  EXPECT_DOUBLE_EQ(ticks[1], 3.5);
  EXPECT_DOUBLE_EQ(ticks.back(), 6.0);
  const std::vector<double> negative = NiceTicks(-1.2, 10.3);
  EXPECT_DOUBLE_EQ(negative.front(), -2.0);
  EXPECT_DOUBLE_EQ(negative.back(), 12.0);
}

TEST(NiceTicks, WidensADegenerateRange) {
  const std::vector<double> ticks = NiceTicks(2.0, 2.0);
  ASSERT_GE(ticks.size(), 2u);
  EXPECT_LE(ticks.front(), 1.8);
  EXPECT_GE(ticks.back(), 2.2);
}

TEST(LogTicks, UseOneTwoFiveWithinFewDecades) {
  EXPECT_EQ(LogTicks(0.0053, 0.84),
            (std::vector<double>{0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0}));
  EXPECT_TRUE(LogTicks(0.0, 1.0).empty());
}

// Pixel (x, y) of an image.
std::array<int, 3> Pixel(const Image& image, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 3;
  return {image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]};
}

TEST(RenderPlot, MarkersLandWhereTheAxesPutThem) {
  LinePlot plot;
  plot.title = "test";
  // One marker at the axis corner (0, 0) and one at the far corner (10, 20),
  // both on ticks.
  plot.series.push_back({"", {0.0, 10.0}, {0.0, 20.0}, false, true, 0});
  Result<Image> image = RenderPlot(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  ASSERT_EQ(image->width, 900);
  ASSERT_EQ(image->height, 600);
  EXPECT_EQ(Pixel(*image, 2, 2),
            (std::array<int, 3>{255, 255, 255}));  // background
  // The far corner is the top-right of the axes: right = width - 24, top = 64.
  EXPECT_EQ(Pixel(*image, 900 - 24 - 2, 64 + 2),
            (std::array<int, 3>{0, 114, 178}));
}

TEST(RenderPlot, RejectsBadInputNamingIt) {
  LinePlot plot;
  plot.title = "empty";
  EXPECT_EQ(RenderPlot(plot).error().message,
            "plot 'empty' has no finite points");
  plot.series.push_back({"a", {1.0, 2.0}, {1.0}, true, false, -1});
  EXPECT_EQ(RenderPlot(plot).error().message,
            "series 'a' has 2 x values and 1 y values");
  plot.series.clear();
  plot.series.push_back({"a", {1.0}, {1.0}, true, false, -1});
  plot.width_px = 10;
  EXPECT_EQ(RenderPlot(plot).error().message,
            "plot size must be 200x150 to 8000x8000 pixels, got 10x600");
}

TEST(RenderPlot, DrawsMarkersOfTheGivenSize) {
  LinePlot plot;
  Series s{"", {0.0, 10.0}, {0.0, 20.0}, false, true, 0};
  s.marker_px = {2.0, 30.0};
  plot.series.push_back(s);
  Result<Image> image = RenderPlot(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  // The 30 px marker at the far corner covers 14 px around it; the 2 px one
  // at the origin does not reach 5 px.
  const int right = 900 - 24, top = 64;
  EXPECT_EQ(Pixel(*image, right - 12, top + 12),
            (std::array<int, 3>{0, 114, 178}));
  s.marker_px = {2.0};
  plot.series = {s};
  EXPECT_EQ(RenderPlot(plot).error().message,
            "series '' has 2 points and 1 marker sizes");
}

TEST(WritePlotPng, WritesAPngFileAndNamesAFileItCannotWrite) {
  LinePlot plot;
  plot.series.push_back(
      {"line", {0.0, 1.0, 2.0}, {1.0, 3.0, 2.0}, true, true, -1});
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "burrlab_plot_test.png";
  ASSERT_TRUE(WritePlotPng(plot, path.string()).ok());
  std::ifstream file(path, std::ios::binary);
  std::string magic(8, '\0');
  file.read(magic.data(), 8);
  EXPECT_EQ(magic, "\x89PNG\r\n\x1a\n");
  std::filesystem::remove(path);
  EXPECT_EQ(WritePlotPng(plot, "/nonexistent-dir/x.png").error().message,
            "/nonexistent-dir/x.png: cannot write PNG file");
}

}  // namespace
}  // namespace burrlab::analysis
