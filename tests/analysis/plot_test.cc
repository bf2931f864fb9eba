// Line plots: tick choice, where data, error bars, reference lines and the
// legend land in the image, golden images, PNG/PDF/SVG output and errors.
#include "burrlab/analysis/plot.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "golden.h"

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

TEST(WritePlot, WritesAPngFileAndNamesAFileItCannotWrite) {
  LinePlot plot;
  plot.series.push_back(
      {"line", {0.0, 1.0, 2.0}, {1.0, 3.0, 2.0}, true, true, -1});
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "burrlab_plot_test.png";
  ASSERT_TRUE(WritePlot(plot, path.string()).ok());
  std::ifstream file(path, std::ios::binary);
  std::string magic(8, '\0');
  file.read(magic.data(), 8);
  EXPECT_EQ(magic, "\x89PNG\r\n\x1a\n");
  std::filesystem::remove(path);
  EXPECT_EQ(WritePlot(plot, "/nonexistent-dir/x.png").error().message,
            "/nonexistent-dir/x.png: cannot write the figure: folder "
            "'/nonexistent-dir' does not exist");
}

// The bounding box of the pixels inside [x0, x1) x [y0, y1) for which
// `match(r, g, b)` holds; empty() when there are none.
struct PixelBox {
  int x0 = 1 << 20, y0 = 1 << 20, x1 = -1, y1 = -1;
  bool empty() const { return x1 < x0; }
};
template <typename Match>
PixelBox FindPixels(const Image& image, Match match, int x0 = 0, int y0 = 0,
                    int x1 = 1 << 20, int y1 = 1 << 20) {
  PixelBox box;
  for (int y = std::max(y0, 0); y < std::min(y1, image.height); ++y) {
    for (int x = std::max(x0, 0); x < std::min(x1, image.width); ++x) {
      const std::array<int, 3> p = Pixel(image, x, y);
      if (match(p[0], p[1], p[2])) {
        box.x0 = std::min(box.x0, x);
        box.y0 = std::min(box.y0, y);
        box.x1 = std::max(box.x1, x);
        box.y1 = std::max(box.y1, y);
      }
    }
  }
  return box;
}

// Palette 0 (0, 114, 178) and palette 1 (213, 94, 0), also where
// antialiasing blends them with white; text and grey lines are neither.
bool Bluish(int r, int, int b) { return b - r > 60; }
bool Orangish(int r, int, int b) { return r - b > 60; }
// The reference lines' dashes (110, 110, 110), blended with white: darker
// than the grid (225) and not black.
bool DashGrey(int r, int g, int b) {
  return r == g && g == b && r > 60 && r < 200;
}

constexpr std::array<int, 3> kLegendFrame = {190, 190, 190};

// The legend's frame: the rows holding a run of at least 60 pixels of its
// grey (text edges have that grey in short runs only).
PixelBox FindLegendFrame(const Image& image) {
  PixelBox box;
  for (int y = 0; y < image.height; ++y) {
    int run = 0;
    for (int x = 0; x < image.width; ++x) {
      run = Pixel(image, x, y) == kLegendFrame ? run + 1 : 0;
      if (run >= 60) {
        box.y0 = std::min(box.y0, y);
        box.y1 = std::max(box.y1, y);
        box.x0 = std::min(box.x0, x - run + 1);
        box.x1 = std::max(box.x1, x);
      }
    }
  }
  return box;
}

// Markers of palette 1 at (0, 0) and (10, 10): the pixel centres of those
// corners, from the markers' boxes.
struct Corners {
  double x0, y0, x10, y10;
};
Corners FindCorners(const Image& image) {
  const PixelBox low =
      FindPixels(image, Orangish, 0, 0, image.width / 2, image.height);
  const PixelBox high = FindPixels(image, Orangish, image.width / 2, 0,
                                   image.width, image.height);
  return {0.5 * (low.x0 + low.x1), 0.5 * (low.y0 + low.y1),
          0.5 * (high.x0 + high.x1), 0.5 * (high.y0 + high.y1)};
}
Series CornerMarkers() {
  return {"", {0.0, 10.0}, {0.0, 10.0}, false, true, 1};
}

TEST(RenderPlot, ErrorBarsSpanTheirIntervalWithCaps) {
  LinePlot plot;
  plot.series.push_back(CornerMarkers());
  Series bar{"", {5.0}, {5.0}, false, false, 0};
  bar.y_low = {2.0};
  bar.y_high = {8.0};
  plot.series.push_back(bar);
  Result<Image> image = RenderPlot(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  const Corners c = FindCorners(*image);
  const PixelBox b = FindPixels(*image, Bluish);
  ASSERT_FALSE(b.empty());
  const double unit_y = (c.y0 - c.y10) / 10.0;  // pixels per y unit
  EXPECT_NEAR(0.5 * (b.x0 + b.x1), 0.5 * (c.x0 + c.x10), 1.0);
  EXPECT_NEAR(b.y0, c.y0 - 8.0 * unit_y, 1.5);  // top cap at y_high
  EXPECT_NEAR(b.y1, c.y0 - 2.0 * unit_y, 1.5);  // bottom cap at y_low
  EXPECT_NEAR(b.x1 - b.x0, 8.0, 1.5);           // caps 8 px wide
}

TEST(RenderPlot, ErrorBarsWidenTheYAxisAndSkipNonFiniteEntries) {
  LinePlot plot;
  Series s{"", {0.0, 1.0}, {1.0, 1.0}, false, true, 0};
  s.y_low = {0.5, std::nan("")};
  s.y_high = {1.5, 30.0};
  plot.series.push_back(s);
  Series marks = CornerMarkers();
  plot.series.push_back(marks);
  Result<Image> image = RenderPlot(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  // Only the first point has a bar: nothing blue above 1.5 (y of the top
  // corner marker is 10).
  const Corners c = FindCorners(*image);
  const PixelBox b = FindPixels(*image, Bluish);
  const double unit_y = (c.y0 - c.y10) / 10.0;
  EXPECT_NEAR(b.y0, c.y0 - 1.5 * unit_y, 1.5);
  s.y_high = {1.5};
  plot.series = {s};
  EXPECT_EQ(RenderPlot(plot).error().message,
            "series '' has 2 points, 2 y_low and 1 y_high values");
}

TEST(RenderPlot, AVerticalReferenceLineLandsAtItsValue) {
  LinePlot plot;
  plot.series.push_back(CornerMarkers());
  plot.reference_lines.push_back({true, 2.5, "cut"});
  Result<Image> image = RenderPlot(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  const Corners c = FindCorners(*image);
  const PixelBox grey =
      FindPixels(*image, DashGrey, static_cast<int>(c.x0) + 3,
                 static_cast<int>(c.y10) + 30, static_cast<int>(c.x10) - 3,
                 static_cast<int>(c.y0) - 5);
  ASSERT_FALSE(grey.empty());
  const double expected_x = c.x0 + 0.25 * (c.x10 - c.x0);
  EXPECT_NEAR(grey.x0, expected_x, 1.5);
  EXPECT_NEAR(grey.x1, expected_x, 1.5);
}

TEST(RenderPlot, AHorizontalReferenceLineAtTheBottomStaysOffTheXAxis) {
  LinePlot plot;
  plot.series.push_back(CornerMarkers());
  plot.reference_lines.push_back({false, 0.0, "chance"});
  Result<Image> image = RenderPlot(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  const Corners c = FindCorners(*image);
  // The x axis: the first black row across the axes below the data.
  int axis_row = -1;
  for (int y = static_cast<int>(c.y0) - 30; y < image->height && axis_row < 0;
       ++y) {
    int black = 0;
    for (int x = static_cast<int>(c.x0) + 10; x < c.x10 - 10; ++x) {
      if (Pixel(*image, x, y)[0] < 80) ++black;
    }
    if (black > 0.9 * (c.x10 - c.x0 - 20)) axis_row = y;
  }
  ASSERT_GT(axis_row, 0);
  // The dashes: a grey row above the axis, at y = 0, where the marker is
  // (left of the middle: the label is at the right end).
  const PixelBox grey = FindPixels(
      *image, DashGrey, static_cast<int>(c.x0) + 10, static_cast<int>(c.y10),
      static_cast<int>(0.5 * (c.x0 + c.x10)), axis_row - 3);
  ASSERT_FALSE(grey.empty());
  EXPECT_NEAR(0.5 * (grey.y0 + grey.y1), c.y0, 1.5);
  EXPECT_GE(axis_row - grey.y1, 6);
}

TEST(RenderPlot, TheLegendTakesACornerWithoutData) {
  LinePlot plot;
  // Markers fill the top-left and the top-right corners.
  Series s{"falling and rising", {}, {}, false, true, 0};
  for (int i = 0; i <= 40; ++i) {
    s.x.push_back(i);
    s.y.push_back(std::abs(i - 20) / 2.0);
  }
  plot.series.push_back(s);
  Result<Image> image = RenderPlot(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  const PixelBox legend = FindLegendFrame(*image);
  ASSERT_FALSE(legend.empty());
  EXPECT_GT(legend.y0, image->height / 2);  // a bottom corner
  // No marker inside the frame: markers of this series are 7 px squares, so
  // any one under the frame would leave blue right of its sample.
  for (int y = legend.y0; y <= legend.y1; ++y) {
    for (int x = legend.x0 + 40; x <= legend.x1; ++x) {
      const std::array<int, 3> p = Pixel(*image, x, y);
      EXPECT_FALSE(Bluish(p[0], p[1], p[2])) << x << ", " << y;
    }
  }
}

TEST(RenderPlot, TheLegendGoesRightOfTheAxesWhenEveryCornerHoldsData) {
  LinePlot plot;
  Series s{"everywhere", {}, {}, false, true, 0};
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      s.x.push_back(i);
      s.y.push_back(j);
    }
  }
  plot.series.push_back(s);
  Result<Image> image = RenderPlot(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  const PixelBox legend = FindLegendFrame(*image);
  ASSERT_FALSE(legend.empty());
  const PixelBox data =
      FindPixels(*image, Bluish, 0, 0, legend.x0, image->height);
  EXPECT_GT(legend.x0, data.x1 + 5);
  EXPECT_LE(legend.x1, image->width - 1);
}

TEST(RenderPlot, XTickLabelsReplaceTheNumbers) {
  LinePlot plot;
  plot.series.push_back({"", {1.0, 2.0, 3.0}, {0.6, 0.7, 0.9}, false, true, 0});
  plot.x_tick_labels = {{1.0, "sub-01"}, {2.0, "sub-02"}, {3.0, "sub-03"}};
  Result<Image> image = RenderPlot(plot);
  ASSERT_TRUE(image.ok()) << image.error().message;
  // Three categories: the axis runs from 0.5 to 3.5, so the markers sit at
  // 1/6, 3/6 and 5/6 of its width.
  const PixelBox first = FindPixels(*image, Bluish, 0, 0, 300, image->height);
  const PixelBox last =
      FindPixels(*image, Bluish, 600, 0, image->width, image->height);
  const double right = 900 - 24;
  const double x1 = 0.5 * (first.x0 + first.x1), x3 = 0.5 * (last.x0 + last.x1);
  const double left = x1 - (x3 - x1) / 4.0;  // x1 - half a category
  EXPECT_NEAR(x3 + (x3 - x1) / 4.0, right, 1.5);
  EXPECT_GT(left, 40.0);
  // Many long names still render (turned or thinned).
  plot.x_tick_labels.clear();
  plot.series[0] = {"", {}, {}, false, true, 0};
  for (int i = 1; i <= 60; ++i) {
    plot.x_tick_labels.push_back({i, "participant-" + std::to_string(i)});
    plot.series[0].x.push_back(i);
    plot.series[0].y.push_back(0.5);
  }
  EXPECT_TRUE(RenderPlot(plot).ok());
}

// Representative figures, compared with tests/analysis/golden/.
LinePlot LogYPlot() {
  LinePlot plot;
  plot.title = "penetration velocity against force";
  plot.x_label = "force held (N)";
  plot.y_label = "velocity (mm/s)";
  plot.log_y = true;
  Series measured{"measured", {}, {}, false, true, 0};
  Series model{"model v = 0.02 F^2.4", {}, {}, true, false, 1};
  for (int i = 0; i <= 12; ++i) {
    const double f = 0.5 + 0.25 * i;
    measured.x.push_back(f);
    measured.y.push_back(0.02 * std::pow(f, 2.4) * (1.0 + 0.15 * std::sin(i)));
  }
  for (int i = 0; i <= 100; ++i) {
    const double f = 0.5 + 0.03 * i;
    model.x.push_back(f);
    model.y.push_back(0.02 * std::pow(f, 2.4));
  }
  plot.series = {measured, model};
  return plot;
}

LinePlot BarHistogramPlot() {
  LinePlot plot;
  plot.title = "sub-01 probe: force, mean 1.84 N";
  plot.x_label = "felt force, peak per trial (N)";
  plot.y_label = "share of samples (%)";
  Series bars{"", {}, {}, false, false, 0};
  bars.bar_width = 0.25;
  for (int k = 0; k < 16; ++k) {
    const double x = 0.125 + 0.25 * k;
    bars.x.push_back(x);
    bars.y.push_back(20.0 * std::exp(-0.5 * std::pow((x - 1.8) / 0.6, 2)));
  }
  plot.series = {bars};
  return plot;
}

LinePlot SubjectsPlot() {
  LinePlot plot;
  plot.title = "proportion correct per participant";
  plot.x_label = "participant";
  plot.y_label = "proportion correct";
  Series means{"mean, 95 % interval", {}, {}, false, true, 0};
  const std::vector<double> p = {0.62, 0.71, 0.55, 0.83, 0.9, 0.76, 0.68, 0.95};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double x = static_cast<double>(i) + 1.0;
    plot.x_tick_labels.push_back({x, "sub-0" + std::to_string(i + 1)});
    means.x.push_back(x);
    means.y.push_back(p[i]);
    means.y_low.push_back(p[i] - 0.12);
    means.y_high.push_back(std::min(1.0, p[i] + 0.1));
  }
  plot.series = {means};
  plot.reference_lines.push_back({false, 0.5, "chance 50 %"});
  return plot;
}

TEST(GoldenPlot, LogYAxis) {
  EXPECT_EQ(testing::CompareWithGolden(LogYPlot(), "log_y"), "");
}

TEST(GoldenPlot, BarHistogram) {
  EXPECT_EQ(testing::CompareWithGolden(BarHistogramPlot(), "bar_histogram"),
            "");
}

TEST(GoldenPlot, TickLabelsWithErrorBarsAndAChanceLine) {
  EXPECT_EQ(testing::CompareWithGolden(SubjectsPlot(), "subjects"), "");
}

std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

TEST(WritePlot, WritesPdfAndSvgTheSameOnEveryWrite) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("burrlab_plot_formats_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const char* name : {"a.pdf", "a.svg", "a.png", "b.PDF"}) {
    ASSERT_TRUE(WritePlot(SubjectsPlot(), (dir / name).string()).ok()) << name;
  }
  const std::string pdf = ReadFile(dir / "a.pdf");
  EXPECT_EQ(pdf.substr(0, 5), "%PDF-");
  EXPECT_TRUE(ReadFile(dir / "b.PDF") == pdf);
  const std::string svg = ReadFile(dir / "a.svg");
  EXPECT_EQ(svg.substr(0, 5), "<?xml");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  for (const char* name : {"a.pdf", "a.svg", "a.png"}) {
    const std::string first = ReadFile(dir / name);
    ASSERT_TRUE(WritePlot(SubjectsPlot(), (dir / name).string()).ok());
    EXPECT_TRUE(ReadFile(dir / name) == first) << name << " changed";
  }
  std::filesystem::remove_all(dir);
}

TEST(WritePlot, NamesTheFileOfAnUnknownFormatOrAnUnwritablePath) {
  LinePlot plot;
  plot.series.push_back({"", {0.0, 1.0}, {0.0, 1.0}, true, false, -1});
  EXPECT_EQ(WritePlot(plot, "out/fit.jpg").error().message,
            "out/fit.jpg: cannot tell the figure format from the extension "
            "'.jpg'; use .png, .pdf or .svg");
  EXPECT_EQ(WritePlot(plot, "fit").error().message,
            "fit: cannot tell the figure format from the extension ''; use "
            ".png, .pdf or .svg");
  EXPECT_EQ(WritePlot(plot, "/nonexistent-dir/x.svg").error().message,
            "/nonexistent-dir/x.svg: cannot write the figure: folder "
            "'/nonexistent-dir' does not exist");
  EXPECT_EQ(WritePlot(plot, "/nonexistent-dir/x.pdf").error().message,
            "/nonexistent-dir/x.pdf: cannot write the figure: folder "
            "'/nonexistent-dir' does not exist");
  LinePlot empty;
  empty.title = "empty";
  EXPECT_EQ(WritePlot(empty, "/tmp/x.pdf").error().message,
            "/tmp/x.pdf: plot 'empty' has no finite points");
}

}  // namespace
}  // namespace burrlab::analysis
