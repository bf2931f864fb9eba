// GLFW window, OpenGL 3.3 core context, Dear ImGui frame, PNG screenshots.
#include "station/window.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <fmt/format.h>
#include <imgui.h>
#include <stb_image_write.h>

#include <algorithm>
#include <filesystem>

#include "station/subject_view.h"
#include "station/surface_renderer.h"

namespace burrlab::runner {
namespace {

// GLFW reports errors through a callback; the last one explains a failure.
thread_local std::string last_glfw_error;

void OnGlfwError(int code, const char* description) {
  last_glfw_error = fmt::format("{} (GLFW error 0x{:x})", description, code);
}

}  // namespace

std::string KeyName(int key) {
  if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) {
    return std::string(1, static_cast<char>('0' + (key - GLFW_KEY_0)));
  }
  if (key >= GLFW_KEY_KP_0 && key <= GLFW_KEY_KP_9) {
    return std::string(1, static_cast<char>('0' + (key - GLFW_KEY_KP_0)));
  }
  if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) {
    return std::string(1, static_cast<char>('A' + (key - GLFW_KEY_A)));
  }
  switch (key) {
    case GLFW_KEY_SPACE:
      return "SPACE";
    case GLFW_KEY_ESCAPE:
      return "ESCAPE";
    case GLFW_KEY_ENTER:
    case GLFW_KEY_KP_ENTER:
      return "ENTER";
    default:
      return "";
  }
}

StationWindow::StationWindow(const WindowOptions& options)
    : options_(options),
      layout_(StationLayout::For(options.width, options.height)) {}

Result<std::unique_ptr<StationWindow>> StationWindow::Open(
    const WindowOptions& options) {
  if (options.width < 320 || options.height < 240 || options.width > 8192 ||
      options.height > 8192) {
    return Error{
        fmt::format("window size {}x{} is outside 320x240 to 8192x8192",
                    options.width, options.height)};
  }
  if (!options.font_path.empty()) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(options.font_path, ec)) {
      return Error{fmt::format(
          "cannot open the subject window: font {} not found (Debian package "
          "fonts-dejavu-core)",
          options.font_path)};
    }
  }
  glfwSetErrorCallback(OnGlfwError);
  last_glfw_error.clear();
  if (glfwInit() == GLFW_FALSE) {
    return Error{"cannot open the subject window: " +
                 (last_glfw_error.empty() ? std::string("glfwInit failed")
                                          : last_glfw_error)};
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_SAMPLES, 0);
  std::unique_ptr<StationWindow> w(new StationWindow(options));
  w->window_ = glfwCreateWindow(options.width, options.height,
                                options.title.c_str(), nullptr, nullptr);
  if (w->window_ == nullptr) {
    const std::string reason = last_glfw_error;
    glfwTerminate();
    return Error{"cannot open the subject window: " + reason};
  }
  glfwMakeContextCurrent(w->window_);
  glfwSwapInterval(1);
  glfwSetWindowUserPointer(w->window_, w.get());
  // Ours first: ImGui's backend chains to callbacks installed before it.
  glfwSetKeyCallback(w->window_, &StationWindow::OnKey);
  glfwSetScrollCallback(w->window_, &StationWindow::OnScroll);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // no imgui.ini: every run starts the same
  io.LogFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 0.0f;
  style.FrameRounding = 3.0f;
  style.WindowPadding = ImVec2(14.0f, 10.0f);
  style.ItemSpacing = ImVec2(10.0f, 8.0f);
  style.FramePadding = ImVec2(12.0f, 6.0f);
  if (!options.font_path.empty()) {
    io.Fonts->AddFontFromFileTTF(options.font_path.c_str(), options.font_px);
  }
  ImGui_ImplGlfw_InitForOpenGL(w->window_, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  w->imgui_ready_ = true;
  Result<std::unique_ptr<SurfaceRenderer>> renderer = SurfaceRenderer::Create();
  if (!renderer.ok()) {
    return Error{"cannot open the subject window: " + renderer.error().message};
  }
  w->renderer_ = std::move(renderer.value());
  return w;
}

StationWindow::~StationWindow() {
  if (window_ != nullptr) glfwMakeContextCurrent(window_);
  renderer_.reset();
  if (imgui_ready_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  if (window_ != nullptr) glfwDestroyWindow(window_);
  glfwTerminate();
}

void StationWindow::OnKey(GLFWwindow* w, int key, int /*scancode*/, int action,
                          int /*mods*/) {
  if (action != GLFW_PRESS) return;
  auto* self = static_cast<StationWindow*>(glfwGetWindowUserPointer(w));
  std::string name = KeyName(key);
  if (self != nullptr && !name.empty()) self->keys_.push_back(std::move(name));
}

void StationWindow::OnScroll(GLFWwindow* w, double /*dx*/, double dy) {
  auto* self = static_cast<StationWindow*>(glfwGetWindowUserPointer(w));
  if (self != nullptr) self->wheel_steps_ += dy;
}

void StationWindow::SetSurface(const SurfaceSnapshot& snapshot) {
  glfwMakeContextCurrent(window_);
  renderer_->Update(snapshot);
}

WindowInput StationWindow::Draw(const StationFrame& frame) {
  glfwMakeContextCurrent(window_);
  glfwPollEvents();
  WindowInput input;
  input.keys.swap(keys_);
  input.close_requested = glfwWindowShouldClose(window_) != 0;
  int fb_w = 0, fb_h = 0;
  glfwGetFramebufferSize(window_, &fb_w, &fb_h);
  glViewport(0, 0, fb_w, fb_h);
  glClearColor(0.08f, 0.08f, 0.10f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const PixelRect& b = layout_.block;
  renderer_->Draw(b.x, fb_h - b.y - b.height, b.width, b.height);
  glViewport(0, 0, fb_w, fb_h);

  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  // Fixed frame time: nothing in a frame depends on the clock.
  ImGui::GetIO().DeltaTime = 1.0f / 60.0f;
  ImGui::NewFrame();
  input.answer = DrawSubjectView(frame.subject, layout_);
  input.action = DrawExperimenterView(frame.experimenter, layout_);
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  return input;
}

void StationWindow::Present() { glfwSwapBuffers(window_); }

Status StationWindow::SaveScreenshot(const std::string& path) const {
  glfwMakeContextCurrent(window_);
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  std::vector<unsigned char> pixels(static_cast<std::size_t>(w) * h * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // OpenGL rows run bottom-up, PNG rows top-down.
  const std::size_t row = static_cast<std::size_t>(w) * 3;
  std::vector<unsigned char> flipped(pixels.size());
  for (int y = 0; y < h; ++y) {
    std::copy_n(
        pixels.begin() + static_cast<std::ptrdiff_t>(
                             (static_cast<std::size_t>(h - 1 - y)) * row),
        row,
        flipped.begin() +
            static_cast<std::ptrdiff_t>(static_cast<std::size_t>(y) * row));
  }
  if (stbi_write_png(path.c_str(), w, h, 3, flipped.data(),
                     static_cast<int>(row)) == 0) {
    return Error{fmt::format("cannot write {}", path)};
  }
  return {};
}

glm::dvec2 StationWindow::CursorInBlock() const {
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(window_, &x, &y);
  const PixelRect& b = layout_.block;
  return {(x - b.x) / b.width, (y - b.y) / b.height};
}

bool StationWindow::LeftButtonDown() const {
  return glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
}

}  // namespace burrlab::runner
