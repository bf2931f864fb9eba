// The `falcon` device: a Novint Falcon running the Novint SDK firmware,
// driven through a Transport (FTDI over USB). Set-up (Open, LoadFirmware,
// CheckFirmware, Home) runs before the haptic loop and returns a Status with
// a full message; ReadPosition and WriteForce run inside the 1 kHz tick.
//
// One tick is one exchange: WriteForce sends a 16-byte command packet and the
// Falcon answers with one 16-byte report, which the next ReadPosition reads
// and turns into a position (encoders -> angles -> forward kinematics).
#ifndef BURRLAB_RUNNER_DEVICES_FALCON_DEVICE_H_
#define BURRLAB_RUNNER_DEVICES_FALCON_DEVICE_H_

#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <string>

#include "burrlab/base/result.h"
#include "devices/device.h"
#include "devices/falcon_packet.h"
#include "devices/falcon_transport.h"

namespace burrlab::runner {

struct FalconOptions {
  int max_silent_reads = 50;     // reads without a report before kNoResponse
  int handshake_attempts = 100;  // firmware-mode handshakes before giving up
  int max_echo_reads = 200;      // reads without echo during firmware upload
  std::size_t max_firmware_bytes = 256 * 1024;  // the real file is ~8 KiB
};

// The Falcon's limits: 8 N, 3 N/mm at 1 kHz; a box inside the reachable
// workspace of the delta mechanism, mm (libnifalcon's frame).
const DeviceSpec& FalconSpec();

class FalconDevice final : public HapticDevice {
 public:
  // `transport` must outlive the device.
  explicit FalconDevice(falcon::Transport* transport,
                        FalconOptions options = {});

  // FTDI set-up for a running firmware: purge both buffers, latency timer
  // 1 ms, baud divisor 2, purge again.
  Status Open();
  // Uploads a firmware image the user supplies: FTDI firmware mode (latency
  // 16 ms, 9600 baud 8N1, no flow control, RTS low, DTR pulse), the
  // handshake, 140000 baud, then the image in 62-byte chunks, each echoed
  // back and compared byte for byte; then Open's set-up again.
  Status LoadFirmware(std::span<const std::uint8_t> image);
  // Reads the file (bounded size) and uploads it.
  Status LoadFirmwareFile(const std::string& path);
  // Whether a firmware answers: exchanges zero-force packets until a valid
  // report arrives, at most `attempts` times.
  Status CheckFirmware(int attempts);
  // Homing: homing mode on and the red LED until all three encoders report
  // their index (the user moves the grip all the way out, then pushes it
  // straight in), at most `max_packets` exchanges; then the green LED.
  Status Home(int max_packets);

  const DeviceSpec& spec() const noexcept override { return FalconSpec(); }
  DeviceStatus ReadPosition(glm::dvec3* position_mm) noexcept override;
  DeviceStatus WriteForce(const glm::dvec3& force_n) noexcept override;

  bool homed() const { return homed_; }
  const falcon::Report& last_report() const { return report_; }
  const falcon::Command& command() const { return command_; }
  std::int64_t malformed_packets() const;

 private:
  // Sends command_ as one packet.
  DeviceStatus SendCommand() noexcept;
  // One read; *got is true when it completed at least one valid report.
  DeviceStatus ReceiveOnce(bool* got) noexcept;
  // SendCommand, then reads until a report or max_silent_reads.
  Status Exchange();
  Status Control(std::uint8_t request, std::uint16_t value, const char* what);
  Status SetRunningMode();
  Status SetFirmwareMode();

  falcon::Transport* transport_;
  FalconOptions options_;
  falcon::Command command_;
  falcon::Report report_;
  falcon::PacketAssembler assembler_;
  std::array<std::uint8_t, falcon::kMaxReadBytes> read_buffer_{};
  glm::dvec3 position_mm_;
  std::int64_t invalid_reports_ = 0;
  int silent_reads_ = 0;
  bool open_ = false;
  bool homed_ = false;
  bool awaiting_report_ = false;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_FALCON_DEVICE_H_
