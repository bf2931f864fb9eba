// Listing USB devices with libusb.
#include "devices/usb_devices.h"

#include <fmt/format.h>
#include <libusb.h>

namespace burrlab::runner {

Result<std::vector<UsbDeviceInfo>> ListUsbDevices() {
  libusb_context* context = nullptr;
  if (const int rc = libusb_init(&context); rc != 0) {
    return Error{fmt::format("libusb cannot start: {}", libusb_error_name(rc))};
  }
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(context, &list);
  if (n < 0) {
    libusb_exit(context);
    return Error{fmt::format("cannot list USB devices: {}",
                             libusb_error_name(static_cast<int>(n)))};
  }
  std::vector<UsbDeviceInfo> out;
  for (ssize_t k = 0; k < n; ++k) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(list[k], &d) != 0) continue;
    out.push_back({d.idVendor, d.idProduct, libusb_get_bus_number(list[k]),
                   libusb_get_device_address(list[k])});
  }
  libusb_free_device_list(list, 1);
  libusb_exit(context);
  return out;
}

}  // namespace burrlab::runner
