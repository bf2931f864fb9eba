// The subject's part of the window (Dear ImGui): trial title, interval and
// time left, the instruction, the force indicator, the question and one button
// per answer with its key. A function of SubjectView only.
#ifndef BURRLAB_RUNNER_STATION_SUBJECT_VIEW_H_
#define BURRLAB_RUNNER_STATION_SUBJECT_VIEW_H_

#include <optional>
#include <string>

#include "station/station_frame.h"
#include "station/station_layout.h"

namespace burrlab::runner {

// Draws the view (inside an ImGui frame); returns the answer of a clicked
// button.
std::optional<std::string> DrawSubjectView(const SubjectView& view,
                                           const StationLayout& layout);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_SUBJECT_VIEW_H_
