// Golden-image checks of plots: RenderPlot's pixels against a PNG committed
// under tests/analysis/golden/. BURRLAB_UPDATE_GOLDEN=1 rewrites the golden
// files instead (look at each before committing it). Every render is also
// written to <temp>/burrlab_golden/<name>.png for looking at.
#ifndef BURRLAB_TESTS_ANALYSIS_GOLDEN_H_
#define BURRLAB_TESTS_ANALYSIS_GOLDEN_H_

#include <cairo.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "burrlab/analysis/plot.h"

namespace burrlab::analysis::testing {

// Pixels may differ (font rasterisers and pixman versions round edges a
// little differently) by more than kGoldenChannelTolerance in some channel in
// at most kGoldenPixelShare of the image.
inline constexpr int kGoldenChannelTolerance = 24;
inline constexpr double kGoldenPixelShare = 0.002;

// Empty when `plot` renders like tests/analysis/golden/<name>.png; else what
// differs.
inline std::string CompareWithGolden(const LinePlot& plot,
                                     const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path golden =
      fs::path(BURRLAB_SOURCE_DIR) / "tests/analysis/golden" / (name + ".png");
  const fs::path shots = fs::temp_directory_path() / "burrlab_golden";
  fs::create_directories(shots);
  for (const char* extension : {".png", ".pdf", ".svg"}) {
    if (Status s = WritePlot(plot, (shots / (name + extension)).string());
        !s.ok()) {
      return s.error().message;
    }
  }
  if (std::getenv("BURRLAB_UPDATE_GOLDEN") != nullptr) {
    fs::copy_file(shots / (name + ".png"), golden,
                  fs::copy_options::overwrite_existing);
    return "";
  }
  Result<Image> image = RenderPlot(plot);
  if (!image.ok()) return image.error().message;
  cairo_surface_t* png = cairo_image_surface_create_from_png(golden.c_str());
  std::string problem;
  if (cairo_surface_status(png) != CAIRO_STATUS_SUCCESS) {
    problem = golden.string() + ": cannot read the PNG";
  } else if (cairo_image_surface_get_width(png) != image->width ||
             cairo_image_surface_get_height(png) != image->height) {
    problem = golden.string() + ": another size";
  } else {
    const unsigned char* data = cairo_image_surface_get_data(png);
    const int stride = cairo_image_surface_get_stride(png);
    long long differing = 0;
    for (int y = 0; y < image->height; ++y) {
      for (int x = 0; x < image->width; ++x) {
        std::uint32_t pixel = 0;
        std::memcpy(&pixel,
                    data + static_cast<std::ptrdiff_t>(y) * stride +
                        static_cast<std::ptrdiff_t>(x) * 4,
                    4);
        const std::size_t i = (static_cast<std::size_t>(y) *
                                   static_cast<std::size_t>(image->width) +
                               static_cast<std::size_t>(x)) *
                              3;
        int worst = 0;
        for (int k = 0; k < 3; ++k) {
          const int golden_value =
              static_cast<int>((pixel >> (16 - 8 * k)) & 0xff);
          worst = std::max(
              worst, std::abs(golden_value -
                              image->rgb[i + static_cast<std::size_t>(k)]));
        }
        if (worst > kGoldenChannelTolerance) ++differing;
      }
    }
    const double share = static_cast<double>(differing) /
                         (static_cast<double>(image->width) * image->height);
    if (share > kGoldenPixelShare) {
      problem = name + ": " + std::to_string(differing) +
                " pixels differ from " + golden.string() + " (see " +
                (shots / (name + ".png")).string() + ")";
    }
  }
  cairo_surface_destroy(png);
  return problem;
}

}  // namespace burrlab::analysis::testing

#endif  // BURRLAB_TESTS_ANALYSIS_GOLDEN_H_
