// Listing USB and HID devices and the backend for each.
#include "cli/devices_command.h"

#include <fmt/format.h>

#include "devices/falcon_transport.h"

namespace burrlab::runner {

std::string FormatDeviceList(const std::vector<UsbDeviceInfo>& usb,
                             const std::optional<std::string>& usb_error,
                             const std::vector<HidDeviceInfo>& hid) {
  std::string text = "USB devices:\n";
  if (usb_error.has_value()) {
    text += fmt::format("  (not listed: {})\n", *usb_error);
  } else if (usb.empty()) {
    text += "  none\n";
  }
  for (const UsbDeviceInfo& d : usb) {
    const bool falcon = d.vendor_id == falcon::kUsbVendorId &&
                        d.product_id == falcon::kUsbProductId;
    text += fmt::format("  {:04x}:{:04x}  bus {} address {}  {}\n", d.vendor_id,
                        d.product_id, d.bus, d.address,
                        falcon ? "falcon (Novint Falcon)" : "-");
  }
  text += "HID devices:\n";
  if (hid.empty()) text += "  none\n";
  for (const HidDeviceInfo& d : hid) {
    std::string name = d.manufacturer;
    if (!d.product.empty()) name += (name.empty() ? "" : " ") + d.product;
    text += fmt::format("  {:04x}:{:04x}  {}  \"{}\"{}  hid\n", d.vendor_id,
                        d.product_id, d.path, name,
                        d.serial.empty() ? "" : " serial " + d.serial);
  }
  text +=
      "Always available: mouse (mouse and keyboard, no force feedback), "
      "simulated (scripted positions)\n";
  return text;
}

int RunDevicesCommand(const Args& args, std::ostream& out, std::ostream& err) {
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h")) {
    out << "usage: burrlab devices\n\nLists USB and HID devices with their "
           "vendor:product ids and the burrlab backend that fits each.\n";
    return 0;
  }
  if (!args.empty()) {
    return Fail(err,
                fmt::format("devices takes no arguments, got '{}'", args[0]));
  }
  Result<std::vector<UsbDeviceInfo>> usb = ListUsbDevices();
  out << FormatDeviceList(
      usb.ok() ? usb.value() : std::vector<UsbDeviceInfo>{},
      usb.ok() ? std::nullopt : std::optional<std::string>(usb.error().message),
      ListHidDevices());
  return 0;
}

}  // namespace burrlab::runner
