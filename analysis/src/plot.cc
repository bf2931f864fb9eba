// Line plots rendered into an RGB buffer and written as PNG with
// stb_image_write; text from stb_easy_font (a quad-based bitmap font), scaled
// up for legibility.
#include "burrlab/analysis/plot.h"

#include <fmt/format.h>
#include <stb_easy_font.h>
#include <stb_image_write.h>
#include <stb_truetype.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>

namespace burrlab::analysis {
namespace {

using Rgb = std::array<unsigned char, 3>;

// A colour-blind-friendly palette (Okabe & Ito, 2008).
constexpr std::array<Rgb, 8> kPalette = {{{0, 114, 178},
                                          {213, 94, 0},
                                          {0, 158, 115},
                                          {204, 121, 167},
                                          {230, 159, 0},
                                          {86, 180, 233},
                                          {120, 120, 120},
                                          {240, 228, 66}}};
constexpr Rgb kBlack = {0, 0, 0};
constexpr Rgb kGrid = {225, 225, 225};
constexpr int kTextScale =
    2;  // stb_easy_font glyphs are ~6 px high; draw them at 2x

// DejaVu Sans from Debian's fonts-dejavu-core, rasterised with stb_truetype;
// when the font file is missing, text falls back to stb_easy_font's bitmap
// glyphs.
constexpr char kFontPath[] = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
constexpr float kFontPixels = 17.0f;

struct Font {
  std::vector<unsigned char> data;
  stbtt_fontinfo info{};
  float scale = 0.0f;  // font units to pixels
  int ascent = 0;
};

const Font* LoadFont() {
  static const std::optional<Font> font = []() -> std::optional<Font> {
    std::ifstream file(kFontPath, std::ios::binary);
    if (!file) return std::nullopt;
    Font f;
    f.data.assign(std::istreambuf_iterator<char>(file),
                  std::istreambuf_iterator<char>());
    if (f.data.empty() || stbtt_InitFont(&f.info, f.data.data(), 0) == 0)
      return std::nullopt;
    f.scale = stbtt_ScaleForPixelHeight(&f.info, kFontPixels);
    int descent = 0, gap = 0;
    stbtt_GetFontVMetrics(&f.info, &f.ascent, &descent, &gap);
    return f;
  }();
  return font ? &*font : nullptr;
}

class Canvas {
 public:
  Canvas(int width, int height)
      : width_(width),
        height_(height),
        rgb_(static_cast<std::size_t>(width) * height * 3, 255) {}

  void Blend(int x, int y, const Rgb& c, double alpha) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_ || alpha <= 0.0) return;
    unsigned char* p = &rgb_[(static_cast<std::size_t>(y) * width_ + x) * 3];
    for (int k = 0; k < 3; ++k) {
      p[k] = static_cast<unsigned char>(
          std::lround(p[k] * (1.0 - alpha) + c[k] * alpha));
    }
  }
  void FillRect(double x0, double y0, double x1, double y1, const Rgb& c) {
    const int ix0 = static_cast<int>(std::floor(std::min(x0, x1)));
    const int ix1 = static_cast<int>(std::ceil(std::max(x0, x1)));
    const int iy0 = static_cast<int>(std::floor(std::min(y0, y1)));
    const int iy1 = static_cast<int>(std::ceil(std::max(y0, y1)));
    for (int y = iy0; y < iy1; ++y)
      for (int x = ix0; x < ix1; ++x) Blend(x, y, c, 1.0);
  }
  // A line of the given width: distance-based coverage around the segment,
  // antialiased.
  void Line(double x0, double y0, double x1, double y1, const Rgb& c,
            double width) {
    const double half = 0.5 * width;
    const int bx0 = static_cast<int>(std::floor(std::min(x0, x1) - half - 1));
    const int bx1 = static_cast<int>(std::ceil(std::max(x0, x1) + half + 1));
    const int by0 = static_cast<int>(std::floor(std::min(y0, y1) - half - 1));
    const int by1 = static_cast<int>(std::ceil(std::max(y0, y1) + half + 1));
    const double dx = x1 - x0, dy = y1 - y0, length2 = dx * dx + dy * dy;
    for (int y = std::max(by0, 0); y <= std::min(by1, height_ - 1); ++y) {
      for (int x = std::max(bx0, 0); x <= std::min(bx1, width_ - 1); ++x) {
        const double px = x + 0.5 - x0, py = y + 0.5 - y0;
        const double t =
            length2 > 0.0 ? std::clamp((px * dx + py * dy) / length2, 0.0, 1.0)
                          : 0.0;
        const double ex = px - t * dx, ey = py - t * dy;
        const double distance = std::sqrt(ex * ex + ey * ey);
        Blend(x, y, c, std::clamp(half + 0.5 - distance, 0.0, 1.0));
      }
    }
  }
  // Text with its top-left corner at (x, y), about 13 px high.
  void Text(double x, double y, const std::string& text, const Rgb& c) {
    if (const Font* font = LoadFont()) {
      double pen = x;
      const int baseline = static_cast<int>(std::lround(
          y + static_cast<double>(font->ascent) * font->scale - 2.0));
      for (std::size_t i = 0; i < text.size(); ++i) {
        const int ch = static_cast<unsigned char>(text[i]);
        int advance = 0, bearing = 0;
        stbtt_GetCodepointHMetrics(&font->info, ch, &advance, &bearing);
        int w = 0, h = 0, xoff = 0, yoff = 0;
        unsigned char* glyph = stbtt_GetCodepointBitmapSubpixel(
            &font->info, font->scale, font->scale,
            static_cast<float>(pen - std::floor(pen)), 0.0f, ch, &w, &h, &xoff,
            &yoff);
        for (int gy = 0; gy < h; ++gy) {
          for (int gx = 0; gx < w; ++gx) {
            Blend(static_cast<int>(std::floor(pen)) + xoff + gx,
                  baseline + yoff + gy, c, glyph[gy * w + gx] / 255.0);
          }
        }
        stbtt_FreeBitmap(glyph, nullptr);
        pen += static_cast<double>(advance) * font->scale;
        if (i + 1 < text.size()) {
          const int kern = stbtt_GetCodepointKernAdvance(
              &font->info, ch, static_cast<unsigned char>(text[i + 1]));
          pen += static_cast<double>(kern) * font->scale;
        }
      }
      return;
    }
    std::vector<char> buffer(text.size() * 300 + 64);
    std::string copy = text;
    const int quads =
        stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, buffer.data(),
                            static_cast<int>(buffer.size()));
    // Each vertex: x, y, z floats and 4 colour bytes (16 bytes); 4 vertices per
    // quad.
    for (int q = 0; q < quads; ++q) {
      float v[2][2];
      for (int corner = 0; corner < 2; ++corner) {
        std::memcpy(v[corner], buffer.data() + (q * 4 + corner * 2) * 16,
                    2 * sizeof(float));
      }
      FillRect(x + v[0][0] * kTextScale, y + v[0][1] * kTextScale,
               x + v[1][0] * kTextScale, y + v[1][1] * kTextScale, c);
    }
  }
  static double TextWidth(const std::string& text) {
    if (const Font* font = LoadFont()) {
      double width = 0.0;
      for (std::size_t i = 0; i < text.size(); ++i) {
        const int ch = static_cast<unsigned char>(text[i]);
        int advance = 0, bearing = 0;
        stbtt_GetCodepointHMetrics(&font->info, ch, &advance, &bearing);
        width += static_cast<double>(advance) * font->scale;
      }
      return width;
    }
    std::string copy = text;
    return stb_easy_font_width(copy.data()) * kTextScale;
  }

  Image Take() { return Image{width_, height_, std::move(rgb_)}; }

 private:
  int width_, height_;
  std::vector<unsigned char> rgb_;
};

const Rgb& ColourOf(const Series& s, std::size_t position) {
  const std::size_t index =
      s.colour >= 0 ? static_cast<std::size_t>(s.colour) : position;
  return kPalette[index % kPalette.size()];
}

std::string TickLabel(double value, double step) {
  if (std::abs(value) < 1e-9 * std::abs(step)) value = 0.0;
  return fmt::format("{:.4g}", value);
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
  const double first = std::floor(low / step + 1e-9) * step;
  for (double t = first; t <= high + 1e-9 * step; t += step) ticks.push_back(t);
  if (ticks.back() < high) ticks.push_back(ticks.back() + step);
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
  if (plot.width_px < 200 || plot.height_px < 150 || plot.width_px > 8000 ||
      plot.height_px > 8000) {
    return Error{
        fmt::format("plot size must be 200x150 to 8000x8000 pixels, got {}x{}",
                    plot.width_px, plot.height_px)};
  }
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  double y_min = x_min, y_max = -x_min;
  for (const Series& s : plot.series) {
    if (s.x.size() != s.y.size()) {
      return Error{fmt::format("series '{}' has {} x values and {} y values",
                               s.label, s.x.size(), s.y.size())};
    }
    if (!s.marker_px.empty() && s.marker_px.size() != s.x.size()) {
      return Error{fmt::format("series '{}' has {} points and {} marker sizes",
                               s.label, s.x.size(), s.marker_px.size())};
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
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if (plot.log_y && !(s.y[i] > 0.0)) continue;
      x_min = std::min(x_min, s.x[i] - half_bar);
      x_max = std::max(x_max, s.x[i] + half_bar);
      y_min =
          std::min(y_min, s.bar_width > 0.0 ? std::min(s.y[i], 0.0) : s.y[i]);
      y_max =
          std::max(y_max, s.bar_width > 0.0 ? std::max(s.y[i], 0.0) : s.y[i]);
    }
  }
  if (!(x_min <= x_max))
    return Error{"plot '" + plot.title + "' has no finite points"};
  std::vector<double> x_ticks = NiceTicks(x_min, x_max);
  double x_lo = x_ticks.front(), x_hi = x_ticks.back();
  const double x_step = x_ticks[1] - x_ticks[0];
  if (plot.x_range.has_value()) {
    const auto [low, high] = *plot.x_range;
    if (!(low < high) || !std::isfinite(low) || !std::isfinite(high)) {
      return Error{fmt::format("plot '{}': x range [{}, {}] is empty",
                               plot.title, low, high)};
    }
    x_lo = low;
    x_hi = high;
    x_ticks.clear();
    for (double t : NiceTicks(low, high)) {
      if (t >= low && t <= high) x_ticks.push_back(t);
    }
  }
  if (plot.integer_x) x_ticks = WholeTicks(x_ticks, x_lo, x_hi);
  std::vector<double> y_ticks =
      plot.log_y ? LogTicks(y_min, y_max) : NiceTicks(y_min, y_max);
  if (plot.integer_y && !plot.log_y) {
    y_ticks = WholeTicks(y_ticks, y_ticks.front(), y_ticks.back());
  }
  // On a log axis positions are log10 of the values.
  const auto ty = [&](double y) { return plot.log_y ? std::log10(y) : y; };
  const double y_lo = ty(y_ticks.front()), y_hi = ty(y_ticks.back());

  Canvas canvas(plot.width_px, plot.height_px);
  double widest_y_label = 0.0;
  for (double t : y_ticks) {
    widest_y_label =
        std::max(widest_y_label,
                 Canvas::TextWidth(TickLabel(t, y_ticks[1] - y_ticks[0])));
  }
  const double left = 24 + widest_y_label, right = plot.width_px - 24.0;
  const double top = 64, bottom = plot.height_px - 64.0;
  const auto px = [&](double x) {
    return left + (x - x_lo) / (x_hi - x_lo) * (right - left);
  };
  const auto py = [&](double value) {
    const double y = ty(value);
    return bottom - (y - y_lo) / (y_hi - y_lo) * (bottom - top);
  };

  // Grid, ticks and labels.
  for (double t : x_ticks) {
    canvas.Line(px(t), top, px(t), bottom, kGrid, 1.0);
    const std::string label = TickLabel(t, x_step);
    canvas.Text(px(t) - Canvas::TextWidth(label) / 2, bottom + 8, label,
                kBlack);
  }
  for (double t : y_ticks) {
    canvas.Line(left, py(t), right, py(t), kGrid, 1.0);
    const std::string label = TickLabel(t, y_ticks[1] - y_ticks[0]);
    canvas.Text(left - 8 - Canvas::TextWidth(label), py(t) - 6, label, kBlack);
  }
  canvas.Line(left, bottom, right, bottom, kBlack, 1.5);
  canvas.Line(left, top, left, bottom, kBlack, 1.5);
  canvas.Text((left + right) / 2 - Canvas::TextWidth(plot.title) / 2, 14,
              plot.title, kBlack);
  canvas.Text((left + right) / 2 - Canvas::TextWidth(plot.x_label) / 2,
              bottom + 36, plot.x_label, kBlack);
  canvas.Text(left - widest_y_label - 12, top - 28, plot.y_label, kBlack);

  // Series.
  for (std::size_t n = 0; n < plot.series.size(); ++n) {
    const Series& s = plot.series[n];
    const Rgb& colour = ColourOf(s, n);
    bool have_previous = false;
    double previous_x = 0.0, previous_y = 0.0;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) ||
          (plot.log_y && !(s.y[i] > 0.0))) {
        have_previous = false;
        continue;
      }
      const double x = px(s.x[i]), y = py(s.y[i]);
      if (s.bar_width > 0.0 && s.y[i] != 0.0) {
        const double half = 0.5 * s.bar_width;
        canvas.FillRect(px(s.x[i] - half) + 1, py(0.0), px(s.x[i] + half) - 1,
                        y, colour);
      }
      if (s.line && have_previous)
        canvas.Line(previous_x, previous_y, x, y, colour, 2.5);
      if (s.markers) {
        const double half =
            0.5 * (s.marker_px.empty()
                       ? 7.0
                       : std::clamp(s.marker_px[i], 1.0, 200.0));
        canvas.FillRect(x - half, y - half, x + half, y + half, colour);
      }
      previous_x = x;
      previous_y = y;
      have_previous = true;
    }
  }
  // Legend, top left inside the axes.
  double legend_width = 0.0;
  int entries = 0;
  for (const Series& s : plot.series) {
    if (s.label.empty()) continue;
    legend_width = std::max(legend_width, Canvas::TextWidth(s.label));
    ++entries;
  }
  if (entries > 0) {
    const double lx = left + 12, ly = top + 10;
    const double height = 22.0 * entries + 8;
    canvas.FillRect(lx, ly, lx + legend_width + 52, ly + height,
                    {255, 255, 255});
    canvas.Line(lx, ly, lx + legend_width + 52, ly, kGrid, 1.0);
    canvas.Line(lx, ly + height, lx + legend_width + 52, ly + height, kGrid,
                1.0);
    int row = 0;
    for (std::size_t n = 0; n < plot.series.size(); ++n) {
      const Series& s = plot.series[n];
      if (s.label.empty()) continue;
      const double y = ly + 14 + 22.0 * row++;
      if (s.bar_width > 0.0)
        canvas.FillRect(lx + 12, y - 6, lx + 32, y + 6, ColourOf(s, n));
      if (s.line) canvas.Line(lx + 8, y, lx + 36, y, ColourOf(s, n), 3.0);
      if (s.markers)
        canvas.FillRect(lx + 18.5, y - 3.5, lx + 25.5, y + 3.5, ColourOf(s, n));
      canvas.Text(lx + 44, y - 6, s.label, kBlack);
    }
  }
  return canvas.Take();
}

Status WritePlotPng(const LinePlot& plot, const std::string& path) {
  Result<Image> image = RenderPlot(plot);
  if (!image.ok()) return Error{path + ": " + image.error().message};
  if (stbi_write_png(path.c_str(), image->width, image->height, 3,
                     image->rgb.data(), image->width * 3) == 0) {
    return Error{path + ": cannot write PNG file"};
  }
  return {};
}

}  // namespace burrlab::analysis
