// `burrlab devices`: the USB and HID devices on this computer with their
// vendor/product ids and the burrlab backend that fits each (falcon for the
// Novint Falcon's FTDI bridge, hid for HID response boxes and gamepads), and
// the backends that need no hardware (mouse, simulated).
#ifndef BURRLAB_RUNNER_DEVICES_COMMAND_H_
#define BURRLAB_RUNNER_DEVICES_COMMAND_H_

#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "command_table.h"
#include "devices/hid_response_box.h"

namespace burrlab::runner {

// A USB device as libusb lists it.
struct UsbDeviceInfo {
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
  int bus = 0;
  int address = 0;
};

// Every USB device libusb sees; an error when libusb cannot start.
Result<std::vector<UsbDeviceInfo>> ListUsbDevices();

// The listing as `burrlab devices` prints it; `usb_error` replaces the USB
// part when libusb could not list.
std::string FormatDeviceList(const std::vector<UsbDeviceInfo>& usb,
                             const std::optional<std::string>& usb_error,
                             const std::vector<HidDeviceInfo>& hid);

int RunDevicesCommand(const Args& args, std::ostream& out, std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_COMMAND_H_
