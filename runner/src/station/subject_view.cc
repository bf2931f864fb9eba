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

// Whether the phase covers the block view with a panel (the pacing phases:
// nothing to feel, so nothing of the block to see).
bool HasPanel(StationPhase phase) {
  return phase == StationPhase::kInstructions || phase == StationPhase::kIsi ||
         phase == StationPhase::kFeedback || phase == StationPhase::kBreak ||
         phase == StationPhase::kIti;
}

// The line under the title: the phase, in words a subject reads.
std::string PhaseLine(StationPhase phase) {
  switch (phase) {
    case StationPhase::kIsi:
      return "between intervals";
    case StationPhase::kIti:
      return "between trials";
    case StationPhase::kBreak:
      return "rest break";
    default:
      return std::string(StationPhaseName(phase));
  }
}

// `text` centred horizontally in the current window at the cursor's height.
void Centred(const std::string& text) {
  const float width = ImGui::CalcTextSize(text.c_str()).x;
  ImGui::SetCursorPosX(
      std::max(0.0f, (ImGui::GetWindowSize().x - width) * 0.5f));
  Text(text);
}

// The panel over the block view: a large heading (green "Correct", orange
// "Wrong") and the text wrapped under it, both centred; blank in the gaps
// but for a short line.
void DrawPanel(const SubjectView& view, const StationLayout& layout) {
  Place(layout.block);
  ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.06f, 0.06f, 0.08f, 1.0f));
  ImGui::Begin("##panel", nullptr, kFixed);
  const float height = ImGui::GetWindowSize().y;
  const bool feedback = view.phase == StationPhase::kFeedback;
  const bool instructions = view.phase == StationPhase::kInstructions;
  ImGui::SetCursorPosY(height * (instructions ? 0.12f : 0.38f));
  if (!view.panel_heading.empty()) {
    ImGui::SetWindowFontScale(feedback ? 3.0f : 2.0f);
    if (feedback) {
      ImGui::PushStyleColor(ImGuiCol_Text,
                            view.panel_good ? ImVec4(0.35f, 0.85f, 0.45f, 1.0f)
                                            : ImVec4(1.0f, 0.55f, 0.25f, 1.0f));
    }
    Centred(view.panel_heading);
    if (feedback) ImGui::PopStyleColor();
    ImGui::SetWindowFontScale(1.0f);
    ImGui::Spacing();
    ImGui::Spacing();
  }
  if (!view.panel_text.empty()) {
    ImGui::SetWindowFontScale(instructions ? 1.25f : 1.1f);
    if (instructions) {
      // Wrapped in a column of 4/5 of the width, left-aligned (a paragraph).
      const float width = ImGui::GetWindowSize().x;
      ImGui::SetCursorPosX(width * 0.1f);
      ImGui::PushTextWrapPos(width * 0.9f);
      ImGui::TextUnformatted(view.panel_text.c_str(),
                             view.panel_text.c_str() + view.panel_text.size());
      ImGui::PopTextWrapPos();
    } else {
      Centred(view.panel_text);
    }
    ImGui::SetWindowFontScale(1.0f);
  }
  ImGui::End();
  ImGui::PopStyleColor();
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
    Text(PhaseLine(view.phase));
  }
  const bool alert = view.phase == StationPhase::kPaused;
  if (alert)
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.6f, 0.3f, 1.0f));
  ImGui::TextWrapped("%s", view.message.c_str());
  if (alert) ImGui::PopStyleColor();
  ImGui::End();

  if (HasPanel(view.phase)) DrawPanel(view, layout);

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
