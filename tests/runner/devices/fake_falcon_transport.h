// A fake Falcon behind the FTDI transport: records every control request and
// write, plays the firmware loader (handshake, baud check, byte echo) and a
// running Novint firmware (one report per command packet, homing after a set
// number of homing packets, encoders of a set end-effector position), and can
// split replies across reads, fall silent or be unplugged.
#ifndef BURRLAB_TESTS_RUNNER_DEVICES_FAKE_FALCON_TRANSPORT_H_
#define BURRLAB_TESTS_RUNNER_DEVICES_FAKE_FALCON_TRANSPORT_H_

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <glm/vec3.hpp>
#include <span>
#include <vector>

#include "devices/falcon_kinematics.h"
#include "devices/falcon_packet.h"
#include "devices/falcon_transport.h"

namespace burrlab::runner::falcon {

struct ControlCall {
  std::uint8_t request;
  std::uint16_t value;
  std::uint16_t index;
  bool operator==(const ControlCall&) const = default;
};

class FakeFalconTransport final : public Transport {
 public:
  // Behaviour knobs.
  std::size_t reply_chunk_bytes = 64;       // payload bytes per read at most
  int handshake_failures = 0;               // handshakes to ignore first
  int homing_packets_needed = 3;            // homing packets before all homed
  bool answer_packets = true;               // running firmware replies
  bool unplugged = false;                   // every call fails with kUnplugged
  std::int64_t corrupt_echo_at = -1;        // firmware byte whose echo is wrong
  glm::dvec3 position_mm{0.0, 0.0, 120.0};  // where the grip is

  // What the host did.
  std::vector<ControlCall> controls;
  std::vector<std::vector<std::uint8_t>> writes;
  std::vector<std::uint8_t> firmware;  // bytes received during upload
  std::vector<Command> commands;       // decoded command packets

  DeviceStatus Control(std::uint8_t request, std::uint16_t value,
                       std::uint16_t index) noexcept override {
    if (unplugged) return Gone();
    controls.push_back({request, value, index});
    if (request == ftdi::kBaudRate) baud_ = value;
    if (request == ftdi::kReset && value == ftdi::kPurgeRx) pending_.clear();
    return {};
  }

  DeviceStatus Write(std::span<const std::uint8_t> bytes) noexcept override {
    if (unplugged) return Gone();
    writes.emplace_back(bytes.begin(), bytes.end());
    if (baud_ == ftdi::kBaud9600) {
      const std::uint8_t handshake[] = {0x0a, 0x43, 0x0d};
      if (std::ranges::equal(bytes, handshake)) {
        if (handshake_failures > 0) {
          --handshake_failures;
          Queue({0x0a, 0x44});  // a wrong answer
        } else {
          Queue({0x0a, 0x44, 0x2c, 0x0d});
        }
      }
    } else if (baud_ == ftdi::kBaud140000) {
      if (!baud_checked_ && bytes.size() == 1 && bytes[0] == 0x41) {
        baud_checked_ = true;
        Queue({0x41});
      } else {
        std::vector<std::uint8_t> echo;
        for (const std::uint8_t sent : bytes) {
          const bool corrupt =
              static_cast<std::int64_t>(firmware.size()) == corrupt_echo_at;
          firmware.push_back(sent);
          echo.push_back(corrupt ? static_cast<std::uint8_t>(sent ^ 0xff)
                                 : sent);
        }
        Queue(echo);
      }
    } else if (bytes.size() == kPacketBytes) {
      Command command;
      if (DecodeCommand(bytes.first<kPacketBytes>(), &command)) {
        commands.push_back(command);
        if (command.homing_mode && homed_ != kAllHomed &&
            ++homing_packets_ >= homing_packets_needed) {
          homed_ = kAllHomed;
        }
        if (answer_packets) {
          const Packet packet = EncodeReport(ReportFor(position_mm));
          Queue(std::vector<std::uint8_t>(packet.begin(), packet.end()));
        }
      }
    }
    return {};
  }

  DeviceStatus Read(std::span<std::uint8_t> buffer,
                    std::size_t* count) noexcept override {
    if (unplugged) return Gone();
    buffer[0] = 0x31;  // FTDI modem status bytes
    buffer[1] = 0x60;
    std::size_t n = kModemStatusBytes;
    while (!pending_.empty() && n < buffer.size() &&
           n - kModemStatusBytes < reply_chunk_bytes) {
      buffer[n++] = pending_.front();
      pending_.pop_front();
    }
    *count = n;
    return {};
  }

  // The report the fake sends for a grip position: encoder counts rounded
  // from the inverse kinematics, homing bits as homed so far.
  Report ReportFor(const glm::dvec3& p) const {
    Report report;
    glm::dvec3 angles;
    if (InverseKinematics(p, &angles)) {
      for (int i = 0; i < 3; ++i) {
        report.encoder[static_cast<std::size_t>(i)] = static_cast<std::int16_t>(
            std::lround(AngleRadToEncoder(angles[i])));
      }
    }
    report.homed = homed_;
    return report;
  }

  void SetHomed(std::uint8_t homed) { homed_ = homed; }

 private:
  static DeviceStatus Gone() {
    return {DeviceCode::kUnplugged, "LIBUSB_ERROR_NO_DEVICE"};
  }
  void Queue(const std::vector<std::uint8_t>& bytes) {
    pending_.insert(pending_.end(), bytes.begin(), bytes.end());
  }

  std::deque<std::uint8_t> pending_;
  std::uint16_t baud_ = 0;
  bool baud_checked_ = false;
  int homing_packets_ = 0;
  std::uint8_t homed_ = 0;
};

}  // namespace burrlab::runner::falcon

#endif  // BURRLAB_TESTS_RUNNER_DEVICES_FAKE_FALCON_TRANSPORT_H_
