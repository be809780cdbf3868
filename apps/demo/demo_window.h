// The demo's window: GLFW with an OpenGL 3.3 core context, and Dear ImGui bound to it (Debian's
// libimgui with its glfw and opengl3 backends). Mouse wheel and cursor motion are collected here
// for the camera controls; ImGui's callbacks chain to ours.
#pragma once
#include <stdexcept>
#include <string>

struct GLFWwindow;

namespace penumbra::demo {

// No display to open a window on (no DISPLAY, or the X server refused).
struct DisplayError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class DemoWindow {
 public:
  // A window of width x height pixels; fixed size when !resizable (scripted runs: one window pixel
  // per frame pixel). Throws DisplayError with how to run headless when no window can be opened.
  DemoWindow(int width, int height, bool resizable, bool vsync, const std::string& title);
  ~DemoWindow();
  DemoWindow(const DemoWindow&) = delete;
  DemoWindow& operator=(const DemoWindow&) = delete;

  GLFWwindow* handle() const { return window_; }
  bool shouldClose() const;
  void pollEvents();
  void framebufferSize(int& width, int& height) const;
  void beginUi();  // ImGui new frame
  void endUi();    // ImGui draws into the back buffer
  void swap();
  // Mouse wheel steps since the last call.
  float takeScroll();

 private:
  GLFWwindow* window_ = nullptr;
  float scroll_ = 0.0f;
  bool imgui_ = false;
};

}  // namespace penumbra::demo
