// Falcon packets byte for byte against hand-worked examples of the protocol
// description (libnifalcon's notes on the Novint SDK firmware): nibbles as
// 'A' + nibble, least significant first; '<' and '>' framing.
#include "devices/falcon_packet.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace burrlab::runner::falcon {
namespace {

std::string Text(const Packet& packet) {
  return std::string(packet.begin(), packet.end());
}

Packet FromText(const std::string& text) {
  Packet packet{};
  for (std::size_t k = 0; k < kPacketBytes; ++k) {
    packet[k] = static_cast<std::uint8_t>(text.at(k));
  }
  return packet;
}

TEST(FalconPacket, ZeroCommandIsAllA) {
  EXPECT_EQ(Text(EncodeCommand(Command{})), "<AAAAAAAAAAAAAA>");
}

TEST(FalconPacket, EncodesMotorsLedsAndHomingByHand) {
  // 1447 = 0x05A7 -> nibbles 7 A 5 0 -> H K F A; -1 = 0xFFFF -> P P P P;
  // 0x1234 -> 4 3 2 1 -> E D C B; flags red 8 | green 2 | homing 1 = 0xB -> L.
  Command command;
  command.motor = {1447, -1, 0x1234};
  command.leds = kRedLed | kGreenLed;
  command.homing_mode = true;
  EXPECT_EQ(Text(EncodeCommand(command)), "<HKFAPPPPEDCBLA>");
  // Blue alone: flags 4 -> E; int16 minimum 0x8000 -> A A A I.
  Command blue;
  blue.motor = {-32768, 0, 32767};  // 0x7FFF -> P P P H
  blue.leds = kBlueLed;
  EXPECT_EQ(Text(EncodeCommand(blue)), "<AAAIAAAAPPPHEA>");
}

TEST(FalconPacket, DecodesTheWorkedEncoderExample) {
  // The protocol notes' example: bytes 4A 46 4B 50 ('J' 'F' 'K' 'P') minus
  // 0x41 are 9 5 A F, low nibble first 0xFA59, the signed 16-bit -1447 (the
  // notes' test program shows its magnitude, 1447).
  Report report;
  ASSERT_TRUE(DecodeReport(FromText("<JFKPAAAAAAAAAA>"), &report));
  EXPECT_EQ(report.encoder[0], -1447);
  EXPECT_EQ(report.encoder[1], 0);
  EXPECT_EQ(report.encoder[2], 0);
  EXPECT_EQ(report.buttons, 0);
  EXPECT_EQ(report.homed, 0);
}

TEST(FalconPacket, ReportFlagsCarryButtonsLowAndHomingHigh) {
  // Buttons 0x5 and all three encoders homed (0x7 << 4): 'A' + 0x75 = 0xB6.
  Packet packet = FromText("<AAAAAAAAAAAAAA>");
  packet[13] = 0xB6;
  Report report;
  ASSERT_TRUE(DecodeReport(packet, &report));
  EXPECT_EQ(report.buttons, 0x5);
  EXPECT_EQ(report.homed, kAllHomed);
  Report expected;
  expected.buttons = 0x5;
  expected.homed = kAllHomed;
  EXPECT_EQ(EncodeReport(expected), packet);
}

TEST(FalconPacket, RoundTripsEveryNibblePattern) {
  for (int value = -32768; value <= 32767; value += 257) {
    Command command;
    command.motor = {static_cast<std::int16_t>(value),
                     static_cast<std::int16_t>(-value - 1),
                     static_cast<std::int16_t>(value / 3)};
    command.leds = static_cast<std::uint8_t>((value & 0x7) << 1);
    command.homing_mode = (value & 1) != 0;
    Command decoded;
    ASSERT_TRUE(DecodeCommand(EncodeCommand(command), &decoded));
    EXPECT_EQ(decoded, command);
    Report report;
    report.encoder = command.motor;
    report.buttons = static_cast<std::uint8_t>(value & 0xf);
    report.homed = static_cast<std::uint8_t>((value >> 4) & 0x7);
    Report decoded_report;
    ASSERT_TRUE(DecodeReport(EncodeReport(report), &decoded_report));
    EXPECT_EQ(decoded_report, report);
  }
}

TEST(FalconPacket, RejectsBadFramingAndNibbles) {
  Report report;
  EXPECT_FALSE(DecodeReport(FromText("AAAAAAAAAAAAAAA>"), &report));
  EXPECT_FALSE(DecodeReport(FromText("<AAAAAAAAAAAAAAA"), &report));
  EXPECT_FALSE(DecodeReport(FromText("<AAAAAQAAAAAAAA>"), &report));  // 0x51
  EXPECT_FALSE(DecodeReport(FromText("<AAAAAAAAAAA@AA>"), &report));  // 0x40
  Command command;
  EXPECT_FALSE(DecodeCommand(FromText("<AAAAAAAAAAAAQA>"), &command));
}

TEST(FalconPacket, AssemblerFindsPacketsSplitAndAmongNoise) {
  const std::string stream =
      "xx<JFKP"           // noise, then a packet split here...
      "AAAAAAAAAA>"       // ...and finished here
      "<AAA>"             // too short: dropped
      "<AAAAAAAAAAAAAA<"  // 16th byte is not '>': dropped, restarts
      "AAAAAAAAAAAAAA>";  // completes the packet begun by that '<'
  PacketAssembler assembler;
  std::vector<std::string> packets;
  Packet packet;
  for (char c : stream) {
    if (assembler.Push(static_cast<std::uint8_t>(c), &packet)) {
      packets.push_back(Text(packet));
    }
  }
  ASSERT_EQ(packets.size(), 2u);
  EXPECT_EQ(packets[0], "<JFKPAAAAAAAAAA>");
  EXPECT_EQ(packets[1], "<AAAAAAAAAAAAAA>");
  EXPECT_EQ(assembler.dropped(), 2);
}

}  // namespace
}  // namespace burrlab::runner::falcon
