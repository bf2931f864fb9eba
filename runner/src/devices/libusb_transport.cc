// libusb-1.0 behind the Falcon transport.
#include "devices/libusb_transport.h"

#include <fmt/format.h>
#include <libusb.h>

#include <limits>

namespace burrlab::runner::falcon {
namespace {

constexpr std::uint8_t kVendorOut = 0x40;  // LIBUSB_REQUEST_TYPE_VENDOR, out
constexpr unsigned char kEndpointOut = 0x02;
constexpr unsigned char kEndpointIn = 0x81;
constexpr unsigned kControlTimeoutMs = 1000;
constexpr unsigned kWriteTimeoutMs = 100;
constexpr unsigned kReadTimeoutMs = 1;  // inside the 1 kHz tick

// libusb's error names are static strings, so a status can carry them.
DeviceStatus FromLibusb(int rc) noexcept {
  if (rc >= 0) return {};
  const char* name = libusb_error_name(rc);
  if (rc == LIBUSB_ERROR_NO_DEVICE) return {DeviceCode::kUnplugged, name};
  return {DeviceCode::kIoError, name};
}

// Calls `visit(device)` for each Falcon on the bus; returns the count or a
// libusb error code.
template <typename Visit>
int ForEachFalcon(libusb_context* context, Visit visit) {
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(context, &list);
  if (n < 0) return static_cast<int>(n);
  int count = 0;
  for (ssize_t k = 0; k < n; ++k) {
    libusb_device_descriptor descriptor{};
    if (libusb_get_device_descriptor(list[k], &descriptor) != 0) continue;
    if (descriptor.idVendor == kUsbVendorId &&
        descriptor.idProduct == kUsbProductId) {
      if (!visit(list[k], count)) break;
      ++count;
    }
  }
  libusb_free_device_list(list, 1);
  return count;
}

Result<libusb_context*> Init() {
  libusb_context* context = nullptr;
  if (const int rc = libusb_init(&context); rc != 0) {
    return Error{
        fmt::format("Falcon: libusb cannot start: {}", libusb_error_name(rc))};
  }
  return context;
}

}  // namespace

Result<int> LibusbTransport::CountFalcons() {
  Result<libusb_context*> context = Init();
  if (!context.ok()) return context.error();
  const int count =
      ForEachFalcon(*context, [](libusb_device*, int) { return true; });
  libusb_exit(*context);
  if (count < 0) {
    return Error{fmt::format("Falcon: cannot list USB devices: {}",
                             libusb_error_name(count))};
  }
  return count;
}

Result<std::unique_ptr<LibusbTransport>> LibusbTransport::Open(int index) {
  Result<libusb_context*> context = Init();
  if (!context.ok()) return context.error();
  libusb_device* found = nullptr;
  const int count = ForEachFalcon(*context, [&](libusb_device* device, int k) {
    if (k == index) found = libusb_ref_device(device);
    return found == nullptr;
  });
  if (found == nullptr) {
    libusb_exit(*context);
    if (count < 0) {
      return Error{fmt::format("Falcon: cannot list USB devices: {}",
                               libusb_error_name(count))};
    }
    return Error{fmt::format(
        "Falcon: no Novint Falcon (USB {:04x}:{:04x}) number {} on the bus "
        "({} found)",
        kUsbVendorId, kUsbProductId, index, count)};
  }
  libusb_device_handle* handle = nullptr;
  int rc = libusb_open(found, &handle);
  libusb_unref_device(found);
  if (rc != 0) {
    libusb_exit(*context);
    return Error{fmt::format("Falcon: cannot open USB {:04x}:{:04x}: {}{}",
                             kUsbVendorId, kUsbProductId, libusb_error_name(rc),
                             rc == LIBUSB_ERROR_ACCESS
                                 ? " (add a udev rule with TAG+=\"uaccess\")"
                                 : "")};
  }
  libusb_set_auto_detach_kernel_driver(handle, 1);  // ftdi_sio may hold it
  if ((rc = libusb_claim_interface(handle, 0)) != 0) {
    libusb_close(handle);
    libusb_exit(*context);
    return Error{fmt::format("Falcon: cannot claim USB interface 0: {}",
                             libusb_error_name(rc))};
  }
  return std::unique_ptr<LibusbTransport>(
      new LibusbTransport(*context, handle));
}

LibusbTransport::~LibusbTransport() {
  libusb_release_interface(handle_, 0);
  libusb_close(handle_);
  libusb_exit(context_);
}

DeviceStatus LibusbTransport::Control(std::uint8_t request, std::uint16_t value,
                                      std::uint16_t index) noexcept {
  return FromLibusb(libusb_control_transfer(handle_, kVendorOut, request, value,
                                            index, nullptr, 0,
                                            kControlTimeoutMs));
}

DeviceStatus LibusbTransport::Write(
    std::span<const std::uint8_t> bytes) noexcept {
  if (bytes.size() >
      static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    return {DeviceCode::kInvalidArgument, "write larger than a transfer"};
  }
  int sent = 0;
  // libusb takes a non-const buffer for both directions; it does not write
  // to an out transfer.
  const int rc = libusb_bulk_transfer(
      handle_, kEndpointOut, const_cast<unsigned char*>(bytes.data()),
      static_cast<int>(bytes.size()), &sent, kWriteTimeoutMs);
  if (rc != 0) return FromLibusb(rc);
  if (static_cast<std::size_t>(sent) != bytes.size()) {
    return {DeviceCode::kIoError, "short bulk write"};
  }
  return {};
}

DeviceStatus LibusbTransport::Read(std::span<std::uint8_t> buffer,
                                   std::size_t* count) noexcept {
  int received = 0;
  const int rc = libusb_bulk_transfer(
      handle_, kEndpointIn, buffer.data(),
      static_cast<int>(std::min<std::size_t>(buffer.size(), kMaxReadBytes)),
      &received, kReadTimeoutMs);
  *count = static_cast<std::size_t>(received);
  if (rc == LIBUSB_ERROR_TIMEOUT) return {};  // silence, counted upstream
  return FromLibusb(rc);
}

}  // namespace burrlab::runner::falcon
