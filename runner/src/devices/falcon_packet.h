// The Novint Falcon's 16-byte packets (Novint SDK firmware), as described by
// libnifalcon's protocol notes. Both directions are printable: '<', twelve
// nibble bytes (three signed 16-bit values, least significant nibble first,
// each nibble sent as 'A' + nibble), one flags byte sent as 'A' + flags, one
// spare byte ('A' + 0), '>'. Host to Falcon: three motor commands, and LED and
// homing-mode bits. Falcon to host: three encoder counts, the grip buttons
// (low nibble) and which encoders are homed (bits 4-6).
#ifndef BURRLAB_RUNNER_DEVICES_FALCON_PACKET_H_
#define BURRLAB_RUNNER_DEVICES_FALCON_PACKET_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace burrlab::runner::falcon {

inline constexpr std::size_t kPacketBytes = 16;
using Packet = std::array<std::uint8_t, kPacketBytes>;

inline constexpr std::uint8_t kPacketStart = '<';
inline constexpr std::uint8_t kPacketEnd = '>';
inline constexpr std::uint8_t kNibbleBase = 'A';  // nibble 0 on the wire

// Flags of the command packet's byte 13.
inline constexpr std::uint8_t kHomingModeFlag = 0x01;
inline constexpr std::uint8_t kGreenLed = 0x02;
inline constexpr std::uint8_t kBlueLed = 0x04;
inline constexpr std::uint8_t kRedLed = 0x08;
// Bits of FalconReport::homed: encoder 1, 2 and 3 found their index.
inline constexpr std::uint8_t kAllHomed = 0x07;

// Host to Falcon.
struct Command {
  std::array<std::int16_t, 3> motor{};  // motor commands, signed counts
  std::uint8_t leds = 0;                // kGreenLed | kBlueLed | kRedLed
  bool homing_mode = false;             // ask the firmware to find the index

  bool operator==(const Command&) const = default;
};

// Falcon to host.
struct Report {
  std::array<std::int16_t, 3> encoder{};  // encoder counts of the three motors
  std::uint8_t buttons = 0;               // grip buttons, low nibble
  std::uint8_t homed = 0;                 // bit i: encoder i+1 is homed

  bool operator==(const Report&) const = default;
};

Packet EncodeCommand(const Command& command) noexcept;
// False when the framing or a nibble byte is wrong.
bool DecodeCommand(std::span<const std::uint8_t, kPacketBytes> packet,
                   Command* command) noexcept;
// The Falcon's side, for fakes and tests.
Packet EncodeReport(const Report& report) noexcept;
// False when the framing or a nibble byte is wrong.
bool DecodeReport(std::span<const std::uint8_t, kPacketBytes> packet,
                  Report* report) noexcept;

// Finds whole packets in a byte stream that may split them across reads or
// carry noise: skips to '<', keeps 16 bytes and accepts them when the last is
// '>'; anything else is dropped and counted.
class PacketAssembler {
 public:
  // Adds one byte; true when it completes a packet, then in `packet`.
  bool Push(std::uint8_t byte, Packet* packet) noexcept;
  // Forgets a partial packet.
  void Reset() noexcept { size_ = 0; }
  std::int64_t dropped() const { return dropped_; }

 private:
  Packet buffer_{};
  std::size_t size_ = 0;
  std::int64_t dropped_ = 0;  // malformed packets thrown away
};

}  // namespace burrlab::runner::falcon

#endif  // BURRLAB_RUNNER_DEVICES_FALCON_PACKET_H_
