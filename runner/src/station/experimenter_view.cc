// The experimenter's panel.
#include "station/experimenter_view.h"

#include <fmt/format.h>
#include <imgui.h>

namespace burrlab::runner {

ExperimenterAction DrawExperimenterView(const ExperimenterView& view,
                                        const StationLayout& layout) {
  const PixelRect& r = layout.experimenter;
  ImGui::SetNextWindowPos(
      ImVec2(static_cast<float>(r.x), static_cast<float>(r.y)));
  ImGui::SetNextWindowSize(
      ImVec2(static_cast<float>(r.width), static_cast<float>(r.height)));
  ImGui::Begin("Experimenter", nullptr,
               ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoSavedSettings);
  // An adaptive protocol's length is not known ahead: then the count only.
  const std::string progress =
      view.trials_total > 0
          ? fmt::format("{} of {} trials", view.trials_done, view.trials_total)
          : fmt::format("{} trials done (adaptive: total not known ahead)",
                        view.trials_done);
  ImGui::TextUnformatted("Progress");
  ImGui::ProgressBar(view.trials_total > 0
                         ? static_cast<float>(view.trials_done) /
                               static_cast<float>(view.trials_total)
                         : 0.0f,
                     ImVec2(-1.0f, 0.0f), progress.c_str());
  ImGui::Separator();
  ImGui::TextWrapped("Current: %s", view.trial_line.c_str());
  ImGui::Separator();
  ImGui::Text("Device: %s", view.device_name.c_str());
  const bool device_ok = view.device_state == "ok";
  ImGui::PushStyleColor(ImGuiCol_Text, device_ok
                                           ? ImVec4(0.5f, 0.9f, 0.5f, 1.0f)
                                           : ImVec4(1.0f, 0.5f, 0.3f, 1.0f));
  ImGui::TextWrapped("State: %s", view.device_state.c_str());
  ImGui::PopStyleColor();
  ImGui::Separator();
  ImGui::TextUnformatted("Haptic loop (1 kHz)");
  const std::string loop = fmt::format(
      "ticks {}\nperiod error p50 {:.1f} us, p99 {:.1f} us\nmissed or "
      "non-finite {}",
      view.loop_ticks, view.loop_p50_us, view.loop_p99_us, view.loop_missed);
  ImGui::TextUnformatted(loop.c_str());
  ImGui::Separator();
  ImGui::TextWrapped("Last: %s", view.last_event.c_str());
  ImGui::Separator();
  ExperimenterAction action = ExperimenterAction::kNone;
  if (view.aborted) {
    ImGui::TextUnformatted("Session aborted.");
  } else if (view.finished) {
    ImGui::TextUnformatted("Session complete.");
  } else if (view.paused) {
    if (ImGui::Button("Resume", ImVec2(120.0f, 36.0f))) {
      action = ExperimenterAction::kResume;
    }
  } else if (ImGui::Button("Pause", ImVec2(120.0f, 36.0f))) {
    action = ExperimenterAction::kPause;
  }
  if (!view.aborted && !view.finished) {
    ImGui::SameLine();
    if (ImGui::Button("Abort", ImVec2(120.0f, 36.0f))) {
      action = ExperimenterAction::kAbort;
    }
  }
  ImGui::End();
  return action;
}

}  // namespace burrlab::runner
