// The subject's view.
#include "station/subject_view.h"

#include <fmt/format.h>
#include <imgui.h>

#include <algorithm>

namespace burrlab::runner {

StationLayout StationLayout::For(int width, int height) {
  StationLayout l;
  const int subject_w = width * 5 / 8;
  const int trial_h = height * 11 / 50;
  const int answers_h = height * 13 / 50;
  l.trial = {0, 0, subject_w, trial_h};
  l.block = {0, trial_h, subject_w, height - trial_h - answers_h};
  l.answers = {0, height - answers_h, subject_w, answers_h};
  l.experimenter = {subject_w, 0, width - subject_w, height};
  return l;
}

namespace {

constexpr ImGuiWindowFlags kFixed =
    ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize |
    ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
    ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoSavedSettings;

void Place(const PixelRect& r) {
  ImGui::SetNextWindowPos(
      ImVec2(static_cast<float>(r.x), static_cast<float>(r.y)));
  ImGui::SetNextWindowSize(
      ImVec2(static_cast<float>(r.width), static_cast<float>(r.height)));
}

void Text(const std::string& text) {
  ImGui::TextUnformatted(text.c_str(), text.c_str() + text.size());
}

}  // namespace

std::optional<std::string> DrawSubjectView(const SubjectView& view,
                                           const StationLayout& layout) {
  Place(layout.trial);
  ImGui::Begin("##trial", nullptr, kFixed);
  ImGui::SetWindowFontScale(1.6f);
  Text(view.title);
  ImGui::SetWindowFontScale(1.0f);
  if (view.phase == StationPhase::kInterval) {
    Text(view.interval_label);
    ImGui::SameLine();
    if (view.time_left_s > 0.0) {
      Text(fmt::format("  {:.1f} s left", view.time_left_s));
    }
  } else {
    Text(std::string(StationPhaseName(view.phase)));
  }
  const bool alert = view.phase == StationPhase::kPaused;
  if (alert)
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.6f, 0.3f, 1.0f));
  ImGui::TextWrapped("%s", view.message.c_str());
  if (alert) ImGui::PopStyleColor();
  ImGui::End();

  Place(layout.answers);
  ImGui::Begin("##answers", nullptr, kFixed);
  const double fraction =
      view.max_force_n > 0.0
          ? std::clamp(view.force_n / view.max_force_n, 0.0, 1.0)
          : 0.0;
  Text("Force");
  ImGui::SameLine(80.0f);
  const std::string force =
      fmt::format("{:.2f} N of {:.1f} N", view.force_n, view.max_force_n);
  ImGui::PushStyleColor(ImGuiCol_PlotHistogram,
                        fraction > 0.8 ? ImVec4(0.9f, 0.3f, 0.2f, 1.0f)
                                       : ImVec4(0.3f, 0.7f, 0.4f, 1.0f));
  ImGui::ProgressBar(static_cast<float>(fraction), ImVec2(-1.0f, 0.0f),
                     force.c_str());
  ImGui::PopStyleColor();
  std::optional<std::string> clicked;
  if (view.phase == StationPhase::kResponse) {
    ImGui::Spacing();
    ImGui::TextWrapped("%s", view.question.c_str());
    for (std::size_t i = 0; i < view.buttons.size(); ++i) {
      const ResponseButton& b = view.buttons[i];
      if (i > 0) ImGui::SameLine();
      const std::string label =
          b.answer == b.key ? fmt::format("  {}  ##{}", b.key, i)
                            : fmt::format("{}  [{}]##{}", b.answer, b.key, i);
      if (ImGui::Button(label.c_str(), ImVec2(0.0f, 44.0f))) {
        clicked = b.answer;
      }
    }
  }
  ImGui::End();
  return clicked;
}

}  // namespace burrlab::runner
