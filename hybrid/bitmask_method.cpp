// Method bitmask: bitmask visibility sampling (Eisemann & Décoret 2007) on the scene's planar
// receivers (the planar meshes of at least 1% of the largest one's area, up to
// raster::kMaxBitmaskReceivers, or --bitmask-receivers), each with its own hidden-samples map, with
// the light samples of the shared pattern (GpuLight::sharedPattern, the one the reference uses
// with --shared-samples). Pixels on a receiver take its map's answer; every other covered pixel is
// answered by the fallback (srt or frt), so that a whole frame is rendered and compared. A receiver
// the light reaches down to (its lowest corner on or below the plane) is left to the fallback. A
// named mesh that is not planar may be a height field over a plane (the paper's extension): its
// heights are rasterized onto the map and each texel's receiver point lies on them.
#include <string>

#include "core/cutouts.h"
#include "core/planar_receivers.h"
#include "hybrid/frame_context.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"
#include "raster/bitmask_pass.h"

namespace penumbra {
namespace {

class BitmaskMethod final : public Method {
 public:
  bool sharedSamplePattern() const override { return true; }

  void run(FrameContext& r, FrameStats& stats) override {
    const shared::GpuLight& light = r.frameData().light;
    if (!shared::isAreaLight(light)) {
      throw InputError("method bitmask samples an area light; give the light a size (--light-size > 0, rect or disk)");
    }
    const raster::BitmaskSettings& settings = r.settings().bitmask;
    if (settings.fallback != "srt" && settings.fallback != "frt") {
      throw InputError("bitmask: fallback '" + settings.fallback + "' is not a method it can use; use srt or frt");
    }
    const std::uint32_t spp = r.frameData().spp;
    if (spp > BITMASK_MAX_SAMPLES) {
      throw InputError("bitmask: --spp " + std::to_string(spp) + " is more than the " +
                       std::to_string(BITMASK_MAX_SAMPLES) + " samples a map holds; use 32 to 1024");
    }
    const vk::DeviceSize range = r.context().storageBufferRange();
    const vk::DeviceSize hiddenBytes = vk::DeviceSize(settings.resolution) * settings.resolution * ((spp + 31) / 32) * 4;
    if (hiddenBytes > range) {
      throw InputError("bitmask: a " + std::to_string(settings.resolution) + "^2 map of " + std::to_string(spp) +
                       " samples needs " + std::to_string(hiddenBytes >> 20) + " MiB, more than one storage binding (" +
                       std::to_string(range >> 20) + " MiB); lower --bitmask-res or --spp");
    }
    if (receivers_.empty()) {
      receivers_ = chooseReceivers(r.scene(), settings.receivers, 1e-5f * r.bounds().radius());
      for (const PlanarReceiver& receiver : receivers_) fields_.push_back(fieldGeometry(r, receiver));
    }
    std::vector<shared::BitmaskFrame> frames;
    std::vector<const raster::SceneGeometry*> fields;
    std::string names;
    for (std::size_t k = 0; k < receivers_.size(); ++k) {
      if (auto frame = frameFor(r, light, receivers_[k])) {
        frames.push_back(*frame);
        fields.push_back(fields_[k].get());
        names += (names.empty() ? "'" : ", '") + receivers_[k].mesh + (receivers_[k].heightField ? "' (height field)" : "'");
      }
    }
    if (frames.empty()) {
      throw InputError("bitmask: the light reaches down to every receiver (its lowest corner on or below their planes); "
                       "move the light above one or use another method");
    }
    // frt: the first receiver's resolve flags every covered pixel off it; the others then only
    // answer their own pixels. srt: the classification answered every pixel first.
    const bool srt = settings.fallback == "srt";
    for (std::size_t k = 0; k < frames.size(); ++k) frames[k].keepOthers = srt || k > 0 ? 1u : 0u;
    if (!table_) table_ = std::make_unique<raster::BitmaskTable>(r.context());
    while (passes_.size() < frames.size()) passes_.push_back(std::make_unique<raster::BitmaskPass>(r.context(), settings.resolution));
    ShadowTracer& tracer = r.tracer(stats);
    const TraceJob job = r.traceJob(tracer, TraceList::Flagged);
    r.context().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      r.recordGBuffer(cmd);
      if (srt) {  // the map, the classification, the mask
        r.recordShadowMap(cmd, stats);
        r.recordClassify(cmd, stats);  // the resolves clear the receivers' flags: no list yet
      } else {
        r.recordUnclassified(cmd);
      }
      r.timer().begin(cmd, "bitmask");
      table_->record(cmd, light, spp);
      for (std::size_t k = 0; k < frames.size(); ++k) {
        passes_[k]->record(cmd, *table_, r.geometry(), fields[k], r.gbuffer(), r.frameBuffer(), frames[k], r.visibility(),
                           r.traceFlags());
      }
      r.timer().end(cmd);
      r.recordTraceList(cmd, TraceList::Flagged, stats);
      r.timer().begin(cmd, "trace");
      tracer.record(cmd, job);
      r.timer().end(cmd);
      if (tracer.onDevice()) r.recordShade(cmd);  // the visibility is final here
    });
    r.finishTrace(tracer, job, stats);
    std::uint64_t bytes = table_->buffer().size(), regions = 0, texels = 0;
    for (std::size_t k = 0; k < frames.size(); ++k) {
      bytes += passes_[k]->bytes();
      const auto [n, t] = passes_[k]->fill();
      regions += n;
      texels += t;
    }
    stats.memoryBytes["bitmask"] = bytes;
    stats.counts["bitmask_regions"] = regions;
    stats.counts["bitmask_fill_texels"] = texels;
    stats.counts["bitmask_map_texels"] = std::uint64_t(settings.resolution) * settings.resolution * frames.size();
    stats.notes.push_back("bitmask: receivers " + names + ", " + std::to_string(settings.resolution) + "^2 maps, " +
                          std::to_string(spp) + " samples; the rest of the frame answered like " + settings.fallback +
                          " (" + tracer.name() + ")");
    if (hasCutouts(r.scene())) {
      stats.notes.push_back("bitmask: its receivers' maps draw cut-outs solid (their textures are not read)");
    }
  }

 private:
  // The receiver's map and the light as the shaders take them; none when the light reaches down
  // to the receiver's plane.
  static std::optional<shared::BitmaskFrame> frameFor(FrameContext& r, const shared::GpuLight& light, PlanarReceiver rec) {
    const glm::vec3 centre(light.position);
    if (!rec.heightField && glm::dot(rec.normal, centre) + rec.offset < 0.0f) {  // the map's side is the light's
      rec.normal = -rec.normal;
      rec.offset = -rec.offset;
    }
    const raster::BitmaskSettings& settings = r.settings().bitmask;
    const std::uint32_t spp = r.frameData().spp;
    const float margin = light.rayEpsilon;  // as the reference's ray origins: nearer casters are the receiver's
    shared::BitmaskFrame f{};
    f.plane = glm::vec4(rec.normal, rec.offset);
    f.origin = glm::vec4(rec.origin, 1.0f);
    f.axisU = glm::vec4(rec.axisU, rec.extentU);
    f.axisV = glm::vec4(rec.axisV, rec.extentV);
    f.lightCentre = glm::vec4(centre, light.size);
    const glm::vec3 t(light.tangent);
    f.lightT = glm::vec4(t, 0.0f);
    f.lightB = glm::vec4(glm::cross(glm::vec3(light.direction), t), margin);
    f.samples = spp;
    f.words = (spp + 31) / 32;
    f.resolution = settings.resolution;
    f.decorrelate = settings.decorrelate ? 1u : 0u;
    f.onPlane = glm::vec4(1e-4f * r.bounds().radius(), 0.99f, light.size, settings.watertight ? 1.0f : 0.0f);
    f.field = glm::vec4(rec.heightField ? 1.0f : 0.0f, rec.top, 0.0f, 0.0f);
    float lowest = INFINITY;  // the light's lowest corner over the plane
    for (int i = 0; i < 4; ++i) lowest = std::min(lowest, glm::dot(rec.normal, shared::lightSquareCorner(f, i)) + rec.offset);
    if (!(lowest > rec.top + 2.0f * margin)) return std::nullopt;  // the light must be above all of it
    f.lightT.w = lowest;
    return f;
  }

  static std::vector<PlanarReceiver> chooseReceivers(const Scene& scene, const std::vector<std::string>& names,
                                                     float tolerance) {
    const std::vector<PlanarReceiver> found = findPlanarReceivers(scene, tolerance);  // largest first
    std::vector<PlanarReceiver> chosen;
    if (names.empty()) {
      for (const PlanarReceiver& r : found) {
        if (r.area >= 0.01 * found.front().area && chosen.size() < raster::kMaxBitmaskReceivers) chosen.push_back(r);
      }
      if (chosen.empty()) {
        throw InputError("bitmask: scene '" + scene.name +
                         "' has no planar mesh to receive shadows (all of a mesh's vertices in one plane); use another method");
      }
      return chosen;
    }
    if (names.size() > raster::kMaxBitmaskReceivers) {
      throw InputError("bitmask: " + std::to_string(names.size()) + " receivers named, at most " +
                       std::to_string(raster::kMaxBitmaskReceivers));
    }
    for (const std::string& name : names) {
      bool known = false;
      for (const PlanarReceiver& r : found) {
        if (r.mesh == name) {
          chosen.push_back(r);
          known = true;
          break;
        }
      }
      if (known) continue;
      if (auto field = findHeightField(scene, name)) {
        chosen.push_back(*field);
        continue;
      }
      std::string planar;
      for (const PlanarReceiver& r : found) planar += (planar.empty() ? "" : ", ") + ("'" + r.mesh + "'");
      throw InputError("bitmask: no planar mesh or height field named '" + name + "' in scene '" + scene.name +
                       "'; planar meshes: " + (planar.empty() ? "none" : planar));
    }
    return chosen;
  }

  // A height field's mesh alone, uploaded for its height pass; null for a plane.
  static std::unique_ptr<raster::SceneGeometry> fieldGeometry(FrameContext& r, const PlanarReceiver& receiver) {
    if (!receiver.heightField) return nullptr;
    Scene field;
    for (const Mesh& mesh : r.scene().meshes) {
      if (mesh.name == receiver.mesh) field.meshes.push_back(mesh);
    }
    return std::make_unique<raster::SceneGeometry>(r.context(), field);
  }

  std::vector<PlanarReceiver> receivers_;
  std::vector<std::unique_ptr<raster::SceneGeometry>> fields_;
  std::unique_ptr<raster::BitmaskTable> table_;
  std::vector<std::unique_ptr<raster::BitmaskPass>> passes_;
};

}  // namespace

void register_bitmask_method(Registry& r) {
  r.method("bitmask", [] { return std::make_unique<BitmaskMethod>(); });
}

}  // namespace penumbra
