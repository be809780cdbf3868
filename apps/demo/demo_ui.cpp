#include "apps/demo/demo_ui.h"

#include <imgui.h>

#include <array>
#include <cstdio>
#include <vector>

#include "hybrid/indirect_pass.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"

namespace penumbra::demo {
namespace {

constexpr std::array<int, 6> kSpp = {1, 4, 8, 16, 32, 64};
constexpr std::array<int, 6> kMapRes = {256, 512, 1024, 2048, 4096, 8192};
constexpr std::array<LightType, 5> kLightTypes = {LightType::Point, LightType::Spot, LightType::Directional,
                                                  LightType::Rect, LightType::Disk};
constexpr std::array<const char*, 5> kLightTypeNames = {"point", "spot", "dir", "rect", "disk"};
constexpr std::array<const char*, 3> kDenoiseModes = {"off", "spatial", "temporal"};
constexpr std::array<const char*, 6> kOverlayLabels = {"none",
                                                       "PIP (traced pixels, red)",
                                                       "penumbra mask",
                                                       "thin-pass coverage",
                                                       "error vs reference",
                                                       "tiles (cleared blue, traced whole orange)"};

template <class T, std::size_t N>
int indexOf(const std::array<T, N>& values, const T& value) {
  for (std::size_t i = 0; i < N; ++i) {
    if (values[i] == value) return int(i);
  }
  return -1;
}

// A combo over fixed integer choices; true when the user picked another one.
template <std::size_t N>
bool intCombo(const char* label, const std::array<int, N>& values, std::uint32_t& value) {
  bool changed = false;
  char current[32];
  std::snprintf(current, sizeof current, "%u", value);
  if (ImGui::BeginCombo(label, current)) {
    for (int v : values) {
      char text[32];
      std::snprintf(text, sizeof text, "%d", v);
      if (ImGui::Selectable(text, std::uint32_t(v) == value) && std::uint32_t(v) != value) {
        value = std::uint32_t(v);
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

// A run of several lights: each shown or hidden, and the one the light controls move.
void lightList(DemoSession& session) {
  const std::size_t count = session.lightCount();
  ImGui::Text("lights: %zu (checked ones light the frame)", count);
  if (session.term() != Term::Shadow)
    ImGui::TextDisabled("%s takes one light: the selected one", session.method().c_str());
  const float rows = float(std::min<std::size_t>(count, 8));
  if (ImGui::BeginChild("lights", ImVec2(0.0f, rows * ImGui::GetFrameHeightWithSpacing()), true)) {
    for (std::size_t i = 0; i < count; ++i) {
      ImGui::PushID(int(i));
      bool shown = session.lightShown(i);
      if (ImGui::Checkbox("##shown", &shown)) session.showLight(i, shown);
      ImGui::SameLine();
      const Light& light = session.lightAt(i);
      char label[96];
      std::snprintf(label, sizeof label, "%zu  %s  (%.2f, %.2f, %.2f)", i,
                    kLightTypeNames[std::max(0, indexOf(kLightTypes, light.type))], light.position.x, light.position.y,
                    light.position.z);
      if (ImGui::Selectable(label, i == session.selectedLight())) session.selectLight(i);
      ImGui::PopID();
    }
  }
  ImGui::EndChild();
}

void controls(DemoSession& session, UiState& state) {
  const std::vector<std::string> methods = methodNames();
  if (ImGui::BeginCombo("method", session.method().c_str())) {
    for (const std::string& m : methods) {
      if (ImGui::Selectable(m.c_str(), m == session.method()) && m != session.method()) session.setMethod(m);
    }
    ImGui::EndCombo();
  }
  RenderSettings settings = session.settings();
  bool settingsChanged = false;
  // Shadow methods pick the shadow tracer; ao and indirect theirs (bvh, bvh-ls, ... and embree).
  const bool indirect = session.term() != Term::Shadow;
  static const std::vector<std::string> shadowTracers = [] {
    std::vector<std::string> names = tracerNames();
    names.insert(names.begin(), "auto");
    return names;
  }();
  std::vector<const char*> tracers;
  for (const std::string& t : indirect ? indirectTracers() : shadowTracers) tracers.push_back(t.c_str());
  std::string& chosen = indirect ? settings.indirect.tracer : settings.tracer;
  int tracer = 0;
  for (std::size_t i = 0; i < tracers.size(); ++i) {
    if (chosen == tracers[i]) tracer = int(i);
  }
  if (ImGui::Combo("tracer", &tracer, tracers.data(), int(tracers.size())) && chosen != tracers[tracer]) {
    chosen = tracers[tracer];
    settingsChanged = true;
  }
  settingsChanged |= intCombo("spp", kSpp, settings.spp);
  settingsChanged |= intCombo("shadow map", kMapRes, settings.shadowMap.resolution);
  int denoise = int(settings.denoise.mode);  // DenoiseMode in kDenoiseModes' order
  if (ImGui::Combo("denoise", &denoise, kDenoiseModes.data(), int(kDenoiseModes.size())) &&
      DenoiseMode(denoise) != settings.denoise.mode) {
    settings.denoise.mode = DenoiseMode(denoise);
    settingsChanged = true;
  }
  if (settingsChanged) session.setSettings(settings);

  ImGui::Separator();
  if (session.lightCount() > 1) lightList(session);
  int type = std::max(0, indexOf(kLightTypes, session.light().type));
  if (ImGui::Combo("light", &type, kLightTypeNames.data(), int(kLightTypeNames.size()))) session.setLightType(kLightTypes[type]);
  const bool area = session.light().type == LightType::Rect || session.light().type == LightType::Disk;
  float size = session.lightSizeFraction();
  ImGui::BeginDisabled(!area);
  if (ImGui::SliderFloat("light size", &size, 0.0f, 0.5f, "%.3f radii") && area) session.setLightSize(size);
  ImGui::EndDisabled();
  ImGui::TextDisabled("right drag: move the light");

  ImGui::Separator();
  int overlay = int(state.overlay);
  for (std::size_t i = 0; i < kOverlayLabels.size(); ++i) ImGui::RadioButton(kOverlayLabels[i], &overlay, int(i));
  state.overlay = Overlay(overlay);
  if (ImGui::Button("compute reference")) state.wantReference = true;
  ImGui::SameLine();
  ImGui::TextUnformatted(session.reference() ? "(current)" : "(none for this view)");
  if (session.animated()) ImGui::Checkbox("pause animation", &state.pauseAnimation);
}

void stats(const DemoSession& session, const UiInfo& info) {
  const Frame& frame = session.frame();
  const FrameStats& s = frame.stats;
  ImGui::Text("%s%s%s  %ux%u", s.method.c_str(), s.tracer ? " on " : "", s.tracer ? s.tracer->c_str() : "", frame.width,
              frame.height);
  ImGui::Text("FPS %.1f   frame %.2f ms", info.fps, s.totalMs);
  if (ImGui::BeginTable("passes", 2)) {
    for (const auto& [pass, ms] : s.passMs) {
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(pass.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%8.3f ms", ms);
    }
    ImGui::EndTable();
  }
  if (!frame.lights.empty()) ImGui::Text("lights in the frame: %zu", frame.lights.size());
  if (s.pipFraction) ImGui::Text("PIP %.2f %% of covered pixels", 100.0 * *s.pipFraction);
  if (s.raysTraced) ImGui::Text("rays %llu", static_cast<unsigned long long>(*s.raysTraced));
  std::uint64_t structures = 0;
  for (const auto& [name, bytes] : s.memoryBytes) structures += bytes;
  ImGui::Text("memory: structures %.1f MB, process RSS %.1f MB", double(structures) / 1e6, double(info.rssBytes) / 1e6);
  if (s.refit) {
    ImGui::Text("refit %.2f ms, SAH x%.3f, %s, rebuilds %llu", s.refit->ms,
                s.refit->growth, s.refit->rebuilt ? "rebuilt" : "refit",
                static_cast<unsigned long long>(s.refit->rebuilds));
  }
  if (session.temporalChange()) ImGui::Text("temporal change %.5f (mean |dV| vs previous frame)", *session.temporalChange());
  if (session.animated()) ImGui::Text("time %.2f s", session.time());
}

}  // namespace

void drawDemoUi(DemoSession& session, UiState& state, const UiInfo& info) {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(390, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Penumbra");
  try {
    controls(session, state);
  } catch (const InputError& e) {
    state.error = e.what();
  }
  if (!state.error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", state.error.c_str());
  if (ImGui::CollapsingHeader("stats", ImGuiTreeNodeFlags_DefaultOpen)) stats(session, info);
  ImGui::TextDisabled("left drag orbit, wheel zoom, WASD/QE fly, R reset");
  ImGui::End();
}

}  // namespace penumbra::demo
