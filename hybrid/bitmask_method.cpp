// Method bitmask: bitmask visibility sampling (Eisemann & Décoret 2007) on the scene's planar
// receiver (the largest planar mesh, or --bitmask-receiver), with the light samples of the shared
// pattern (GpuLight::sharedPattern, the one the reference uses with --shared-samples). Pixels on
// the receiver take the hidden-samples map's answer; every other covered pixel is traced like frt
// (the fallback), so that a whole frame is rendered and compared.
#include <string>

#include "core/planar_receivers.h"
#include "hybrid/method.h"
#include "hybrid/renderer.h"
#include "raster/bitmask_pass.h"
#include "shared/compact.h"

namespace penumbra {
namespace {

class BitmaskMethod final : public Method {
 public:
  bool sharedSamplePattern() const override { return true; }

  void run(Renderer& r, FrameStats& stats) override {
    const shared::GpuLight& light = r.frameData().light;
    if (!shared::isAreaLight(light)) {
      throw InputError("method bitmask samples an area light; give the light a size (--light-size > 0, rect or disk)");
    }
    const shared::BitmaskFrame frame = frameFor(r, light);
    const vk::DeviceSize range = r.context().storageBufferRange();
    const vk::DeviceSize hiddenBytes = vk::DeviceSize(frame.resolution) * frame.resolution * frame.words * 4;
    if (hiddenBytes > range) {
      throw InputError("bitmask: a " + std::to_string(frame.resolution) + "^2 map of " + std::to_string(frame.samples) +
                       " samples needs " + std::to_string(hiddenBytes >> 20) + " MiB, more than one storage binding (" +
                       std::to_string(range >> 20) + " MiB); lower --bitmask-res or --spp");
    }
    if (!pass_) pass_ = std::make_unique<raster::BitmaskPass>(r.context(), frame.resolution);
    ShadowTracer& tracer = r.tracer(stats);
    const TraceJob job = r.traceJob(false);
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      r.recordGBuffer(cmd);
      if (frame.keepOthers) {  // srt answers the other pixels: the map, the classification, the mask
        r.recordShadowMap(cmd, stats);
        r.recordClassify(cmd, stats, false);  // the resolve clears the receiver's flags: no list yet
      } else {
        r.recordUnclassified(cmd);
      }
      r.timer().begin(cmd, "bitmask");
      pass_->record(cmd, r.geometry(), r.gbuffer(), r.frameBuffer(), light, frame, r.visibility(), r.traceFlags());
      r.timer().end(cmd);
      r.recordCompact(cmd, COMPACT_FLAGGED);
      r.timer().begin(cmd, "trace");
      tracer.record(cmd, job);
      r.timer().end(cmd);
    });
    r.finishTrace(tracer, job, stats);
    stats.memoryBytes["bitmask"] = pass_->bytes();
    const auto [regions, texels] = pass_->fill();
    stats.counts["bitmask_regions"] = regions;
    stats.counts["bitmask_fill_texels"] = texels;
    stats.counts["bitmask_map_texels"] = std::uint64_t(frame.resolution) * frame.resolution;
    stats.notes.push_back("bitmask: receiver '" + receiver_->mesh + "', " + std::to_string(frame.resolution) + "^2 map, " +
                          std::to_string(frame.samples) + " samples; the rest of the frame answered like " +
                          r.settings().bitmask.fallback + " (" + tracer.name() + ")");
  }

 private:
  shared::BitmaskFrame frameFor(Renderer& r, const shared::GpuLight& light) {
    const float radius = r.bounds().radius();
    if (!receiver_) receiver_ = chooseReceiver(r.scene(), r.settings().bitmask.receiver, 1e-5f * radius);
    PlanarReceiver rec = *receiver_;
    const glm::vec3 centre(light.position);
    if (glm::dot(rec.normal, centre) + rec.offset < 0.0f) {  // the map's side is the light's
      rec.normal = -rec.normal;
      rec.offset = -rec.offset;
    }
    const glm::vec3 t(light.tangent), b = glm::cross(glm::vec3(light.direction), t);
    float lowest = INFINITY;
    for (int i = 0; i < 4; ++i) {
      const glm::vec3 corner = centre + 0.5f * light.size * ((i & 1) ? t : -t) + 0.5f * light.size * ((i & 2) ? b : -b);
      lowest = std::min(lowest, glm::dot(rec.normal, corner) + rec.offset);
    }
    const float margin = light.rayEpsilon;  // as the reference's ray origins: nearer casters are the receiver's
    if (!(lowest > 2.0f * margin)) {
      throw InputError("bitmask: the light reaches down to the receiver '" + rec.mesh +
                       "' (its lowest corner lies on or below the plane); move the light above it or use another method");
    }
    const std::uint32_t spp = r.frameData().spp;
    if (spp > BITMASK_MAX_SAMPLES) {
      throw InputError("bitmask: --spp " + std::to_string(spp) + " is more than the " +
                       std::to_string(BITMASK_MAX_SAMPLES) + " samples a map holds; use 32 to 1024");
    }
    shared::BitmaskFrame f{};
    f.plane = glm::vec4(rec.normal, rec.offset);
    f.origin = glm::vec4(rec.origin, 1.0f);
    f.axisU = glm::vec4(rec.axisU, rec.extentU);
    f.axisV = glm::vec4(rec.axisV, rec.extentV);
    f.lightCentre = glm::vec4(centre, light.size);
    f.lightT = glm::vec4(t, lowest);
    f.lightB = glm::vec4(b, margin);
    f.samples = spp;
    f.words = (spp + 31) / 32;
    f.resolution = r.settings().bitmask.resolution;
    const std::string& fallback = r.settings().bitmask.fallback;
    if (fallback != "srt" && fallback != "frt") {
      throw InputError("bitmask: fallback '" + fallback + "' is not a method it can use; use srt or frt");
    }
    f.keepOthers = fallback == "srt" ? 1u : 0u;
    f.decorrelate = r.settings().bitmask.decorrelate ? 1u : 0u;
    f.onPlane = glm::vec4(1e-4f * radius, 0.99f, light.size, r.settings().bitmask.watertight ? 1.0f : 0.0f);
    return f;
  }

  static PlanarReceiver chooseReceiver(const Scene& scene, const std::string& name, float tolerance) {
    const std::vector<PlanarReceiver> found = findPlanarReceivers(scene, tolerance);
    if (name.empty()) {
      if (found.empty()) {
        throw InputError("bitmask: scene '" + scene.name +
                         "' has no planar mesh to receive shadows (all of a mesh's vertices in one plane); use another method");
      }
      return found.front();
    }
    for (const PlanarReceiver& r : found) {
      if (r.mesh == name) return r;
    }
    std::string planar;
    for (const PlanarReceiver& r : found) planar += (planar.empty() ? "" : ", ") + ("'" + r.mesh + "'");
    throw InputError("bitmask: no planar mesh named '" + name + "' in scene '" + scene.name + "'; planar meshes: " +
                     (planar.empty() ? "none" : planar));
  }

  std::optional<PlanarReceiver> receiver_;
  std::unique_ptr<raster::BitmaskPass> pass_;
};

}  // namespace

std::unique_ptr<Method> makeBitmaskMethod() { return std::make_unique<BitmaskMethod>(); }

}  // namespace penumbra
