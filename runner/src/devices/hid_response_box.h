// The `hid` backend: a HID response box or gamepad through hidapi (hidraw on
// Linux). A reader thread timestamps each input report on arrival
// (CLOCK_MONOTONIC) and turns button changes into presses and releases
// through a configurable mapping from button number to key; an unplug (a read
// error or the device node gone) becomes an event, and Reconnect opens the
// same device again when it is back. Nothing here runs in the 1 kHz loop
// (hid_write can take milliseconds), so the event queue takes a lock.
#ifndef BURRLAB_RUNNER_DEVICES_HID_RESPONSE_BOX_H_
#define BURRLAB_RUNNER_DEVICES_HID_RESPONSE_BOX_H_

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::runner {

// One button of the box and the key it stands for.
struct HidButton {
  int number = 1;   // 1-based: bit (number - 1) of the button bytes
  std::string key;  // what StationController receives, e.g. "1" or "S"
};

struct HidBoxOptions {
  std::uint16_t vendor_id = 0;   // required
  std::uint16_t product_id = 0;  // required
  std::string serial;            // empty: the first box with these ids
  int button_offset = 0;  // byte of the report where the button bits start
  std::vector<HidButton> buttons;  // at least one
  int read_timeout_ms = 20;        // how often the reader checks for unplug

  // Names the first field that breaks its rule.
  Status Validate() const;
};

struct HidEvent {
  enum class Kind { kPress, kRelease, kUnplugged, kReplugged };
  Kind kind = Kind::kPress;
  std::string key;           // kPress/kRelease: the mapped key
  int button = 0;            // kPress/kRelease: the button number
  std::int64_t time_ns = 0;  // CLOCK_MONOTONIC when the report arrived
  std::string reason;        // kUnplugged: why
};

// A HID device as hidapi enumerates it.
struct HidDeviceInfo {
  std::string path;
  std::uint16_t vendor_id = 0;
  std::uint16_t product_id = 0;
  std::string serial;
  std::string manufacturer;
  std::string product;
};

// Every HID device hidapi sees (empty when none or hidapi fails).
std::vector<HidDeviceInfo> ListHidDevices();

// CLOCK_MONOTONIC in ns (the clock of HidEvent::time_ns).
std::int64_t MonotonicNowNs() noexcept;

class HidResponseBox {
 public:
  // Finds the box by ids (and serial), opens it and starts reading.
  static Result<std::unique_ptr<HidResponseBox>> Open(HidBoxOptions options);
  ~HidResponseBox();
  HidResponseBox(const HidResponseBox&) = delete;
  HidResponseBox& operator=(const HidResponseBox&) = delete;

  // The events since the last call, oldest first.
  std::vector<HidEvent> TakeEvents();
  // Whether the box is open and being read.
  bool connected() const { return connected_.load(); }
  // After an unplug: opens the box again if it is back (a kReplugged event);
  // an error says it is still missing.
  Status Reconnect();
  const std::string& path() const { return path_; }

 private:
  explicit HidResponseBox(HidBoxOptions options);
  Status OpenDevice();
  void Read() noexcept;
  void Push(HidEvent event);
  void StopReader();

  HidBoxOptions options_;
  void* device_ = nullptr;  // hid_device*
  std::string path_;
  std::thread reader_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> connected_{false};
  std::mutex mutex_;
  std::vector<HidEvent> events_;
  std::vector<bool> pressed_;
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_DEVICES_HID_RESPONSE_BOX_H_
