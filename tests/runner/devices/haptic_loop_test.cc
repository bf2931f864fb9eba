// The haptic loop body with a fake clock and the simulated device: no
// allocation over 10,000 ticks, the watchdog (late or non-finite force -> zero
// force that tick, counted), sample-estimate-hold and the clamp, a property
// test over random positions and the built-in materials, and the thread
// stopping on an unplug. No timing thresholds: the fake clock decides what is
// late.
#include "devices/haptic_loop.h"

#include <gtest/gtest.h>

#include <atomic>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_real_distribution.hpp>
#include <cmath>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <new>
#include <vector>

#include "burrlab/sim/phantoms.h"
#include "burrlab/stimuli/materials.h"
#include "devices/fake_falcon_transport.h"
#include "devices/falcon_device.h"
#include "devices/falcon_kinematics.h"
#include "devices/mouse_device.h"
#include "devices/sim_force_source.h"
#include "devices/simulated_device.h"
#include "half_space.h"
#include "station/surface_snapshot.h"

// Counts heap allocations while enabled (replaces the global operator new for
// this binary, as tests/sim/step_test.cc does). GCC cannot see that the
// replaced new and delete pair up through malloc/free; the pairing is correct.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<bool> g_count_allocations{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  if (g_count_allocations.load(std::memory_order_relaxed)) ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// The nothrow forms too (std::stable_sort's temporary buffer uses them), so
// that every new of this binary pairs with the free() below.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  if (g_count_allocations.load(std::memory_order_relaxed)) ++g_allocations;
  return std::malloc(size == 0 ? 1 : size);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace burrlab::runner {
namespace {

constexpr std::int64_t kPeriodNs = 1'000'000;

// Time stands still unless a test or a slow source moves it.
class FakeClock final : public LoopClock {
 public:
  std::int64_t NowNs() noexcept override { return now_ns; }
  void SleepUntilNs(std::int64_t time_ns) noexcept override {
    if (time_ns > now_ns) now_ns = time_ns;
  }
  std::int64_t now_ns = 0;
};

// Returns scripted forces; on chosen ticks it is slow or returns NaN.
class ScriptedSource final : public ForceSource {
 public:
  ScriptedSource(FakeClock* clock, std::vector<glm::dvec3> forces_n)
      : clock_(clock), forces_n_(std::move(forces_n)) {}
  glm::dvec3 Force(const glm::dvec3&) noexcept override {
    const std::size_t k = calls_++;
    if (k == slow_call) clock_->now_ns += slow_by_ns;
    return forces_n_[std::min(k, forces_n_.size() - 1)];
  }
  std::size_t slow_call = static_cast<std::size_t>(-1);
  std::int64_t slow_by_ns = 0;

 private:
  FakeClock* clock_;
  std::vector<glm::dvec3> forces_n_;
  std::size_t calls_ = 0;
};

// Runs `ticks` ticks on the fake clock, each at its deadline.
void RunTicks(HapticLoop& loop, FakeClock& clock, int ticks) {
  for (int k = 0; k < ticks; ++k) {
    const std::int64_t deadline_ns = (k + 1) * kPeriodNs;
    clock.now_ns = deadline_ns;
    (void)loop.Tick(deadline_ns);
  }
}

LoopOptions TestOptions() {
  LoopOptions options;
  options.realtime = false;
  options.max_samples = 20'000;
  return options;
}

SimulatedDevice MakeDevice(std::vector<glm::dvec3> positions,
                           std::size_t record = 20'000) {
  SimulatedDeviceOptions options;
  options.positions_mm = std::move(positions);
  options.record_capacity = record;
  return SimulatedDevice(std::move(options));
}

TEST(HapticLoop, AllocatesNothingOverTenThousandTicks) {
  sim::Model model;
  model.radius_mm = 3.0;
  model.material.alpha_per_s = 1.0;
  sim::State state = sim::State::Create(model, HalfSpace(), 7).value();
  // Sliding a quarter radius deep while drilling: force, friction, erosion.
  std::vector<glm::dvec3> positions;
  for (int k = 0; k < 10'000; ++k) {
    positions.emplace_back(5.0 + 0.0008 * k, 9.6, 9.6 + 3.0 - 0.75);
  }
  SimulatedDevice device = MakeDevice(positions);
  SimForceSource source(model, &state, glm::dvec3(0.0),
                        glm::dvec3(0.0, 0.0, 2000.0));
  FakeClock clock;
  HapticLoop loop(&device, &source, &clock, TestOptions());
  g_allocations = 0;
  g_count_allocations = true;
  RunTicks(loop, clock, 10'000);
  g_count_allocations = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(loop.counters().ticks, 10'000);
  EXPECT_EQ(device.forces_n().size(), 10'000u);
  EXPECT_GT(glm::length(device.forces_n().back()), 0.0);
  EXPECT_GT(state.counters().removed_mm3, 0.0);
}

// The station's path: the mouse device in the loop, and every 33 ticks the
// height map around the burr updated and published for the window.
TEST(HapticLoop, MouseTicksAndWindowSnapshotsAllocateNothing) {
  sim::Model model;
  model.radius_mm = 3.0;
  model.material.alpha_per_s = 1.0;
  sim::State state = sim::State::Create(model, HalfSpace(), 7).value();
  MouseDevice mouse(MouseDeviceOptions{
      Workspace{glm::dvec3(-9.6, -9.6, -6.0), glm::dvec3(9.6, 9.6, 6.0)}, 0.5,
      3.0, 8.0});
  const glm::dvec3 offset(9.6, 9.6, 6.6);
  SimForceSource source(model, &state, offset, glm::dvec3(0.0, 0.0, 2000.0));
  FakeClock clock;
  HapticLoop loop(&mouse, &source, &clock, TestOptions());
  SurfaceSnapshot snapshot;
  snapshot.surface = HeightMap::For(state.volume());
  snapshot.burr_radius_mm = model.radius_mm;
  SnapshotExchange exchange(snapshot);
  mouse.SetCursor({0.4, 0.5}, -4.0, false);  // 2 mm down: 2 mm deep
  g_allocations = 0;
  g_count_allocations = true;
  for (int k = 0; k < 10'000; ++k) {
    clock.now_ns = static_cast<std::int64_t>(k) * kPeriodNs;
    if (k % 1000 == 0) mouse.SetCursor({0.4 + k * 1e-5, 0.5}, -4.0, false);
    (void)loop.Tick(clock.now_ns);
    if (k % 33 == 0) {
      glm::dvec3 device_mm;
      (void)mouse.ReadPosition(&device_mm);
      snapshot.burr_mm = device_mm + offset;
      UpdateHeightMap(state.volume(), snapshot.burr_mm, 3.6, &snapshot.surface);
      snapshot.force_n = loop.last_force_n();
      exchange.Publish(snapshot);
    }
  }
  g_count_allocations = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(loop.counters().ticks, 10'000);
  EXPECT_GT(mouse.force_magnitude_n(), 0.0);
  EXPECT_GT(state.counters().removed_mm3, 0.0);
  const SurfaceSnapshot* newest = exchange.TakeNewest();
  ASSERT_NE(newest, nullptr);
  EXPECT_EQ(newest->tick, 0);  // the tick field is the caller's to set
  EXPECT_GT(glm::length(newest->force_n), 0.0);
}

TEST(HapticLoop, SlowStepGivesZeroForceForThatTickAndIsCounted) {
  FakeClock clock;
  ScriptedSource source(&clock, {glm::dvec3(0.0, 0.0, 2.0)});
  source.slow_call = 5;
  source.slow_by_ns = 1'500'000;  // 1.5 ms: past the 1 ms budget
  SimulatedDevice device = MakeDevice({glm::dvec3(0.0)});
  HapticLoop loop(&device, &source, &clock, TestOptions());
  RunTicks(loop, clock, 10);
  ASSERT_EQ(device.forces_n().size(), 10u);
  for (std::size_t k = 0; k < 10; ++k) {
    EXPECT_EQ(device.forces_n()[k],
              k == 5 ? glm::dvec3(0.0) : glm::dvec3(0.0, 0.0, 2.0))
        << "tick " << k;
  }
  EXPECT_EQ(loop.counters().missed_deadlines, 1);
  EXPECT_EQ(loop.Stats().overruns, 1);
  EXPECT_EQ(loop.counters().non_finite, 0);
}

TEST(HapticLoop, ForceReadyExactlyAtTheBudgetIsSent) {
  FakeClock clock;
  ScriptedSource source(&clock, {glm::dvec3(0.0, 0.0, 2.0)});
  source.slow_call = 0;
  source.slow_by_ns = kPeriodNs;  // ready exactly one period after deadline
  SimulatedDevice device = MakeDevice({glm::dvec3(0.0)});
  HapticLoop loop(&device, &source, &clock, TestOptions());
  RunTicks(loop, clock, 1);
  EXPECT_EQ(device.forces_n()[0], glm::dvec3(0.0, 0.0, 2.0));
  EXPECT_EQ(loop.counters().missed_deadlines, 0);
}

TEST(HapticLoop, NonFiniteForceGivesZeroForceAndIsCounted) {
  FakeClock clock;
  const double nan = std::nan("");
  const double inf = std::numeric_limits<double>::infinity();
  ScriptedSource source(&clock, {glm::dvec3(1.0), glm::dvec3(nan, 0.0, 0.0),
                                 glm::dvec3(0.0, inf, 0.0), glm::dvec3(1.0)});
  SimulatedDevice device = MakeDevice({glm::dvec3(0.0)});
  HapticLoop loop(&device, &source, &clock, TestOptions());
  RunTicks(loop, clock, 4);
  ASSERT_EQ(device.forces_n().size(), 4u);
  EXPECT_EQ(device.forces_n()[1], glm::dvec3(0.0));
  EXPECT_EQ(device.forces_n()[2], glm::dvec3(0.0));
  EXPECT_EQ(device.forces_n()[3], glm::dvec3(1.0));  // filter restarted
  EXPECT_EQ(loop.counters().non_finite, 2);
}

TEST(HapticLoop, HoldsTheSampleEstimateAndClampsToTheDevice) {
  // H_k = F_k + (F_k - F_{k-1}) / 2: 1, 2.5, 3.5; then 10 N -> clamped to 8.
  FakeClock clock;
  ScriptedSource source(
      &clock, {glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(0.0, 0.0, 2.0),
               glm::dvec3(0.0, 0.0, 3.0), glm::dvec3(0.0, 0.0, 10.0)});
  SimulatedDevice device = MakeDevice({glm::dvec3(0.0)});
  HapticLoop loop(&device, &source, &clock, TestOptions());
  RunTicks(loop, clock, 4);
  ASSERT_EQ(device.forces_n().size(), 4u);
  EXPECT_DOUBLE_EQ(device.forces_n()[0].z, 1.0);
  EXPECT_DOUBLE_EQ(device.forces_n()[1].z, 2.5);
  EXPECT_DOUBLE_EQ(device.forces_n()[2].z, 3.5);
  EXPECT_DOUBLE_EQ(device.forces_n()[3].z, 8.0);  // 13.5 held, 8 N limit
  EXPECT_EQ(loop.counters().clamped, 1);
}

TEST(HapticLoop, ClampsToTheStationLimitBelowTheDevicesAndCountsIt) {
  // The station file asks for 3 N on an 8 N device: 2 N passes, more comes
  // out as 3 N along its direction; a 20 N station limit above the device's
  // leaves the device's 8 N.
  FakeClock clock;
  ScriptedSource source(&clock,
                        {glm::dvec3(0.0, 0.0, 2.0), glm::dvec3(0.0, 3.0, 4.0)});
  SimulatedDevice device = MakeDevice({glm::dvec3(0.0)});
  LoopOptions options = TestOptions();
  options.max_force_n = 3.0;
  HapticLoop loop(&device, &source, &clock, options);
  EXPECT_DOUBLE_EQ(loop.max_force_n(), 3.0);
  RunTicks(loop, clock, 1);
  EXPECT_DOUBLE_EQ(device.forces_n()[0].z, 2.0);
  EXPECT_EQ(loop.counters().clamped, 0);
  RunTicks(loop, clock, 2);
  ASSERT_EQ(device.forces_n().size(), 3u);
  // Tick 2 holds (0, 4.5, 5) N, tick 3 (0, 3, 4) N: both over 3 N.
  EXPECT_NEAR(glm::length(device.forces_n()[1]), 3.0, 1e-12);
  EXPECT_NEAR(glm::length(device.forces_n()[2]), 3.0, 1e-12);
  EXPECT_NEAR(device.forces_n()[2].y / device.forces_n()[2].z, 0.75, 1e-12);
  EXPECT_EQ(loop.counters().clamped, 2);

  SimulatedDevice device8 = MakeDevice({glm::dvec3(0.0)});
  options.max_force_n = 20.0;
  HapticLoop loose(&device8, &source, &clock, options);
  EXPECT_DOUBLE_EQ(loose.max_force_n(), 8.0);
}

TEST(HapticLoop, ForceNeverExceedsTheDeviceLimitAndIsNeverNaN) {
  // Property: random positions in and around a half-space of each built-in
  // material, probing and drilling, through the loop body.
  for (const std::string& name : stimuli::BuiltinMaterialNames()) {
    SCOPED_TRACE(name);
    const stimuli::MaterialSet set = stimuli::LoadBuiltinMaterial(name).value();
    sim::Model model;
    model.material = set.material;
    model.radius_mm = 3.0;
    model.material.c_i_n_s_per_mm3 = 0.01;  // let velocity jumps push too
    sim::State state = sim::State::Create(model, HalfSpace(), 11).value();
    boost::random::mt19937 rng(2024);
    boost::random::uniform_real_distribution<double> xy(4.0, 15.2);
    boost::random::uniform_real_distribution<double> z(9.6 - 6.0, 9.6 + 4.0);
    std::vector<glm::dvec3> positions;
    for (int k = 0; k < 3000; ++k) {
      positions.emplace_back(xy(rng), xy(rng), z(rng));
    }
    SimulatedDevice device = MakeDevice(positions);
    SimForceSource source(model, &state, glm::dvec3(0.0),
                          glm::dvec3(0.0, 0.0, 1500.0));
    FakeClock clock;
    HapticLoop loop(&device, &source, &clock, TestOptions());
    RunTicks(loop, clock, 3000);
    const double limit_n = device.spec().max_force_n;
    ASSERT_EQ(device.forces_n().size(), 3000u);
    for (const glm::dvec3& force_n : device.forces_n()) {
      ASSERT_TRUE(std::isfinite(force_n.x) && std::isfinite(force_n.y) &&
                  std::isfinite(force_n.z));
      ASSERT_LE(glm::length(force_n), limit_n * (1.0 + 1e-12));
    }
    // The limit was exercised: deep random positions ask for more than 8 N.
    EXPECT_GT(loop.counters().clamped, 100);
  }
}

TEST(HapticLoop, UnplugStopsTheThreadWithZeroForce) {
  SimulatedDeviceOptions options;
  options.positions_mm = {glm::dvec3(0.0)};
  options.record_capacity = 100;
  options.unplug_after_reads = 20;
  SimulatedDevice device(options);
  MonotonicClock clock;
  FakeClock unused;
  ScriptedSource source(&unused, {glm::dvec3(0.0, 0.0, 1.0)});
  HapticLoop loop(&device, &source, &clock, TestOptions());
  ASSERT_TRUE(loop.Start().ok());
  loop.Wait();
  EXPECT_EQ(loop.fault().code, DeviceCode::kUnplugged);
  EXPECT_EQ(loop.counters().ticks, 21);  // 20 good reads, then the unplug
  EXPECT_EQ(loop.counters().device_errors, 1);
  EXPECT_EQ(loop.last_force_n(), glm::dvec3(0.0));
  EXPECT_EQ(device.forces_n().size(), 20u);
  EXPECT_FALSE(loop.realtime().fifo);
  EXPECT_EQ(loop.realtime().note, "real-time scheduling not requested");
}

TEST(HapticLoop, ThreadRunsTheRequestedTicksAndReportsPeriodErrors) {
  SimulatedDevice device = MakeDevice({glm::dvec3(0.0)}, 200);
  MonotonicClock clock;
  FakeClock unused;
  ScriptedSource source(&unused, {glm::dvec3(0.0, 0.0, 1.0)});
  HapticLoop loop(&device, &source, &clock, TestOptions());
  ASSERT_TRUE(loop.Start(50).ok());
  loop.Wait();
  EXPECT_EQ(loop.counters().ticks, 50);
  EXPECT_EQ(device.reads(), 50);
  EXPECT_EQ(device.writes(), 51);  // 50 ticks and the zero force at the end
  EXPECT_EQ(device.forces_n().back(), glm::dvec3(0.0));
  const LoopStats stats = loop.Stats();
  EXPECT_EQ(stats.samples, 50);
  EXPECT_GE(stats.p50_us, 0.0);  // the spin never wakes a tick early
  EXPECT_LE(stats.p50_us, stats.p99_us);
  EXPECT_LE(stats.p99_us, stats.max_us);
}

TEST(HapticLoop, StartRefusesANonPositiveRate) {
  SimulatedDevice device = MakeDevice({glm::dvec3(0.0)});
  FakeClock clock;
  ScriptedSource source(&clock, {glm::dvec3(0.0)});
  LoopOptions options = TestOptions();
  options.rate_hz = 0.0;
  HapticLoop loop(&device, &source, &clock, options);
  const Status status = loop.Start(10);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message,
            "haptic loop: rate_hz must be positive, got 0");
  EXPECT_EQ(device.reads(), 0);
}

// A Falcon that answers every command packet with one fixed, homed report
// and records nothing, so the device path itself can be checked for
// allocations.
class QuietFalcon final : public falcon::Transport {
 public:
  explicit QuietFalcon(const glm::dvec3& position_mm) {
    falcon::FakeFalconTransport encoder;  // only to encode the report
    encoder.SetHomed(falcon::kAllHomed);
    reply_ = falcon::EncodeReport(encoder.ReportFor(position_mm));
  }
  DeviceStatus Control(std::uint8_t, std::uint16_t,
                       std::uint16_t) noexcept override {
    return {};
  }
  DeviceStatus Write(std::span<const std::uint8_t> bytes) noexcept override {
    if (bytes.size() == falcon::kPacketBytes) {
      ++pending_;
      last_ = falcon::Packet{};
      std::copy(bytes.begin(), bytes.end(), last_.begin());
    }
    return {};
  }
  DeviceStatus Read(std::span<std::uint8_t> buffer,
                    std::size_t* count) noexcept override {
    buffer[0] = 0x31;
    buffer[1] = 0x60;
    *count = falcon::kModemStatusBytes;
    if (pending_ > 0) {
      --pending_;
      std::copy(reply_.begin(), reply_.end(), buffer.begin() + 2);
      *count += falcon::kPacketBytes;
    }
    return {};
  }
  const falcon::Packet& last_command() const { return last_; }

 private:
  falcon::Packet reply_{};
  falcon::Packet last_{};
  int pending_ = 0;
};

TEST(HapticLoop, FalconTicksAllocateNothing) {
  QuietFalcon transport({5.0, -3.0, 125.0});
  FalconDevice falcon(&transport);
  ASSERT_TRUE(falcon.Open().ok());
  ASSERT_TRUE(falcon.Home(10).ok());
  FakeClock clock;
  ScriptedSource source(&clock, {glm::dvec3(1.0, -2.0, 3.0)});
  HapticLoop loop(&falcon, &source, &clock, TestOptions());
  g_allocations = 0;
  g_count_allocations = true;
  RunTicks(loop, clock, 10'000);
  g_count_allocations = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(loop.counters().device_errors, 0);
  falcon::Command command;
  ASSERT_TRUE(falcon::DecodeCommand(transport.last_command(), &command));
  EXPECT_NE(command.motor, (std::array<std::int16_t, 3>{}));
}

TEST(HapticLoop, FalconUnplugMidRunIsAFaultWithZeroForce) {
  falcon::FakeFalconTransport fake;
  fake.homing_packets_needed = 1;
  fake.position_mm = {0.0, 0.0, 110.0};
  FalconDevice falcon(&fake);
  ASSERT_TRUE(falcon.Open().ok());
  ASSERT_TRUE(falcon.Home(10).ok());
  FakeClock clock;
  ScriptedSource source(&clock, {glm::dvec3(0.0, 0.0, 4.0)});
  HapticLoop loop(&falcon, &source, &clock, TestOptions());
  RunTicks(loop, clock, 20);
  EXPECT_EQ(loop.counters().device_errors, 0);
  // On the axis, 4 N along z loads the three motors equally.
  const falcon::Command pushing = fake.commands.back();
  EXPECT_NE(pushing.motor[0], 0);
  EXPECT_EQ(pushing.motor[1], pushing.motor[0]);
  EXPECT_EQ(pushing.motor[2], pushing.motor[0]);
  fake.unplugged = true;
  clock.now_ns = 21 * kPeriodNs;
  const DeviceStatus status = loop.Tick(21 * kPeriodNs);
  EXPECT_EQ(status.code, DeviceCode::kUnplugged);
  EXPECT_TRUE(IsFault(status.code));
  EXPECT_EQ(loop.last_force_n(), glm::dvec3(0.0));
  EXPECT_EQ(loop.counters().device_errors, 1);
}

}  // namespace
}  // namespace burrlab::runner
