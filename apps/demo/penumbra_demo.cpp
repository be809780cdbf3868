// penumbra-demo: the real-time demo. Penumbra renders each frame with Vulkan (any method, any
// tracer), the frame is shown in a GLFW/OpenGL window with overlays, and Dear ImGui panels switch
// methods and settings and show live stats. With --frames N it is a scripted run (fixed steps per
// frame, screenshot, per-frame CSV) for tests and recordings. Takes the same scene, camera, light
// and quality options as `penumbra render`. Errors print one line on stderr and exit non-zero.
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "apps/demo/camera_controller.h"
#include "apps/demo/demo_script.h"
#include "apps/demo/demo_session.h"
#include "apps/demo/demo_ui.h"
#include "apps/demo/demo_window.h"
#include "apps/demo/presenter.h"
#include "apps/run_config.h"
#include "core/image_io.h"
#include "core/view.h"
#include "hybrid/method.h"

using namespace penumbra;
using namespace penumbra::demo;

namespace {

// Ctrl-C or SIGTERM closes an interactive window normally (so --screenshot and --save-view are
// still written) and stops a scripted run with an error.
volatile std::sig_atomic_t interrupted = 0;
void onSignal(int) { interrupted = 1; }

// Outputs are checked before any work, so a typo in a path does not cost a whole run.
void requireWritableFolder(const std::string& path, const char* option) {
  if (path.empty()) return;
  const std::filesystem::path folder = std::filesystem::absolute(path).parent_path();
  if (!std::filesystem::is_directory(folder)) {
    throw InputError(std::string(option) + " '" + path + "': the folder '" + folder.string() + "' does not exist");
  }
}

// Mouse and keyboard, unless ImGui has them: left drag orbits, right drag moves the light, the
// wheel zooms, WASD/QE fly, R resets the camera, Escape quits.
void handleInput(DemoWindow& window, DemoSession& session, float wheel, double dx, double dy, float seconds) {
  GLFWwindow* w = window.handle();
  const ImGuiIO& io = ImGui::GetIO();
  CameraController& camera = session.cameraController();
  if (!io.WantCaptureMouse) {
    if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
      camera.orbit(-float(dx) * kDegreesPerPixel, float(dy) * kDegreesPerPixel);
    }
    if (glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS && (dx != 0.0 || dy != 0.0)) {
      Light light = session.light();
      moveLight(light, session.bounds(), -float(dx) * kDegreesPerPixel, -float(dy) * kDegreesPerPixel);
      session.setLight(light);
    }
    if (wheel != 0.0f) camera.zoom(wheel);
  }
  if (io.WantCaptureKeyboard) return;
  auto key = [w](int k) { return glfwGetKey(w, k) == GLFW_PRESS ? 1.0f : 0.0f; };
  const glm::vec3 move{key(GLFW_KEY_D) - key(GLFW_KEY_A), key(GLFW_KEY_E) - key(GLFW_KEY_Q), key(GLFW_KEY_W) - key(GLFW_KEY_S)};
  if (move != glm::vec3(0.0f)) camera.fly(move, seconds);
  if (key(GLFW_KEY_R) > 0.0f) camera.reset();
  if (key(GLFW_KEY_ESCAPE) > 0.0f) glfwSetWindowShouldClose(w, GLFW_TRUE);
}

int runDemo(RunConfig config, const std::string& method, const ScriptOptions& script) {
  const Overlay startOverlay = parseOverlay(script.overlay);
  // --save-view is written for the last frame shown, not (as prepareRun would) before the first.
  const std::string saveView = config.saveView;
  config.saveView.clear();
  requireWritableFolder(saveView, "--save-view");
  requireWritableFolder(script.screenshot, "--screenshot");
  std::vector<std::string> methods{method};
  if (script.temporalReference || startOverlay == Overlay::Error) methods.push_back("ref");
  requireWritableFolder(script.statsCsv, "--stats-csv");
  RunSetup setup = prepareRun(config, methods);

  // Scripted runs: one window pixel per frame pixel, so the screenshot is the frame itself.
  const bool scripted = script.scripted();
  const int width = int(setup.settings.width), height = int(setup.settings.height);
  DemoWindow window(scripted ? width : std::max(width, 1280), scripted ? height : std::max(height, 800), !scripted, !scripted,
                    "Penumbra demo");
  std::optional<StatsCsv> csv;  // created once a window is open: a run refused for lack of a display writes nothing
  if (!script.statsCsv.empty()) csv.emplace(script.statsCsv);
  gpu::Context context({.validate = config.validate});
  DemoSession session(context, std::move(setup), method, !saveView.empty());
  session.selectLight(script.selectLight);
  std::string renderedMethod = method;  // the last method that rendered a frame
  Presenter presenter;
  UiState ui;
  ui.overlay = startOverlay;

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last = start;
  double animationTime = 0.0, fps = 0.0;
  double cursorX = 0.0, cursorY = 0.0;
  glfwGetCursorPos(window.handle(), &cursorX, &cursorY);
  Presenter::Image shot;
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  for (std::uint32_t frame = 0;; ++frame) {
    if (scripted && interrupted) throw std::runtime_error("interrupted after " + std::to_string(frame) + " frames");
    window.pollEvents();
    const auto now = Clock::now();
    const double seconds = std::chrono::duration<double>(now - last).count();
    last = now;
    if (frame > 0) fps = fps == 0.0 ? 1.0 / seconds : 0.9 * fps + 0.1 / std::max(seconds, 1e-6);
    if (scripted) {
      // Fixed steps per frame: the same run on any machine.
      if (frame > 0 && script.orbit) session.cameraController().orbit(kOrbitStepDeg, 0.0f);
      if (frame > 0 && script.lightPath == "circle") {
        Light light = session.light();
        moveLight(light, session.bounds(), kLightStepDeg, 0.0f);
        session.setLight(light);
      }
      session.setTime(frame * kScriptedFrameSeconds);
    } else {
      double x = 0.0, y = 0.0;
      glfwGetCursorPos(window.handle(), &x, &y);
      handleInput(window, session, window.takeScroll(), x - cursorX, y - cursorY, float(seconds));
      cursorX = x;
      cursorY = y;
      if (!ui.pauseAnimation) animationTime += seconds;  // wall clock
      session.setTime(animationTime);
    }

    // The last frame: the script's, or the first after the window was asked to close (drawn in
    // full, so --screenshot and --save-view get the view that was on screen).
    const bool lastFrame = scripted ? frame + 1 == script.frames : window.shouldClose() || interrupted;

    try {
      session.render();
      renderedMethod = session.method();
    } catch (const InputError& e) {  // e.g. a method or tracer the UI switched to refused this scene or light
      if (scripted || frame == 0) throw;
      ui.error = e.what();
      if (session.method() != renderedMethod) {
        session.setMethod(renderedMethod);  // bitmask under a point light: back to the method that worked
      } else {
        RenderSettings settings = session.settings();
        settings.tracer = "bvh";
        session.setSettings(settings);
      }
      session.render();
    }
    // The reference: every frame when its temporal change is asked for or a scripted run shows
    // the error overlay; interactively on the button, kept until the view changes.
    const bool wantReference = script.temporalReference || (scripted && ui.overlay == Overlay::Error) || ui.wantReference;
    ui.wantReference = false;
    if (wantReference) session.renderReference();

    std::vector<std::uint8_t> heatmap;
    if (ui.overlay == Overlay::Error && session.reference()) heatmap = session.errorHeatmap();
    presenter.upload(session.frame(), session.selectedPip(), heatmap, session.selectedMaskTiles());
    int fbWidth = 0, fbHeight = 0;
    window.framebufferSize(fbWidth, fbHeight);
    presenter.draw(fbWidth, fbHeight, ui.overlay);
    // The screenshot is read before ImGui draws: it is the frame as presented, without the panels.
    if (!script.screenshot.empty() && lastFrame) shot = presenter.screenshot();
    if (!script.hideUi) {
      window.beginUi();
      drawDemoUi(session, ui, {fps, residentBytes()});
      window.endUi();
    }
    window.swap();

    if (csv) {
      csv->write({frame, session.time(), &session.frame().stats, residentBytes(), session.temporalChange(),
                  script.temporalReference ? session.referenceTemporalChange() : std::nullopt});
    }
    if (lastFrame) break;
    if (scripted && window.shouldClose()) throw std::runtime_error("the window was closed during the scripted run");
  }

  if (!script.screenshot.empty() && !shot.rgba.empty()) {
    if (scripted && (shot.width != width || shot.height != height)) {
      std::cerr << "penumbra-demo: the window is " << shot.width << "x" << shot.height << ", not " << width << "x" << height
                << "; the screenshot is the scaled frame\n";
    }
    writePngRgba8(script.screenshot, shot.width, shot.height, shot.rgba);
    std::cout << "wrote " << script.screenshot << "\n";
  }
  if (!saveView.empty()) {
    writeViewFile(saveView, session.view(), session.scene().origin);
    std::cout << "wrote " << saveView << " (the last frame's view)\n";
  }
  const auto messages = context.validationMessages();
  if (!messages.empty()) {
    std::cerr << "penumbra-demo: " << messages.size() << " Vulkan validation message(s), see above\n";
    return 3;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"penumbra-demo: real-time hybrid shadows in a window (GLFW + OpenGL + Dear ImGui); "
               "--frames N for a scripted run"};
  RunConfig config;
  config.settings.reuseLightPasses = true;  // interactive: a still light's map is kept, as an engine keeps it
  addRunOptions(app, config);
  std::string method = "srt";
  app.add_option("--method", method, "Method: " + [] {
    std::string s;
    for (const auto& n : methodNames()) s += (s.empty() ? "" : ", ") + n;
    return s;
  }())->capture_default_str();
  ScriptOptions script;
  addScriptOptions(app, script);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "penumbra-demo: " << e.what() << " (see --help)\n";
    return 2;
  }
  try {
    return runDemo(config, method, script);
  } catch (const std::exception& e) {
    std::cerr << "penumbra-demo: " << e.what() << "\n";
    return 2;
  }
}
