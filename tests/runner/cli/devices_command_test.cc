// `burrlab devices`: the listing's text, and the command on this computer.
#include "cli/devices_command.h"

#include <gtest/gtest.h>

#include "run_cli.h"

namespace burrlab::runner {
namespace {

TEST(FormatDeviceList, NamesTheBackendOfEachDevice) {
  HidDeviceInfo box;
  box.path = "/dev/hidraw0";
  box.vendor_id = 0x16c0;
  box.product_id = 0x05df;
  box.manufacturer = "Lab";
  box.product = "Response box";
  box.serial = "RB7";
  EXPECT_EQ(FormatDeviceList({{0x0403, 0xcb48, 1, 4}, {0x1d6b, 0x0002, 1, 1}},
                             std::nullopt, {box}),
            "USB devices:\n"
            "  0403:cb48  bus 1 address 4  falcon (Novint Falcon)\n"
            "  1d6b:0002  bus 1 address 1  -\n"
            "HID devices:\n"
            "  16c0:05df  /dev/hidraw0  \"Lab Response box\" serial RB7  hid\n"
            "Always available: mouse (mouse and keyboard, no force feedback), "
            "simulated (scripted positions)\n");
}

TEST(FormatDeviceList, SaysWhyUsbWasNotListed) {
  EXPECT_EQ(FormatDeviceList({}, "libusb cannot start: LIBUSB_ERROR_OTHER", {}),
            "USB devices:\n"
            "  (not listed: libusb cannot start: LIBUSB_ERROR_OTHER)\n"
            "HID devices:\n"
            "  none\n"
            "Always available: mouse (mouse and keyboard, no force feedback), "
            "simulated (scripted positions)\n");
}

TEST(DevicesCommand, ListsWhatThisComputerHas) {
  const CliRun run = RunBurrlab({"devices"});
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_TRUE(run.out.starts_with("USB devices:\n")) << run.out;
  EXPECT_NE(run.out.find("\nHID devices:\n"), std::string::npos);
  EXPECT_NE(run.out.find("Always available: mouse"), std::string::npos);
}

TEST(DevicesCommand, RefusesArguments) {
  const CliRun run = RunBurrlab({"devices", "--all"});
  EXPECT_EQ(run.code, 1);
  EXPECT_EQ(run.err, "burrlab: devices takes no arguments, got '--all'\n");
}

}  // namespace
}  // namespace burrlab::runner
