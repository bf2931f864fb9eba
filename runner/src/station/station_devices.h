// The devices of a station run, opened before the subject window and the
// journal so a missing device fails the run at once with what is missing:
// `simulated` (the script's path), `mouse` (the window's cursor), `hid` (the
// cursor for the burr, the response box for answers), `falcon` (libusb
// transport, FTDI set-up, firmware from the user's file when none runs,
// homing).
#ifndef BURRLAB_RUNNER_STATION_STATION_DEVICES_H_
#define BURRLAB_RUNNER_STATION_STATION_DEVICES_H_

#include <memory>
#include <optional>
#include <string>

#include "burrlab/base/result.h"
#include "devices/falcon_device.h"
#include "devices/hid_response_box.h"
#include "devices/libusb_transport.h"
#include "devices/mouse_device.h"
#include "devices/simulated_device.h"
#include "station/station_file.h"
#include "station/station_script.h"

namespace burrlab::runner {

struct StationDeviceRequest {
  std::string backend;                     // mouse, hid, falcon or simulated
  const StationConfig* station = nullptr;  // the station file, if any
  const StationScript* script = nullptr;   // simulated: the script
  std::string firmware_path;           // falcon: loaded when no firmware runs
  int falcon_homing_packets = 60'000;  // falcon: a minute at 1 kHz
};

// What a station run holds open. `haptic` points at one of the others.
struct StationDevices {
  std::unique_ptr<SimulatedDevice> simulated;
  std::unique_ptr<MouseDevice> mouse;
  std::unique_ptr<HidResponseBox> box;
  std::unique_ptr<falcon::LibusbTransport> transport;
  std::unique_ptr<FalconDevice> falcon;
  HapticDevice* haptic = nullptr;
};

// Opens the request's devices; the error names the device and what is
// missing.
Result<StationDevices> OpenStationDevices(const StationDeviceRequest& request);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_DEVICES_H_
