// The scripted device: positions per read, the last held; forces recorded as
// sent (clamped, NaN refused); unplugging.
#include "devices/simulated_device.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>

namespace burrlab::runner {
namespace {

TEST(SimulatedDevice, SamplesWaypointsLinearlyAtTheRate) {
  const Waypoint waypoints[] = {{0.0, {0.0, 0.0, 0.0}},
                                {0.002, {2.0, 0.0, 0.0}},
                                {0.004, {2.0, 4.0, 0.0}}};
  const std::vector<glm::dvec3> positions = SampleWaypoints(waypoints, 1000.0);
  ASSERT_EQ(positions.size(), 5u);
  EXPECT_EQ(positions[0], glm::dvec3(0.0, 0.0, 0.0));
  EXPECT_EQ(positions[1], glm::dvec3(1.0, 0.0, 0.0));
  EXPECT_EQ(positions[2], glm::dvec3(2.0, 0.0, 0.0));
  EXPECT_EQ(positions[3], glm::dvec3(2.0, 2.0, 0.0));
  EXPECT_EQ(positions[4], glm::dvec3(2.0, 4.0, 0.0));
}

TEST(SimulatedDevice, PlaysTheScriptAndHoldsTheLastPosition) {
  SimulatedDeviceOptions options;
  options.positions_mm = {{1.0, 0.0, 0.0}, {2.0, 0.0, 0.0}};
  SimulatedDevice device(options);
  glm::dvec3 p;
  ASSERT_TRUE(device.ReadPosition(&p).ok());
  EXPECT_EQ(p, glm::dvec3(1.0, 0.0, 0.0));
  ASSERT_TRUE(device.ReadPosition(&p).ok());
  EXPECT_EQ(p, glm::dvec3(2.0, 0.0, 0.0));
  ASSERT_TRUE(device.ReadPosition(&p).ok());
  EXPECT_EQ(p, glm::dvec3(2.0, 0.0, 0.0));
  EXPECT_EQ(device.reads(), 3);
}

TEST(SimulatedDevice, RecordsForcesClampedToItsSpec) {
  SimulatedDeviceOptions options;
  options.record_capacity = 2;
  SimulatedDevice device(options);
  ASSERT_TRUE(device.WriteForce({0.0, 3.0, 4.0}).ok());
  ASSERT_TRUE(device.WriteForce({0.0, 30.0, 40.0}).ok());  // 50 N -> 8 N
  const DeviceStatus nan = device.WriteForce({std::nan(""), 0.0, 0.0});
  EXPECT_EQ(nan.code, DeviceCode::kInvalidArgument);
  ASSERT_EQ(device.forces_n().size(), 2u);  // the capacity
  EXPECT_EQ(device.forces_n()[0], glm::dvec3(0.0, 3.0, 4.0));
  EXPECT_NEAR(device.forces_n()[1].y, 4.8, 1e-12);
  EXPECT_NEAR(device.forces_n()[1].z, 6.4, 1e-12);
  EXPECT_EQ(device.writes(), 3);
}

TEST(SimulatedDevice, UnplugsAfterTheScriptedReads) {
  SimulatedDeviceOptions options;
  options.unplug_after_reads = 2;
  SimulatedDevice device(options);
  glm::dvec3 p(5.0);
  ASSERT_TRUE(device.ReadPosition(&p).ok());
  ASSERT_TRUE(device.ReadPosition(&p).ok());
  p = glm::dvec3(5.0);
  const DeviceStatus status = device.ReadPosition(&p);
  EXPECT_EQ(status.code, DeviceCode::kUnplugged);
  EXPECT_STREQ(status.reason, "simulated device unplugged");
  EXPECT_EQ(p, glm::dvec3(5.0));
  EXPECT_EQ(device.WriteForce(glm::dvec3(0.0)).code, DeviceCode::kUnplugged);
  EXPECT_EQ(DeviceCodeName(status.code), "unplugged");
}

TEST(SimulatedDevice, RewindsUnplugsLaterAndReplugs) {
  SimulatedDeviceOptions options;
  options.positions_mm = {{1.0, 0.0, 0.0}, {2.0, 0.0, 0.0}};
  SimulatedDevice device(options);
  glm::dvec3 p;
  ASSERT_TRUE(device.ReadPosition(&p).ok());
  ASSERT_TRUE(device.ReadPosition(&p).ok());
  device.Rewind();
  device.UnplugAfterReads(1);
  ASSERT_TRUE(device.ReadPosition(&p).ok());
  EXPECT_EQ(p, glm::dvec3(1.0, 0.0, 0.0));  // the script starts again
  EXPECT_EQ(device.ReadPosition(&p).code, DeviceCode::kUnplugged);
  EXPECT_EQ(device.ReadPosition(&p).code, DeviceCode::kUnplugged);  // stays
  device.Replug();
  ASSERT_TRUE(device.ReadPosition(&p).ok());
  EXPECT_EQ(p, glm::dvec3(2.0, 0.0, 0.0));
  EXPECT_TRUE(device.WriteForce(glm::dvec3(0.0)).ok());
}

}  // namespace
}  // namespace burrlab::runner
