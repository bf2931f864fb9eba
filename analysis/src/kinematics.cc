// Force and speed histograms, mean force and removal rate from the traces.
#include "burrlab/analysis/kinematics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "burrlab/results_schema/dataset_layout.h"

namespace burrlab::analysis {
namespace {

using results_schema::BehFile;
using results_schema::PhysioFile;

constexpr double kContactForceN = 0.01;

// The samples of one subject and block, before binning.
struct Samples {
  KinematicsSummary summary;
  std::vector<double> force_n;
  std::vector<double> speed_mm_s;
};

std::optional<std::size_t> ColumnOf(const PhysioFile& f,
                                    const std::string& name) {
  const auto it = std::find(f.columns.begin(), f.columns.end(), name);
  if (it == f.columns.end()) return std::nullopt;
  return static_cast<std::size_t>(it - f.columns.begin());
}

Status Collect(const BehFile& file, Samples* out) {
  double removed = 0.0;
  bool has_removed = !file.physio.empty();
  double force_sum = 0.0, force_sum2 = 0.0, speed_sum = 0.0;
  long long contact = 0;
  for (const PhysioFile& physio : file.physio) {
    const std::optional<std::size_t> trial = ColumnOf(physio, "trial_index");
    const std::optional<std::size_t> interval =
        ColumnOf(physio, "interval_index");
    const std::optional<std::size_t> z = ColumnOf(physio, "position_z_mm");
    const std::optional<std::size_t> force = ColumnOf(physio, "force_n");
    const std::optional<std::size_t> removed_column =
        ColumnOf(physio, "removed_mm3");
    if (!trial || !interval || !z || !force) {
      return Error{fmt::format(
          "{}: the traces need the columns trial_index, interval_index, "
          "position_z_mm and force_n",
          physio.data_path.string())};
    }
    has_removed = has_removed && removed_column.has_value();
    double last_trial = -1.0, last_interval = -1.0, last_z = 0.0;
    double interval_removed = 0.0;
    const double fs = physio.sampling_frequency_hz;
    Status s = results_schema::ForEachPhysioRow(
        physio, [&](std::span<const double> row) {
          const bool same =
              row[*trial] == last_trial && row[*interval] == last_interval;
          if (!same) {
            removed += interval_removed;
            interval_removed = 0.0;
            ++out->summary.intervals;
          }
          const double f = row[*force];
          if (std::isfinite(f)) {
            out->force_n.push_back(f);
            force_sum += f;
            force_sum2 += f * f;
            out->summary.max_force_n = std::max(out->summary.max_force_n, f);
            contact += f > kContactForceN ? 1 : 0;
          }
          if (same && std::isfinite(row[*z]) && std::isfinite(last_z)) {
            const double v = std::abs(row[*z] - last_z) * fs;
            out->speed_mm_s.push_back(v);
            speed_sum += v;
          }
          if (removed_column && std::isfinite(row[*removed_column])) {
            interval_removed = std::max(interval_removed, row[*removed_column]);
          }
          last_trial = row[*trial];
          last_interval = row[*interval];
          last_z = row[*z];
          ++out->summary.samples;
          out->summary.duration_s += 1.0 / fs;
          return true;
        });
    if (!s.ok()) return s.error();
    removed += interval_removed;
  }
  KinematicsSummary& k = out->summary;
  const double n = static_cast<double>(out->force_n.size());
  if (n > 0) {
    k.mean_force_n = force_sum / n;
    k.sd_force_n =
        n > 1 ? std::sqrt(std::max(
                    0.0, (force_sum2 - force_sum * force_sum / n) / (n - 1)))
              : 0.0;
    k.contact_fraction = static_cast<double>(contact) / n;
  }
  if (!out->speed_mm_s.empty()) {
    k.mean_speed_mm_s = speed_sum / static_cast<double>(out->speed_mm_s.size());
  }
  if (has_removed) {
    k.removed_mm3 = removed;
    if (k.duration_s > 0.0) k.removal_rate_mm3_per_s = removed / k.duration_s;
  }
  return {};
}

Histogram Bin(const std::vector<double>& values, double high, int bins) {
  Histogram h;
  h.low = 0.0;
  h.width = (high > 0.0 ? high : 1.0) / bins;
  h.counts.assign(static_cast<std::size_t>(bins), 0);
  for (double v : values) {
    const double k = std::floor((v - h.low) / h.width);
    if (v == h.low + bins * h.width) {
      ++h.counts.back();
    } else if (k < 0.0 || k >= bins) {
      ++h.outside;
    } else {
      ++h.counts[static_cast<std::size_t>(k)];
    }
  }
  return h;
}

LinePlot HistogramPlot(const Histogram& h, const std::string& title,
                       const std::string& x_label, int colour) {
  LinePlot plot;
  plot.title = title;
  plot.x_label = x_label;
  plot.y_label = "share of samples (%)";
  Series bars;
  bars.line = false;
  bars.bar_width = h.width;
  bars.colour = colour;
  long long total = h.outside;
  for (long long c : h.counts) total += c;
  for (std::size_t k = 0; k < h.counts.size(); ++k) {
    bars.x.push_back(h.low + (static_cast<double>(k) + 0.5) * h.width);
    bars.y.push_back(total > 0 ? 100.0 * static_cast<double>(h.counts[k]) /
                                     static_cast<double>(total)
                               : 0.0);
  }
  plot.series.push_back(std::move(bars));
  return plot;
}

}  // namespace

Result<std::vector<KinematicsSummary>> SummarizeKinematics(
    std::span<const BehFile> files, const KinematicsOptions& options) {
  if (options.bins < 1 || options.bins > 10000) {
    return Error{fmt::format("bins must be 1 to 10000, got {}", options.bins)};
  }
  if (!(options.force_max_n >= 0.0) || !(options.speed_max_mm_s >= 0.0)) {
    return Error{"histogram ranges must be 0 (automatic) or above"};
  }
  std::vector<Samples> all;
  for (const BehFile& file : files) {
    if (file.physio.empty()) continue;
    Samples s;
    s.summary.subject = file.subject;
    s.summary.session = file.session;
    s.summary.block = file.task;
    s.summary.task = file.table.trials.front().task;
    if (Status status = Collect(file, &s); !status.ok()) return status.error();
    all.push_back(std::move(s));
  }
  if (all.empty()) {
    return Error{
        "no traces: the results have no _physio.tsv.gz files (intervals of "
        "real samples are not recorded)"};
  }
  double force_max = options.force_max_n, speed_max = options.speed_max_mm_s;
  if (force_max == 0.0 || speed_max == 0.0) {
    double f = 0.0, v = 0.0;
    for (const Samples& s : all) {
      for (double x : s.force_n) f = std::max(f, x);
      for (double x : s.speed_mm_s) v = std::max(v, x);
    }
    if (force_max == 0.0) force_max = f;
    if (speed_max == 0.0) speed_max = v;
  }
  std::vector<KinematicsSummary> out;
  for (Samples& s : all) {
    s.summary.force = Bin(s.force_n, force_max, options.bins);
    s.summary.speed = Bin(s.speed_mm_s, speed_max, options.bins);
    out.push_back(std::move(s.summary));
  }
  return out;
}

LinePlot ForceHistogramPlot(const KinematicsSummary& s) {
  return HistogramPlot(
      s.force,
      fmt::format("{} {} ({}): force, mean {:.3g} N",
                  results_schema::SessionName(s.subject, s.session), s.block,
                  s.task, s.mean_force_n),
      "felt force (N)", 0);
}

LinePlot SpeedHistogramPlot(const KinematicsSummary& s) {
  return HistogramPlot(
      s.speed,
      fmt::format("{} {} ({}): burr speed, mean {:.3g} mm/s",
                  results_schema::SessionName(s.subject, s.session), s.block,
                  s.task, s.mean_speed_mm_s),
      "burr speed |dz/dt| (mm/s)", 1);
}

}  // namespace burrlab::analysis
