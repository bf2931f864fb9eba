// `burrlab devices`: the USB and HID devices on this computer with their
// vendor/product ids and the burrlab backend that fits each (falcon for the
// Novint Falcon's FTDI bridge, hid for HID response boxes and gamepads), and
// the backends that need no hardware (mouse, simulated).
#ifndef BURRLAB_RUNNER_CLI_DEVICES_COMMAND_H_
#define BURRLAB_RUNNER_CLI_DEVICES_COMMAND_H_

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cli/command_table.h"
#include "devices/hid_response_box.h"
#include "devices/usb_devices.h"

namespace burrlab::runner {

// The listing as `burrlab devices` prints it; `usb_error` replaces the USB
// part when libusb could not list.
std::string FormatDeviceList(const std::vector<UsbDeviceInfo>& usb,
                             const std::optional<std::string>& usb_error,
                             const std::vector<HidDeviceInfo>& hid);

int RunDevicesCommand(const Args& args, std::ostream& out, std::ostream& err);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_CLI_DEVICES_COMMAND_H_
