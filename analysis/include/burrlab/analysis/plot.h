// Line plots drawn with cairo and written as PNG, PDF or SVG from the same
// code: titled, labelled axes with "nice" ticks, several labelled series with
// lines, markers, bars and error bars, dashed reference lines and a legend
// that never covers data, so every burrlab result people look at can come
// with a figure fit for print.
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
  // Vertical error bars with small caps from y_low[i] to y_high[i]; empty: no
  // error bars, else as long as y; a non-finite entry: no bar at that point.
  // The y axis includes them.
  std::vector<double> y_low = {};
  std::vector<double> y_high = {};
};

// A dashed grey line across the axes (horizontal at y = value, or vertical at
// x = value) labelled inside the axes, e.g. chance or a threshold; the axis
// range includes the value.
struct ReferenceLine {
  bool vertical = false;
  double value = 0.0;
  std::string label;
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
  // Non-empty: the x ticks are exactly these positions with these labels
  // (e.g. subject names), rotated or thinned when they would overlap.
  std::vector<std::pair<double, std::string>> x_tick_labels;
  std::vector<ReferenceLine> reference_lines;
  int width_px = 900;
  int height_px = 600;
};

// Tick positions covering [low, high] at a 1, 2 or 5 x 10^k spacing, about
// `target` of them.
std::vector<double> NiceTicks(double low, double high, int target = 6);
// Ticks of a logarithmic axis covering [low, high] (low > 0): 1-2-5 steps when
// the range spans at most three decades, else one per decade.
std::vector<double> LogTicks(double low, double high);

// An RGB image of the plot, row-major, 3 bytes per pixel; one pixel is one
// point of the PDF and SVG output.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<unsigned char> rgb;
};
Result<Image> RenderPlot(const LinePlot& plot);

// Draws and writes the plot as PNG, PDF or SVG, chosen by the extension of
// `path` (.png, .pdf, .svg, any case); the same plot gives the same bytes on
// every run. Errors name the file.
Status WritePlot(const LinePlot& plot, const std::string& path);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_PLOT_H_
