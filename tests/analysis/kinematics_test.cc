// Tests of the kinematics summary on traces written through the journal and
// the BIDS export, in both layouts (a simulated interval's position_z_mm and
// force_n, a station's 3-D position and force components): mean force, speed
// from position steps within intervals (never across them), removal rate,
// histogram counts, and the summary of a subject over all its blocks.
#include "burrlab/analysis/kinematics.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <string>
#include <vector>

#include "burrlab/results_schema/bids_export.h"
#include "burrlab/results_schema/journal.h"

namespace burrlab::analysis {
namespace {

namespace fs = std::filesystem;
namespace rs = results_schema;

// The session of subject `label` in these tests.
rs::SessionInfo Session(const std::string& label) {
  rs::SessionInfo s;
  s.study = "k";
  s.protocol_path = "p.toml";
  s.protocol_sha256 = std::string(64, 'a');
  s.subject_label = label;
  s.master_seed = 1;
  s.burrlab_version = "0";
  s.started_utc = "2024-01-01T00:00:00Z";
  return s;
}

class KinematicsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern =
        (fs::path(::testing::TempDir()) / "burrlab_kin_XXXXXX").string();
    dir_ = mkdtemp(pattern.data());
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Two drill trials of one interval each at 100 Hz: the burr moves down
  // 0.01 mm per sample (1 mm/s), the force alternates 1 N and 3 N, and 0.5
  // mm^3 is removed per interval.
  void Write() {
    const rs::SessionInfo s = Session("01");
    auto journal = rs::Journal::Create(dir_, s);
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    for (int i = 0; i < 2; ++i) {
      rs::TrialRecord t;
      t.trial_index = i;
      t.block = "drill";
      t.method = "same_different";
      t.task = "drill";
      t.interval_materials = {"bone"};
      rs::TraceSamples trace;
      trace.trial_index = i;
      trace.sampling_frequency_hz = 100.0;
      trace.start_time_s = 10.0 * i;
      trace.columns = {"position_z_mm", "force_n", "depth_mm", "target_force_n",
                       "removed_mm3"};
      for (int r = 0; r < 50; ++r) {
        // The second trial starts 5 mm lower: no speed across intervals.
        trace.rows.push_back({2.0 - 5.0 * i - 0.01 * r, r % 2 ? 3.0 : 1.0, 0.0,
                              2.0, 0.01 * (r + 1)});
      }
      ASSERT_TRUE(journal->Append(t, {trace}).ok());
    }
    ASSERT_TRUE(rs::ExportBids(dir_, "01").ok());
  }

  fs::path dir_;
};

// Two subjects probing and drilling (one interval per trial, 100 Hz, 50
// samples): probing alternates 0.3 N with 0.7 N (sub-01) or 1.0 N (sub-02),
// drilling 1 N with 3 N.
void WriteProbeAndDrill(const fs::path& dir) {
  for (const char* subject : {"01", "02"}) {
    const rs::SessionInfo s = Session(subject);
    auto journal = rs::Journal::Create(dir, s);
    ASSERT_TRUE(journal.ok()) << journal.error().message;
    const double probe_high = std::string(subject) == "01" ? 0.7 : 1.0;
    for (int i = 0; i < 4; ++i) {
      const bool probe = i < 2;
      rs::TrialRecord t;
      t.trial_index = i;
      t.block = probe ? "probe" : "drill";
      t.method = "same_different";
      t.task = t.block;
      t.interval_materials = {"bone"};
      rs::TraceSamples trace;
      trace.trial_index = i;
      trace.sampling_frequency_hz = 100.0;
      trace.start_time_s = 10.0 * i;
      trace.columns = {"position_z_mm", "force_n"};
      for (int r = 0; r < 50; ++r) {
        trace.rows.push_back({-0.01 * r, probe ? (r % 2 ? probe_high : 0.3)
                                               : (r % 2 ? 3.0 : 1.0)});
      }
      ASSERT_TRUE(journal->Append(t, {trace}).ok());
    }
    ASSERT_TRUE(rs::ExportBids(dir, subject).ok());
  }
}

// Histogram ranges are common to the blocks of one task: probing's ends at
// its largest force, 1.0 N, not at drilling's 3 N; the subjects' summaries
// over all blocks span 3 N. The group figure of the probe block averages
// each subject's shares per bin (5 bins of 0.2 N): 0.3 N is bin 1 for both
// (50 %), 0.7 N bin 3 and 1.0 N (the upper edge) bin 4 for one subject each:
// mean 25 % with SEM sd({50, 0}) / sqrt 2 = 25 %.
TEST_F(KinematicsTest, RangesPerTaskAndTheGroupHistogram) {
  WriteProbeAndDrill(dir_);
  auto files = rs::ReadBidsDataset(dir_);
  ASSERT_TRUE(files.ok()) << files.error().message;
  KinematicsOptions o;
  o.bins = 5;
  Result<KinematicsReport> r = SummarizeKinematics(*files, o);
  ASSERT_TRUE(r.ok()) << r.error().message;
  std::vector<KinematicsSummary> probe;
  for (const KinematicsSummary& k : r->blocks) {
    const double top = k.force.low + 5 * k.force.width;
    EXPECT_DOUBLE_EQ(top, k.task == "probe" ? 1.0 : 3.0) << k.task;
    if (k.task == "probe") probe.push_back(k);
  }
  for (const KinematicsSummary& k : r->subjects) {
    EXPECT_DOUBLE_EQ(k.force.low + 5 * k.force.width, 3.0);
  }
  ASSERT_EQ(probe.size(), 2u);
  const LinePlot plot = GroupForceHistogramPlot(probe);
  ASSERT_EQ(plot.series.size(), 1u);
  const Series& bars = plot.series[0];
  EXPECT_EQ(bars.y, (std::vector<double>{0.0, 50.0, 0.0, 25.0, 25.0}));
  EXPECT_DOUBLE_EQ(bars.y_high[3] - bars.y[3], 25.0);
  EXPECT_DOUBLE_EQ(bars.y[1] - bars.y_low[1], 0.0);
  EXPECT_EQ(plot.title, "probe, 2 subjects: force, mean 0.575 N");
  EXPECT_EQ(plot.y_label, "share of samples (%), mean ± SEM over subjects");
}

// Per material felt: two trials of two intervals each, PVC then bone, the
// burr pressed with 3 N into PVC at 2 mm/s and 1 N into bone at 1 mm/s (20
// samples at 100 Hz each). The block mixes them (mean force 2 N); its
// PVC:bone summaries hold each material's intervals alone.
TEST_F(KinematicsTest, SummariesPerMaterialFelt) {
  const rs::SessionInfo s = Session("01");
  auto journal = rs::Journal::Create(dir_, s);
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  for (int i = 0; i < 2; ++i) {
    rs::TrialRecord t;
    t.trial_index = i;
    t.block = "sd";
    t.method = "same_different";
    t.task = "probe";
    t.interval_materials = {"pvc", "bone"};
    std::vector<rs::TraceSamples> traces;
    for (int interval = 0; interval < 2; ++interval) {
      rs::TraceSamples trace;
      trace.trial_index = i;
      trace.interval_index = interval;
      trace.sampling_frequency_hz = 100.0;
      trace.start_time_s = 10.0 * i + 4.0 * interval;
      trace.columns = {"position_z_mm", "force_n"};
      const double step_mm = interval == 0 ? 0.02 : 0.01;
      for (int r = 0; r < 20; ++r) {
        trace.rows.push_back({-step_mm * r, interval == 0 ? 3.0 : 1.0});
      }
      traces.push_back(trace);
    }
    ASSERT_TRUE(journal->Append(t, traces).ok());
  }
  ASSERT_TRUE(rs::ExportBids(dir_, "01").ok());
  auto files = rs::ReadBidsDataset(dir_);
  ASSERT_TRUE(files.ok()) << files.error().message;
  Result<KinematicsReport> r = SummarizeKinematics(*files, {});
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->blocks.size(), 1u);
  EXPECT_DOUBLE_EQ(r->blocks[0].mean_force_n, 2.0);
  EXPECT_EQ(r->blocks[0].intervals, 4);
  ASSERT_EQ(r->materials.size(), 2u);
  const KinematicsSummary& pvc = r->materials[0];
  const KinematicsSummary& bone = r->materials[1];
  EXPECT_EQ(pvc.material, "pvc");
  EXPECT_EQ(pvc.block, "sd");
  EXPECT_EQ(bone.material, "bone");
  EXPECT_EQ(pvc.intervals, 2);
  EXPECT_EQ(pvc.samples, 40);
  EXPECT_DOUBLE_EQ(pvc.mean_force_n, 3.0);
  EXPECT_DOUBLE_EQ(bone.mean_force_n, 1.0);
  EXPECT_NEAR(pvc.mean_speed_mm_s, 2.0, 1e-9);
  EXPECT_NEAR(bone.mean_speed_mm_s, 1.0, 1e-9);
  // The figures name the material.
  EXPECT_EQ(ForceHistogramPlot(pvc).title,
            "sub-01 sd pvc (probe): force, mean 3 N");
}

TEST_F(KinematicsTest, MeanForceSpeedAndRemovalRate) {
  Write();
  auto files = rs::ReadBidsDataset(dir_);
  ASSERT_TRUE(files.ok()) << files.error().message;
  KinematicsOptions o;
  o.bins = 4;
  o.force_max_n = 4.0;
  o.speed_max_mm_s = 3.0;
  Result<KinematicsReport> k = SummarizeKinematics(*files, o);
  ASSERT_TRUE(k.ok()) << k.error().message;
  ASSERT_EQ(k->blocks.size(), 1u);
  const KinematicsSummary& s = k->blocks[0];
  EXPECT_EQ(s.force_measure, "force_n");
  EXPECT_EQ(s.speed_measure, "|dz/dt| of position_z_mm");
  EXPECT_EQ(s.intervals, 2);
  EXPECT_EQ(s.samples, 100);
  EXPECT_NEAR(s.duration_s, 1.0, 1e-12);
  EXPECT_NEAR(s.mean_force_n, 2.0, 1e-12);
  EXPECT_NEAR(s.max_force_n, 3.0, 1e-12);
  EXPECT_NEAR(s.mean_speed_mm_s, 1.0, 1e-9);
  ASSERT_TRUE(s.removed_mm3.has_value());
  EXPECT_NEAR(*s.removed_mm3, 1.0, 1e-12);
  EXPECT_NEAR(*s.removal_rate_mm3_per_s, 1.0, 1e-12);
  // Force bins of 1 N: 50 samples at 1 N (bin 1), 50 at 3 N (bin 3).
  EXPECT_EQ(s.force.counts, (std::vector<long long>{0, 50, 0, 50}));
  // Speed bins of 0.75 mm/s: 98 steps of 1 mm/s (49 per interval) in bin 1.
  EXPECT_EQ(s.speed.counts, (std::vector<long long>{0, 98, 0, 0}));
  EXPECT_TRUE(RenderPlot(ForceHistogramPlot(s)).ok());
  EXPECT_TRUE(RenderPlot(SpeedHistogramPlot(s)).ok());
  // One block: the subject's summary over all blocks is the same.
  ASSERT_EQ(k->subjects.size(), 1u);
  const KinematicsSummary& all = k->subjects[0];
  EXPECT_EQ(all.block, "");
  EXPECT_EQ(all.task, "drill");
  EXPECT_EQ(all.samples, s.samples);
  EXPECT_EQ(all.mean_force_n, s.mean_force_n);
  EXPECT_EQ(all.mean_speed_mm_s, s.mean_speed_mm_s);
  EXPECT_EQ(all.removal_rate_mm3_per_s, s.removal_rate_mm3_per_s);
  EXPECT_EQ(all.force.counts, s.force.counts);
  EXPECT_EQ(all.speed.counts, s.speed.counts);
}

TEST_F(KinematicsTest, NoTracesIsAnError) {
  std::vector<rs::BehFile> files(1);
  files[0].table.trials.resize(1);
  Result<KinematicsReport> k = SummarizeKinematics(files, {});
  ASSERT_FALSE(k.ok());
  EXPECT_EQ(k.error().message,
            "no traces: the results have no _physio.tsv.gz files (intervals "
            "of real samples are not recorded)");
}

// A station's traces: 3-D position and force components at 200 Hz. Truth
// computed by hand, independently of the code: a burr moving on a straight
// line at (3, 4, 12) mm/s has the speed sqrt(9 + 16 + 144) = 13 mm/s (its
// vertical speed alone is 12 mm/s), and the force (0.6, 0.8, 2.4) N has
// |F| = 2.6 N. Subject 01 presses in block "press" (two intervals of one
// trial, the second with no force) and drills in block "cut" (one interval,
// its burr still); the subject's summary pools both blocks.
TEST_F(KinematicsTest, StationTracesGiveSpeedAndForceIn3D) {
  rs::SessionInfo info;
  info.study = "k";
  info.protocol_path = "p.toml";
  info.protocol_sha256 = std::string(64, 'a');
  info.subject_label = "01";
  info.master_seed = 1;
  info.burrlab_version = "0";
  info.started_utc = "2024-01-01T00:00:00Z";
  auto journal = rs::Journal::Create(dir_, info);
  ASSERT_TRUE(journal.ok()) << journal.error().message;
  const auto trace = [](int trial, int interval, double x0, double force) {
    rs::TraceSamples t;
    t.trial_index = trial;
    t.interval_index = interval;
    t.sampling_frequency_hz = 200.0;
    t.start_time_s = 10.0 * trial + interval;
    t.columns = {"position_x_mm", "position_y_mm", "position_z_mm",
                 "force_x_n",     "force_y_n",     "force_z_n"};
    for (int r = 0; r < 20; ++r) {
      const double s = r / 200.0;  // time into the interval
      t.rows.push_back({x0 + 3.0 * s, 4.0 * s, 5.0 - 12.0 * s, 0.6 * force,
                        0.8 * force, 2.4 * force});
    }
    return t;
  };
  rs::TrialRecord press;
  press.trial_index = 0;
  press.block = "press";
  press.method = "two_interval";
  press.task = "probe";
  press.interval_materials = {"a", "b"};
  // The second interval starts 40 mm away: no speed across intervals.
  ASSERT_TRUE(
      journal->Append(press, {trace(0, 0, 0.0, 1.0), trace(0, 1, 40.0, 0.0)})
          .ok());
  rs::TrialRecord cut = press;
  cut.trial_index = 1;
  cut.block = "cut";
  cut.task = "drill";
  cut.interval_materials = {"a"};
  rs::TraceSamples still = trace(1, 0, 0.0, 1.0);
  for (std::vector<double>& row : still.rows) {
    row[0] = 1.0;
    row[1] = 2.0;
    row[2] = 3.0;
  }
  ASSERT_TRUE(journal->Append(cut, {still}).ok());
  ASSERT_TRUE(rs::ExportBids(dir_, "01").ok());

  auto files = rs::ReadBidsDataset(dir_);
  ASSERT_TRUE(files.ok()) << files.error().message;
  KinematicsOptions o;
  o.bins = 4;
  o.force_max_n = 4.0;    // bins of 1 N
  o.speed_max_mm_s = 20;  // bins of 5 mm/s
  Result<KinematicsReport> k = SummarizeKinematics(*files, o);
  ASSERT_TRUE(k.ok()) << k.error().message;
  ASSERT_EQ(k->blocks.size(), 2u);
  const KinematicsSummary& p = k->blocks[0];
  EXPECT_EQ(p.block, "press");
  EXPECT_EQ(p.force_measure, "|F| of force_x_n, force_y_n, force_z_n");
  EXPECT_EQ(p.speed_measure,
            "|dp/dt| of position_x_mm, position_y_mm, position_z_mm");
  EXPECT_EQ(p.intervals, 2);
  EXPECT_EQ(p.samples, 40);
  EXPECT_NEAR(p.mean_speed_mm_s, 13.0, 1e-9);
  EXPECT_NEAR(p.max_force_n, 2.6, 1e-12);
  EXPECT_NEAR(p.mean_force_n, 1.3, 1e-12);  // 20 samples of 2.6 N, 20 of 0
  EXPECT_NEAR(p.contact_fraction, 0.5, 1e-12);
  EXPECT_FALSE(p.removed_mm3.has_value());
  EXPECT_EQ(p.force.counts, (std::vector<long long>{20, 0, 20, 0}));
  // 19 steps per interval, all at 13 mm/s (bin [10, 15)).
  EXPECT_EQ(p.speed.counts, (std::vector<long long>{0, 0, 38, 0}));

  const KinematicsSummary& c = k->blocks[1];
  EXPECT_EQ(c.block, "cut");
  EXPECT_EQ(c.mean_speed_mm_s, 0.0);
  EXPECT_NEAR(c.mean_force_n, 2.6, 1e-12);

  // The subject over both blocks: 60 force samples, 57 speed steps.
  ASSERT_EQ(k->subjects.size(), 1u);
  const KinematicsSummary& all = k->subjects[0];
  EXPECT_EQ(all.block, "");
  EXPECT_EQ(all.task, "drill+probe");
  EXPECT_EQ(all.intervals, 3);
  EXPECT_EQ(all.samples, 60);
  EXPECT_NEAR(all.duration_s, 0.3, 1e-12);
  EXPECT_NEAR(all.mean_force_n, 2.6 * 40 / 60, 1e-12);
  EXPECT_NEAR(all.mean_speed_mm_s, 13.0 * 38 / 57, 1e-9);
  EXPECT_EQ(all.force.counts, (std::vector<long long>{20, 0, 40, 0}));
  EXPECT_EQ(all.speed.counts, (std::vector<long long>{19, 0, 38, 0}));
  EXPECT_TRUE(RenderPlot(ForceHistogramPlot(all)).ok());
  EXPECT_EQ(ForceHistogramPlot(all).title,
            "sub-01 all blocks (drill+probe): force, mean 1.73 N");
  EXPECT_EQ(SpeedHistogramPlot(p).x_label,
            "burr speed, |dp/dt| of position_x_mm, position_y_mm, "
            "position_z_mm (mm/s)");
}

TEST_F(KinematicsTest, TracesWithoutPositionOrForceAreAnError) {
  std::vector<rs::BehFile> files(1);
  files[0].table.trials.resize(1);
  files[0].physio.resize(1);
  files[0].physio[0].data_path = "sub-01_task-a_physio.tsv.gz";
  files[0].physio[0].columns = {"trial_index",   "interval_index", "time",
                                "position_x_mm", "position_z_mm",  "force_x_n",
                                "force_y_n",     "force_z_n"};
  Result<KinematicsReport> k = SummarizeKinematics(files, {});
  ASSERT_FALSE(k.ok());
  EXPECT_EQ(k.error().message,
            "sub-01_task-a_physio.tsv.gz: the traces need the columns "
            "trial_index, interval_index, a position (position_x_mm, "
            "position_y_mm and position_z_mm, or position_z_mm alone) and a "
            "force (force_x_n, force_y_n and force_z_n, or force_n); they "
            "have trial_index, interval_index, time, position_x_mm, "
            "position_z_mm, force_x_n, force_y_n, force_z_n");
}

// Experts' and trainees' mean forces compared per block and over all
// blocks. Truth: R's t.test(x, y) and wilcox.test(x, y) on the same values
// (the first case of fixtures/r/two_sample_tests.csv, printed by
// make_two_group_fixtures.R).
TEST(KinematicsGroups, ComparesEachMeasureBetweenTheGroups) {
  const std::vector<double> expert = {0.71, 1.28, 0.93, 1.05},
                            trainee = {0.82, 1.1, 0.97, 0.88, 1.02};
  ParticipantGroups groups;
  groups.column = "group";
  groups.groups = {"expert", "trainee"};
  KinematicsReport report;
  for (int i = 0; i < 10; ++i) {
    KinematicsSummary k;
    k.subject = (i < 9 ? "0" : "") + std::to_string(i + 1);
    // Experts are subjects 01, 03, 05, 07; trainees 02, 04, 06, 08, 09;
    // subject 10's group is n/a.
    if (i == 9) {
      groups.left_out.push_back(k.subject);
    } else {
      const bool is_expert = i % 2 == 0 && i < 8;
      groups.group_of[k.subject] = is_expert ? "expert" : "trainee";
      k.mean_force_n =
          is_expert ? expert[static_cast<std::size_t>(i / 2)]
                    : trainee[i < 8 ? static_cast<std::size_t>(i / 2) : 4u];
    }
    k.mean_speed_mm_s = 10.0 + i;
    k.block = "drill";
    report.blocks.push_back(k);
    k.block = "";
    report.subjects.push_back(k);
  }
  Result<KinematicsGroupComparison> c = CompareKinematicsGroups(report, groups);
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c->groups, (std::array<std::string, 2>{"expert", "trainee"}));
  EXPECT_EQ(c->subjects[0], (std::vector<std::string>{"01", "03", "05", "07"}));
  EXPECT_EQ(c->subjects[1],
            (std::vector<std::string>{"02", "04", "06", "08", "09"}));
  EXPECT_EQ(c->left_out, (std::vector<std::string>{"10"}));
  // Five measures per level (no removal rates), the block then all blocks.
  ASSERT_EQ(c->comparisons.size(), 10u);
  for (std::size_t level = 0; level < 2; ++level) {
    const KinematicsComparison& force = c->comparisons[5 * level];
    EXPECT_EQ(force.block, level == 0 ? "drill" : "");
    EXPECT_EQ(force.measure, "mean_force_n");
    EXPECT_EQ(force.values[0], expert);
    EXPECT_EQ(force.values[1], trainee);
    ASSERT_TRUE(force.welch.has_value()) << force.welch_note;
    EXPECT_NEAR(force.welch->t, 0.26774303495989027, 1e-6);
    EXPECT_NEAR(force.welch->df, 4.0445604740238084, 1e-6);
    EXPECT_NEAR(force.welch->p_two_sided, 0.8019976021210693, 1e-6);
    ASSERT_TRUE(force.mann_whitney.has_value());
    EXPECT_EQ(force.mann_whitney->w, 11.0);
    EXPECT_NEAR(force.mann_whitney->p_two_sided, 0.90476190476190466, 1e-6);
    EXPECT_TRUE(force.mann_whitney->exact);
    // Every subject's SD is 0: no t, the reason kept.
    const KinematicsComparison& sd = c->comparisons[5 * level + 1];
    EXPECT_EQ(sd.measure, "sd_force_n");
    EXPECT_FALSE(sd.welch.has_value());
    EXPECT_EQ(sd.welch_note,
              "both groups are constant (0 and 0): the t statistic is "
              "undefined");
    EXPECT_EQ(sd.mann_whitney_note,
              "all 9 values are equal (0): the rank-sum test is undefined");
    EXPECT_EQ(c->comparisons[5 * level + 4].measure, "mean_speed_mm_s");
  }

  groups.left_out.clear();
  EXPECT_EQ(CompareKinematicsGroups(report, groups).error().message,
            "sub-10 has traces but no row in the participants file; add it "
            "(n/a in the group column leaves it out)");
}

}  // namespace
}  // namespace burrlab::analysis
