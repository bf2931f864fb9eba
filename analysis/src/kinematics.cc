// Force and speed histograms, mean force and removal rate from the traces.
#include "burrlab/analysis/kinematics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "burrlab/results_schema/dataset_layout.h"

namespace burrlab::analysis {
namespace {

using results_schema::BehFile;
using results_schema::PhysioFile;

constexpr double kContactForceN = 0.01;

// The samples of one subject and block (or of all a subject's blocks),
// before binning.
struct Samples {
  KinematicsSummary summary;
  std::vector<double> force_n;
  std::vector<double> speed_mm_s;
  bool has_removed = true;  // every trace file had removed_mm3
  double removed_mm3 = 0.0;
};

std::optional<std::size_t> ColumnOf(const PhysioFile& f,
                                    const std::string& name) {
  const auto it = std::find(f.columns.begin(), f.columns.end(), name);
  if (it == f.columns.end()) return std::nullopt;
  return static_cast<std::size_t>(it - f.columns.begin());
}

// Where one trace file keeps the burr's position and the felt force.
struct TraceLayout {
  std::size_t trial = 0, interval = 0;
  std::vector<std::size_t> position;  // x, y, z, or z alone
  std::vector<std::size_t> force;     // x, y, z components, or force_n
  std::optional<std::size_t> removed;
  std::string force_measure, speed_measure;
};

// The columns of `names` when the file has every one of them.
std::optional<std::vector<std::size_t>> AllOf(
    const PhysioFile& f, std::initializer_list<const char*> names) {
  std::vector<std::size_t> at;
  for (const char* name : names) {
    const std::optional<std::size_t> c = ColumnOf(f, name);
    if (!c) return std::nullopt;
    at.push_back(*c);
  }
  return at;
}

Result<TraceLayout> LayoutOf(const PhysioFile& f) {
  TraceLayout layout;
  const std::optional<std::size_t> trial = ColumnOf(f, "trial_index");
  const std::optional<std::size_t> interval = ColumnOf(f, "interval_index");
  // A station traces the burr in 3-D; a simulated interval moves it along z
  // only (and then |dz/dt| is its whole speed).
  const bool lateral = ColumnOf(f, "position_x_mm").has_value() ||
                       ColumnOf(f, "position_y_mm").has_value();
  std::optional<std::vector<std::size_t>> position =
      AllOf(f, {"position_x_mm", "position_y_mm", "position_z_mm"});
  if (position) {
    layout.speed_measure =
        "|dp/dt| of position_x_mm, position_y_mm, position_z_mm";
  } else if (!lateral) {
    position = AllOf(f, {"position_z_mm"});
    layout.speed_measure = "|dz/dt| of position_z_mm";
  }
  std::optional<std::vector<std::size_t>> force =
      AllOf(f, {"force_x_n", "force_y_n", "force_z_n"});
  if (force) {
    layout.force_measure = "|F| of force_x_n, force_y_n, force_z_n";
  } else {
    force = AllOf(f, {"force_n"});
    layout.force_measure = "force_n";
  }
  if (!trial || !interval || !position || !force) {
    return Error{fmt::format(
        "{}: the traces need the columns trial_index, interval_index, a "
        "position (position_x_mm, position_y_mm and position_z_mm, or "
        "position_z_mm alone) and a force (force_x_n, force_y_n and "
        "force_z_n, or force_n); they have {}",
        f.data_path.string(), fmt::join(f.columns, ", "))};
  }
  layout.trial = *trial;
  layout.interval = *interval;
  layout.position = std::move(*position);
  layout.force = std::move(*force);
  layout.removed = ColumnOf(f, "removed_mm3");
  return layout;
}

// Euclidean norm of the row's values at `at` (|x| for one column).
double Norm(std::span<const double> row, const std::vector<std::size_t>& at) {
  if (at.size() == 1) return std::abs(row[at[0]]);
  double sum = 0.0;
  for (std::size_t c : at) sum += row[c] * row[c];
  return std::sqrt(sum);
}

// Adds `measure` to the list in `text` unless it is there.
void AddMeasure(const std::string& measure, std::string* text) {
  if (text->empty()) {
    *text = measure;
  } else if (text->find(measure) == std::string::npos) {
    *text += " and " + measure;
  }
}

// The running state of one stream of rows (a block's, or one material's
// within it) through one trace file.
struct RowStream {
  double last_trial = -1.0, last_interval = -1.0;
  std::vector<double> last;
  double interval_removed = 0.0;
};

// Adds one trace row to `out`: its force, its speed from the previous row of
// the same interval, and the interval's removed volume.
void AddRow(std::span<const double> row, const TraceLayout& at, double fs,
            RowStream* st, Samples* out) {
  KinematicsSummary& k = out->summary;
  if (st->last.size() != at.position.size()) {
    st->last.assign(at.position.size(), 0.0);
  }
  const bool same =
      row[at.trial] == st->last_trial && row[at.interval] == st->last_interval;
  if (!same) {
    out->removed_mm3 += st->interval_removed;
    st->interval_removed = 0.0;
    ++k.intervals;
  }
  const double f = Norm(row, at.force);
  if (std::isfinite(f)) {
    out->force_n.push_back(f);
    k.max_force_n = std::max(k.max_force_n, f);
  }
  if (same) {
    // |p(i) - p(i-1)| fs: the mean speed over the sample period.
    double sum = 0.0;
    for (std::size_t c = 0; c < at.position.size(); ++c) {
      const double d = row[at.position[c]] - st->last[c];
      sum += d * d;
    }
    const double v = std::sqrt(sum) * fs;
    if (std::isfinite(v)) out->speed_mm_s.push_back(v);
  }
  if (at.removed && std::isfinite(row[*at.removed])) {
    st->interval_removed = std::max(st->interval_removed, row[*at.removed]);
  }
  st->last_trial = row[at.trial];
  st->last_interval = row[at.interval];
  for (std::size_t c = 0; c < at.position.size(); ++c) {
    st->last[c] = row[at.position[c]];
  }
  ++k.samples;
  k.duration_s += 1.0 / fs;
}

// The samples of `file` into `out` and, per material felt (the trial's
// interval_materials at the row's interval), into `materials` (in order of
// first appearance).
Status Collect(const BehFile& file, Samples* out,
               std::vector<std::pair<std::string, Samples>>* materials) {
  KinematicsSummary& k = out->summary;
  std::map<double, const results_schema::TrialRecord*> trials;
  for (const results_schema::TrialRecord& t : file.table.trials) {
    trials[static_cast<double>(t.trial_index)] = &t;
  }
  for (const PhysioFile& physio : file.physio) {
    Result<TraceLayout> layout = LayoutOf(physio);
    if (!layout.ok()) return layout.error();
    const TraceLayout& at = *layout;
    AddMeasure(at.force_measure, &k.force_measure);
    AddMeasure(at.speed_measure, &k.speed_measure);
    out->has_removed = out->has_removed && at.removed.has_value();
    RowStream stream;
    std::map<std::string, RowStream> material_streams;
    const double fs = physio.sampling_frequency_hz;
    // The material of the row's interval; empty when the trial is unknown.
    const auto material_of = [&](std::span<const double> row) {
      const auto it = trials.find(row[at.trial]);
      const double interval = row[at.interval];
      if (it == trials.end() || !(interval >= 0.0) ||
          interval >=
              static_cast<double>(it->second->interval_materials.size())) {
        return std::string();
      }
      return it->second->interval_materials[static_cast<std::size_t>(interval)];
    };
    // The material's entry of the interval being read (rows of one interval
    // are consecutive); none for rows of an unknown trial.
    double current_trial = -1.0, current_interval = -1.0;
    std::size_t current = materials->size();
    RowStream* current_stream = nullptr;
    Status s = results_schema::ForEachPhysioRow(
        physio, [&](std::span<const double> row) {
          AddRow(row, at, fs, &stream, out);
          if (row[at.trial] != current_trial ||
              row[at.interval] != current_interval) {
            current_trial = row[at.trial];
            current_interval = row[at.interval];
            const std::string material = material_of(row);
            current = static_cast<std::size_t>(
                std::find_if(materials->begin(), materials->end(),
                             [&](const auto& entry) {
                               return entry.first == material;
                             }) -
                materials->begin());
            if (material.empty()) {
              current_stream = nullptr;
              return true;
            }
            if (current == materials->size()) {
              Samples fresh;
              fresh.summary.subject = k.subject;
              fresh.summary.session = k.session;
              fresh.summary.block = k.block;
              fresh.summary.task = k.task;
              fresh.summary.material = material;
              materials->emplace_back(material, std::move(fresh));
            }
            Samples& m = (*materials)[current].second;
            AddMeasure(at.force_measure, &m.summary.force_measure);
            AddMeasure(at.speed_measure, &m.summary.speed_measure);
            m.has_removed = m.has_removed && at.removed.has_value();
            current_stream = &material_streams[material];
          }
          if (current_stream != nullptr) {
            AddRow(row, at, fs, current_stream, &(*materials)[current].second);
          }
          return true;
        });
    if (!s.ok()) return s.error();
    out->removed_mm3 += stream.interval_removed;
    for (auto& [material, st] : material_streams) {
      for (auto& entry : *materials) {
        if (entry.first == material) {
          entry.second.removed_mm3 += st.interval_removed;
        }
      }
    }
  }
  return {};
}

// Means, SD, contact share and removal rate from the collected samples.
void Finish(Samples* s) {
  KinematicsSummary& k = s->summary;
  double force_sum = 0.0, force_sum2 = 0.0, speed_sum = 0.0;
  long long contact = 0;
  for (double f : s->force_n) {
    force_sum += f;
    force_sum2 += f * f;
    contact += f > kContactForceN ? 1 : 0;
  }
  for (double v : s->speed_mm_s) speed_sum += v;
  const double n = static_cast<double>(s->force_n.size());
  if (n > 0) {
    k.mean_force_n = force_sum / n;
    k.sd_force_n =
        n > 1 ? std::sqrt(std::max(
                    0.0, (force_sum2 - force_sum * force_sum / n) / (n - 1)))
              : 0.0;
    k.contact_fraction = static_cast<double>(contact) / n;
  }
  if (!s->speed_mm_s.empty()) {
    k.mean_speed_mm_s = speed_sum / static_cast<double>(s->speed_mm_s.size());
  }
  if (s->has_removed) {
    k.removed_mm3 = s->removed_mm3;
    if (k.duration_s > 0.0) {
      k.removal_rate_mm3_per_s = s->removed_mm3 / k.duration_s;
    }
  }
}

// `from`'s samples added to a subject's samples over all its blocks.
void AddToSubject(const Samples& from, Samples* into) {
  KinematicsSummary& k = into->summary;
  const KinematicsSummary& f = from.summary;
  if (k.task.empty()) {
    k.task = f.task;
  } else if (k.task != f.task) {
    k.task = "drill+probe";
  }
  k.intervals += f.intervals;
  k.samples += f.samples;
  k.duration_s += f.duration_s;
  k.max_force_n = std::max(k.max_force_n, f.max_force_n);
  AddMeasure(f.force_measure, &k.force_measure);
  AddMeasure(f.speed_measure, &k.speed_measure);
  into->force_n.insert(into->force_n.end(), from.force_n.begin(),
                       from.force_n.end());
  into->speed_mm_s.insert(into->speed_mm_s.end(), from.speed_mm_s.begin(),
                          from.speed_mm_s.end());
  into->has_removed = into->has_removed && from.has_removed;
  into->removed_mm3 += from.removed_mm3;
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

// "sub-01 probe (probe)" or "sub-01 all blocks (probe)".
std::string Who(const KinematicsSummary& s) {
  return fmt::format("{} {}{} ({})",
                     results_schema::SessionName(s.subject, s.session),
                     s.block.empty() ? "all blocks" : s.block,
                     s.material.empty() ? "" : " " + s.material, s.task);
}

}  // namespace

Result<KinematicsReport> SummarizeKinematics(std::span<const BehFile> files,
                                             const KinematicsOptions& options) {
  if (options.bins < 1 || options.bins > 10000) {
    return Error{fmt::format("bins must be 1 to 10000, got {}", options.bins)};
  }
  if (!(options.force_max_n >= 0.0) || !(options.speed_max_mm_s >= 0.0)) {
    return Error{"histogram ranges must be 0 (automatic) or above"};
  }
  std::vector<Samples> blocks, subjects, materials;
  for (const BehFile& file : files) {
    if (file.physio.empty()) continue;
    Samples s;
    s.summary.subject = file.subject;
    s.summary.session = file.session;
    s.summary.block = file.task;
    s.summary.task = file.table.trials.front().task;
    std::vector<std::pair<std::string, Samples>> by_material;
    if (Status status = Collect(file, &s, &by_material); !status.ok()) {
      return status.error();
    }
    Finish(&s);
    for (auto& [material, m] : by_material) {
      Finish(&m);
      materials.push_back(std::move(m));
    }
    // The files come sorted by subject: a new subject starts a new summary.
    if (subjects.empty() || subjects.back().summary.subject != file.subject) {
      subjects.emplace_back();
      subjects.back().summary.subject = file.subject;
    }
    AddToSubject(s, &subjects.back());
    blocks.push_back(std::move(s));
  }
  if (blocks.empty()) {
    return Error{
        "no traces: the results have no _physio.tsv.gz files (intervals of "
        "real samples are not recorded)"};
  }
  for (Samples& s : subjects) Finish(&s);
  // Common ranges: from 0 to the largest value over the blocks of one task
  // (probing presses far less hard than drilling, and its histograms would
  // crowd into a corner of a drilling range), and over every block for the
  // subjects' summaries over all their blocks; --force-max/--speed-max fix
  // them.
  struct Range {
    double force = 0.0, speed = 0.0;
  };
  std::map<std::string, Range> by_task;
  Range all;
  for (const Samples& s : blocks) {
    Range& task = by_task[s.summary.task];
    for (double x : s.force_n) task.force = std::max(task.force, x);
    for (double x : s.speed_mm_s) task.speed = std::max(task.speed, x);
    all.force = std::max(all.force, task.force);
    all.speed = std::max(all.speed, task.speed);
  }
  const auto bin = [&](Samples& s, const Range& range) {
    s.summary.force =
        Bin(s.force_n,
            options.force_max_n > 0.0 ? options.force_max_n : range.force,
            options.bins);
    s.summary.speed =
        Bin(s.speed_mm_s,
            options.speed_max_mm_s > 0.0 ? options.speed_max_mm_s : range.speed,
            options.bins);
  };
  KinematicsReport out;
  for (Samples& s : blocks) {
    bin(s, by_task.at(s.summary.task));
    out.blocks.push_back(std::move(s.summary));
  }
  for (Samples& s : subjects) {
    bin(s, all);
    out.subjects.push_back(std::move(s.summary));
  }
  for (Samples& s : materials) {
    bin(s, by_task.at(s.summary.task));
    out.materials.push_back(std::move(s.summary));
  }
  return out;
}

std::span<const char* const> ComparedKinematicsMeasures() {
  static constexpr const char* kMeasures[] = {
      "mean_force_n",     "sd_force_n",      "max_force_n",
      "contact_fraction", "mean_speed_mm_s", "removal_rate_mm3_per_s"};
  return kMeasures;
}

namespace {

// The value of `measure` (a ComparedKinematicsMeasures name) in `k`.
std::optional<double> MeasureOf(const KinematicsSummary& k,
                                std::string_view measure) {
  if (measure == "mean_force_n") return k.mean_force_n;
  if (measure == "sd_force_n") return k.sd_force_n;
  if (measure == "max_force_n") return k.max_force_n;
  if (measure == "contact_fraction") return k.contact_fraction;
  if (measure == "mean_speed_mm_s") return k.mean_speed_mm_s;
  return k.removal_rate_mm3_per_s;
}

// Every measure of the summaries of one block (all from `summaries` whose
// block is `block`) compared between the groups.
void CompareBlock(const std::vector<KinematicsSummary>& summaries,
                  const std::string& block, const KinematicsGroupComparison& g,
                  const ParticipantGroups& groups,
                  std::vector<KinematicsComparison>* out) {
  for (const char* measure : ComparedKinematicsMeasures()) {
    KinematicsComparison c;
    c.block = block;
    c.measure = measure;
    // The subject is the unit: a subject with several sessions of the block
    // contributes the mean of its sessions' values.
    std::map<std::string, std::pair<double, int>> per_subject;
    std::vector<std::string> order;
    for (const KinematicsSummary& k : summaries) {
      if (k.block != block) continue;
      if (!groups.group_of.contains(k.subject)) continue;  // n/a: left out
      const std::optional<double> v = MeasureOf(k, measure);
      if (!v) continue;
      auto [it, added] = per_subject.try_emplace(k.subject, 0.0, 0);
      if (added) order.push_back(k.subject);
      it->second.first += *v;
      it->second.second += 1;
    }
    for (const std::string& subject : order) {
      const auto& [sum, n] = per_subject.at(subject);
      c.values[groups.group_of.at(subject) == g.groups[0] ? 0 : 1].push_back(
          sum / n);
    }
    if (c.values[0].empty() && c.values[1].empty()) continue;
    if (Result<WelchTTestResult> t = WelchTTest(c.values[0], c.values[1]);
        t.ok()) {
      c.welch = *t;
    } else {
      c.welch_note = t.error().message;
    }
    if (Result<MannWhitneyResult> u = MannWhitneyTest(c.values[0], c.values[1]);
        u.ok()) {
      c.mann_whitney = *u;
    } else {
      c.mann_whitney_note = u.error().message;
    }
    out->push_back(std::move(c));
  }
}

}  // namespace

Result<KinematicsGroupComparison> CompareKinematicsGroups(
    const KinematicsReport& report, const ParticipantGroups& groups) {
  KinematicsGroupComparison out;
  out.column = groups.column;
  out.groups = {groups.groups.at(0), groups.groups.at(1)};
  for (const KinematicsSummary& k : report.subjects) {
    const auto it = groups.group_of.find(k.subject);
    if (it != groups.group_of.end()) {
      out.subjects[it->second == out.groups[0] ? 0 : 1].push_back(k.subject);
    } else if (std::find(groups.left_out.begin(), groups.left_out.end(),
                         k.subject) != groups.left_out.end()) {
      out.left_out.push_back(k.subject);
    } else {
      return Error{fmt::format(
          "sub-{} has traces but no row in the participants file; add it "
          "(n/a in the {} column leaves it out)",
          k.subject, groups.column)};
    }
  }
  std::vector<std::string> blocks;
  for (const KinematicsSummary& k : report.blocks) {
    if (std::find(blocks.begin(), blocks.end(), k.block) == blocks.end()) {
      blocks.push_back(k.block);
    }
  }
  for (const std::string& block : blocks) {
    CompareBlock(report.blocks, block, out, groups, &out.comparisons);
  }
  CompareBlock(report.subjects, "", out, groups, &out.comparisons);
  return out;
}

LinePlot ForceHistogramPlot(const KinematicsSummary& s) {
  return HistogramPlot(
      s.force, fmt::format("{}: force, mean {:.3g} N", Who(s), s.mean_force_n),
      fmt::format("felt force, {} (N)", s.force_measure), 0);
}

LinePlot SpeedHistogramPlot(const KinematicsSummary& s) {
  return HistogramPlot(s.speed,
                       fmt::format("{}: burr speed, mean {:.3g} mm/s", Who(s),
                                   s.mean_speed_mm_s),
                       fmt::format("burr speed, {} (mm/s)", s.speed_measure),
                       1);
}

namespace {

// The group's histogram of one measure: per bin, each subject's share of its
// samples, averaged over the subjects (error bars: SEM across them).
LinePlot GroupHistogram(std::span<const KinematicsSummary> summaries,
                        bool force) {
  const KinematicsSummary& first = summaries.front();
  const Histogram& shape = force ? first.force : first.speed;
  std::vector<std::vector<double>> shares(shape.counts.size());
  double mean_of_means = 0.0;
  for (const KinematicsSummary& k : summaries) {
    const Histogram& h = force ? k.force : k.speed;
    long long total = h.outside;
    for (long long c : h.counts) total += c;
    for (std::size_t b = 0; b < h.counts.size() && b < shares.size(); ++b) {
      shares[b].push_back(total > 0 ? 100.0 * static_cast<double>(h.counts[b]) /
                                          static_cast<double>(total)
                                    : 0.0);
    }
    mean_of_means += (force ? k.mean_force_n : k.mean_speed_mm_s) /
                     static_cast<double>(summaries.size());
  }
  LinePlot plot;
  const std::string who = fmt::format(
      "{}{}{}, {} subject{}", first.block,
      first.material.empty() ? std::string() : " " + first.material,
      first.block == first.task ? std::string() : " (" + first.task + ")",
      summaries.size(), summaries.size() == 1 ? "" : "s");
  plot.title =
      force
          ? fmt::format("{}: force, mean {:.3g} N", who, mean_of_means)
          : fmt::format("{}: burr speed, mean {:.3g} mm/s", who, mean_of_means);
  plot.x_label =
      force ? fmt::format("felt force, {} (N)", first.force_measure)
            : fmt::format("burr speed, {} (mm/s)", first.speed_measure);
  plot.y_label = summaries.size() > 1
                     ? "share of samples (%), mean ± SEM over subjects"
                     : "share of samples (%)";
  Series bars{"", {}, {}, false, false, force ? 0 : 1};
  bars.bar_width = shape.width;
  for (std::size_t b = 0; b < shares.size(); ++b) {
    bars.x.push_back(shape.low + (static_cast<double>(b) + 0.5) * shape.width);
    Result<MeanSem> m = MeanAndSem(shares[b]);
    const double mean = Mean(shares[b]);
    bars.y.push_back(mean);
    bars.y_low.push_back(m.ok() ? mean - m->sem
                                : std::numeric_limits<double>::quiet_NaN());
    bars.y_high.push_back(m.ok() ? mean + m->sem
                                 : std::numeric_limits<double>::quiet_NaN());
  }
  plot.series.push_back(std::move(bars));
  return plot;
}

}  // namespace

LinePlot GroupForceHistogramPlot(std::span<const KinematicsSummary> block) {
  return GroupHistogram(block, true);
}

LinePlot GroupSpeedHistogramPlot(std::span<const KinematicsSummary> block) {
  return GroupHistogram(block, false);
}

}  // namespace burrlab::analysis
