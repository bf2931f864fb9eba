// Tests of the kinematics summary on traces written through the journal and
// the BIDS export: mean force, speed from position steps within intervals
// (never across them), removal rate, and histogram counts.
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
    rs::SessionInfo s;
    s.study = "k";
    s.protocol_path = "p.toml";
    s.protocol_sha256 = std::string(64, 'a');
    s.subject_label = "01";
    s.master_seed = 1;
    s.burrlab_version = "0";
    s.started_utc = "2024-01-01T00:00:00Z";
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

TEST_F(KinematicsTest, MeanForceSpeedAndRemovalRate) {
  Write();
  auto files = rs::ReadBidsDataset(dir_);
  ASSERT_TRUE(files.ok()) << files.error().message;
  KinematicsOptions o;
  o.bins = 4;
  o.force_max_n = 4.0;
  o.speed_max_mm_s = 3.0;
  Result<std::vector<KinematicsSummary>> k = SummarizeKinematics(*files, o);
  ASSERT_TRUE(k.ok()) << k.error().message;
  ASSERT_EQ(k->size(), 1u);
  const KinematicsSummary& s = (*k)[0];
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
}

TEST_F(KinematicsTest, NoTracesIsAnError) {
  std::vector<rs::BehFile> files(1);
  files[0].table.trials.resize(1);
  Result<std::vector<KinematicsSummary>> k = SummarizeKinematics(files, {});
  ASSERT_FALSE(k.ok());
  EXPECT_EQ(k.error().message,
            "no traces: the results have no _physio.tsv.gz files (intervals "
            "of real samples are not recorded)");
}

}  // namespace
}  // namespace burrlab::analysis
