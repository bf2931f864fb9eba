// Station scripts (format "burrlab-station-script/1"): what a scripted subject
// does at a station run with `burrlab run --device simulated --script FILE`,
// for tests and dry runs of the real session path: the burr's path in every
// interval (waypoints for the simulated device), the key pressed at each
// question, how quickly it goes on from instructions, rest breaks and
// feedback, and device unplugs. Untrusted input, parsed from (path, text)
// with diagnostics in the style of protocol files.
#ifndef BURRLAB_RUNNER_STATION_STATION_SCRIPT_H_
#define BURRLAB_RUNNER_STATION_STATION_SCRIPT_H_

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "burrlab/protocols/protocol.h"
#include "devices/simulated_device.h"

namespace burrlab::runner {

inline constexpr std::string_view kStationScriptFormat =
    "burrlab-station-script/1";

// The simulated device goes away during one interval of one presentation.
struct ScriptedUnplug {
  int presentation = 1;  // the n-th trial presented in this run (1-based; a
                         // trial presented again after a pause counts again)
  int interval = 1;      // 1-based interval of that trial
  double after_s = 0.0;  // s after the interval starts
  bool resume = false;   // re-plugged and resumed by the experimenter; false:
                         // the session stops paused
};

struct StationScript {
  // The burr centre in every interval, device frame (origin at the centre of
  // the block's untouched surface, z up), s from the interval's start.
  std::vector<Waypoint> path;
  std::vector<std::string> answers;  // key pressed at each question, in order
  double start_delay_s = 0.05;       // ready screen to SPACE
  double response_delay_s = 0.1;     // question to the answer's key
  // Instructions (SPACE) or a rest break (a key) to the key that goes on.
  double continue_delay_s = 0.05;
  // Feedback to a key that ends it early; none: it stays its full second.
  std::optional<double> end_feedback_after_s;
  std::vector<ScriptedUnplug> unplugs;
};

struct StationScriptParseOutcome {
  std::optional<StationScript> script;  // none when there are diagnostics
  std::vector<protocols::Diagnostic> diagnostics;
};

StationScriptParseOutcome ParseStationScript(std::string_view path,
                                             std::string_view text);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_SCRIPT_H_
