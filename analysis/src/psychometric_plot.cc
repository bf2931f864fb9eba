// Data with Wilson intervals, fitted curve, chance and threshold intervals as
// line-plot series and reference lines.
#include "burrlab/analysis/psychometric_plot.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <limits>

#include "non_finite.h"

namespace burrlab::analysis {
namespace {

using detail::kNaN;
constexpr double kLargestMarkerPx = 22.0;  // side of the block with most trials
constexpr double kSmallestMarkerPx = 4.0;
constexpr int kCurvePoints = 300;

// The bound of `e` at conf `level`: BCa when available, else percentile;
// NaN when neither is.
double IntervalBound(const PsychometricOptions& options,
                     const BootstrapEstimate& e, double level) {
  for (std::size_t k = 0; k < options.conf.size(); ++k) {
    if (std::abs(options.conf[k] - level) < 1e-12) {
      return std::isfinite(e.bca[k]) ? e.bca[k] : e.percentile[k];
    }
  }
  return kNaN;
}

// The 95 % Wilson score interval of `correct` successes in `total` trials
// (Wilson, 1927; Brown, Cai & DasGupta, 2001).
std::pair<double, double> WilsonInterval95(int correct, int total) {
  const double z = boost::math::quantile(boost::math::normal(), 0.975);
  const double n = total, p = correct / n, z2 = z * z;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half =
      z / (1 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

}  // namespace

LinePlot MakePsychometricPlot(std::span<const DataBlock> data,
                              const PsychometricAnalysis& analysis,
                              const std::string& x_label) {
  const PsychometricOptions& o = analysis.options;
  LinePlot plot;
  plot.title =
      fmt::format("{} fit, {}: alpha {:.4g}, beta {:.4g}, lambda {:.3g}",
                  SigmoidName(o.sigmoid),
                  o.n_intervals == 1 ? std::string("yes/no")
                                     : fmt::format("{}-AFC", o.n_intervals),
                  analysis.fit.params.alpha, analysis.fit.params.beta,
                  analysis.fit.params.lambda);
  plot.x_label = x_label;
  plot.y_label = o.n_intervals == 1 ? "proportion 'yes'" : "proportion correct";

  Series points{"data ± 95 % Wilson (area ~ n)", {}, {}, false, true, 0};
  int most = 1;
  for (const DataBlock& b : data) most = std::max(most, b.n_total);
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (const DataBlock& b : data) {
    points.x.push_back(b.level);
    points.y.push_back(static_cast<double>(b.n_correct) / b.n_total);
    const auto [wilson_low, wilson_high] =
        b.n_total > 0 ? WilsonInterval95(b.n_correct, b.n_total)
                      : std::pair(kNaN, kNaN);
    points.y_low.push_back(wilson_low);
    points.y_high.push_back(wilson_high);
    points.marker_px.push_back(std::max(
        kSmallestMarkerPx,
        kLargestMarkerPx * std::sqrt(static_cast<double>(b.n_total) / most)));
    low = std::min(low, b.level);
    high = std::max(high, b.level);
  }

  Series curve{"fitted psi", {}, {}, true, false, 1};
  const double pad = 0.05 * (high - low);
  double from = low - pad;
  if (o.sigmoid == Sigmoid::kWeibull) from = std::max(from, 0.5 * low);
  const double to = high + pad;
  for (int i = 0; i <= kCurvePoints; ++i) {
    const double x = from + (to - from) * i / kCurvePoints;
    curve.x.push_back(x);
    curve.y.push_back(Psi(o.sigmoid, analysis.fit.params, x));
  }

  Series bars{"thresholds, 95 % interval", {}, {}, true, false, 2};
  Series centres{"", {}, {}, false, true, 2};
  for (const BootstrapEstimate& t : analysis.thresholds) {
    const double y = Psi(o.sigmoid, analysis.fit.params, t.value);
    centres.x.push_back(t.value);
    centres.y.push_back(y);
    if (std::isfinite(t.value)) {
      plot.reference_lines.push_back(
          {true, t.value,
           fmt::format("{:.0f} % at {:.3g}", 100.0 * y, t.value)});
    }
    const double lo = IntervalBound(o, t, 0.025),
                 hi = IntervalBound(o, t, 0.975);
    if (std::isfinite(lo) && std::isfinite(hi)) {
      bars.x.insert(bars.x.end(), {lo, hi, kNaN});
      bars.y.insert(bars.y.end(), {y, y, kNaN});
    }
  }
  const double gamma = analysis.fit.params.gamma;
  if (gamma > 0.0) {
    plot.reference_lines.push_back(
        {false, gamma,
         o.n_intervals == 1 ? fmt::format("guess rate {:.3g} %", 100.0 * gamma)
                            : fmt::format("chance {:.3g} %", 100.0 * gamma)});
  }
  plot.series.push_back(std::move(curve));
  plot.series.push_back(std::move(points));
  if (!bars.x.empty()) plot.series.push_back(std::move(bars));
  plot.series.push_back(std::move(centres));
  return plot;
}

LinePlot MakeConditionsPlot(std::span<const std::vector<DataBlock>> data,
                            std::span<const PsychometricAnalysis> analyses,
                            std::span<const std::string> names,
                            const std::string& x_label) {
  LinePlot plot;
  const PsychometricOptions& o = analyses.front().options;
  plot.title =
      fmt::format("{} fits, {}, by condition", SigmoidName(o.sigmoid),
                  o.n_intervals == 1 ? std::string("yes/no")
                                     : fmt::format("{}-AFC", o.n_intervals));
  plot.x_label = x_label;
  for (std::size_t k = 0; k < analyses.size(); ++k) {
    LinePlot one = MakePsychometricPlot(data[k], analyses[k], x_label);
    if (k == 0) {
      plot.y_label = one.y_label;
      // Chance (or the guess rate) once; threshold lines would crowd the
      // conditions' own intervals.
      for (const ReferenceLine& line : one.reference_lines) {
        if (!line.vertical) plot.reference_lines.push_back(line);
      }
    }
    const int colour = static_cast<int>(k);
    for (Series& series : one.series) {
      series.colour = colour;
      if (series.label == "fitted psi") {
        series.label = names[k];
      } else {
        series.label.clear();  // one legend entry per condition
      }
      plot.series.push_back(std::move(series));
    }
  }
  return plot;
}

}  // namespace burrlab::analysis
