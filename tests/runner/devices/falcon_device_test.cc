// The Falcon over a fake transport: the FTDI set-up as control requests, the
// firmware upload, homing, one exchange per tick, force to motor commands,
// and unplug and silence reported as statuses.
#include "devices/falcon_device.h"

#include <gtest/gtest.h>

#include <vector>

#include "devices/falcon_kinematics.h"
#include "fake_falcon_transport.h"

namespace burrlab::runner {
namespace {

using falcon::ControlCall;
using falcon::FakeFalconTransport;
namespace ftdi = falcon::ftdi;

const std::vector<ControlCall> kRunningSetUp = {
    {ftdi::kLatencyTimer, 1, 0},
    {ftdi::kBaudRate, 0x0002, 0},
    {ftdi::kReset, ftdi::kPurgeRx, 0},
    {ftdi::kReset, ftdi::kPurgeTx, 0},
};

std::vector<std::uint8_t> Image(std::size_t size) {
  std::vector<std::uint8_t> image(size);
  for (std::size_t k = 0; k < size; ++k) {
    image[k] = static_cast<std::uint8_t>((k * 37 + 11) & 0xff);
  }
  return image;
}

TEST(FalconDevice, OpenSendsTheFtdiSetUpForRunning) {
  FakeFalconTransport fake;
  FalconDevice falcon(&fake);
  ASSERT_TRUE(falcon.Open().ok());
  std::vector<ControlCall> expected = {{ftdi::kReset, ftdi::kPurgeRx, 0},
                                       {ftdi::kReset, ftdi::kPurgeTx, 0}};
  expected.insert(expected.end(), kRunningSetUp.begin(), kRunningSetUp.end());
  EXPECT_EQ(fake.controls, expected);
  EXPECT_TRUE(fake.writes.empty());
}

TEST(FalconDevice, LoadsFirmwareInEchoedChunks) {
  FakeFalconTransport fake;
  fake.reply_chunk_bytes = 7;  // echoes arrive in pieces
  fake.handshake_failures = 2;
  FalconDevice falcon(&fake);
  const std::vector<std::uint8_t> image = Image(200);
  const Status status = falcon.LoadFirmware(image);
  ASSERT_TRUE(status.ok()) << status.error().message;
  EXPECT_EQ(fake.firmware, image);
  std::vector<ControlCall> expected = {
      {ftdi::kReset, ftdi::kPurgeRx, 0},  {ftdi::kReset, ftdi::kPurgeTx, 0},
      {ftdi::kLatencyTimer, 16, 0},       {ftdi::kBaudRate, 0x4138, 0},
      {ftdi::kLineProperties, 0x0008, 0}, {ftdi::kFlowControl, 0x0000, 0},
      {ftdi::kModemControl, 0x0200, 0},  // RTS low
      {ftdi::kModemControl, 0x0100, 0},  // DTR low
      {ftdi::kModemControl, 0x0101, 0},  // DTR high
      {ftdi::kModemControl, 0x0100, 0},  // DTR low after the handshake
      {ftdi::kBaudRate, 0x0015, 0},      // 140000 baud
  };
  expected.insert(expected.end(), kRunningSetUp.begin(), kRunningSetUp.end());
  EXPECT_EQ(fake.controls, expected);
  // Three handshakes (two unanswered), the 'A' check, then 62 + 62 + 62 + 14.
  const std::vector<std::uint8_t> handshake = {0x0a, 0x43, 0x0d};
  ASSERT_EQ(fake.writes.size(), 3u + 1u + 4u);
  EXPECT_EQ(fake.writes[0], handshake);
  EXPECT_EQ(fake.writes[2], handshake);
  EXPECT_EQ(fake.writes[3], std::vector<std::uint8_t>{0x41});
  EXPECT_EQ(fake.writes[4].size(), 62u);
  EXPECT_EQ(fake.writes[7].size(), 14u);
}

TEST(FalconDevice, FirmwareEchoMismatchNamesTheByte) {
  FakeFalconTransport fake;
  fake.corrupt_echo_at = 100;
  FalconDevice falcon(&fake);
  const std::vector<std::uint8_t> image = Image(200);
  const Status status = falcon.LoadFirmware(image);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message,
            "Falcon: firmware echo mismatch at byte 100: sent 0x7f, got 0x80");
}

TEST(FalconDevice, UnansweredHandshakeIsAnError) {
  FakeFalconTransport fake;
  fake.handshake_failures = 1000;
  FalconDevice falcon(&fake);
  const Status status = falcon.LoadFirmware(Image(10));
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message,
            "Falcon: the firmware loader did not answer the handshake (sent 0a "
            "43 0d 100 times, expected 0a 44 2c 0d); unplug the Falcon's power "
            "and USB, plug them back in and try again");
}

TEST(FalconDevice, FirmwareFileErrorsNameTheFile) {
  FakeFalconTransport fake;
  FalconDevice falcon(&fake);
  const Status status = falcon.LoadFirmwareFile("/nonexistent/novint.bin");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message,
            "cannot open firmware file '/nonexistent/novint.bin': No such file "
            "or directory");
  EXPECT_TRUE(fake.writes.empty());
}

TEST(FalconDevice, HomesWithRedThenGreenAndReadsThePosition) {
  FakeFalconTransport fake;
  fake.homing_packets_needed = 5;
  fake.position_mm = {12.0, -7.5, 131.0};
  FalconDevice falcon(&fake);
  ASSERT_TRUE(falcon.Open().ok());
  glm::dvec3 p(0.0);
  EXPECT_EQ(falcon.ReadPosition(&p).code, DeviceCode::kNotReady);
  const Status homed = falcon.Home(100);
  ASSERT_TRUE(homed.ok()) << homed.error().message;
  ASSERT_EQ(fake.commands.size(), 6u);  // five homing packets, one green
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_TRUE(fake.commands[k].homing_mode);
    EXPECT_EQ(fake.commands[k].leds, falcon::kRedLed);
  }
  EXPECT_FALSE(fake.commands[5].homing_mode);
  EXPECT_EQ(fake.commands[5].leds, falcon::kGreenLed);

  // The position is the forward kinematics of the reported encoders, within
  // encoder resolution of the grip.
  fake.position_mm = {-20.0, 15.0, 100.0};
  const DeviceStatus read = falcon.ReadPosition(&p);
  ASSERT_TRUE(read.ok()) << read.reason;
  const falcon::Report report = fake.ReportFor(fake.position_mm);
  glm::dvec3 expected;
  ASSERT_TRUE(
      falcon::ForwardKinematics({falcon::EncoderToAngleRad(report.encoder[0]),
                                 falcon::EncoderToAngleRad(report.encoder[1]),
                                 falcon::EncoderToAngleRad(report.encoder[2])},
                                falcon::kWorkspaceCentreMm, &expected));
  EXPECT_NEAR(p.x, expected.x, 1e-9);
  EXPECT_NEAR(p.y, expected.y, 1e-9);
  EXPECT_NEAR(p.z, expected.z, 1e-9);
  EXPECT_NEAR(p.x, -20.0, 0.1);
  EXPECT_NEAR(p.y, 15.0, 0.1);
  EXPECT_NEAR(p.z, 100.0, 0.1);
}

TEST(FalconDevice, HomingTimesOutWithInstructions) {
  FakeFalconTransport fake;
  fake.homing_packets_needed = 1000;
  FalconDevice falcon(&fake);
  ASSERT_TRUE(falcon.Open().ok());
  const Status status = falcon.Home(20);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message,
            "Falcon: not homed after 20 packets (0 of 3 encoders found their "
            "index): move the grip all the way out, then push it straight in");
}

class HomedFalcon : public ::testing::Test {
 protected:
  void SetUp() override {
    fake_.homing_packets_needed = 1;
    ASSERT_TRUE(falcon_.Open().ok());
    ASSERT_TRUE(falcon_.Home(10).ok());
  }
  FakeFalconTransport fake_;
  FalconDevice falcon_{&fake_};
};

TEST_F(HomedFalcon, ForceBecomesMotorCommandsThroughTheJacobian) {
  glm::dvec3 p;
  ASSERT_TRUE(falcon_.ReadPosition(&p).ok());
  const glm::dvec3 force_n(1.0, -2.0, 3.0);
  ASSERT_TRUE(falcon_.WriteForce(force_n).ok());
  glm::dvec3 torques_n_m;
  ASSERT_TRUE(falcon::ForceToTorques(p, force_n, &torques_n_m));
  EXPECT_EQ(fake_.commands.back().motor,
            falcon::TorquesToMotorCommands(torques_n_m));
  EXPECT_NE(fake_.commands.back().motor, (std::array<std::int16_t, 3>{}));
  EXPECT_EQ(fake_.commands.back().leds, falcon::kGreenLed);
}

TEST_F(HomedFalcon, ForceIsClampedToEightNewtonsAndNanRefused) {
  glm::dvec3 p;
  ASSERT_TRUE(falcon_.ReadPosition(&p).ok());
  ASSERT_TRUE(falcon_.WriteForce({0.0, 0.0, 8.0}).ok());
  const auto at_limit = fake_.commands.back().motor;
  ASSERT_TRUE(falcon_.ReadPosition(&p).ok());
  ASSERT_TRUE(falcon_.WriteForce({0.0, 0.0, 80.0}).ok());
  EXPECT_EQ(fake_.commands.back().motor, at_limit);
  ASSERT_TRUE(falcon_.ReadPosition(&p).ok());
  const DeviceStatus nan = falcon_.WriteForce({std::nan(""), 0.0, 0.0});
  EXPECT_EQ(nan.code, DeviceCode::kInvalidArgument);
  EXPECT_EQ(fake_.commands.back().motor, (std::array<std::int16_t, 3>{}));
}

TEST_F(HomedFalcon, UnplugIsReportedByReadAndWrite) {
  glm::dvec3 p(1.0, 2.0, 3.0);
  fake_.unplugged = true;
  const DeviceStatus read = falcon_.ReadPosition(&p);
  EXPECT_EQ(read.code, DeviceCode::kUnplugged);
  EXPECT_STREQ(read.reason, "LIBUSB_ERROR_NO_DEVICE");
  EXPECT_EQ(p, glm::dvec3(1.0, 2.0, 3.0));
  EXPECT_EQ(falcon_.WriteForce({0.0, 0.0, 1.0}).code, DeviceCode::kUnplugged);
  EXPECT_TRUE(IsFault(read.code));
}

TEST_F(HomedFalcon, SilenceIsStaleThenNoResponse) {
  glm::dvec3 p;
  ASSERT_TRUE(falcon_.ReadPosition(&p).ok());
  const glm::dvec3 last = p;
  fake_.answer_packets = false;
  for (int k = 1; k < 50; ++k) {
    const DeviceStatus status = falcon_.ReadPosition(&p);
    ASSERT_EQ(status.code, DeviceCode::kStale) << k;
    EXPECT_EQ(p, last);
  }
  const DeviceStatus status = falcon_.ReadPosition(&p);
  EXPECT_EQ(status.code, DeviceCode::kNoResponse);
  EXPECT_TRUE(IsFault(status.code));
}

TEST_F(HomedFalcon, RepliesSplitAcrossReadsAreReassembled) {
  fake_.reply_chunk_bytes = 5;
  glm::dvec3 p;
  // A 16-byte reply in reads of 5: stale, stale, stale, then the position.
  EXPECT_EQ(falcon_.ReadPosition(&p).code, DeviceCode::kStale);
  EXPECT_EQ(falcon_.ReadPosition(&p).code, DeviceCode::kStale);
  EXPECT_EQ(falcon_.ReadPosition(&p).code, DeviceCode::kStale);
  EXPECT_EQ(falcon_.ReadPosition(&p).code, DeviceCode::kOk);
  EXPECT_EQ(falcon_.malformed_packets(), 0);
}

}  // namespace
}  // namespace burrlab::runner
