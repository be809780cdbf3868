// The demo's ImGui panels: controls (method, tracer, spp, shadow-map resolution, light type and
// size, overlay, animation pause, "compute reference") applied to the DemoSession, and live stats
// of the last frame (ms per pass from the timestamp queries, PIP %, rays, memory, refit, temporal
// change, FPS).
#pragma once
#include <cstdint>
#include <string>

#include "apps/demo/demo_session.h"
#include "apps/demo/overlay.h"

namespace penumbra::demo {

struct UiState {
  Overlay overlay = Overlay::None;
  bool pauseAnimation = false;
  bool wantReference = false;  // "compute reference" pressed this frame
  std::string error;           // the last refused change, shown until the next change
};

struct UiInfo {
  double fps = 0.0;
  std::uint64_t rssBytes = 0;
};

// Draws the panels for the session's last frame and applies what the user changed to `session`
// (a setting fixed per Renderer makes a new one). A refused change (InputError) is put in
// state.error and leaves the session as it was.
void drawDemoUi(DemoSession& session, UiState& state, const UiInfo& info);

}  // namespace penumbra::demo
