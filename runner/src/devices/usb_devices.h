// Listing the USB devices on this computer (libusb), for `burrlab devices`.
#ifndef BURRLAB_RUNNER_DEVICES_USB_DEVICES_H_
#define BURRLAB_RUNNER_DEVICES_USB_DEVICES_H_

#include <cstdint>
#include <vector>

#include "burrlab/base/result.h"

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

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_USB_DEVICES_H_
