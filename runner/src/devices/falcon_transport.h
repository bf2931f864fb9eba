// The USB side of the Falcon: an FTDI FT232 serial bridge (USB id 0403:cb48).
// Set-up is a series of FTDI vendor control requests; data moves in bulk
// transfers, out on endpoint 0x02 and in on endpoint 0x81, where every
// transfer in starts with the FTDI's two modem-status bytes. FalconDevice
// speaks the protocol through this interface, so it is tested byte for byte
// with a fake; a libusb implementation plugs in behind it.
#ifndef BURRLAB_RUNNER_DEVICES_FALCON_TRANSPORT_H_
#define BURRLAB_RUNNER_DEVICES_FALCON_TRANSPORT_H_

#include <cstddef>
#include <cstdint>
#include <span>

#include "devices/device.h"

namespace burrlab::runner::falcon {

inline constexpr std::uint16_t kUsbVendorId = 0x0403;
inline constexpr std::uint16_t kUsbProductId = 0xcb48;
inline constexpr std::size_t kModemStatusBytes = 2;  // leading each read
inline constexpr std::size_t kMaxReadBytes = 64;     // one full-speed packet

// FTDI vendor requests (bmRequestType 0x40, host to device) and their values.
namespace ftdi {
inline constexpr std::uint8_t kReset = 0;           // value: what to purge
inline constexpr std::uint8_t kModemControl = 1;    // value: DTR/RTS bits
inline constexpr std::uint8_t kFlowControl = 2;     // value 0: none (in index)
inline constexpr std::uint8_t kBaudRate = 3;        // value: clock divisor
inline constexpr std::uint8_t kLineProperties = 4;  // value: bits/parity/stop
inline constexpr std::uint8_t kLatencyTimer = 9;    // value: ms

inline constexpr std::uint16_t kPurgeRx = 1;
inline constexpr std::uint16_t kPurgeTx = 2;
inline constexpr std::uint16_t kBaud9600 = 0x4138;
inline constexpr std::uint16_t kBaud140000 = 0x0015;  // firmware upload
inline constexpr std::uint16_t kBaudNormal = 0x0002;  // running firmware
inline constexpr std::uint16_t kLine8N1 = 0x0008;
inline constexpr std::uint16_t kFlowNone = 0x0000;
inline constexpr std::uint16_t kRtsLow = 0x0200;   // mask 0x02, value 0
inline constexpr std::uint16_t kDtrLow = 0x0100;   // mask 0x01, value 0
inline constexpr std::uint16_t kDtrHigh = 0x0101;  // mask 0x01, value 1
// The FTDI sends what it has every latency-timer period: at the default
// 16 ms the loop would be capped near 62 Hz, so running needs 1 ms.
inline constexpr std::uint16_t kLatencyRunningMs = 1;
inline constexpr std::uint16_t kLatencyFirmwareMs = 16;
}  // namespace ftdi

class Transport {
 public:
  virtual ~Transport() = default;
  // An FTDI vendor request without data.
  virtual DeviceStatus Control(std::uint8_t request, std::uint16_t value,
                               std::uint16_t index) noexcept = 0;
  // A bulk transfer out of all of `bytes`.
  virtual DeviceStatus Write(std::span<const std::uint8_t> bytes) noexcept = 0;
  // A bulk transfer in of at most buffer.size() bytes, the modem-status
  // bytes included; *count is how many arrived.
  virtual DeviceStatus Read(std::span<std::uint8_t> buffer,
                            std::size_t* count) noexcept = 0;
};

}  // namespace burrlab::runner::falcon

#endif  // BURRLAB_RUNNER_DEVICES_FALCON_TRANSPORT_H_
