// The libusb backend against a Novint Falcon emulated by umockdev (ctest runs
// this binary under umockdev-wrapper, whose preload library redirects /sys,
// /dev and the usbdevfs ioctls): libusb enumerates the mocked FTDI bridge
// 0403:cb48 from its sysfs descriptors, `burrlab devices` reports it with the
// falcon backend, LibusbTransport opens and claims it, and the Falcon's FTDI
// set-up and packets travel as usbdevfs URBs that the test's ioctl handler
// answers like the device (control transfers acknowledged, bulk out taken,
// bulk in answered with the FTDI's two modem-status bytes and a report); a
// device that is gone answers ENODEV, which the transport reports as
// unplugged.
#include <gtest/gtest.h>
#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>
#include <umockdev.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "burrlab/runner/cli.h"
#include "cli/devices_command.h"
#include "devices/falcon_device.h"
#include "devices/falcon_packet.h"
#include "devices/libusb_transport.h"

namespace burrlab::runner {
namespace {

using Bytes = std::vector<std::uint8_t>;

// The Falcon's FTDI bridge as sysfs shows it: device descriptor 0403:cb48,
// one configuration, interface 0 with bulk endpoints 0x81 (in) and 0x02
// (out). A second, unrelated device (a receiver 046d:c52b) has no backend.
constexpr const char* kDevices =
    "P: /devices/pci0000:00/usb1/1-1\n"
    "N: bus/usb/001/002\n"
    "E: SUBSYSTEM=usb\n"
    "E: DEVTYPE=usb_device\n"
    "E: BUSNUM=001\n"
    "E: DEVNUM=002\n"
    "E: DEVNAME=/dev/bus/usb/001/002\n"
    "A: busnum=1\\n\n"
    "A: devnum=2\\n\n"
    "A: speed=12\\n\n"
    "A: bConfigurationValue=1\\n\n"
    "H: descriptors=12010002000000400304"
    "48cb000601020301"
    "09022000010100802d"
    "0904000002ffffff02"
    "07058102400000"
    "07050202400000\n"
    "\n"
    "P: /devices/pci0000:00/usb1/1-2\n"
    "N: bus/usb/001/003\n"
    "E: SUBSYSTEM=usb\n"
    "E: DEVTYPE=usb_device\n"
    "E: BUSNUM=001\n"
    "E: DEVNUM=003\n"
    "E: DEVNAME=/dev/bus/usb/001/003\n"
    "A: busnum=1\\n\n"
    "A: devnum=3\\n\n"
    "A: speed=12\\n\n"
    "A: bConfigurationValue=1\\n\n"
    "H: descriptors=1201000200000008"
    "6d042bc5001201020001"
    "09021200010100a032"
    "090400000003010102\n";

// One URB the host submitted.
struct Urb {
  unsigned char type = 0;  // USBDEVFS_URB_TYPE_*
  unsigned char endpoint = 0;
  Bytes bytes;     // control: the 8-byte setup packet; bulk out: the data
  int length = 0;  // buffer length
};

// The device's side of usbdevfs, called on umockdev's thread.
struct FalconUsb {
  std::mutex mutex;
  std::vector<Urb> submitted;
  std::deque<UMockdevIoctlData*> flying;
  std::deque<Bytes> in_data;  // bulk-in transfers still to answer
  int claimed = -1;
  bool gone = false;
};

gboolean OnIoctl(UMockdevIoctlBase*, UMockdevIoctlClient* client,
                 gpointer user) {
  auto* usb = static_cast<FalconUsb*>(user);
  std::lock_guard<std::mutex> lock(usb->mutex);
  const gulong request = umockdev_ioctl_client_get_request(client);
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  if (usb->gone) {
    umockdev_ioctl_client_complete(client, -1, ENODEV);
    return TRUE;
  }
  switch (request) {
    case USBDEVFS_GET_CAPABILITIES: {
      UMockdevIoctlData* d =
          umockdev_ioctl_data_resolve(arg, 0, sizeof(guint32), nullptr);
      *reinterpret_cast<guint32*>(d->data) = USBDEVFS_CAP_BULK_CONTINUATION |
                                             USBDEVFS_CAP_NO_PACKET_SIZE_LIM |
                                             USBDEVFS_CAP_REAP_AFTER_DISCONNECT;
      umockdev_ioctl_client_complete(client, 0, 0);
      umockdev_ioctl_data_unref(d);
      return TRUE;
    }
    case USBDEVFS_GETDRIVER:  // no kernel driver holds the interface
    case USBDEVFS_IOCTL:      // (USBDEVFS_DISCONNECT): nothing to detach
      umockdev_ioctl_client_complete(client, -1, ENODATA);
      return TRUE;
    case USBDEVFS_CLAIMINTERFACE: {
      UMockdevIoctlData* d =
          umockdev_ioctl_data_resolve(arg, 0, sizeof(unsigned int), nullptr);
      usb->claimed =
          static_cast<int>(*reinterpret_cast<unsigned int*>(d->data));
      umockdev_ioctl_client_complete(client, 0, 0);
      umockdev_ioctl_data_unref(d);
      return TRUE;
    }
    case USBDEVFS_RELEASEINTERFACE:
      umockdev_ioctl_client_complete(client, 0, 0);
      return TRUE;
    case USBDEVFS_SUBMITURB: {
      UMockdevIoctlData* urb_data =
          umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), nullptr);
      auto* urb = reinterpret_cast<usbdevfs_urb*>(urb_data->data);
      UMockdevIoctlData* buffer = umockdev_ioctl_data_resolve(
          urb_data, offsetof(usbdevfs_urb, buffer),
          static_cast<gsize>(urb->buffer_length), nullptr);
      Urb u;
      u.type = urb->type;
      u.endpoint = urb->endpoint;
      u.length = urb->buffer_length;
      const auto* b = buffer->data;
      if (urb->type == USBDEVFS_URB_TYPE_CONTROL) {
        u.bytes.assign(b, b + std::min(8, urb->buffer_length));
      } else if ((urb->endpoint & 0x80) == 0) {
        u.bytes.assign(b, b + urb->buffer_length);
      }
      usb->submitted.push_back(std::move(u));
      usb->flying.push_back(urb_data);  // keeps the reference
      umockdev_ioctl_data_unref(buffer);
      umockdev_ioctl_client_complete(client, 0, 0);
      return TRUE;
    }
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY: {
      if (usb->flying.empty()) {
        umockdev_ioctl_client_complete(client, -1, EAGAIN);
        return TRUE;
      }
      UMockdevIoctlData* urb_data = usb->flying.front();
      usb->flying.pop_front();
      auto* urb = reinterpret_cast<usbdevfs_urb*>(urb_data->data);
      urb->status = 0;
      if (urb->type == USBDEVFS_URB_TYPE_CONTROL) {
        urb->actual_length = 0;  // no data stage
      } else if ((urb->endpoint & 0x80) == 0) {
        urb->actual_length = urb->buffer_length;
      } else {
        // The FTDI's two modem-status bytes, then what the Falcon sent.
        Bytes answer = {0x31, 0x60};
        if (!usb->in_data.empty()) {
          answer.insert(answer.end(), usb->in_data.front().begin(),
                        usb->in_data.front().end());
          usb->in_data.pop_front();
        }
        const int n =
            std::min(static_cast<int>(answer.size()), urb->buffer_length);
        UMockdevIoctlData* buffer = umockdev_ioctl_data_resolve(
            urb_data, offsetof(usbdevfs_urb, buffer),
            static_cast<gsize>(urb->buffer_length), nullptr);
        std::memcpy(buffer->data, answer.data(), static_cast<std::size_t>(n));
        urb->actual_length = n;
        umockdev_ioctl_data_unref(buffer);
      }
      UMockdevIoctlData* pointer =
          umockdev_ioctl_data_resolve(arg, 0, sizeof(gpointer), nullptr);
      umockdev_ioctl_data_set_ptr(pointer, 0, urb_data);
      umockdev_ioctl_client_complete(client, 0, 0);
      umockdev_ioctl_data_unref(pointer);
      umockdev_ioctl_data_unref(urb_data);
      return TRUE;
    }
    case USBDEVFS_DISCARDURB:
      umockdev_ioctl_client_complete(client, -1, EINVAL);
      return TRUE;
    default:
      return FALSE;
  }
}

class FalconUsbTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* preload = std::getenv("LD_PRELOAD");
    if (preload == nullptr ||
        std::strstr(preload, "libumockdev-preload") == nullptr) {
      GTEST_SKIP() << "not under umockdev-wrapper: run this test through "
                      "ctest (Debian package umockdev)";
    }
    bed_ = umockdev_testbed_new();
    handler_ = umockdev_ioctl_base_new();
    g_signal_connect(handler_, "handle-ioctl",
                     reinterpret_cast<GCallback>(&OnIoctl), &usb_);
    GError* error = nullptr;
    // Before the device exists, so its node is the emulated one.
    ASSERT_TRUE(umockdev_testbed_attach_ioctl(bed_, "/dev/bus/usb/001/002",
                                              handler_, &error));
    ASSERT_TRUE(umockdev_testbed_add_from_string(bed_, kDevices, &error))
        << (error != nullptr ? error->message : "");
  }

  void TearDown() override {
    if (bed_ == nullptr) return;
    for (UMockdevIoctlData* d : usb_.flying) umockdev_ioctl_data_unref(d);
    g_object_unref(handler_);
    g_object_unref(bed_);
  }

  std::vector<Urb> Submitted() {
    std::lock_guard<std::mutex> lock(usb_.mutex);
    return usb_.submitted;
  }

  UMockdevTestbed* bed_ = nullptr;
  UMockdevIoctlBase* handler_ = nullptr;
  FalconUsb usb_;
};

TEST_F(FalconUsbTest, LibusbEnumeratesTheFalconAndDevicesNamesItsBackend) {
  const Result<std::vector<UsbDeviceInfo>> usb = ListUsbDevices();
  ASSERT_TRUE(usb.ok()) << usb.error().message;
  ASSERT_EQ(usb->size(), 2u);
  const Result<int> falcons = falcon::LibusbTransport::CountFalcons();
  ASSERT_TRUE(falcons.ok()) << falcons.error().message;
  EXPECT_EQ(falcons.value(), 1);

  std::ostringstream out, err;
  EXPECT_EQ(RunCli({"devices"}, out, err), 0) << err.str();
  const std::string text = out.str();
  EXPECT_NE(text.find("USB devices:\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  0403:cb48  bus 1 address 2  falcon (Novint "
                      "Falcon)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("  046d:c52b  bus 1 address 3  -\n"), std::string::npos)
      << text;
}

TEST_F(FalconUsbTest, OpensClaimsAndSendsTheFtdiSetUpAsControlTransfers) {
  Result<std::unique_ptr<falcon::LibusbTransport>> transport =
      falcon::LibusbTransport::Open(0);
  ASSERT_TRUE(transport.ok()) << transport.error().message;
  EXPECT_EQ(usb_.claimed, 0);
  FalconDevice falcon(transport->get());
  ASSERT_TRUE(falcon.Open().ok());
  // Vendor requests out (0x40): purge rx, purge tx, latency 1 ms, baud
  // divisor 2, purge rx, purge tx; wValue and wIndex little-endian.
  const std::vector<Bytes> setups = {
      {0x40, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00},
      {0x40, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00},
      {0x40, 0x09, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00},
      {0x40, 0x03, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00},
      {0x40, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00},
      {0x40, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00}};
  std::vector<Bytes> sent;
  for (const Urb& u : Submitted()) {
    EXPECT_EQ(u.type, USBDEVFS_URB_TYPE_CONTROL);
    EXPECT_EQ(u.endpoint, 0);
    sent.push_back(u.bytes);
  }
  EXPECT_EQ(sent, setups);
}

TEST_F(FalconUsbTest, PacketsTravelInBulkTransfersAndAFirmwareAnswers) {
  Result<std::unique_ptr<falcon::LibusbTransport>> transport =
      falcon::LibusbTransport::Open(0);
  ASSERT_TRUE(transport.ok()) << transport.error().message;
  FalconDevice falcon(transport->get());
  ASSERT_TRUE(falcon.Open().ok());
  const std::size_t setup_urbs = Submitted().size();
  falcon::Report report;
  report.encoder = {120, -340, 5};
  report.homed = falcon::kAllHomed;
  const falcon::Packet packet = falcon::EncodeReport(report);
  {
    std::lock_guard<std::mutex> lock(usb_.mutex);
    usb_.in_data.emplace_back(packet.begin(), packet.end());
  }
  ASSERT_TRUE(falcon.CheckFirmware(5).ok());
  EXPECT_EQ(falcon.last_report(), report);
  const std::vector<Urb> urbs = Submitted();
  ASSERT_GE(urbs.size(), setup_urbs + 2);
  // A zero-force command out on endpoint 0x02, then a read on 0x81.
  const Urb& out = urbs[setup_urbs];
  EXPECT_EQ(out.type, USBDEVFS_URB_TYPE_BULK);
  EXPECT_EQ(out.endpoint, 0x02);
  const falcon::Packet command = falcon::EncodeCommand(falcon.command());
  EXPECT_EQ(out.bytes, Bytes(command.begin(), command.end()));
  const Urb& in = urbs[setup_urbs + 1];
  EXPECT_EQ(in.type, USBDEVFS_URB_TYPE_BULK);
  EXPECT_EQ(in.endpoint, 0x81);
  EXPECT_EQ(in.length, static_cast<int>(falcon::kMaxReadBytes));
}

TEST_F(FalconUsbTest, ADeviceThatIsGoneIsReportedAsUnplugged) {
  Result<std::unique_ptr<falcon::LibusbTransport>> transport =
      falcon::LibusbTransport::Open(0);
  ASSERT_TRUE(transport.ok()) << transport.error().message;
  {
    std::lock_guard<std::mutex> lock(usb_.mutex);
    usb_.gone = true;
  }
  const Bytes bytes(16, 0x41);
  const DeviceStatus write = (*transport)->Write(bytes);
  EXPECT_EQ(write.code, DeviceCode::kUnplugged);
  EXPECT_STREQ(write.reason, "LIBUSB_ERROR_NO_DEVICE");
  EXPECT_EQ((*transport)->Control(0, 1, 0).code, DeviceCode::kUnplugged);
}

}  // namespace
}  // namespace burrlab::runner
