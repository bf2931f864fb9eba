// hidapi response boxes: enumerate, open, timestamped reads, unplug, re-plug.
#include "devices/hid_response_box.h"

#include <fmt/format.h>
#include <hidapi.h>
#include <time.h>
#include <unistd.h>

#include <array>
#include <cwchar>
#include <set>

namespace burrlab::runner {
namespace {

std::string Narrow(const wchar_t* text) {
  if (text == nullptr) return "";
  std::string out;
  for (; *text != L'\0'; ++text) {
    const wchar_t c = *text;
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  return out;
}

hid_device* Handle(void* device) { return static_cast<hid_device*>(device); }

bool HidInit() {
  static const bool ok = hid_init() == 0;
  return ok;
}

}  // namespace

std::int64_t MonotonicNowNs() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

Status HidBoxOptions::Validate() const {
  if (vendor_id == 0 || product_id == 0) {
    return Error{fmt::format(
        "hid: vendor_id and product_id are required (got {:04x}:{:04x})",
        vendor_id, product_id)};
  }
  if (button_offset < 0 || button_offset > 63) {
    return Error{
        fmt::format("hid: button_offset {} is outside 0-63", button_offset)};
  }
  if (buttons.empty()) return Error{"hid: the button mapping is empty"};
  std::set<int> seen;
  for (const HidButton& b : buttons) {
    const int max_button = (64 - button_offset) * 8;
    if (b.number < 1 || b.number > max_button) {
      return Error{
          fmt::format("hid: button {} is outside 1-{}", b.number, max_button)};
    }
    if (!seen.insert(b.number).second) {
      return Error{fmt::format("hid: button {} is mapped twice", b.number)};
    }
    if (b.key.empty()) {
      return Error{fmt::format("hid: button {} has no key", b.number)};
    }
  }
  if (read_timeout_ms < 1 || read_timeout_ms > 1000) {
    return Error{fmt::format("hid: read_timeout_ms {} is outside 1-1000",
                             read_timeout_ms)};
  }
  return {};
}

std::vector<HidDeviceInfo> ListHidDevices() {
  std::vector<HidDeviceInfo> out;
  if (!HidInit()) return out;
  hid_device_info* list = hid_enumerate(0, 0);
  for (hid_device_info* d = list; d != nullptr; d = d->next) {
    HidDeviceInfo info;
    info.path = d->path != nullptr ? d->path : "";
    info.vendor_id = d->vendor_id;
    info.product_id = d->product_id;
    info.serial = Narrow(d->serial_number);
    info.manufacturer = Narrow(d->manufacturer_string);
    info.product = Narrow(d->product_string);
    out.push_back(std::move(info));
  }
  hid_free_enumeration(list);
  return out;
}

HidResponseBox::HidResponseBox(HidBoxOptions options)
    : options_(std::move(options)) {
  int max_button = 0;
  for (const HidButton& b : options_.buttons) {
    max_button = std::max(max_button, b.number);
  }
  pressed_.assign(static_cast<std::size_t>(max_button) + 1, false);
}

Result<std::unique_ptr<HidResponseBox>> HidResponseBox::Open(
    HidBoxOptions options) {
  if (Status s = options.Validate(); !s.ok()) return s.error();
  std::unique_ptr<HidResponseBox> box(new HidResponseBox(std::move(options)));
  if (Status s = box->OpenDevice(); !s.ok()) return s.error();
  return box;
}

HidResponseBox::~HidResponseBox() { StopReader(); }

void HidResponseBox::StopReader() {
  stop_ = true;
  if (reader_.joinable()) reader_.join();
  if (device_ != nullptr) {
    hid_close(Handle(device_));
    device_ = nullptr;
  }
  connected_ = false;
}

Status HidResponseBox::OpenDevice() {
  if (!HidInit()) return Error{"hid: hid_init failed"};
  std::string path;
  for (const HidDeviceInfo& d : ListHidDevices()) {
    if (d.vendor_id == options_.vendor_id &&
        d.product_id == options_.product_id &&
        (options_.serial.empty() || d.serial == options_.serial)) {
      path = d.path;
      break;
    }
  }
  const std::string which =
      fmt::format("{:04x}:{:04x}{}", options_.vendor_id, options_.product_id,
                  options_.serial.empty() ? "" : " serial " + options_.serial);
  if (path.empty()) {
    return Error{fmt::format("hid: no device {} is connected", which)};
  }
  hid_device* device = hid_open_path(path.c_str());
  if (device == nullptr) {
    return Error{fmt::format(
        "hid: cannot open {} ({}): {} (a udev rule with TAG+=\"uaccess\" "
        "gives non-root users access)",
        path, which, Narrow(hid_error(nullptr)))};
  }
  device_ = device;
  path_ = path;
  std::fill(pressed_.begin(), pressed_.end(), false);
  stop_ = false;
  connected_ = true;
  reader_ = std::thread([this] { Read(); });
  return {};
}

void HidResponseBox::Push(HidEvent event) {
  std::lock_guard<std::mutex> lock(mutex_);
  events_.push_back(std::move(event));
}

void HidResponseBox::Read() noexcept {
  std::array<unsigned char, 64> report{};
  while (!stop_) {
    const int n = hid_read_timeout(Handle(device_), report.data(),
                                   report.size(), options_.read_timeout_ms);
    const std::int64_t now_ns = MonotonicNowNs();
    if (n < 0 || access(path_.c_str(), F_OK) != 0) {
      HidEvent e;
      e.kind = HidEvent::Kind::kUnplugged;
      e.time_ns = now_ns;
      e.reason = n < 0 ? "read failed: " + Narrow(hid_error(Handle(device_)))
                       : "the device node " + path_ + " is gone";
      connected_ = false;
      Push(std::move(e));
      return;
    }
    for (const HidButton& b : options_.buttons) {
      const int byte = options_.button_offset + (b.number - 1) / 8;
      if (byte >= n) continue;
      const bool down =
          ((report[static_cast<std::size_t>(byte)] >> ((b.number - 1) % 8)) &
           1) != 0;
      const auto at = static_cast<std::size_t>(b.number);
      if (down == pressed_[at]) continue;
      pressed_[at] = down;
      HidEvent e;
      e.kind = down ? HidEvent::Kind::kPress : HidEvent::Kind::kRelease;
      e.key = b.key;
      e.button = b.number;
      e.time_ns = now_ns;
      Push(std::move(e));
    }
  }
}

std::vector<HidEvent> HidResponseBox::TakeEvents() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<HidEvent> out;
  out.swap(events_);
  return out;
}

Status HidResponseBox::Reconnect() {
  if (connected_) return {};
  StopReader();
  if (Status s = OpenDevice(); !s.ok()) return s;
  HidEvent e;
  e.kind = HidEvent::Kind::kReplugged;
  e.time_ns = MonotonicNowNs();
  Push(std::move(e));
  return {};
}

}  // namespace burrlab::runner
