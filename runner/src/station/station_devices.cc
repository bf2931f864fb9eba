// Opening a station's devices.
#include "station/station_devices.h"

#include <fmt/format.h>

#include <filesystem>

#include "station/station_session.h"

namespace burrlab::runner {
namespace {

// The cursor moves the burr over the block; the top of the workspace holds
// it 4 mm above the surface, each wheel step lowers it 0.5 mm and the left
// button 3 mm.
MouseDeviceOptions CursorOptions(double max_force_n) {
  MouseDeviceOptions o;
  o.workspace =
      Workspace{glm::dvec3(-kBlockHalfWidthMm, -kBlockHalfWidthMm, -8.0),
                glm::dvec3(kBlockHalfWidthMm, kBlockHalfWidthMm, 4.0)};
  o.max_force_n = max_force_n;
  return o;
}

Result<StationDevices> OpenFalcon(const StationDeviceRequest& r) {
  StationDevices d;
  Result<std::unique_ptr<falcon::LibusbTransport>> transport =
      falcon::LibusbTransport::Open(0);
  if (!transport.ok()) {
    std::string why = transport.error().message;
    if (why.starts_with("Falcon: ")) why.erase(0, 8);
    return Error{fmt::format(
        "cannot use the Falcon: {}; connect it and check that `burrlab "
        "devices` lists it",
        why)};
  }
  d.transport = std::move(transport.value());
  if (!r.firmware_path.empty()) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(r.firmware_path, ec)) {
      return Error{
          fmt::format("cannot use the Falcon: firmware file {} not found",
                      r.firmware_path)};
    }
  }
  d.falcon = std::make_unique<FalconDevice>(d.transport.get());
  if (Status s = d.falcon->Open(); !s.ok()) {
    return Error{"cannot use the Falcon: " + s.error().message};
  }
  if (Status s = d.falcon->CheckFirmware(20); !s.ok()) {
    if (r.firmware_path.empty()) {
      return Error{fmt::format(
          "cannot use the Falcon: no firmware answers ({}); give the "
          "firmware file with --firmware FILE",
          s.error().message)};
    }
    if (Status l = d.falcon->LoadFirmwareFile(r.firmware_path); !l.ok()) {
      return Error{"cannot use the Falcon: " + l.error().message};
    }
    if (Status c = d.falcon->CheckFirmware(100); !c.ok()) {
      return Error{fmt::format(
          "cannot use the Falcon: the firmware from {} does not answer: {}",
          r.firmware_path, c.error().message)};
    }
  }
  if (Status s = d.falcon->Home(r.falcon_homing_packets); !s.ok()) {
    return Error{"cannot use the Falcon: homing failed: " + s.error().message};
  }
  d.haptic = d.falcon.get();
  return d;
}

}  // namespace

Result<StationDevices> OpenStationDevices(const StationDeviceRequest& r) {
  const double max_force_n =
      r.station != nullptr ? r.station->max_force_n : 8.0;
  if (r.backend == "simulated") {
    if (r.script == nullptr) {
      return Error{"the simulated device needs a station script"};
    }
    SimulatedDeviceOptions o;
    o.positions_mm = SampleWaypoints(r.script->path, 1000.0);
    StationDevices d;
    d.simulated = std::make_unique<SimulatedDevice>(std::move(o));
    d.haptic = d.simulated.get();
    return d;
  }
  if (r.backend == "mouse" || r.backend == "hid") {
    StationDevices d;
    d.mouse = std::make_unique<MouseDevice>(CursorOptions(max_force_n));
    d.haptic = d.mouse.get();
    if (r.backend == "hid") {
      if (r.station == nullptr || !r.station->response_box.has_value()) {
        return Error{
            "the hid backend needs a station file with a "
            "[response_box] table"};
      }
      Result<std::unique_ptr<HidResponseBox>> box =
          HidResponseBox::Open(*r.station->response_box);
      if (!box.ok()) {
        return Error{"cannot use the response box: " + box.error().message};
      }
      d.box = std::move(box.value());
    }
    return d;
  }
  if (r.backend == "falcon") return OpenFalcon(r);
  return Error{fmt::format("unknown device backend '{}'", r.backend)};
}

}  // namespace burrlab::runner
