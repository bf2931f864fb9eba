// The Falcon over a transport: FTDI set-up, firmware upload, homing and the
// per-tick exchange.
#include "devices/falcon_device.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>
#include <vector>

#include "burrlab/sim/finite.h"
#include "devices/falcon_kinematics.h"

namespace burrlab::runner {
namespace {

using falcon::kModemStatusBytes;
namespace ftdi = falcon::ftdi;

// The firmware-mode handshake: the host sends LF 'C' CR and the loader
// answers LF 'D' ',' CR (macOS prefixes a zero byte); then the host sends 'A'
// and the loader echoes it.
constexpr std::uint8_t kHandshakeSend[] = {0x0a, 0x43, 0x0d};
constexpr std::uint8_t kHandshakeReply[] = {0x0a, 0x44, 0x2c, 0x0d};
constexpr std::uint8_t kBaudCheck = 0x41;
// Upload chunk: a full-speed packet is 64 bytes and the FTDI prefixes two.
constexpr std::size_t kFirmwareChunkBytes = 62;

std::string Reason(const DeviceStatus& status) {
  return fmt::format("{} ({})", status.reason, DeviceCodeName(status.code));
}

}  // namespace

const DeviceSpec& FalconSpec() {
  static const DeviceSpec spec{
      "falcon",
      8.0,
      3.0,
      {glm::dvec3(-35.0, -35.0, 80.0), glm::dvec3(35.0, 35.0, 160.0)}};
  return spec;
}

FalconDevice::FalconDevice(falcon::Transport* transport, FalconOptions options)
    : transport_(transport),
      options_(options),
      position_mm_(falcon::kWorkspaceCentreMm) {}

std::int64_t FalconDevice::malformed_packets() const {
  return assembler_.dropped() + invalid_reports_;
}

Status FalconDevice::Control(std::uint8_t request, std::uint16_t value,
                             const char* what) {
  const DeviceStatus status = transport_->Control(request, value, 0);
  if (!status.ok()) {
    return Error{fmt::format("Falcon: cannot {}: {}", what, Reason(status))};
  }
  return {};
}

Status FalconDevice::SetRunningMode() {
  if (Status s = Control(ftdi::kLatencyTimer, ftdi::kLatencyRunningMs,
                         "set the FTDI latency timer to 1 ms");
      !s.ok()) {
    return s;
  }
  if (Status s =
          Control(ftdi::kBaudRate, ftdi::kBaudNormal, "set the FTDI baud rate");
      !s.ok()) {
    return s;
  }
  if (Status s = Control(ftdi::kReset, ftdi::kPurgeRx,
                         "purge the FTDI receive buffer");
      !s.ok()) {
    return s;
  }
  if (Status s = Control(ftdi::kReset, ftdi::kPurgeTx,
                         "purge the FTDI transmit buffer");
      !s.ok()) {
    return s;
  }
  assembler_.Reset();
  awaiting_report_ = false;
  silent_reads_ = 0;
  return {};
}

Status FalconDevice::Open() {
  open_ = false;
  homed_ = false;
  if (Status s = Control(ftdi::kReset, ftdi::kPurgeRx,
                         "purge the FTDI receive buffer");
      !s.ok()) {
    return s;
  }
  if (Status s = Control(ftdi::kReset, ftdi::kPurgeTx,
                         "purge the FTDI transmit buffer");
      !s.ok()) {
    return s;
  }
  if (Status s = SetRunningMode(); !s.ok()) return s;
  open_ = true;
  return {};
}

Status FalconDevice::SetFirmwareMode() {
  struct Step {
    std::uint8_t request;
    std::uint16_t value;
    const char* what;
  };
  static constexpr Step kSteps[] = {
      {ftdi::kReset, ftdi::kPurgeRx, "purge the FTDI receive buffer"},
      {ftdi::kReset, ftdi::kPurgeTx, "purge the FTDI transmit buffer"},
      {ftdi::kLatencyTimer, ftdi::kLatencyFirmwareMs,
       "set the FTDI latency timer to 16 ms"},
      {ftdi::kBaudRate, ftdi::kBaud9600, "set 9600 baud"},
      {ftdi::kLineProperties, ftdi::kLine8N1, "set 8N1"},
      {ftdi::kFlowControl, ftdi::kFlowNone, "turn flow control off"},
      {ftdi::kModemControl, ftdi::kRtsLow, "set RTS low"},
      {ftdi::kModemControl, ftdi::kDtrLow, "set DTR low"},
      {ftdi::kModemControl, ftdi::kDtrHigh, "set DTR high"},
  };
  for (const Step& step : kSteps) {
    if (Status s = Control(step.request, step.value, step.what); !s.ok()) {
      return s;
    }
  }
  bool answered = false;
  for (int attempt = 0; attempt < options_.handshake_attempts && !answered;
       ++attempt) {
    if (DeviceStatus s = transport_->Write(kHandshakeSend); !s.ok()) {
      return Error{fmt::format("Falcon: firmware handshake write failed: {}",
                               Reason(s))};
    }
    std::size_t count = 0;
    if (DeviceStatus s = transport_->Read(read_buffer_, &count); !s.ok()) {
      return Error{
          fmt::format("Falcon: firmware handshake read failed: {}", Reason(s))};
    }
    const std::span<const std::uint8_t> payload =
        count > kModemStatusBytes
            ? std::span<const std::uint8_t>(read_buffer_)
                  .subspan(kModemStatusBytes, count - kModemStatusBytes)
            : std::span<const std::uint8_t>();
    const std::span<const std::uint8_t> expected(kHandshakeReply);
    answered = std::ranges::equal(payload, expected) ||
               (payload.size() == expected.size() + 1 && payload[0] == 0 &&
                std::ranges::equal(payload.subspan(1), expected));
  }
  if (!answered) {
    return Error{fmt::format(
        "Falcon: the firmware loader did not answer the handshake (sent 0a 43 "
        "0d {} times, expected 0a 44 2c 0d); unplug the Falcon's power and "
        "USB, plug them back in and try again",
        options_.handshake_attempts)};
  }
  if (Status s = Control(ftdi::kModemControl, ftdi::kDtrLow, "set DTR low");
      !s.ok()) {
    return s;
  }
  if (Status s = Control(ftdi::kBaudRate, ftdi::kBaud140000, "set 140000 baud");
      !s.ok()) {
    return s;
  }
  const std::uint8_t check[] = {kBaudCheck};
  if (DeviceStatus s = transport_->Write(check); !s.ok()) {
    return Error{fmt::format("Falcon: baud check write failed: {}", Reason(s))};
  }
  std::size_t count = 0;
  if (DeviceStatus s = transport_->Read(read_buffer_, &count); !s.ok()) {
    return Error{fmt::format("Falcon: baud check read failed: {}", Reason(s))};
  }
  if (count != kModemStatusBytes + 1 ||
      read_buffer_[kModemStatusBytes] != kBaudCheck) {
    return Error{fmt::format(
        "Falcon: the firmware loader did not echo 0x41 at 140000 baud (got {} "
        "bytes)",
        count < kModemStatusBytes ? 0 : count - kModemStatusBytes)};
  }
  return {};
}

Status FalconDevice::LoadFirmware(std::span<const std::uint8_t> image) {
  open_ = false;
  homed_ = false;
  if (image.empty()) return Error{"Falcon: the firmware image is empty"};
  if (Status s = SetFirmwareMode(); !s.ok()) return s;
  std::size_t sent = 0;
  while (sent < image.size()) {
    const std::span<const std::uint8_t> chunk =
        image.subspan(sent, std::min(kFirmwareChunkBytes, image.size() - sent));
    if (DeviceStatus s = transport_->Write(chunk); !s.ok()) {
      return Error{
          fmt::format("Falcon: firmware upload failed at byte {} of {}: {}",
                      sent, image.size(), Reason(s))};
    }
    // The loader echoes every byte; the echo may come in several reads.
    std::size_t echoed = 0;
    int empty_reads = 0;
    while (echoed < chunk.size()) {
      std::size_t count = 0;
      if (DeviceStatus s = transport_->Read(read_buffer_, &count); !s.ok()) {
        return Error{fmt::format(
            "Falcon: firmware upload failed reading the echo of byte {}: {}",
            sent + echoed, Reason(s))};
      }
      if (count <= kModemStatusBytes) {
        if (++empty_reads >= options_.max_echo_reads) {
          return Error{fmt::format(
              "Falcon: no echo of firmware byte {} of {} after {} reads",
              sent + echoed, image.size(), empty_reads)};
        }
        continue;
      }
      empty_reads = 0;
      for (std::size_t k = kModemStatusBytes; k < count; ++k) {
        if (echoed == chunk.size()) {
          return Error{fmt::format(
              "Falcon: the firmware loader echoed more bytes than sent after "
              "byte {}",
              sent + echoed)};
        }
        if (read_buffer_[k] != chunk[echoed]) {
          return Error{fmt::format(
              "Falcon: firmware echo mismatch at byte {}: sent 0x{:02x}, got "
              "0x{:02x}",
              sent + echoed, chunk[echoed], read_buffer_[k])};
        }
        ++echoed;
      }
    }
    sent += chunk.size();
  }
  if (Status s = SetRunningMode(); !s.ok()) return s;
  open_ = true;
  return {};
}

Status FalconDevice::LoadFirmwareFile(const std::string& path) {
  errno = 0;
  std::ifstream file(path, std::ios::binary);
  if (!file.is_open()) {
    return Error{fmt::format(
        "cannot open firmware file '{}'{}", path,
        errno != 0 ? std::string(": ") + std::strerror(errno) : std::string())};
  }
  std::vector<std::uint8_t> image;
  char byte = 0;
  while (file.get(byte)) {
    if (image.size() == options_.max_firmware_bytes) {
      return Error{fmt::format(
          "firmware file '{}' is larger than {} bytes; is it the Falcon "
          "firmware?",
          path, options_.max_firmware_bytes)};
    }
    image.push_back(static_cast<std::uint8_t>(byte));
  }
  if (file.bad()) {
    return Error{fmt::format("cannot read firmware file '{}'", path)};
  }
  if (image.empty()) {
    return Error{fmt::format("firmware file '{}' is empty", path)};
  }
  if (Status s = LoadFirmware(image); !s.ok()) {
    return Error{fmt::format("{}: {}", path, s.error().message)};
  }
  return {};
}

DeviceStatus FalconDevice::SendCommand() noexcept {
  const falcon::Packet packet = falcon::EncodeCommand(command_);
  const DeviceStatus status = transport_->Write(packet);
  if (status.ok()) awaiting_report_ = true;
  return status;
}

DeviceStatus FalconDevice::ReceiveOnce(bool* got) noexcept {
  *got = false;
  std::size_t count = 0;
  const DeviceStatus status = transport_->Read(read_buffer_, &count);
  if (!status.ok()) return status;
  count = std::min(count, read_buffer_.size());
  falcon::Packet packet;
  for (std::size_t k = kModemStatusBytes; k < count; ++k) {
    if (!assembler_.Push(read_buffer_[k], &packet)) continue;
    falcon::Report report;
    if (falcon::DecodeReport(packet, &report)) {
      report_ = report;
      *got = true;
    } else {
      ++invalid_reports_;
    }
  }
  if (*got) {
    awaiting_report_ = false;
    silent_reads_ = 0;
  }
  return {};
}

Status FalconDevice::Exchange() {
  if (DeviceStatus s = SendCommand(); !s.ok()) {
    return Error{fmt::format("Falcon: write failed: {}", Reason(s))};
  }
  for (int read = 0; read < options_.max_silent_reads; ++read) {
    bool got = false;
    if (DeviceStatus s = ReceiveOnce(&got); !s.ok()) {
      return Error{fmt::format("Falcon: read failed: {}", Reason(s))};
    }
    if (got) return {};
  }
  return Error{fmt::format("Falcon: no report after {} reads",
                           options_.max_silent_reads)};
}

Status FalconDevice::CheckFirmware(int attempts) {
  if (!open_) return Error{"Falcon: not opened"};
  command_ = falcon::Command{};
  for (int attempt = 0; attempt < attempts; ++attempt) {
    if (Exchange().ok()) return {};
  }
  return Error{fmt::format(
      "Falcon: no firmware answers ({} attempts); load the firmware file "
      "first",
      attempts)};
}

Status FalconDevice::Home(int max_packets) {
  if (!open_) return Error{"Falcon: not opened"};
  homed_ = false;
  command_ = falcon::Command{};
  command_.homing_mode = true;
  command_.leds = falcon::kRedLed;
  bool all_homed = false;
  for (int packet = 0; packet < max_packets && !all_homed; ++packet) {
    if (Status s = Exchange(); !s.ok()) return s;
    all_homed = (report_.homed & falcon::kAllHomed) == falcon::kAllHomed;
  }
  if (!all_homed) {
    const int count = ((report_.homed & 1) != 0) + ((report_.homed & 2) != 0) +
                      ((report_.homed & 4) != 0);
    return Error{fmt::format(
        "Falcon: not homed after {} packets ({} of 3 encoders found their "
        "index): move the grip all the way out, then push it straight in",
        max_packets, count)};
  }
  command_.homing_mode = false;
  command_.leds = falcon::kGreenLed;
  if (Status s = Exchange(); !s.ok()) return s;
  const glm::dvec3 angles(falcon::EncoderToAngleRad(report_.encoder[0]),
                          falcon::EncoderToAngleRad(report_.encoder[1]),
                          falcon::EncoderToAngleRad(report_.encoder[2]));
  glm::dvec3 position;
  if (!falcon::ForwardKinematics(angles, falcon::kWorkspaceCentreMm,
                                 &position)) {
    return Error{fmt::format(
        "Falcon: homed, but encoders {}, {}, {} give no end-effector position",
        report_.encoder[0], report_.encoder[1], report_.encoder[2])};
  }
  position_mm_ = position;
  homed_ = true;
  return {};
}

DeviceStatus FalconDevice::ReadPosition(glm::dvec3* position_mm) noexcept {
  if (!open_) return {DeviceCode::kNotReady, "Falcon not opened"};
  if (!homed_) return {DeviceCode::kNotReady, "Falcon not homed"};
  if (!awaiting_report_) {
    if (DeviceStatus s = SendCommand(); !s.ok()) return s;
  }
  bool got = false;
  if (DeviceStatus s = ReceiveOnce(&got); !s.ok()) return s;
  if (!got) {
    if (++silent_reads_ >= options_.max_silent_reads) {
      return {DeviceCode::kNoResponse,
              "no report from the Falcon for max_silent_reads reads"};
    }
    *position_mm = position_mm_;
    return {DeviceCode::kStale, "no new report this tick"};
  }
  const glm::dvec3 angles(falcon::EncoderToAngleRad(report_.encoder[0]),
                          falcon::EncoderToAngleRad(report_.encoder[1]),
                          falcon::EncoderToAngleRad(report_.encoder[2]));
  glm::dvec3 position;
  if (!falcon::ForwardKinematics(angles, position_mm_, &position)) {
    return {DeviceCode::kKinematicsFailed,
            "encoder angles with no end-effector position"};
  }
  position_mm_ = position;
  *position_mm = position;
  return {};
}

DeviceStatus FalconDevice::WriteForce(const glm::dvec3& force_n) noexcept {
  if (!open_) return {DeviceCode::kNotReady, "Falcon not opened"};
  if (!homed_) return {DeviceCode::kNotReady, "Falcon not homed"};
  DeviceStatus result;
  glm::dvec3 force = force_n;
  if (!sim::IsFinite(force)) {
    force = glm::dvec3(0.0);
    result = {DeviceCode::kInvalidArgument,
              "non-finite force refused; zero force sent"};
  } else if (const double magnitude_n = glm::length(force);
             magnitude_n > FalconSpec().max_force_n) {
    force *= FalconSpec().max_force_n / magnitude_n;
  }
  glm::dvec3 torques_n_m;
  if (falcon::ForceToTorques(position_mm_, force, &torques_n_m)) {
    command_.motor = falcon::TorquesToMotorCommands(torques_n_m);
  } else {
    command_.motor = {};
    result = {DeviceCode::kKinematicsFailed,
              "no Jacobian at the last position; zero force sent"};
  }
  if (DeviceStatus s = SendCommand(); !s.ok()) return s;
  return result;
}

}  // namespace burrlab::runner
