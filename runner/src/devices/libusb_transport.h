// The Falcon's Transport over libusb-1.0: claims interface 0 of the FTDI
// bridge (USB 0403:cb48), sends its vendor requests as control transfers and
// moves data in bulk transfers (out 0x02, in 0x81). A vanished device
// (LIBUSB_ERROR_NO_DEVICE) is reported as kUnplugged; a read that times out
// returns no bytes and lets FalconDevice count the silence.
#ifndef BURRLAB_RUNNER_DEVICES_LIBUSB_TRANSPORT_H_
#define BURRLAB_RUNNER_DEVICES_LIBUSB_TRANSPORT_H_

#include <memory>

#include "burrlab/base/result.h"
#include "devices/falcon_transport.h"

struct libusb_context;
struct libusb_device_handle;

namespace burrlab::runner::falcon {

class LibusbTransport final : public Transport {
 public:
  // Opens the index-th Falcon on the bus (0 = the first).
  static Result<std::unique_ptr<LibusbTransport>> Open(int index);
  // How many Falcons are on the bus; an error when libusb cannot start.
  static Result<int> CountFalcons();
  ~LibusbTransport() override;
  LibusbTransport(const LibusbTransport&) = delete;
  LibusbTransport& operator=(const LibusbTransport&) = delete;

  DeviceStatus Control(std::uint8_t request, std::uint16_t value,
                       std::uint16_t index) noexcept override;
  DeviceStatus Write(std::span<const std::uint8_t> bytes) noexcept override;
  DeviceStatus Read(std::span<std::uint8_t> buffer,
                    std::size_t* count) noexcept override;

 private:
  LibusbTransport(libusb_context* context, libusb_device_handle* handle)
      : context_(context), handle_(handle) {}

  libusb_context* context_;
  libusb_device_handle* handle_;
};

}  // namespace burrlab::runner::falcon

#endif  // BURRLAB_RUNNER_DEVICES_LIBUSB_TRANSPORT_H_
