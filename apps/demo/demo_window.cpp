#include "apps/demo/demo_window.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <cstdlib>

namespace penumbra::demo {
namespace {

std::string lastGlfwError;
void onGlfwError(int code, const char* text) { lastGlfwError = std::string(text) + " (GLFW error " + std::to_string(code) + ")"; }

void onScroll(GLFWwindow* window, double, double dy) {
  if (auto* self = static_cast<float*>(glfwGetWindowUserPointer(window))) *self += float(dy);
}

[[noreturn]] void noDisplay(const std::string& what) {
  throw DisplayError(what + ": " + (lastGlfwError.empty() ? "unknown reason" : lastGlfwError) +
                     ". The demo needs an X display; on a headless machine run it under Xvfb, e.g. "
                     "xvfb-run -a -s \"-screen 0 1024x768x24\" penumbra-demo --frames 60 --screenshot shot.png");
}

}  // namespace

DemoWindow::DemoWindow(int width, int height, bool resizable, bool vsync, const std::string& title) {
  glfwSetErrorCallback(onGlfwError);
  const char* display = std::getenv("DISPLAY");
  if ((!display || !*display) && !std::getenv("WAYLAND_DISPLAY")) {
    lastGlfwError = "DISPLAY is not set";
    noDisplay("cannot open a window");
  }
  if (!glfwInit()) noDisplay("cannot open a window");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_RESIZABLE, resizable ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    noDisplay("cannot create an OpenGL 3.3 core window");
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(vsync ? 1 : 0);
  // Our scroll callback first: ImGui's backend chains to the callbacks installed before it.
  glfwSetWindowUserPointer(window_, &scroll_);
  glfwSetScrollCallback(window_, onScroll);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini written into the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window_, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  imgui_ = true;
}

DemoWindow::~DemoWindow() {
  if (imgui_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

bool DemoWindow::shouldClose() const { return glfwWindowShouldClose(window_); }
void DemoWindow::pollEvents() { glfwPollEvents(); }
void DemoWindow::framebufferSize(int& width, int& height) const { glfwGetFramebufferSize(window_, &width, &height); }

void DemoWindow::beginUi() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void DemoWindow::endUi() {
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void DemoWindow::swap() { glfwSwapBuffers(window_); }

float DemoWindow::takeScroll() {
  const float steps = scroll_;
  scroll_ = 0.0f;
  return steps;
}

}  // namespace penumbra::demo
