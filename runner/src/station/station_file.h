// Station files (`station.toml`, format "burrlab-station/1"): which haptic
// device, its force limit, the response box and its button mapping, and the
// screen. Untrusted input: parsed from (path, text) with every problem
// reported as a Diagnostic (line, column, what is wrong and what is
// accepted), in the style of protocol files.
#ifndef BURRLAB_RUNNER_STATION_STATION_FILE_H_
#define BURRLAB_RUNNER_STATION_STATION_FILE_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/protocols/protocol.h"
#include "devices/hid_response_box.h"

namespace burrlab::runner {

inline constexpr std::string_view kStationFormat = "burrlab-station/1";

struct StationConfig {
  std::string device = "mouse";  // mouse, hid, falcon or simulated
  double max_force_n = 8.0;      // clamp of the haptic loop, N (0-20]
  // Stiffest contact rendered, N/mm (0-50]; 0 = the device's own limit.
  double max_stiffness_n_per_mm = 0.0;
  std::optional<HidBoxOptions> response_box;  // [response_box], when given
  int screen_width = 1280;                    // pixels
  int screen_height = 720;
  bool fullscreen = false;
};

struct StationParseOutcome {
  std::optional<StationConfig> station;  // none when there are diagnostics
  std::vector<protocols::Diagnostic> diagnostics;
};

// Whether `text` declares format = "burrlab-station/...".
bool LooksLikeStationFile(std::string_view text);

StationParseOutcome ParseStation(std::string_view path, std::string_view text);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_FILE_H_
