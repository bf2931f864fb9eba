// The station's window: GLFW 3.3 with an OpenGL 3.3 core context, Dear ImGui
// for the text and buttons, SurfaceRenderer for the block. Draws a
// StationFrame, reports keys and clicks as input, reads the cursor for the
// mouse device, and saves the frame as a PNG. All calls on one thread.
#ifndef BURRLAB_RUNNER_STATION_WINDOW_H_
#define BURRLAB_RUNNER_STATION_WINDOW_H_

#include <glm/vec2.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "burrlab/base/result.h"
#include "station/experimenter_view.h"
#include "station/station_frame.h"
#include "station/station_layout.h"
#include "station/surface_snapshot.h"

struct GLFWwindow;

namespace burrlab::runner {

class SurfaceRenderer;

// The font of the window: fixed, so screenshots are reproducible.
inline constexpr const char* kStationFont =
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

struct WindowOptions {
  int width = 1280;  // pixels; the framebuffer has the same size
  int height = 720;
  std::string title = "burrlab";
  bool visible = true;
  std::string font_path = kStationFont;  // TrueType; empty: ImGui's own font
  float font_px = 20.0f;
};

// What happened in the window since the last frame.
struct WindowInput {
  std::vector<std::string> keys;      // "1", "S", "SPACE", "ESCAPE", ...
  std::optional<std::string> answer;  // a response button clicked
  ExperimenterAction action = ExperimenterAction::kNone;
  bool close_requested = false;
};

class StationWindow {
 public:
  // Opens the window; fails with GLFW's reason (e.g. no display).
  static Result<std::unique_ptr<StationWindow>> Open(
      const WindowOptions& options);
  ~StationWindow();
  StationWindow(const StationWindow&) = delete;
  StationWindow& operator=(const StationWindow&) = delete;

  // Takes the newest block view (call when the exchange has a new one).
  void SetSurface(const SurfaceSnapshot& snapshot);
  // Processes window events and draws `frame` into the back buffer; the keys
  // pressed since the last call and the buttons clicked while drawing come
  // back. Call Present to show it.
  WindowInput Draw(const StationFrame& frame);
  // Shows the frame drawn last.
  void Present();
  // Writes the frame drawn last as an RGB PNG (before Present).
  Status SaveScreenshot(const std::string& path) const;
  // The cursor over the block view, (0, 0) top left to (1, 1) bottom right,
  // and whether the left button is down (for the mouse device).
  glm::dvec2 CursorInBlock() const;
  bool LeftButtonDown() const;
  // Mouse wheel steps since the window opened (up is positive).
  double WheelSteps() const { return wheel_steps_; }

  int width() const { return options_.width; }
  int height() const { return options_.height; }

 private:
  explicit StationWindow(const WindowOptions& options);
  static void OnKey(GLFWwindow* w, int key, int scancode, int action, int mods);
  static void OnScroll(GLFWwindow* w, double dx, double dy);

  WindowOptions options_;
  GLFWwindow* window_ = nullptr;
  std::unique_ptr<SurfaceRenderer> renderer_;
  StationLayout layout_;
  std::vector<std::string> keys_;
  double wheel_steps_ = 0.0;
  bool imgui_ready_ = false;
};

// The name of a GLFW key as StationController expects it ("" for others).
std::string KeyName(int glfw_key);

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_WINDOW_H_
