// Line plots written as PNG: titled axes with "nice" ticks, several labelled
// series with lines and/or markers, and a legend. Small and dependency-light
// (stb for PNG and text), so every burrlab result people look at can come with
// a figure.
#ifndef BURRLAB_ANALYSIS_PLOT_H_
#define BURRLAB_ANALYSIS_PLOT_H_

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::analysis {

// One data series; x and y have the same length. Non-finite points are skipped;
// a series with an empty label has no legend entry.
struct Series {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;
  bool line = true;      // join consecutive points
  bool markers = false;  // draw a square at each point
  int colour = -1;       // palette index; -1 takes the series' position
  // Side of each point's marker in pixels (e.g. growing with a count);
  // empty: 7 px for every point.
  std::vector<double> marker_px = {};
  // > 0: each point is a bar from y = 0 to y, this wide in x units (a
  // histogram); the y axis then includes 0.
  double bar_width = 0.0;
};

struct LinePlot {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<Series> series;
  bool log_y = false;  // logarithmic y axis; points with y <= 0 are skipped
  // Fixed x axis limits (low < high); unset: ticks around the data.
  std::optional<std::pair<double, double>> x_range;
  // Counts: ticks only at whole numbers (every one when at most 25 fit).
  bool integer_x = false;
  bool integer_y = false;
  int width_px = 900;
  int height_px = 600;
};

// Tick positions covering [low, high] at a 1, 2 or 5 x 10^k spacing, about
// `target` of them.
std::vector<double> NiceTicks(double low, double high, int target = 6);
// Ticks of a logarithmic axis covering [low, high] (low > 0): 1-2-5 steps when
// the range spans at most three decades, else one per decade.
std::vector<double> LogTicks(double low, double high);

// An RGB image of the plot, row-major, 3 bytes per pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<unsigned char> rgb;
};
Result<Image> RenderPlot(const LinePlot& plot);

// Renders and writes a PNG; errors name the file.
Status WritePlotPng(const LinePlot& plot, const std::string& path);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_PLOT_H_
