// The mouse device: cursor to position, wheel and button to depth, forces kept
// for the indicator, status with reasons.
#include "devices/mouse_device.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace burrlab::runner {
namespace {

TEST(MouseDevice, IsNotReadyBeforeTheWindowReportsTheCursor) {
  MouseDevice m;
  glm::dvec3 p(1.0);
  const DeviceStatus s = m.ReadPosition(&p);
  EXPECT_EQ(s.code, DeviceCode::kNotReady);
  EXPECT_STREQ(s.reason, "the window has not reported the cursor yet");
  EXPECT_EQ(p, glm::dvec3(1.0));
}

TEST(MouseDevice, MapsTheCursorAcrossTheWorkspace) {
  MouseDevice m;  // -20..20 mm on each axis
  m.SetCursor({0.25, 0.0}, 0.0, false);
  glm::dvec3 p;
  ASSERT_TRUE(m.ReadPosition(&p).ok());
  EXPECT_DOUBLE_EQ(p.x, -10.0);
  EXPECT_DOUBLE_EQ(p.y, 20.0);  // top of the view = far side
  EXPECT_DOUBLE_EQ(p.z, 20.0);  // hovering at the top
  EXPECT_EQ(m.ReadPosition(&p).code, DeviceCode::kStale);
}

TEST(MouseDevice, WheelAndButtonLowerTheBurr) {
  MouseDevice m;
  glm::dvec3 p;
  m.SetCursor({0.5, 0.5}, -4.0, false);  // four notches down
  ASSERT_TRUE(m.ReadPosition(&p).ok());
  EXPECT_DOUBLE_EQ(p.z, 18.0);
  m.SetCursor({0.5, 0.5}, -4.0, true);
  ASSERT_TRUE(m.ReadPosition(&p).ok());
  EXPECT_DOUBLE_EQ(p.z, 15.0);
  m.SetCursor({2.0, std::numeric_limits<double>::quiet_NaN()}, -1e9, false);
  ASSERT_TRUE(m.ReadPosition(&p).ok());
  EXPECT_EQ(p, glm::dvec3(20.0, 0.0, -20.0));  // clamped, NaN -> centre
}

TEST(MouseDevice, KeepsTheClampedForceAndRefusesNaN) {
  MouseDevice m;
  EXPECT_TRUE(m.WriteForce({3.0, 4.0, 0.0}).ok());
  EXPECT_DOUBLE_EQ(m.force_magnitude_n(), 5.0);
  EXPECT_TRUE(m.WriteForce({0.0, 0.0, 100.0}).ok());
  EXPECT_DOUBLE_EQ(m.force_magnitude_n(), 8.0);
  const DeviceStatus s =
      m.WriteForce({std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0});
  EXPECT_EQ(s.code, DeviceCode::kInvalidArgument);
  EXPECT_STREQ(s.reason, "non-finite force");
  EXPECT_DOUBLE_EQ(m.force_magnitude_n(), 0.0);
  EXPECT_EQ(m.spec().name, "mouse");
}

}  // namespace
}  // namespace burrlab::runner
