// Falcon packet encoding and decoding.
#include "devices/falcon_packet.h"

namespace burrlab::runner::falcon {
namespace {

constexpr std::size_t kFlagsByte = 13;
constexpr std::size_t kSpareByte = 14;
constexpr std::uint8_t kLastNibble = kNibbleBase + 0x0f;  // 'P'

// Writes three signed 16-bit values into bytes 1..12, low nibble first.
void PutValues(const std::array<std::int16_t, 3>& values, Packet* packet) {
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto bits = static_cast<std::uint16_t>(values[axis]);
    for (std::size_t nibble = 0; nibble < 4; ++nibble) {
      (*packet)[1 + 4 * axis + nibble] = static_cast<std::uint8_t>(
          kNibbleBase + ((bits >> (4 * nibble)) & 0x0f));
    }
  }
}

// Reads bytes 1..12; false when one is outside 'A'..'P'.
bool GetValues(std::span<const std::uint8_t, kPacketBytes> packet,
               std::array<std::int16_t, 3>* values) {
  for (std::size_t axis = 0; axis < 3; ++axis) {
    std::uint16_t bits = 0;
    for (std::size_t nibble = 0; nibble < 4; ++nibble) {
      const std::uint8_t byte = packet[1 + 4 * axis + nibble];
      if (byte < kNibbleBase || byte > kLastNibble) return false;
      bits = static_cast<std::uint16_t>(bits | (byte - kNibbleBase)
                                                   << (4 * nibble));
    }
    (*values)[axis] = static_cast<std::int16_t>(bits);
  }
  return true;
}

bool Framed(std::span<const std::uint8_t, kPacketBytes> packet) {
  return packet[0] == kPacketStart && packet[kPacketBytes - 1] == kPacketEnd;
}

Packet Frame(std::uint8_t flags) {
  Packet packet{};
  packet[0] = kPacketStart;
  packet[kFlagsByte] = static_cast<std::uint8_t>(kNibbleBase + flags);
  packet[kSpareByte] = kNibbleBase;
  packet[kPacketBytes - 1] = kPacketEnd;
  return packet;
}

}  // namespace

Packet EncodeCommand(const Command& command) noexcept {
  const auto flags = static_cast<std::uint8_t>(
      (command.leds & (kGreenLed | kBlueLed | kRedLed)) |
      (command.homing_mode ? kHomingModeFlag : 0));
  Packet packet = Frame(flags);
  PutValues(command.motor, &packet);
  return packet;
}

bool DecodeCommand(std::span<const std::uint8_t, kPacketBytes> packet,
                   Command* command) noexcept {
  Command decoded;
  if (!Framed(packet) || !GetValues(packet, &decoded.motor)) return false;
  const std::uint8_t flags_byte = packet[kFlagsByte];
  if (flags_byte < kNibbleBase || flags_byte > kLastNibble) return false;
  const auto flags = static_cast<std::uint8_t>(flags_byte - kNibbleBase);
  decoded.leds = flags & (kGreenLed | kBlueLed | kRedLed);
  decoded.homing_mode = (flags & kHomingModeFlag) != 0;
  *command = decoded;
  return true;
}

Packet EncodeReport(const Report& report) noexcept {
  const auto flags = static_cast<std::uint8_t>((report.buttons & 0x0f) |
                                               ((report.homed & 0x07) << 4));
  Packet packet = Frame(flags);
  PutValues(report.encoder, &packet);
  return packet;
}

bool DecodeReport(std::span<const std::uint8_t, kPacketBytes> packet,
                  Report* report) noexcept {
  Report decoded;
  if (!Framed(packet) || !GetValues(packet, &decoded.encoder)) return false;
  // The flags byte carries homing bits above the nibble: 'A' .. 'A' + 0x7f.
  const std::uint8_t flags_byte = packet[kFlagsByte];
  if (flags_byte < kNibbleBase || flags_byte > kNibbleBase + 0x7f) return false;
  const auto flags = static_cast<std::uint8_t>(flags_byte - kNibbleBase);
  decoded.buttons = flags & 0x0f;
  decoded.homed = (flags >> 4) & 0x07;
  *report = decoded;
  return true;
}

bool PacketAssembler::Push(std::uint8_t byte, Packet* packet) noexcept {
  if (size_ == 0) {
    if (byte != kPacketStart) return false;  // noise between packets
    buffer_[size_++] = byte;
    return false;
  }
  if (size_ == kPacketBytes - 1) {
    size_ = 0;
    if (byte == kPacketEnd) {
      buffer_[kPacketBytes - 1] = byte;
      *packet = buffer_;
      return true;
    }
    ++dropped_;
    if (byte == kPacketStart) buffer_[size_++] = byte;
    return false;
  }
  if (byte == kPacketEnd || byte == kPacketStart) {  // too short
    ++dropped_;
    size_ = 0;
    if (byte == kPacketStart) buffer_[size_++] = byte;
    return false;
  }
  buffer_[size_++] = byte;
  return false;
}

}  // namespace burrlab::runner::falcon
