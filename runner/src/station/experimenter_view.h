// The experimenter's panel (Dear ImGui): progress, the current trial, loop
// timing, device state, the last event, and pause / resume / abort. A function
// of ExperimenterView only.
#ifndef BURRLAB_RUNNER_STATION_EXPERIMENTER_VIEW_H_
#define BURRLAB_RUNNER_STATION_EXPERIMENTER_VIEW_H_

#include "station/station_frame.h"
#include "station/station_layout.h"

namespace burrlab::runner {

enum class ExperimenterAction { kNone, kPause, kResume, kAbort };

// Draws the panel (inside an ImGui frame); returns the button clicked.
ExperimenterAction DrawExperimenterView(const ExperimenterView& view,
                                        const StationLayout& layout);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_EXPERIMENTER_VIEW_H_
