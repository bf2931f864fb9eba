// Line plots drawn with cairo: one drawing routine for an image surface (PNG
// and the RGB Image tests look at), a PDF surface and an SVG surface. Text is
// DejaVu Sans through cairo's font API with hinting off, so text is laid out
// the same on every surface.
#include "burrlab/analysis/plot.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <numbers>
#include <string_view>

namespace burrlab::analysis {
namespace {

// 0-255 components, as in the tests' pixels.
struct PlotColour {
  int r, g, b;
};

// A colour-blind-friendly palette (Okabe & Ito, 2008).
constexpr std::array<PlotColour, 8> kPlotPalette = {{{0, 114, 178},
                                                     {213, 94, 0},
                                                     {0, 158, 115},
                                                     {204, 121, 167},
                                                     {230, 159, 0},
                                                     {86, 180, 233},
                                                     {120, 120, 120},
                                                     {240, 228, 66}}};
constexpr PlotColour kPlotBlack = {0, 0, 0};
constexpr PlotColour kPlotGrid = {225, 225, 225};
constexpr PlotColour kPlotReference = {110, 110, 110};
constexpr PlotColour kPlotReferenceText = {60, 60, 60};

constexpr char kPlotFontFamily[] = "DejaVu Sans";  // fonts-dejavu-core
constexpr double kTickFontPx = 15.0;
constexpr double kAxisNameFontPx = 16.0;
constexpr double kTitleFontPx = 18.0;
constexpr double kLegendFontPx = 15.0;
constexpr double kReferenceFontPx = 14.0;
constexpr double kAxesTopPx = 64.0;    // below the title
constexpr double kAxesRightPx = 24.0;  // gap right of the axes
constexpr double kLegendRowPx = 22.0;
constexpr double kErrorCapHalfPx = 4.0;

struct CairoSurfaceCloser {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct CairoContextCloser {
  void operator()(cairo_t* cr) const { cairo_destroy(cr); }
};
using CairoSurface = std::unique_ptr<cairo_surface_t, CairoSurfaceCloser>;
using CairoContext = std::unique_ptr<cairo_t, CairoContextCloser>;

void SetColour(cairo_t* cr, const PlotColour& c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, alpha);
}

// Unhinted outlines and metrics, greyscale antialiasing: the same layout on
// image and vector surfaces, no colour fringes in PNGs.
void SetPlotFont(cairo_t* cr, double size_px, bool bold = false) {
  cairo_select_font_face(
      cr, kPlotFontFamily, CAIRO_FONT_SLANT_NORMAL,
      bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size_px);
  cairo_font_options_t* options = cairo_font_options_create();
  cairo_font_options_set_hint_style(options, CAIRO_HINT_STYLE_NONE);
  cairo_font_options_set_hint_metrics(options, CAIRO_HINT_METRICS_OFF);
  cairo_font_options_set_antialias(options, CAIRO_ANTIALIAS_GRAY);
  cairo_set_font_options(cr, options);
  cairo_font_options_destroy(options);
}

double TextWidth(cairo_t* cr, const std::string& text) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, text.c_str(), &e);
  return e.x_advance;
}

double FontAscent(cairo_t* cr) {
  cairo_font_extents_t e;
  cairo_font_extents(cr, &e);
  return e.ascent;
}

// Text whose left end of the baseline is at (x, baseline).
void ShowText(cairo_t* cr, double x, double baseline, const std::string& text) {
  cairo_move_to(cr, x, baseline);
  cairo_show_text(cr, text.c_str());
  cairo_new_path(cr);
}

const PlotColour& SeriesColour(const Series& s, std::size_t position) {
  const std::size_t index =
      s.colour >= 0 ? static_cast<std::size_t>(s.colour) : position;
  return kPlotPalette[index % kPlotPalette.size()];
}

// "1e+06" -> "1e6", "1e-05" -> "1e-5".
std::string CompactExponent(std::string text) {
  const std::size_t e = text.find('e');
  if (e == std::string::npos) return text;
  std::string mantissa = text.substr(0, e), exponent = text.substr(e + 1);
  const bool negative = !exponent.empty() && exponent[0] == '-';
  if (!exponent.empty() && (exponent[0] == '+' || exponent[0] == '-')) {
    exponent.erase(0, 1);
  }
  while (exponent.size() > 1 && exponent[0] == '0') exponent.erase(0, 1);
  return mantissa + "e" + (negative ? "-" : "") + exponent;
}

// A linear axis' label: as many decimals as the tick step needs.
std::string LinearTickLabel(double value, double step) {
  if (std::abs(value) < 1e-9 * std::abs(step)) value = 0.0;
  if (std::max(std::abs(value), std::abs(step)) >= 1e6 ||
      std::abs(step) < 1e-4) {
    return CompactExponent(fmt::format("{:.3g}", value));
  }
  const int decimals = std::max(
      0, -static_cast<int>(std::floor(std::log10(std::abs(step)) + 1e-9)));
  return fmt::format("{:.{}f}", value, decimals);
}

std::string LogTickLabel(double value) {
  return CompactExponent(fmt::format("{:g}", value));
}

// Ticks at whole numbers covering [low, high]: every one when at most 14
// fit; else `ticks` when their step is whole, else every one up to 26.
std::vector<double> WholeTicks(std::vector<double> ticks, double low,
                               double high) {
  std::vector<double> whole;
  for (double t = std::ceil(low); t <= std::floor(high) + 1e-9; t += 1.0) {
    whole.push_back(t);
  }
  if (whole.size() >= 2 && whole.size() <= 14) return whole;
  if (ticks.size() >= 2 && ticks[1] - ticks[0] >= 1.0) return ticks;
  return whole.size() >= 2 && whole.size() <= 26 ? whole : ticks;
}

bool PointDrawn(const LinePlot& plot, double x, double y) {
  return std::isfinite(x) && std::isfinite(y) && (!plot.log_y || y > 0.0);
}

bool HasErrorBar(const LinePlot& plot, const Series& s, std::size_t i) {
  return !s.y_low.empty() && PointDrawn(plot, s.x[i], s.y_low[i]) &&
         PointDrawn(plot, s.x[i], s.y_high[i]) && std::isfinite(s.y[i]);
}

// Checks the plot's input; the extent of everything it draws.
struct PlotExtent {
  double x_min = std::numeric_limits<double>::infinity();
  double x_max = -std::numeric_limits<double>::infinity();
  double y_min = std::numeric_limits<double>::infinity();
  double y_max = -std::numeric_limits<double>::infinity();
};

Result<PlotExtent> MeasurePlot(const LinePlot& plot) {
  if (plot.width_px < 200 || plot.height_px < 150 || plot.width_px > 8000 ||
      plot.height_px > 8000) {
    return Error{
        fmt::format("plot size must be 200x150 to 8000x8000 pixels, got {}x{}",
                    plot.width_px, plot.height_px)};
  }
  PlotExtent e;
  const auto add_y = [&](double y) {
    e.y_min = std::min(e.y_min, y);
    e.y_max = std::max(e.y_max, y);
  };
  for (const Series& s : plot.series) {
    if (s.x.size() != s.y.size()) {
      return Error{fmt::format("series '{}' has {} x values and {} y values",
                               s.label, s.x.size(), s.y.size())};
    }
    if (!s.marker_px.empty() && s.marker_px.size() != s.x.size()) {
      return Error{fmt::format("series '{}' has {} points and {} marker sizes",
                               s.label, s.x.size(), s.marker_px.size())};
    }
    if ((!s.y_low.empty() || !s.y_high.empty()) &&
        (s.y_low.size() != s.y.size() || s.y_high.size() != s.y.size())) {
      return Error{fmt::format(
          "series '{}' has {} points, {} y_low and {} y_high values", s.label,
          s.y.size(), s.y_low.size(), s.y_high.size())};
    }
    if (s.bar_width < 0.0 || !std::isfinite(s.bar_width) ||
        (s.bar_width > 0.0 && plot.log_y)) {
      return Error{fmt::format(
          "series '{}': bar_width must be a finite number >= 0 on a linear "
          "y axis",
          s.label)};
    }
    const double half_bar = 0.5 * s.bar_width;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!PointDrawn(plot, s.x[i], s.y[i])) continue;
      e.x_min = std::min(e.x_min, s.x[i] - half_bar);
      e.x_max = std::max(e.x_max, s.x[i] + half_bar);
      add_y(s.y[i]);
      if (s.bar_width > 0.0) add_y(0.0);
      if (HasErrorBar(plot, s, i)) {
        add_y(s.y_low[i]);
        add_y(s.y_high[i]);
      }
    }
  }
  if (!(e.x_min <= e.x_max)) {
    return Error{"plot '" + plot.title + "' has no finite points"};
  }
  for (const ReferenceLine& r : plot.reference_lines) {
    if (!std::isfinite(r.value) ||
        (!r.vertical && plot.log_y && r.value <= 0)) {
      return Error{
          fmt::format("plot '{}': reference line '{}' at {} is not on the axis",
                      plot.title, r.label, r.value)};
    }
    if (r.vertical) {
      e.x_min = std::min(e.x_min, r.value);
      e.x_max = std::max(e.x_max, r.value);
    } else {
      add_y(r.value);
    }
  }
  for (const auto& [x, label] : plot.x_tick_labels) {
    if (!std::isfinite(x)) {
      return Error{fmt::format("plot '{}': x tick '{}' is not at a finite x",
                               plot.title, label)};
    }
  }
  return e;
}

struct PlotAxis {
  double lo = 0.0, hi = 1.0;  // axis limits (log10 of them on a log axis)
  std::vector<double> ticks;  // values
  std::vector<std::string> labels;
};

struct PlotBox {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  bool Contains(double x, double y) const {
    return x >= x0 && x <= x1 && y >= y0 && y <= y1;
  }
  bool Overlaps(const PlotBox& o) const {
    return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1;
  }
};

// Where everything goes, in pixels (points on vector surfaces).
struct PlotLayout {
  PlotAxis x_axis, y_axis;
  bool log_y = false;
  double left = 0.0, right = 0.0, top = 0.0, bottom = 0.0;
  double x_label_angle = 0.0;  // radians, 0 or pi/4
  std::size_t x_label_every = 1;
  bool legend = false;
  bool legend_outside = false;
  PlotBox legend_box;
  std::vector<PlotBox> reference_label_boxes;  // one per reference line

  double Px(double x) const {
    return left + (x - x_axis.lo) / (x_axis.hi - x_axis.lo) * (right - left);
  }
  double Py(double value) const {
    const double v = log_y ? std::log10(value) : value;
    return bottom - (v - y_axis.lo) / (y_axis.hi - y_axis.lo) * (bottom - top);
  }
};

// Moves the axis limits a little beyond a reference line that would fall
// on them, so the line is never drawn on the axis itself.
void PadForReferenceLines(const LinePlot& plot, bool vertical, PlotAxis* a) {
  const double span = a->hi - a->lo, pad = 0.03 * span;
  bool low = false, high = false;
  for (const ReferenceLine& r : plot.reference_lines) {
    if (r.vertical != vertical) continue;
    const double v = !vertical && plot.log_y ? std::log10(r.value) : r.value;
    low = low || std::abs(v - a->lo) <= 1e-9 * span;
    high = high || std::abs(v - a->hi) <= 1e-9 * span;
  }
  if (low) a->lo -= pad;
  if (high) a->hi += pad;
}

PlotAxis XAxis(const LinePlot& plot, const PlotExtent& e) {
  PlotAxis a;
  if (!plot.x_tick_labels.empty()) {
    std::vector<double> positions;
    for (const auto& tick : plot.x_tick_labels) positions.push_back(tick.first);
    std::sort(positions.begin(), positions.end());
    double spacing = std::numeric_limits<double>::infinity();
    for (std::size_t i = 1; i < positions.size(); ++i) {
      if (positions[i] > positions[i - 1]) {
        spacing = std::min(spacing, positions[i] - positions[i - 1]);
      }
    }
    if (!std::isfinite(spacing)) spacing = 1.0;
    a.lo = std::min(e.x_min, positions.front() - 0.5 * spacing);
    a.hi = std::max(e.x_max, positions.back() + 0.5 * spacing);
    if (plot.x_range.has_value()) std::tie(a.lo, a.hi) = *plot.x_range;
    for (const auto& [x, label] : plot.x_tick_labels) {
      if (x >= a.lo && x <= a.hi) {
        a.ticks.push_back(x);
        a.labels.push_back(label);
      }
    }
    PadForReferenceLines(plot, true, &a);
    return a;
  }
  a.ticks = NiceTicks(e.x_min, e.x_max);
  a.lo = a.ticks.front();
  a.hi = a.ticks.back();
  if (plot.x_range.has_value()) {
    std::tie(a.lo, a.hi) = *plot.x_range;
    a.ticks.clear();
    for (double t : NiceTicks(a.lo, a.hi)) {
      if (t >= a.lo && t <= a.hi) a.ticks.push_back(t);
    }
  }
  if (plot.integer_x) a.ticks = WholeTicks(a.ticks, a.lo, a.hi);
  const double step = a.ticks.size() >= 2 ? a.ticks[1] - a.ticks[0] : 1.0;
  for (double t : a.ticks) a.labels.push_back(LinearTickLabel(t, step));
  PadForReferenceLines(plot, true, &a);
  return a;
}

PlotAxis YAxis(const LinePlot& plot, const PlotExtent& e) {
  PlotAxis a;
  a.ticks =
      plot.log_y ? LogTicks(e.y_min, e.y_max) : NiceTicks(e.y_min, e.y_max);
  if (plot.integer_y && !plot.log_y) {
    a.ticks = WholeTicks(a.ticks, a.ticks.front(), a.ticks.back());
  }
  const double step = a.ticks.size() >= 2 ? a.ticks[1] - a.ticks[0] : 1.0;
  for (double t : a.ticks) {
    a.labels.push_back(plot.log_y ? LogTickLabel(t) : LinearTickLabel(t, step));
  }
  a.lo = plot.log_y ? std::log10(a.ticks.front()) : a.ticks.front();
  a.hi = plot.log_y ? std::log10(a.ticks.back()) : a.ticks.back();
  PadForReferenceLines(plot, false, &a);
  return a;
}

// Whether the segment (x0, y0)-(x1, y1) passes through `box`
// (Liang-Barsky clipping).
bool SegmentHitsBox(double x0, double y0, double x1, double y1,
                    const PlotBox& box) {
  double t0 = 0.0, t1 = 1.0;
  const double dx = x1 - x0, dy = y1 - y0;
  const std::array<double, 4> p = {-dx, dx, -dy, dy};
  const std::array<double, 4> q = {x0 - box.x0, box.x1 - x0, y0 - box.y0,
                                   box.y1 - y0};
  for (std::size_t k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  return true;
}

double MarkerSidePx(const Series& s, std::size_t i) {
  return s.marker_px.empty() ? 7.0 : std::clamp(s.marker_px[i], 1.0, 200.0);
}

// Whether anything a series draws (markers, lines, bars, error bars) or a
// reference line's label falls inside `box`.
bool CoversData(const LinePlot& plot, const PlotLayout& l, const PlotBox& box) {
  for (const Series& s : plot.series) {
    bool have_previous = false;
    double px0 = 0.0, py0 = 0.0;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!PointDrawn(plot, s.x[i], s.y[i])) {
        have_previous = false;
        continue;
      }
      const double x = l.Px(s.x[i]), y = l.Py(s.y[i]);
      if (box.Contains(x, y)) return true;
      if (s.markers) {
        const double half = 0.5 * MarkerSidePx(s, i);
        if (box.Overlaps({x - half, y - half, x + half, y + half})) return true;
      }
      if (s.bar_width > 0.0) {
        const double half = 0.5 * s.bar_width;
        const PlotBox bar{l.Px(s.x[i] - half), std::min(y, l.Py(0.0)),
                          l.Px(s.x[i] + half), std::max(y, l.Py(0.0))};
        if (box.Overlaps(bar)) return true;
      }
      if (HasErrorBar(plot, s, i)) {
        const PlotBox bar{x - kErrorCapHalfPx, l.Py(s.y_high[i]),
                          x + kErrorCapHalfPx, l.Py(s.y_low[i])};
        if (box.Overlaps(bar)) return true;
      }
      if (s.line && have_previous && SegmentHitsBox(px0, py0, x, y, box)) {
        return true;
      }
      px0 = x;
      py0 = y;
      have_previous = true;
    }
  }
  for (const PlotBox& label : l.reference_label_boxes) {
    if (box.Overlaps(label)) return true;
  }
  return false;
}

// Places the reference lines' labels where they hide no data, no other
// label and not the legend: a horizontal line's above or below it at its
// right or left end; a vertical line's right or left of it, in the first
// free row from the top (else from the bottom). When every place is taken,
// the first one.
void PlaceReferenceLabels(cairo_t* cr, const LinePlot& plot, PlotLayout* l) {
  SetPlotFont(cr, kReferenceFontPx);
  const double height = kReferenceFontPx + 4.0;
  l->reference_label_boxes.clear();
  std::vector<PlotBox> placed;
  std::vector<PlotBox> taken;  // other labels and the legend
  if (l->legend) taken.push_back(l->legend_box);
  for (const ReferenceLine& r : plot.reference_lines) {
    if (r.label.empty()) {
      placed.push_back({-1e9, -1e9, -1e9, -1e9});  // nowhere
      continue;
    }
    const double w = TextWidth(cr, r.label) + 6.0;
    std::vector<PlotBox> candidates;
    if (r.vertical) {
      const double x = l->Px(r.value);
      const int rows = std::max(
          1, static_cast<int>((l->bottom - l->top - 8.0) / (height + 2.0)));
      for (int k = 0; k < rows; ++k) {
        const double y =
            k < (rows + 1) / 2
                ? l->top + 4.0 + k * (height + 2.0)
                : l->bottom - 4.0 - height - (rows - 1 - k) * (height + 2.0);
        candidates.push_back({x + 4.0, y, x + 4.0 + w, y + height});
        candidates.push_back({x - 4.0 - w, y, x - 4.0, y + height});
      }
    } else {
      const double y = l->Py(r.value);
      for (double x0 : {l->right - 6.0 - w, l->left + 6.0}) {
        candidates.push_back({x0, y - 3.0 - height, x0 + w, y - 3.0});
        candidates.push_back({x0, y + 3.0, x0 + w, y + 3.0 + height});
      }
    }
    const auto fits = [&](const PlotBox& b) {
      if (b.x0 < l->left + 2.0 || b.x1 > l->right - 2.0 || b.y0 < l->top ||
          b.y1 > l->bottom - 2.0) {
        return false;
      }
      for (const PlotBox& other : taken) {
        if (b.Overlaps(other)) return false;
      }
      return !CoversData(plot, *l, b);
    };
    const auto free = std::find_if(candidates.begin(), candidates.end(), fits);
    placed.push_back(free != candidates.end() ? *free : candidates.front());
    taken.push_back(placed.back());
  }
  l->reference_label_boxes = std::move(placed);
}

// The axes' frame for a given right edge: margins from the text they hold,
// x tick labels turned by 45 degrees or thinned when they would overlap.
void FrameAxes(cairo_t* cr, const LinePlot& plot, double right, PlotLayout* l) {
  SetPlotFont(cr, kTickFontPx);
  const double tick_ascent = FontAscent(cr);
  double widest_y = 0.0;
  for (const std::string& label : l->y_axis.labels) {
    widest_y = std::max(widest_y, TextWidth(cr, label));
  }
  SetPlotFont(cr, kAxisNameFontPx);
  const double name_ascent = FontAscent(cr);
  l->left = std::round(12.0 + name_ascent + 10.0 + widest_y + 8.0);
  l->right = std::round(right);
  l->top = kAxesTopPx;

  SetPlotFont(cr, kTickFontPx);
  double widest_x = 0.0, first_x = 0.0;
  for (const std::string& label : l->x_axis.labels) {
    widest_x = std::max(widest_x, TextWidth(cr, label));
  }
  if (!l->x_axis.labels.empty())
    first_x = TextWidth(cr, l->x_axis.labels.front());
  double spacing = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < l->x_axis.ticks.size(); ++i) {
    spacing = std::min(
        spacing, std::abs(l->x_axis.ticks[i] - l->x_axis.ticks[i - 1]) /
                     (l->x_axis.hi - l->x_axis.lo) * (l->right - l->left));
  }
  l->x_label_angle = 0.0;
  l->x_label_every = 1;
  double tick_label_height = tick_ascent + 4.0;
  if (widest_x + 10.0 > spacing) {
    l->x_label_angle = std::numbers::pi / 4.0;
    const double needed = 1.5 * tick_ascent + 4.0;
    l->x_label_every =
        static_cast<std::size_t>(std::max(1.0, std::ceil(needed / spacing)));
    const double s = std::sin(l->x_label_angle);
    tick_label_height = (widest_x + tick_ascent) * s + 4.0;
    l->left = std::max(l->left, std::round(first_x * s + 8.0));
  }
  l->bottom = std::round(plot.height_px -
                         (8.0 + tick_label_height + 10.0 + name_ascent + 14.0));
}

Result<PlotLayout> LayOut(cairo_t* cr, const LinePlot& plot) {
  Result<PlotExtent> extent = MeasurePlot(plot);
  if (!extent.ok()) return extent.error();
  if (plot.x_range.has_value()) {
    const auto [low, high] = *plot.x_range;
    if (!(low < high) || !std::isfinite(low) || !std::isfinite(high)) {
      return Error{fmt::format("plot '{}': x range [{}, {}] is empty",
                               plot.title, low, high)};
    }
  }
  PlotLayout l;
  l.log_y = plot.log_y;
  l.x_axis = XAxis(plot, *extent);
  l.y_axis = YAxis(plot, *extent);
  const double inside_right = plot.width_px - kAxesRightPx;
  FrameAxes(cr, plot, inside_right, &l);
  if (l.bottom - l.top < 40.0 || l.right - l.left < 40.0) {
    return Error{fmt::format("plot '{}': {}x{} pixels leave no room for axes",
                             plot.title, plot.width_px, plot.height_px)};
  }

  SetPlotFont(cr, kLegendFontPx);
  double widest = 0.0;
  int entries = 0;
  for (const Series& s : plot.series) {
    if (s.label.empty()) continue;
    widest = std::max(widest, TextWidth(cr, s.label));
    ++entries;
  }
  if (entries == 0) {
    PlaceReferenceLabels(cr, plot, &l);
    return l;
  }
  l.legend = true;
  const double w = std::ceil(widest + 54.0), h = kLegendRowPx * entries + 8.0;
  const double gap = 10.0;
  const std::array<PlotBox, 4> corners = {{
      {l.left + gap, l.top + gap, l.left + gap + w, l.top + gap + h},
      {l.right - gap - w, l.top + gap, l.right - gap, l.top + gap + h},
      {l.left + gap, l.bottom - gap - h, l.left + gap + w, l.bottom - gap},
      {l.right - gap - w, l.bottom - gap - h, l.right - gap, l.bottom - gap},
  }};
  for (const PlotBox& b : corners) {
    if (b.x0 >= l.left && b.x1 <= l.right && b.y0 >= l.top &&
        b.y1 <= l.bottom && !CoversData(plot, l, b)) {
      l.legend_box = b;
      PlaceReferenceLabels(cr, plot, &l);
      return l;
    }
  }
  // Every corner holds data: shrink the axes and put the legend right of
  // them.
  FrameAxes(cr, plot, inside_right - w - 12.0, &l);
  if (l.right - l.left < 40.0) {
    return Error{fmt::format("plot '{}': the legend leaves no room for axes",
                             plot.title)};
  }
  l.legend_outside = true;
  l.legend_box = {l.right + 12.0, l.top, l.right + 12.0 + w, l.top + h};
  PlaceReferenceLabels(cr, plot, &l);
  return l;
}

// A 1 px line on pixel centres (crisp on the image surface).
double PlotCrisp(double v) { return std::floor(v) + 0.5; }

void DrawGrid(cairo_t* cr, const PlotLayout& l) {
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  // Grid.
  SetColour(cr, kPlotGrid);
  cairo_set_line_width(cr, 1.0);
  for (double t : l.x_axis.ticks) {
    const double x = PlotCrisp(l.Px(t));
    cairo_move_to(cr, x, l.top);
    cairo_line_to(cr, x, l.bottom);
  }
  for (double t : l.y_axis.ticks) {
    const double y = PlotCrisp(l.Py(t));
    cairo_move_to(cr, l.left, y);
    cairo_line_to(cr, l.right, y);
  }
  cairo_stroke(cr);
}

void DrawTicksAndNames(cairo_t* cr, const LinePlot& plot, const PlotLayout& l) {
  // Axis lines and tick marks.
  SetColour(cr, kPlotBlack);
  cairo_set_line_width(cr, 1.5);
  cairo_move_to(cr, l.left, l.top);
  cairo_line_to(cr, l.left, l.bottom);
  cairo_line_to(cr, l.right, l.bottom);
  cairo_stroke(cr);
  cairo_set_line_width(cr, 1.0);
  for (double t : l.x_axis.ticks) {
    const double x = PlotCrisp(l.Px(t));
    cairo_move_to(cr, x, l.bottom);
    cairo_line_to(cr, x, l.bottom + 5.0);
  }
  for (double t : l.y_axis.ticks) {
    const double y = PlotCrisp(l.Py(t));
    cairo_move_to(cr, l.left - 5.0, y);
    cairo_line_to(cr, l.left, y);
  }
  cairo_stroke(cr);

  // Tick labels.
  SetPlotFont(cr, kTickFontPx);
  const double ascent = FontAscent(cr);
  for (std::size_t i = 0; i < l.x_axis.ticks.size(); ++i) {
    if (i % l.x_label_every != 0) continue;
    const std::string& label = l.x_axis.labels[i];
    const double x = l.Px(l.x_axis.ticks[i]), w = TextWidth(cr, label);
    if (l.x_label_angle == 0.0) {
      ShowText(cr, x - w / 2, l.bottom + 8.0 + ascent, label);
      continue;
    }
    // Turned labels end just below their tick.
    cairo_save(cr);
    cairo_translate(cr, x + 0.35 * ascent, l.bottom + 8.0 + 0.35 * ascent);
    cairo_rotate(cr, -l.x_label_angle);
    ShowText(cr, -w, 0.5 * ascent, label);
    cairo_restore(cr);
  }
  for (std::size_t i = 0; i < l.y_axis.ticks.size(); ++i) {
    const std::string& label = l.y_axis.labels[i];
    ShowText(cr, l.left - 9.0 - TextWidth(cr, label),
             l.Py(l.y_axis.ticks[i]) + 0.36 * ascent, label);
  }

  // Axis names and title.
  SetPlotFont(cr, kAxisNameFontPx);
  const double name_ascent = FontAscent(cr);
  ShowText(cr, (l.left + l.right) / 2 - TextWidth(cr, plot.x_label) / 2,
           plot.height_px - 14.0, plot.x_label);
  cairo_save(cr);
  cairo_translate(cr, 12.0 + name_ascent, (l.top + l.bottom) / 2);
  cairo_rotate(cr, -std::numbers::pi / 2);
  ShowText(cr, -TextWidth(cr, plot.y_label) / 2, 0.0, plot.y_label);
  cairo_restore(cr);

  double title_px = kTitleFontPx;
  SetPlotFont(cr, title_px, true);
  const double room = plot.width_px - 16.0;
  const double title_w = TextWidth(cr, plot.title);
  if (title_w > room) {
    title_px = std::max(9.0, title_px * room / title_w);
    SetPlotFont(cr, title_px, true);
  }
  double title_x = (l.left + l.right) / 2 - TextWidth(cr, plot.title) / 2;
  title_x = std::clamp(
      title_x, 8.0,
      std::max(8.0, plot.width_px - 8.0 - TextWidth(cr, plot.title)));
  ShowText(cr, title_x, 34.0, plot.title);
}

void DrawReferenceLines(cairo_t* cr, const LinePlot& plot,
                        const PlotLayout& l) {
  const std::array<double, 2> dashes = {6.0, 4.0};
  cairo_set_dash(cr, dashes.data(), 2, 0.0);
  cairo_set_line_width(cr, 1.5);
  SetColour(cr, kPlotReference);
  for (const ReferenceLine& r : plot.reference_lines) {
    if (r.vertical) {
      const double x = l.Px(r.value);
      cairo_move_to(cr, x, l.top);
      cairo_line_to(cr, x, l.bottom);
    } else {
      const double y = l.Py(r.value);
      cairo_move_to(cr, l.left, y);
      cairo_line_to(cr, l.right, y);
    }
  }
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0.0);
}

void DrawReferenceLabels(cairo_t* cr, const LinePlot& plot,
                         const PlotLayout& l) {
  SetPlotFont(cr, kReferenceFontPx);
  const double ascent = FontAscent(cr);
  for (std::size_t k = 0; k < plot.reference_lines.size(); ++k) {
    const ReferenceLine& r = plot.reference_lines[k];
    if (r.label.empty()) continue;
    const PlotBox& b = l.reference_label_boxes[k];
    cairo_set_source_rgba(cr, 1.0, 1.0, 1.0, 0.85);
    cairo_rectangle(cr, b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0);
    cairo_fill(cr);
    SetColour(cr, kPlotReferenceText);
    ShowText(cr, b.x0 + 3.0, b.y0 + 2.0 + ascent, r.label);
  }
}

void DrawSeries(cairo_t* cr, const LinePlot& plot, const PlotLayout& l) {
  cairo_save(cr);
  // Markers at the axes' edges show whole; data outside an x_range do not.
  cairo_rectangle(cr, l.left - 16.0, l.top - 16.0, l.right - l.left + 32.0,
                  l.bottom - l.top + 32.0);
  cairo_clip(cr);
  for (std::size_t n = 0; n < plot.series.size(); ++n) {
    const Series& s = plot.series[n];
    if (s.bar_width <= 0.0) continue;
    SetColour(cr, SeriesColour(s, n));
    const double half = 0.5 * s.bar_width;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!PointDrawn(plot, s.x[i], s.y[i]) || s.y[i] == 0.0) continue;
      const double x0 = l.Px(s.x[i] - half) + 1.0,
                   x1 = l.Px(s.x[i] + half) - 1.0;
      const double y0 = l.Py(0.0), y1 = l.Py(s.y[i]);
      cairo_rectangle(cr, x0, std::min(y0, y1), x1 - x0, std::abs(y1 - y0));
    }
    cairo_fill(cr);
  }
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (std::size_t n = 0; n < plot.series.size(); ++n) {
    const Series& s = plot.series[n];
    if (!s.line) continue;
    SetColour(cr, SeriesColour(s, n));
    cairo_set_line_width(cr, 2.5);
    bool have_previous = false;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!PointDrawn(plot, s.x[i], s.y[i])) {
        have_previous = false;
        continue;
      }
      const double x = l.Px(s.x[i]), y = l.Py(s.y[i]);
      if (have_previous) {
        cairo_line_to(cr, x, y);
      } else {
        cairo_move_to(cr, x, y);
      }
      have_previous = true;
    }
    cairo_stroke(cr);
  }
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  for (std::size_t n = 0; n < plot.series.size(); ++n) {
    const Series& s = plot.series[n];
    SetColour(cr, SeriesColour(s, n));
    cairo_set_line_width(cr, 1.5);
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!PointDrawn(plot, s.x[i], s.y[i]) || !HasErrorBar(plot, s, i))
        continue;
      const double x = l.Px(s.x[i]);
      const double lo = l.Py(s.y_low[i]), hi = l.Py(s.y_high[i]);
      cairo_move_to(cr, x, lo);
      cairo_line_to(cr, x, hi);
      cairo_move_to(cr, x - kErrorCapHalfPx, lo);
      cairo_line_to(cr, x + kErrorCapHalfPx, lo);
      cairo_move_to(cr, x - kErrorCapHalfPx, hi);
      cairo_line_to(cr, x + kErrorCapHalfPx, hi);
    }
    cairo_stroke(cr);
    if (!s.markers) continue;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!PointDrawn(plot, s.x[i], s.y[i])) continue;
      const double half = 0.5 * MarkerSidePx(s, i);
      cairo_rectangle(cr, l.Px(s.x[i]) - half, l.Py(s.y[i]) - half, 2 * half,
                      2 * half);
    }
    cairo_fill(cr);
  }
  cairo_restore(cr);
}

void DrawLegend(cairo_t* cr, const LinePlot& plot, const PlotLayout& l) {
  if (!l.legend) return;
  const PlotBox& b = l.legend_box;
  cairo_rectangle(cr, PlotCrisp(b.x0), PlotCrisp(b.y0), std::round(b.x1 - b.x0),
                  std::round(b.y1 - b.y0));
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_fill_preserve(cr);
  SetColour(cr, {190, 190, 190});
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  SetPlotFont(cr, kLegendFontPx);
  const double ascent = FontAscent(cr);
  int row = 0;
  for (std::size_t n = 0; n < plot.series.size(); ++n) {
    const Series& s = plot.series[n];
    if (s.label.empty()) continue;
    const double x = b.x0, y = b.y0 + 4.0 + kLegendRowPx * (row++ + 0.5);
    SetColour(cr, SeriesColour(s, n));
    if (s.bar_width > 0.0) {
      cairo_rectangle(cr, x + 12, y - 6, 20, 12);
      cairo_fill(cr);
    }
    if (s.line) {
      cairo_set_line_width(cr, 3.0);
      cairo_move_to(cr, x + 8, y);
      cairo_line_to(cr, x + 36, y);
      cairo_stroke(cr);
    }
    if (!s.y_low.empty()) {
      cairo_set_line_width(cr, 1.5);
      cairo_move_to(cr, x + 22, y - 7);
      cairo_line_to(cr, x + 22, y + 7);
      cairo_move_to(cr, x + 22 - kErrorCapHalfPx, y - 7);
      cairo_line_to(cr, x + 22 + kErrorCapHalfPx, y - 7);
      cairo_move_to(cr, x + 22 - kErrorCapHalfPx, y + 7);
      cairo_line_to(cr, x + 22 + kErrorCapHalfPx, y + 7);
      cairo_stroke(cr);
    }
    if (s.markers) {
      cairo_rectangle(cr, x + 18.5, y - 3.5, 7, 7);
      cairo_fill(cr);
    }
    SetColour(cr, kPlotBlack);
    ShowText(cr, x + 44, y + 0.36 * ascent, s.label);
  }
}

void DrawPlot(cairo_t* cr, const LinePlot& plot, const PlotLayout& l) {
  cairo_set_source_rgb(cr, 1.0, 1.0, 1.0);
  cairo_paint(cr);
  DrawGrid(cr, l);
  DrawTicksAndNames(cr, plot, l);
  DrawReferenceLines(cr, plot, l);
  DrawSeries(cr, plot, l);
  DrawReferenceLabels(cr, plot, l);
  DrawLegend(cr, plot, l);
}

// Lays out and draws `plot` on `surface`; errors as text.
Status DrawOnSurface(cairo_surface_t* surface, const LinePlot& plot) {
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    return Error{
        fmt::format("cairo cannot make a surface: {}",
                    cairo_status_to_string(cairo_surface_status(surface)))};
  }
  CairoContext cr(cairo_create(surface));
  Result<PlotLayout> layout = LayOut(cr.get(), plot);
  if (!layout.ok()) return layout.error();
  DrawPlot(cr.get(), plot, *layout);
  if (cairo_status(cr.get()) != CAIRO_STATUS_SUCCESS) {
    return Error{fmt::format("cairo cannot draw the plot: {}",
                             cairo_status_to_string(cairo_status(cr.get())))};
  }
  return {};
}

cairo_status_t AppendToBytes(void* closure, const unsigned char* data,
                             unsigned int length) {
  static_cast<std::string*>(closure)->append(
      reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// cairo 1.16 names the SVG's top group "surface<n>" with n from a counter
// shared by every surface the process makes, so a second write of one plot
// would differ; nothing refers to that id, so every file calls it surface1.
void NumberSvgSurfaceOne(std::string* svg) {
  constexpr std::string_view kOpen = "<g id=\"surface";
  const std::size_t at = svg->find(kOpen);
  if (at == std::string::npos) return;
  const std::size_t digits = at + kOpen.size();
  std::size_t end = digits;
  while (end < svg->size() &&
         std::isdigit(static_cast<unsigned char>((*svg)[end]))) {
    ++end;
  }
  svg->replace(digits, end - digits, "1");
}

// The plot as the bytes of a PNG, PDF or SVG file.
Result<std::string> EncodePlot(const LinePlot& plot,
                               const std::string& format) {
  std::string bytes;
  const double w = plot.width_px, h = plot.height_px;
  if (format == "png") {
    CairoSurface surface(cairo_image_surface_create(
        CAIRO_FORMAT_ARGB32, plot.width_px, plot.height_px));
    if (Status s = DrawOnSurface(surface.get(), plot); !s.ok())
      return s.error();
    const cairo_status_t status =
        cairo_surface_write_to_png_stream(surface.get(), AppendToBytes, &bytes);
    if (status != CAIRO_STATUS_SUCCESS) {
      return Error{fmt::format("cairo cannot encode the PNG: {}",
                               cairo_status_to_string(status))};
    }
    return bytes;
  }
  CairoSurface surface(
      format == "pdf"
          ? cairo_pdf_surface_create_for_stream(AppendToBytes, &bytes, w, h)
          : cairo_svg_surface_create_for_stream(AppendToBytes, &bytes, w, h));
  if (format == "pdf") {
    // A fixed date: cairo 1.16 stamps the time of writing otherwise, so two
    // writes of one plot would differ.
    cairo_pdf_surface_set_metadata(
        surface.get(), CAIRO_PDF_METADATA_CREATE_DATE, "2000-01-01T00:00:00Z");
    cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_TITLE,
                                   plot.title.c_str());
    cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_CREATOR,
                                   "burrlab");
  } else {
    cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_PX);
  }
  if (Status s = DrawOnSurface(surface.get(), plot); !s.ok()) return s.error();
  cairo_surface_finish(surface.get());
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS) {
    return Error{fmt::format(
        "cairo cannot write the {}: {}", format == "pdf" ? "PDF" : "SVG",
        cairo_status_to_string(cairo_surface_status(surface.get())))};
  }
  if (format == "svg") NumberSvgSurfaceOne(&bytes);
  return bytes;
}

Status WriteFileBytes(const std::string& path, const std::string& bytes) {
  namespace fs = std::filesystem;
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) {
    const fs::path folder = fs::path(path).parent_path();
    std::error_code ec;
    if (!folder.empty() && !fs::is_directory(folder, ec)) {
      return Error{
          fmt::format("{}: cannot write the figure: folder '{}' does "
                      "not exist",
                      path, folder.string())};
    }
    return Error{path + ": cannot open the file for writing"};
  }
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  file.close();
  if (!file) return Error{path + ": cannot write the figure (disk full?)"};
  return {};
}

}  // namespace

std::vector<double> NiceTicks(double low, double high, int target) {
  std::vector<double> ticks;
  if (!std::isfinite(low) || !std::isfinite(high) || target < 1) return ticks;
  if (high < low) std::swap(low, high);
  if (high == low) {
    const double pad = low == 0.0 ? 1.0 : 0.1 * std::abs(low);
    low -= pad;
    high += pad;
  }
  const double raw = (high - low) / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * magnitude;
    if (step >= raw) break;
  }
  // Multiples of the step, not a running sum: 0.4 + 6 x 0.1 must reach 1.0.
  const double first = std::floor(low / step + 1e-9);
  for (double k = first; k * step <= high + 1e-9 * step; k += 1.0) {
    ticks.push_back(k * step);
  }
  if (ticks.back() < high - 1e-9 * step) ticks.push_back(ticks.back() + step);
  return ticks;
}

std::vector<double> LogTicks(double low, double high) {
  std::vector<double> ticks;
  if (!(low > 0.0) || !std::isfinite(high) || high < low) return ticks;
  const int first = static_cast<int>(std::floor(std::log10(low))) - 1;
  const int last = static_cast<int>(std::ceil(std::log10(high))) + 1;
  const bool fine =
      last - first <= 5;  // 1-2-5 steps when few decades are spanned
  std::vector<double> candidates;
  for (int k = first; k <= last; ++k) {
    for (double m : {1.0, 2.0, 5.0}) {
      if (m == 1.0 || fine) candidates.push_back(m * std::pow(10.0, k));
    }
  }
  // From the largest candidate <= low to the smallest >= high.
  std::size_t from = 0, to = candidates.size() - 1;
  while (from + 1 < candidates.size() &&
         candidates[from + 1] <= low * (1 + 1e-12))
    ++from;
  while (to > 0 && candidates[to - 1] >= high * (1 - 1e-12)) --to;
  ticks.assign(candidates.begin() + static_cast<std::ptrdiff_t>(from),
               candidates.begin() + static_cast<std::ptrdiff_t>(to) + 1);
  if (ticks.size() == 1) ticks.push_back(ticks.front() * (fine ? 2.0 : 10.0));
  return ticks;
}

Result<Image> RenderPlot(const LinePlot& plot) {
  if (Result<PlotExtent> e = MeasurePlot(plot); !e.ok()) return e.error();
  CairoSurface surface(cairo_image_surface_create(
      CAIRO_FORMAT_ARGB32, plot.width_px, plot.height_px));
  if (Status s = DrawOnSurface(surface.get(), plot); !s.ok()) return s.error();
  cairo_surface_flush(surface.get());
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  Image image{plot.width_px, plot.height_px, {}};
  image.rgb.resize(static_cast<std::size_t>(plot.width_px) *
                   static_cast<std::size_t>(plot.height_px) * 3);
  std::size_t out = 0;
  for (int y = 0; y < plot.height_px; ++y) {
    for (int x = 0; x < plot.width_px; ++x) {
      // ARGB32 is a native-endian 32-bit word; the background is opaque, so
      // the premultiplied components are the colour.
      std::uint32_t pixel = 0;
      std::memcpy(&pixel,
                  data + static_cast<std::ptrdiff_t>(y) * stride +
                      static_cast<std::ptrdiff_t>(x) * 4,
                  4);
      image.rgb[out++] = static_cast<unsigned char>((pixel >> 16) & 0xff);
      image.rgb[out++] = static_cast<unsigned char>((pixel >> 8) & 0xff);
      image.rgb[out++] = static_cast<unsigned char>(pixel & 0xff);
    }
  }
  return image;
}

Status WritePlot(const LinePlot& plot, const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  if (extension != ".png" && extension != ".pdf" && extension != ".svg") {
    return Error{fmt::format(
        "{}: cannot tell the figure format from the extension '{}'; use .png, "
        ".pdf or .svg",
        path, extension)};
  }
  Result<std::string> bytes = EncodePlot(plot, extension.substr(1));
  if (!bytes.ok()) return Error{path + ": " + bytes.error().message};
  return WriteFileBytes(path, *bytes);
}

}  // namespace burrlab::analysis
