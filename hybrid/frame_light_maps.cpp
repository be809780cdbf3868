// FrameContext's light maps: each light's shadow map, thin mask and edge pyramid, at the resolution
// its footprint needs, shared by the frame's lights or kept per light (--reuse-light-passes,
// --light-maps-memory), and rendered again only when the light or what its map sees moved.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "hybrid/frame_context.h"

namespace penumbra {
namespace {

// Whether a box comes within `radius` of `at`.
bool reaches(const Bounds& box, const glm::vec3& at, float radius) {
  return !box.empty() && glm::distance(glm::clamp(at, box.lo, box.hi), at) <= radius;
}

}  // namespace

// A point or spot light whose range the camera is outside of needs fine texels only where the range
// comes nearest the camera, and there at most at the range's distance from the light: its map takes
// the least power of two from 128 whose texel there is at most half a pixel (at one texel a pixel,
// sm got 52 pixels wrong over the street's 16 lamps at 128^2, against 7 at full resolution), up to
// settings().shadowMap's resolution (which every other light gets).
std::uint32_t FrameContext::mapResolution() const {
  const std::uint32_t most = settings_.shadowMap.resolution;
  const shared::GpuLight& light = frameData_.light;
  if (!settings_.footprintMaps || light.range <= 0.0f || (light.type != LIGHT_POINT && light.type != LIGHT_SPOT)) {
    return most;
  }
  const float nearest = glm::distance(cameraPosition_, glm::vec3(light.position)) - light.range;
  if (nearest <= view_.nearPlane) return most;
  // texelWorld: a texel's width at unit distance from the light, at resolution `most`
  const float texelAtRange = raster::makeShadowMapInfo(light, bounds_, settings_.shadowMap).texelWorld * light.range;
  const float pixelAtNearest = 2.0f * nearest / (std::abs(view_.proj[1][1]) * float(settings_.height));  // y flipped
  const float need = 2.0f * float(most) * texelAtRange / pixelAtNearest;
  std::uint32_t resolution = 128;
  while (resolution < most && float(resolution) < need) resolution *= 2;
  return std::min(resolution, most);
}

bool FrameContext::LightPassesKey::operator==(const LightPassesKey& other) const {
  return geometryVersion == other.geometryVersion && std::memcmp(&shadow, &other.shadow, sizeof(shadow)) == 0;
}

// The map's placement, and the version of the last move whose swept boxes came into what the map
// sees: a point or spot light's map ends at its far plane (the light's range), so it sees no farther
// from the light than that plane's corners; a directional light's map sees the whole scene. Where
// the kept moves run out, the version before the oldest, so an older move may only cost a render.
FrameContext::LightPassesKey FrameContext::lightPassesKey() const {
  const shared::ShadowMapInfo& shadow = frameData_.shadow;
  std::uint64_t version = geometry_.version();
  if (shadow.kind != SHADOW_ORTHO) {
    const float tanHalf = shadow.kind == SHADOW_CUBE ? 1.0f : 0.5f * shadow.texelWorld * float(shadow.resolution);
    const float sees = 1.001f * shadow.farPlane * std::sqrt(1.0f + 2.0f * tanHalf * tanHalf);
    const glm::vec3 at(shadow.lightPosition);
    for (auto move = moves_.rbegin(); move != moves_.rend() && move->version == version; ++move) {
      if (std::any_of(move->swept.begin(), move->swept.end(), [&](const Bounds& b) { return reaches(b, at, sees); }))
        break;
      --version;
    }
  }
  return {shadow, version};
}

FrameContext::LightMaps& FrameContext::maps() {
  if (!maps_) maps_ = &chooseMaps();
  return *maps_;
}

// A frame of several lights that keeps still lights' maps gives each light maps of its own, first
// come first kept, while their estimated bytes fit settings().lightMapsMiB; a light past it renders
// shared maps again. A light keeps its own until its resolution or face count changes (its footprint
// did) or the frame has fewer lights.
FrameContext::LightMaps& FrameContext::chooseMaps() {
  using Key = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>;
  const std::uint32_t resolution = mapSettings_.resolution, faces = frameData_.shadow.faceCount;
  const Key shared{kSharedMaps, resolution, faces};
  mapsPastBudget_ = false;
  if (!settings_.reuseLightPasses || slot_.count == 1) return lightMaps_[shared];
  const Key own{slot_.index, resolution, faces};
  std::erase_if(lightMaps_, [&](const auto& m) {
    const std::uint32_t owner = std::get<0>(m.first);
    return owner != kSharedMaps && (owner >= slot_.count || (owner == slot_.index && m.first != own));
  });
  if (auto it = lightMaps_.find(own); it != lightMaps_.end()) return it->second;
  // the map, the thin mask and the edge pyramid (about a map each), and the texel copies of the
  // first two where the passes read maps from buffers
  const std::uint64_t copies = settings_.shadowMap.reads == raster::ShadowMapSettings::Reads::Buffer ? 5 : 3;
  const auto bytes = [&](const Key& k) {
    return std::uint64_t(std::get<1>(k)) * std::get<1>(k) * std::get<2>(k) * 4 * copies;
  };
  std::uint64_t kept = bytes(own);
  for (const auto& [key, m] : lightMaps_) kept += std::get<0>(key) == kSharedMaps ? 0 : bytes(key);
  if (kept > std::uint64_t(settings_.lightMapsMiB) << 20) {
    mapsPastBudget_ = true;
    return lightMaps_[shared];
  }
  return lightMaps_[own];
}

void FrameContext::recordShadowMap(const vk::raii::CommandBuffer& cmd, FrameStats& stats) {
  // Made on first use for each resolution and face count the frame's lights need.
  LightMaps& m = maps();
  if (!m.shadowMap)
    m.shadowMap = std::make_unique<raster::ShadowMapPass>(context_, mapSettings_, frameData_.shadow.faceCount);
  std::uint64_t bytes = 0, all = 0, own = 0;  // the maps the frame's lights keep; with their thin masks and pyramids
  for (const auto& [key, maps] : lightMaps_) {
    bytes += maps.shadowMap ? maps.shadowMap->depth().bytes() : 0;
    all += (maps.shadowMap ? maps.shadowMap->depth().bytes() + maps.shadowMap->texels().size() : 0) +
           (maps.thin ? maps.thin->bytes() : 0) + (maps.pyramid ? maps.pyramid->tiles().size() : 0);
    own += std::get<0>(key) != kSharedMaps;
  }
  stats.memoryBytes["shadow_map"] = bytes;
  stats.memoryBytes["light_maps"] = all;
  if (slot_.count > 1 && settings_.reuseLightPasses) stats.counts["lights_with_own_maps"] = own;
  stats.counts["shadow_map_texels"] =
      std::uint64_t(mapSettings_.resolution) * mapSettings_.resolution * frameData_.shadow.faceCount;
  const LightPassesKey key = lightPassesKey();
  if (settings_.reuseLightPasses && m.shadowMapKey == key) {
    stats.reusedPasses.push_back("shadow_map");
    return;
  }
  timer_.begin(cmd, "shadow_map");
  m.shadowMap->record(cmd, geometry_, frameData_.shadow);
  timer_.end(cmd);
  m.shadowMapKey = key;
}

}  // namespace penumbra
