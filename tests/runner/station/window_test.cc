// The subject window for real: a GLFW window with an OpenGL 3.3 core context
// (under Xvfb in ctest), a two-trial protocol driven by scripted input, the
// mouse device moving the burr through the 1 kHz loop body into the simulator,
// the eroding block shown from loop snapshots. Each trial phase is saved as a
// PNG (build/.../station_screenshots/) and compared with the committed golden
// image with a tolerance; so is each pacing phase (instructions, the gap
// between intervals, feedback, the gap after the answer, a rest break).
// BURRLAB_UPDATE_GOLDEN=1 rewrites the golden images.
#include "station/window.h"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include "burrlab/protocols/engine.h"
#include "burrlab/protocols/protocol.h"
#include "burrlab/sim/phantoms.h"
#include "burrlab/sim/step.h"
#include "devices/haptic_loop.h"
#include "devices/mouse_device.h"
#include "devices/sim_force_source.h"
#include "station/station_controller.h"
#include "station/surface_snapshot.h"

namespace burrlab::runner {
namespace {

namespace fs = std::filesystem;

constexpr const char* kProtocol = R"(format = "burrlab-protocol/1"

[study]
name = "Station window check"

[materials.bone]
builtin = "human_temporal_bone"

[materials.pvc]
builtin = "pvc_k70"

[[blocks]]
name = "drill2afc"
method = "two_interval"
design = "2afc"
task = "drill"
standard = "bone"
comparison = "pvc"
question = "Which interval was easier to drill?"
trials = 2
interval_s = 2
)";

// Two practice trials with feedback and a gap between intervals, then a
// scored block after a rest break; instructions for the study and each
// block.
constexpr const char* kPacedProtocol = R"(format = "burrlab-protocol/1"

[study]
name = "Station pacing check"
instructions = """
In each trial you drill into the block twice, once in each interval. After
the second interval, say which interval was easier to drill."""
breaks_between_blocks = true

[materials.bone]
builtin = "human_temporal_bone"

[materials.pvc]
builtin = "pvc_k70"

[[blocks]]
name = "practice"
method = "two_interval"
design = "2afc"
task = "drill"
standard = "bone"
comparison = "pvc"
question = "Which interval was easier to drill?"
trials = 2
interval_s = 2
practice = true
isi_s = 1
iti_s = 1.5
instructions = "Two practice trials first: after each answer you will see whether it was right."

[[blocks]]
name = "scored"
method = "two_interval"
design = "2afc"
task = "drill"
standard = "bone"
comparison = "pvc"
question = "Which interval was easier to drill?"
trials = 2
interval_s = 2
instructions = "Now the scored trials, without feedback."
)";

// Time stands still unless the test moves it.
class FakeClock final : public LoopClock {
 public:
  std::int64_t NowNs() noexcept override { return now_ns; }
  void SleepUntilNs(std::int64_t time_ns) noexcept override {
    if (time_ns > now_ns) now_ns = time_ns;
  }
  std::int64_t now_ns = 0;
};

// Differences between a screenshot and its golden image.
struct ImageDiff {
  double mean_abs = 0.0;   // per channel, 0-255
  double differing = 0.0;  // fraction of pixels off by more than 48
  std::string error;       // set when the images cannot be compared
};

ImageDiff Compare(const std::string& actual, const std::string& golden) {
  ImageDiff d;
  int aw = 0, ah = 0, an = 0, gw = 0, gh = 0, gn = 0;
  unsigned char* a = stbi_load(actual.c_str(), &aw, &ah, &an, 3);
  unsigned char* g = stbi_load(golden.c_str(), &gw, &gh, &gn, 3);
  if (a == nullptr || g == nullptr) {
    d.error = "cannot read " + (a == nullptr ? actual : golden);
  } else if (aw != gw || ah != gh) {
    d.error = "size differs";
  } else {
    const std::size_t pixels = static_cast<std::size_t>(aw) * ah;
    double sum = 0.0;
    std::size_t off = 0;
    for (std::size_t p = 0; p < pixels; ++p) {
      int worst = 0;
      for (int c = 0; c < 3; ++c) {
        const int diff = std::abs(a[p * 3 + c] - g[p * 3 + c]);
        sum += diff;
        worst = std::max(worst, diff);
      }
      if (worst > 48) ++off;
    }
    d.mean_abs = sum / (3.0 * static_cast<double>(pixels));
    d.differing = static_cast<double>(off) / static_cast<double>(pixels);
  }
  stbi_image_free(a);
  stbi_image_free(g);
  return d;
}

// The station with its parts: protocol engine, controller, mouse device, loop
// body over the simulator, window.
class StationWindowTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::getenv("BURRLAB_NO_XVFB") != nullptr) {
      GTEST_SKIP() << "xvfb-run was not found when the build was configured: "
                      "the window tests need it (Debian package xvfb)";
    }
    if (std::getenv("DISPLAY") == nullptr) {
      GTEST_SKIP() << "no DISPLAY: run this test through ctest (it wraps it "
                      "in xvfb-run)";
    }
    protocols::ParseOutcome parsed =
        protocols::ParseProtocol("station.toml", kProtocol);
    ASSERT_TRUE(parsed.protocol.has_value());
    protocol_ = std::move(*parsed.protocol);
    shots_ = fs::path(BURRLAB_BINARY_DIR) / "station_screenshots";
    fs::create_directories(shots_);
  }

  // A fresh block of `material` (solid below z = 8 mm, 19.2 mm square).
  void NewBlock(const sim::Material& material) {
    sim::PhantomGrid grid;
    grid.nx = grid.ny = 64;
    grid.nz = 40;
    model_ = sim::Model{};
    model_.material = material;
    model_.radius_mm = 2.0;
    state_.emplace(
        sim::State::Create(
            model_,
            sim::MakeHalfSpace(grid, {9.6, 9.6, 8.0}, {0.0, 0.0, 1.0}).value(),
            7)
            .value());
    source_.emplace(model_, &*state_, glm::dvec3(9.6, 9.6, 4.5),
                    glm::dvec3(0.0, 0.0, 600.0));
    loop_.emplace(&mouse_, &*source_, &clock_);
    snapshot_ = SurfaceSnapshot{};
    snapshot_.surface = HeightMap::For(state_->volume());
    UpdateHeightMap(state_->volume(), {}, -1.0, &snapshot_.surface);
    snapshot_.burr_radius_mm = model_.radius_mm;
    exchange_.emplace(snapshot_);
    exchange_->Publish(snapshot_);  // the untouched block
    tick_ = 0;
  }

  // Runs the loop body for `seconds` of virtual time with the cursor held,
  // publishing a snapshot every 33 ticks (the window's ~30 Hz).
  void Drill(double seconds, const glm::dvec2& cursor, double wheel) {
    mouse_.SetCursor(cursor, wheel, false);
    const auto ticks = static_cast<std::int64_t>(std::llround(seconds * 1000));
    for (std::int64_t k = 0; k < ticks; ++k, ++tick_) {
      clock_.now_ns = tick_ * 1'000'000;
      const DeviceStatus s = loop_->Tick(clock_.now_ns);
      ASSERT_TRUE(s.usable()) << s.reason;
      if (tick_ % 33 == 0) {
        glm::dvec3 device_mm;
        (void)mouse_.ReadPosition(&device_mm);
        snapshot_.burr_mm = device_mm + glm::dvec3(9.6, 9.6, 4.5);
        UpdateHeightMap(state_->volume(), snapshot_.burr_mm,
                        model_.radius_mm + 0.6, &snapshot_.surface);
        snapshot_.force_n = loop_->last_force_n();
        snapshot_.tick = tick_;
        exchange_->Publish(snapshot_);
      }
    }
    controller_->SetForce(mouse_.force_magnitude_n());
    controller_->SetLoop(
        loop_->counters().ticks, 0.0, 0.0,
        loop_->counters().missed_deadlines + loop_->counters().non_finite);
  }

  // Draws the frame, saves it as `name`.png and compares it with the golden.
  void Shoot(const std::string& name) {
    if (const SurfaceSnapshot* s = exchange_->TakeNewest()) {
      window_->SetSurface(*s);
    }
    (void)window_->Draw(controller_->frame());
    const std::string path = (shots_ / (name + ".png")).string();
    ASSERT_TRUE(window_->SaveScreenshot(path).ok());
    window_->Present();
    const fs::path golden = fs::path(BURRLAB_SOURCE_DIR) /
                            "tests/runner/station/golden" / (name + ".png");
    if (std::getenv("BURRLAB_UPDATE_GOLDEN") != nullptr) {
      fs::copy_file(path, golden, fs::copy_options::overwrite_existing);
      return;
    }
    const ImageDiff d = Compare(path, golden.string());
    ASSERT_TRUE(d.error.empty()) << name << ": " << d.error;
    EXPECT_LT(d.mean_abs, 1.5) << name << " differs from " << golden;
    EXPECT_LT(d.differing, 0.005) << name << " differs from " << golden;
    std::printf("%s: mean |diff| %.3f per channel, %.4f%% of pixels off\n",
                name.c_str(), d.mean_abs, 100.0 * d.differing);
  }

  protocols::Protocol protocol_;
  fs::path shots_;
  FakeClock clock_;
  MouseDevice mouse_{MouseDeviceOptions{
      Workspace{glm::dvec3(-9.6, -9.6, -6.0), glm::dvec3(9.6, 9.6, 6.0)}, 0.5,
      3.0, 8.0}};
  sim::Model model_;
  std::optional<sim::State> state_;
  std::optional<SimForceSource> source_;
  std::optional<HapticLoop> loop_;
  SurfaceSnapshot snapshot_;
  std::optional<SnapshotExchange> exchange_;
  std::optional<StationController> controller_;
  std::unique_ptr<StationWindow> window_;
  std::int64_t tick_ = 0;
};

TEST_F(StationWindowTest, ScreenshotsOfEachTrialPhaseMatchTheGoldenImages) {
  Result<std::unique_ptr<StationWindow>> opened = StationWindow::Open({});
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  window_ = std::move(opened.value());
  Result<protocols::Engine> engine =
      protocols::Engine::Create(protocol_, 0, 11);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  controller_.emplace(2, "mouse", 8.0);  // the protocol's two trials

  // Trial 1: ready, both intervals half way, the question, an answer by key.
  protocols::TrialSpec trial = engine->current();
  controller_->BeginTrial(trial, 0);
  NewBlock(trial.intervals[0].material->material);
  Shoot("01_trial1_ready");
  double now_s = 0.0;
  ASSERT_FALSE(controller_->OnInput("SPACE", now_s).has_value());
  EXPECT_EQ(controller_->phase(), StationPhase::kInterval);
  Drill(1.0, {0.5, 0.5}, -6.0);  // burr 3 mm lower than the hover height
  Drill(0.2, {0.7, 0.3}, 0.0);   // lifted aside: the pit shows
  now_s += 1.2;
  controller_->Advance(now_s);
  EXPECT_EQ(controller_->frame().subject.interval_label, "Interval 1 of 2");
  EXPECT_NEAR(controller_->frame().subject.time_left_s, 0.8, 1e-9);
  Shoot("02_trial1_interval1");

  now_s += 0.8;
  controller_->Advance(now_s);
  EXPECT_EQ(controller_->frame().subject.interval_label, "Interval 2 of 2");
  NewBlock(trial.intervals[1].material->material);
  Drill(1.5, {0.4, 0.45}, -6.0);
  now_s += 1.5;
  controller_->Advance(now_s);
  Shoot("03_trial1_interval2");

  now_s += 0.5;
  controller_->Advance(now_s);
  ASSERT_EQ(controller_->phase(), StationPhase::kResponse);
  Shoot("04_trial1_response");
  ASSERT_FALSE(controller_->OnInput("7", now_s + 0.3).has_value());
  std::optional<protocols::Response> answer =
      controller_->OnInput("2", now_s + 0.84);
  ASSERT_TRUE(answer.has_value());
  EXPECT_EQ(answer->answer, "2");
  EXPECT_NEAR(*answer->response_time_s, 0.84, 1e-9);
  ASSERT_TRUE(engine->Respond(*answer).ok());

  // Trial 2: the device goes away in the first interval; the trial is
  // aborted and the session paused with the reason on both views.
  trial = engine->current();
  controller_->BeginTrial(trial, 1);
  NewBlock(trial.intervals[0].material->material);
  now_s += 2.0;
  (void)controller_->OnInput("SPACE", now_s);
  Drill(0.5, {0.6, 0.55}, -4.0);
  controller_->SetDeviceState("unplugged: the device was disconnected");
  controller_->Pause("the device was disconnected; reconnect it to go on");
  EXPECT_TRUE(controller_->trial_aborted());
  EXPECT_EQ(controller_->frame().experimenter.last_event,
            "trial 2 aborted: the device was disconnected; reconnect it to "
            "go on");
  Shoot("05_trial2_paused");

  // Resumed: the trial runs again from its start and is answered.
  controller_->SetDeviceState("ok");
  controller_->Resume();
  EXPECT_EQ(controller_->phase(), StationPhase::kReady);
  (void)controller_->OnInput("SPACE", now_s);
  now_s += 4.0;
  controller_->Advance(now_s);
  answer = controller_->OnInput("1", now_s + 0.5);
  ASSERT_TRUE(answer.has_value());
  ASSERT_TRUE(engine->Respond(*answer).ok());
  ASSERT_TRUE(engine->finished());
  controller_->Finish();
  Shoot("06_finished");
}

// The pacing phases of a session (§13.5.1: familiarization before the scored
// trials) as the subject sees them: the study's and a block's instructions,
// the blank gap between intervals, feedback, the gap after the answer and a
// rest break, each over the block view.
TEST_F(StationWindowTest, ScreenshotsOfThePacingPhasesMatchTheGoldenImages) {
  Result<std::unique_ptr<StationWindow>> opened = StationWindow::Open({});
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  window_ = std::move(opened.value());
  protocols::ParseOutcome parsed =
      protocols::ParseProtocol("paced.toml", kPacedProtocol);
  ASSERT_TRUE(parsed.protocol.has_value());
  protocol_ = std::move(*parsed.protocol);
  Result<protocols::Engine> engine =
      protocols::Engine::Create(protocol_, 0, 11);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  controller_.emplace(4, "mouse", 8.0);

  protocols::TrialSpec trial = engine->current();
  controller_->BeginTrial(trial, 0);
  NewBlock(trial.intervals[0].material->material);
  ASSERT_EQ(controller_->screen(), "instructions_study");
  Shoot("07_instructions_study");
  (void)controller_->OnInput("SPACE", 0.0);
  ASSERT_EQ(controller_->screen(), "instructions_block");
  Shoot("08_instructions_block");
  (void)controller_->OnInput("SPACE", 0.0);
  ASSERT_EQ(controller_->phase(), StationPhase::kReady);
  double now_s = 1.0;
  (void)controller_->OnInput("SPACE", now_s);
  Drill(1.0, {0.5, 0.5}, -6.0);
  now_s += 2.25;  // the 2 s interval is over; 0.75 s of the 1 s gap left
  controller_->Advance(now_s);
  ASSERT_EQ(controller_->phase(), StationPhase::kIsi);
  Shoot("09_isi");
  now_s += 0.75;
  controller_->Advance(now_s);
  ASSERT_EQ(controller_->phase(), StationPhase::kInterval);
  now_s += 2.0;
  controller_->Advance(now_s);
  ASSERT_EQ(controller_->phase(), StationPhase::kResponse);
  std::optional<protocols::Response> answer =
      controller_->OnInput(trial.correct_answer, now_s + 0.5);
  ASSERT_TRUE(answer.has_value());
  Result<protocols::Outcome> outcome = engine->Respond(*answer);
  ASSERT_TRUE(outcome.ok()) << outcome.error().message;
  controller_->BeginAfterAnswer(outcome->correct, now_s + 0.5);
  ASSERT_EQ(controller_->phase(), StationPhase::kFeedback);
  Shoot("10_feedback_correct");
  controller_->Advance(now_s + 1.6);
  ASSERT_EQ(controller_->phase(), StationPhase::kIti);
  Shoot("11_iti");

  // The second practice trial answered wrongly.
  trial = engine->current();
  controller_->BeginTrial(trial, 1);
  ASSERT_EQ(controller_->phase(), StationPhase::kReady);
  now_s += 10.0;
  (void)controller_->OnInput("SPACE", now_s);
  now_s += 5.0;
  controller_->Advance(now_s);
  ASSERT_EQ(controller_->phase(), StationPhase::kResponse);
  answer = controller_->OnInput(trial.correct_answer == "1" ? "2" : "1",
                                now_s + 0.8);
  ASSERT_TRUE(answer.has_value());
  outcome = engine->Respond(*answer);
  ASSERT_TRUE(outcome.ok()) << outcome.error().message;
  controller_->BeginAfterAnswer(outcome->correct, now_s + 0.8);
  EXPECT_EQ(controller_->frame().subject.panel_heading, "Wrong");
  Shoot("12_feedback_wrong");

  // The scored block starts with a rest break.
  trial = engine->current();
  ASSERT_TRUE(trial.break_before);
  controller_->BeginTrial(trial, 2);
  ASSERT_EQ(controller_->phase(), StationPhase::kBreak);
  Shoot("13_break");
}

// Drilling bone, then a comparison whose erosion rate the subject steps.
constexpr const char* kAdjustmentProtocol = R"(format = "burrlab-protocol/1"

[study]
name = "Station adjustment view"

[materials.bone]
builtin = "human_temporal_bone"

[axes.alpha_ratio]
kind = "ratio"
parameter = "alpha_per_s"
reference = "bone"

[[blocks]]
name = "adjust"
method = "adjustment"
task = "drill"
axis = "alpha_ratio"
standard_level = 1.0
start_level = 2.0
step = 0.05
step_scale = "log10"
max_steps = 40
interval_s = 2
question = "Step the second block until it drills like the first."
)";

// The method of adjustment as the subject sees it: the question with its
// three keys, and the comparison felt again after a step; the experimenter
// sees the count of trials done (an adaptive session's length is not known
// ahead).
TEST_F(StationWindowTest, ScreenshotsOfAnAdjustmentMatchTheGoldenImages) {
  Result<std::unique_ptr<StationWindow>> opened = StationWindow::Open({});
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  window_ = std::move(opened.value());
  protocols::ParseOutcome parsed =
      protocols::ParseProtocol("adjust.toml", kAdjustmentProtocol);
  ASSERT_TRUE(parsed.protocol.has_value());
  protocol_ = std::move(*parsed.protocol);
  Result<protocols::Engine> engine =
      protocols::Engine::Create(protocol_, 0, 11);
  ASSERT_TRUE(engine.ok()) << engine.error().message;
  controller_.emplace(0, "mouse", 8.0);

  const protocols::TrialSpec trial = engine->current();
  controller_->BeginTrial(trial, 0);
  NewBlock(trial.intervals[0].material->material);
  double now_s = 0.0;
  (void)controller_->OnInput("SPACE", now_s);
  Drill(1.0, {0.5, 0.5}, -6.0);
  now_s += 2.0;
  controller_->Advance(now_s);
  NewBlock(trial.intervals[1].material->material);
  Drill(1.0, {0.45, 0.5}, -6.0);
  now_s += 2.0;
  controller_->Advance(now_s);
  ASSERT_EQ(controller_->phase(), StationPhase::kResponse);
  Shoot("14_adjustment_question");

  (void)controller_->OnInput("DOWN", now_s + 1.0);
  ASSERT_EQ(controller_->TakeAdjustmentStep(), std::optional<int>(-1));
  Result<double> level = engine->PreviewAdjustment("-");
  ASSERT_TRUE(level.ok()) << level.error().message;
  EXPECT_NEAR(*level, 2.0 * std::pow(10.0, -0.05), 1e-9);
  Result<stimuli::MaterialSet> set = engine->MaterialAt(*level);
  ASSERT_TRUE(set.ok()) << set.error().message;
  protocols::PlannedInterval comparison = trial.intervals[1];
  comparison.material = *set;
  comparison.level = *level;
  controller_->PresentAdjustedComparison(comparison, '-', now_s + 1.0);
  NewBlock(set->material);
  Drill(1.2, {0.55, 0.45}, -6.0);
  controller_->Advance(now_s + 2.2);
  ASSERT_EQ(controller_->screen(), "interval3");
  Shoot("15_adjustment_step");
}

TEST(StationWindow, TheGoldenComparisonSeesAnotherPhase) {
  const std::string dir =
      std::string(BURRLAB_SOURCE_DIR) + "/tests/runner/station/golden/";
  const ImageDiff same =
      Compare(dir + "04_trial1_response.png", dir + "04_trial1_response.png");
  ASSERT_TRUE(same.error.empty()) << same.error;
  EXPECT_EQ(same.mean_abs, 0.0);
  const ImageDiff other =
      Compare(dir + "04_trial1_response.png", dir + "05_trial2_paused.png");
  ASSERT_TRUE(other.error.empty()) << other.error;
  EXPECT_GT(other.differing, 0.005);  // the tolerance would catch it
}

TEST(StationWindow, RefusesAnAbsurdSize) {
  WindowOptions o;
  o.width = 10;
  Result<std::unique_ptr<StationWindow>> opened = StationWindow::Open(o);
  ASSERT_FALSE(opened.ok());
  EXPECT_EQ(opened.error().message,
            "window size 10x720 is outside 320x240 to 8192x8192");
}

TEST(StationWindow, NamesAMissingFont) {
  WindowOptions o;
  o.font_path = "/nonexistent/font.ttf";
  Result<std::unique_ptr<StationWindow>> opened = StationWindow::Open(o);
  ASSERT_FALSE(opened.ok());
  EXPECT_EQ(opened.error().message,
            "cannot open the subject window: font /nonexistent/font.ttf not "
            "found (Debian package fonts-dejavu-core)");
}

}  // namespace
}  // namespace burrlab::runner
