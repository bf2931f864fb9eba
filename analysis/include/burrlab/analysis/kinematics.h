// Kinematics of recorded intervals (dissertation ch. 12, Fig. 12.4-12.6):
// per subject and block, histograms of the felt force and of the burr's speed,
// the mean force and the material removal rate, from the exported traces
// (_physio.tsv.gz: position_z_mm, force_n and, for drilling, removed_mm3).
#ifndef BURRLAB_ANALYSIS_KINEMATICS_H_
#define BURRLAB_ANALYSIS_KINEMATICS_H_

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "burrlab/analysis/plot.h"
#include "burrlab/base/result.h"
#include "burrlab/results_schema/bids_read.h"

namespace burrlab::analysis {

// Counts in equal bins [low + k width, low + (k + 1) width); the last bin
// also takes its upper edge.
struct Histogram {
  double low = 0.0;
  double width = 1.0;
  std::vector<long long> counts;
  long long outside = 0;  // samples beyond [low, low + bins x width]
};

struct KinematicsOptions {
  int bins = 30;  // per histogram
  // Common histogram ranges (so subjects compare bin for bin); 0: from 0 to
  // the largest value over every subject and block.
  double force_max_n = 0.0;
  double speed_max_mm_s = 0.0;
};

struct KinematicsSummary {
  std::string subject;
  std::string session;  // the files' session label; empty: not labelled
  std::string block;    // the task label of the files
  std::string task;     // "probe" or "drill"
  int intervals = 0;
  long long samples = 0;
  double duration_s = 0.0;    // traced time
  double mean_force_n = 0.0;  // over every sample
  double sd_force_n = 0.0;
  double max_force_n = 0.0;
  double contact_fraction = 0.0;  // samples with force above 0.01 N
  double mean_speed_mm_s = 0.0;   // |dz/dt| between samples of an interval
  // Material removed over the intervals and per traced second; none when
  // the traces have no removed_mm3 column.
  std::optional<double> removed_mm3;
  std::optional<double> removal_rate_mm3_per_s;
  Histogram force;
  Histogram speed;
};

// One summary per subject and block with traces, in the files' order. An
// error names a file whose traces lack position_z_mm or force_n, or when no
// file has traces.
Result<std::vector<KinematicsSummary>> SummarizeKinematics(
    std::span<const results_schema::BehFile> files,
    const KinematicsOptions& options);

// The force and speed histograms of one summary as two plots.
LinePlot ForceHistogramPlot(const KinematicsSummary& summary);
LinePlot SpeedHistogramPlot(const KinematicsSummary& summary);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_KINEMATICS_H_
