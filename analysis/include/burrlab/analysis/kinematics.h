// Kinematics of recorded intervals (dissertation ch. 12, Fig. 12.4-12.6):
// per subject and block, per subject, block and material felt, and per
// subject over all its blocks (one figure per surgeon, as Fig. 12.4-12.6),
// histograms of the felt force and of the burr's speed, the mean force and the
// material removal rate, from the exported traces (_physio.tsv.gz). Two trace
// layouts are read: a station's (position_x_mm, position_y_mm, position_z_mm
// and force_x_n, force_y_n, force_z_n: the burr moves and is pushed in 3-D) and
// a simulated interval's (position_z_mm and force_n: the burr moves along z
// only), with removed_mm3 when drilling.
#ifndef BURRLAB_ANALYSIS_KINEMATICS_H_
#define BURRLAB_ANALYSIS_KINEMATICS_H_

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "burrlab/analysis/group_stats.h"
#include "burrlab/analysis/participant_groups.h"
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
  // the largest value over every subject's blocks of the same task (probe,
  // drill), and over every block for the summaries over all blocks.
  double force_max_n = 0.0;
  double speed_max_mm_s = 0.0;
};

struct KinematicsSummary {
  std::string subject;
  std::string session;  // the files' session label; empty: not labelled
  // The task label of the files; empty in a subject's summary over all its
  // blocks.
  std::string block;
  std::string task;  // "probe", "drill", or "drill+probe" over mixed blocks
  // The material felt (a trial's interval_materials at the interval) in a
  // per-material summary; empty otherwise.
  std::string material;
  int intervals = 0;
  long long samples = 0;
  double duration_s = 0.0;  // traced time
  // The force of every sample: |F| of force_x_n, force_y_n and force_z_n, or
  // force_n (the vertical force) where the traces have only that.
  double mean_force_n = 0.0;
  double sd_force_n = 0.0;
  double max_force_n = 0.0;
  double contact_fraction = 0.0;  // samples with force above 0.01 N
  // Speed between consecutive samples of one interval, |p(i+1) - p(i)| fs:
  // 3-D from position_x_mm, position_y_mm and position_z_mm, or |dz/dt| from
  // position_z_mm where the burr moves along z only.
  double mean_speed_mm_s = 0.0;
  // What the force and the speed were computed from, e.g. "|F| of force_x_n,
  // force_y_n, force_z_n" (both layouts joined by " and " when mixed).
  std::string force_measure;
  std::string speed_measure;
  // Material removed over the intervals and per traced second; none when
  // the traces have no removed_mm3 column.
  std::optional<double> removed_mm3;
  std::optional<double> removal_rate_mm3_per_s;
  Histogram force;
  Histogram speed;
};

// Per subject and block (in the files' order), and per subject over all its
// blocks (in subject order), every histogram over the same ranges.
struct KinematicsReport {
  std::vector<KinematicsSummary> blocks;
  std::vector<KinematicsSummary> subjects;
  // Per subject, block and material felt (in the files' order, materials in
  // order of first appearance), over the block's task's ranges.
  std::vector<KinematicsSummary> materials;
};

// The summaries of every file with traces. An error names a file whose
// traces lack a position or a force, or says that no file has traces.
Result<KinematicsReport> SummarizeKinematics(
    std::span<const results_schema::BehFile> files,
    const KinematicsOptions& options);

// One per-subject measure of one block (or of the subjects' summaries over
// all blocks) compared between two groups: Welch's t-test and the
// Mann-Whitney U test, each absent with the reason in its note when the
// groups are too small or constant.
struct KinematicsComparison {
  std::string block;    // empty: the subjects' summaries over all blocks
  std::string measure;  // a KinematicsSummary field, e.g. "mean_force_n"
  std::array<std::vector<double>, 2> values;  // per group, in subject order
  std::optional<WelchTTestResult> welch;
  std::string welch_note;
  std::optional<MannWhitneyResult> mann_whitney;
  std::string mann_whitney_note;
};

struct KinematicsGroupComparison {
  std::string column;                 // the participants file's group column
  std::array<std::string, 2> groups;  // x and y of the tests
  std::array<std::vector<std::string>, 2> subjects;  // with traces, per group
  std::vector<std::string> left_out;  // subjects with traces whose group is n/a
  std::vector<KinematicsComparison> comparisons;
};

// The measures compared, in order: mean_force_n, sd_force_n, max_force_n,
// contact_fraction, mean_speed_mm_s and removal_rate_mm3_per_s (subjects
// without removed_mm3 left out of that one). Intervals, samples and traced
// time are set by the protocol and are not compared.
std::span<const char* const> ComparedKinematicsMeasures();

// Compares the groups of `groups` per block (in the report's order) and over
// all blocks. An error names a subject with traces but no row in the
// participants file.
Result<KinematicsGroupComparison> CompareKinematicsGroups(
    const KinematicsReport& report, const ParticipantGroups& groups);

// The force and speed histograms of one summary as two plots.
LinePlot ForceHistogramPlot(const KinematicsSummary& summary);
LinePlot SpeedHistogramPlot(const KinematicsSummary& summary);

// The group's force and speed histograms of one block: `block` holds every
// subject's summary of it (same ranges). Per bin the mean over subjects of
// each subject's share of its samples, with the SEM across subjects as
// error bars (none with one subject).
LinePlot GroupForceHistogramPlot(std::span<const KinematicsSummary> block);
LinePlot GroupSpeedHistogramPlot(std::span<const KinematicsSummary> block);

}  // namespace burrlab::analysis

#endif  // BURRLAB_ANALYSIS_KINEMATICS_H_
