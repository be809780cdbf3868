#include "apps/run_config.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <thread>

#include "apps/declared_options.h"
#include "core/animation.h"
#include "core/builtin_scenes.h"
#include "core/cutouts.h"
#include "core/lights_file.h"
#include "core/metrics.h"
#include "core/scene_loader.h"
#include "core/view.h"
#include "hybrid/method.h"
#include "hybrid/registry.h"
#include "hybrid/shade_pass.h"
#include "raster/color_textures.h"

namespace penumbra {
namespace {

void parseResolution(const std::string& text, std::uint32_t& width, std::uint32_t& height) {
  unsigned w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%u%c%u%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 1 || h < 1 ||
      w > 16384 || h > 16384) {
    throw InputError("--res '" + text + "' is not a resolution; use WxH with 1..16384 each, e.g. 256x256");
  }
  width = w;
  height = h;
}

// Host memory (lavapipe's device memory) the run's GPU buffers need, estimated before allocating,
// by what drives it.
struct MemoryEstimate {
  std::uint64_t lightMaps = 0, perPixel = 0, geometry = 0, textures = 0, lineSpace = 0;
  std::uint64_t total() const { return lightMaps + perPixel + geometry + textures + lineSpace; }
  // The largest term, and what lowers it.
  std::string largest(const RenderSettings& s, std::uint64_t triangles) const {
    const auto mib = [](std::uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; };
    const std::uint64_t top = std::max({lightMaps, perPixel, geometry, textures, lineSpace});
    if (top == perPixel) {
      return "the " + std::to_string(s.width) + "x" + std::to_string(s.height) + " frame's buffers (" + mib(perPixel) +
             "): lower --res";
    }
    if (top == lightMaps) {
      return "the light's maps at " + std::to_string(s.shadowMap.resolution) + "^2 (" + mib(lightMaps) +
             "): lower --shadow-map-res" + (s.reuseLightPasses ? " or --light-maps-memory" : "");
    }
    if (top == geometry) {
      return "the scene's " + std::to_string(triangles) + " triangles (" + mib(geometry) +
             "): load a smaller scene or level";
    }
    if (top == textures) return "the scene's textures (" + mib(textures) + "): use smaller images";
    return "the line space's pools (" + mib(lineSpace) + "): lower --linespace-budget";
  }
};

MemoryEstimate estimateBytes(const RenderSettings& s, std::uint64_t triangles, bool usesLineSpace) {
  MemoryEstimate e;
  const std::uint64_t pixels = std::uint64_t(s.width) * s.height;
  const std::uint64_t face = std::uint64_t(s.shadowMap.resolution) * s.shadowMap.resolution * 4;
  // Worst case a cube: the map, msm's own map, the thin mask, and the edge pyramid (as much as a map:
  // two floats per tile of 1/3 of a map's texels, a fit of four per tile from level 2, 1/12 of them);
  // the corner maps (--penumbra-maps 5) add one more map and pyramid.
  const std::uint64_t maps = s.pip.penumbraMaps == 5 ? 4 : 3;
  e.lightMaps = face * 6 * maps + face * 6 * (maps - 2);
  // G-buffer images (with depth) and readbacks; visibility, colour, sm visibility, trace flags,
  // ray max, and the compacted ShadingPoints
  e.perPixel = pixels * (16 + 16 + 4 + 4 + 4) * 2 + pixels * (4 + 4 + 4 + 4 + 4 + sizeof(shared::ShadingPoint));
  // the denoiser, once per denoised method: blocker distances, accumulated values, two histories
  if (s.denoise.mode != DenoiseMode::Off) e.perPixel += pixels * (4 + 8 + 2 * 16) * 2;
  // raster vertices and indices, the GPU BVH (48-byte triangles, ~64 bytes of nodes per triangle)
  e.geometry = triangles * (3 * 4 + 3 * 36 + 48 + 64);
  // The line space refuses itself before allocating when its pools exceed its budget, so an
  // explicit --linespace-budget is what it may add; the default (a quarter of the available
  // memory) is left out, as it adapts to what is free.
  e.lineSpace = usesLineSpace ? s.lineSpace.budgetBytes : 0;
  return e;
}

std::uint64_t physicalMemoryBytes() {
  return std::uint64_t(sysconf(_SC_PHYS_PAGES)) * std::uint64_t(sysconf(_SC_PAGE_SIZE));
}

// lavapipe's device memory is host memory: half of it stays for the driver, the host copies and
// the reference tracer. InputError naming the limit and the largest term when the run needs more.
void requireFits(const MemoryEstimate& need, const RenderSettings& s, std::uint64_t triangles) {
  const std::uint64_t have = physicalMemoryBytes(), limit = have / 2;
  if (need.total() <= limit) return;
  throw InputError("this run needs about " + std::to_string(need.total() >> 20) + " MiB of GPU buffers, over the limit of " +
                   std::to_string(limit >> 20) + " MiB (half of this machine's " + std::to_string(have >> 20) +
                   " MiB); most of it is " + need.largest(s, triangles));
}

}  // namespace

void addRunOptions(CLI::App& app, RunConfig& c) {
  // --help lists them by topic, each group declared before its options.
  app.option_defaults()->group("Scene, camera and light");
  app.add_option("--scene", c.scene, "Scene: builtin:NAME[:LEVEL] (courtyard, wires, square, checker, room, foliage, level, knot), a .gltf/.glb or .obj file")
      ->capture_default_str();
  app.add_option("--camera", c.camera, "Camera 'ex,ey,ez:tx,ty,tz[:fovy]' (default: the scene's, else a three-quarter view)");
  app.add_option("--light", c.lights,
                 "Light 'dir:dx,dy,dz' | 'point:x,y,z' | 'spot:x,y,z:tx,ty,tz[:angle]' | 'rect:x,y,z:tx,ty,tz' | "
                 "'disk:...'; repeat it for several lights (default: every light of the scene)")
      ->take_last()
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app.add_option("--lights", c.lightsFile,
                 "JSON file of lights, each with its own size, colour, intensity and range (docs/cli.md); "
                 "with --light, both sets");
  app.add_option("--light-size", c.lightSize,
                 "Area light extent as a fraction of the scene radius (0 = point light); given, it sizes every light")
      ->each([&c](const std::string&) { c.lightSizeGiven = true; });
  app.add_option("--time", c.time, "Animated scenes (e.g. builtin:courtyard-moving): pose at this many seconds")
      ->each([&c](const std::string&) { c.timeGiven = true; });
  app.add_option("--view", c.viewFile, "JSON view file pinning camera, light, light size and resolution");
  app.add_option("--save-view", c.saveView, "Write the resolved camera, light, light size and resolution to this JSON file");
  app.add_option("--res", c.resolution, "Image resolution WxH")->capture_default_str();
  app.option_defaults()->group("Ray tracing");
  std::string shadowTracers;
  for (const auto& [name, entry] : registry().tracers()) shadowTracers += name + " (" + entry.help + "), ";
  app.add_option("--tracer", c.tracer,
                 "Ray tracer of srt and frt: " + shadowTracers +
                     "or auto (rq on a GPU that has ray queries, else bvh). Methods ao and indirect take a "
                     "comma-separated list of " + indirectTracerList() +
                     " (auto = bvh) and render once per tracer: bvh exact, bvh-ls the BVH with candidate line spaces, "
                     "ntree the N-tree's line space in exact mode (exact), ntree-ls the N-tree with candidate line "
                     "spaces (--ntree-ls-depth; its bounces' shadow rays on the binary line space)")
      ->capture_default_str();
  addDeclaredOptions(app, c.settings, renderOptions());  // shadow maps, srt, baselines, indirect, line space, ...
  app.option_defaults()->group("Soft shadows and denoising");
  app.add_option(
         "--denoise-frames", c.denoiseFrames,
         "--denoise temporal: each method renders a sequence from a cut and reports this frame of it (and later "
         "ones with --repeat)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000u));
  app.option_defaults()->group("Measuring and output");
  app.add_option("--warmup", c.warmup, "Frames rendered and discarded before the measured one (shader JIT, caches)")
      ->capture_default_str()->check(CLI::Range(0u, 100u));
  app.add_option("--repeat", c.repeat, "Measured frames per method; the median frame is reported with min/max")
      ->capture_default_str()->check(CLI::Range(1u, 1000u));
  app.add_flag("--validate", c.validate, "Enable Vulkan validation layers; any message makes the run fail");
  app.add_option("--out", c.outDir, "Output folder")->capture_default_str();
  app.option_defaults()->group("Options");  // what the command adds after these
}

FrameSequence::FrameSequence(const RunConfig& config, const RenderSettings& settings, std::string method)
    : method_(std::move(method)),
      sequence_(settings.denoise.mode == DenoiseMode::Temporal && method_ != "ref"),
      warmup_(sequence_ ? std::max(config.warmup, config.denoiseFrames - 1) : config.warmup) {}

Frame FrameSequence::next(Renderer& renderer, const Camera& camera, std::span<const Light> lights) {
  renderer.setFrame(sequence_ ? frame_++ : 0u);
  return renderer.render(method_, camera, lights);
}

std::vector<std::string> splitList(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) items.push_back(item);
  }
  if (items.empty()) throw InputError("--methods '" + list + "' names no method; e.g. --methods sm,pcf");
  return items;
}

std::vector<std::string> expandMethods(const RunConfig& c, const std::vector<std::string>& methods) {
  const std::vector<std::string> tracers = c.tracer.empty() ? std::vector<std::string>{"auto"} : splitList(c.tracer);
  std::vector<std::string> shadowTracers = tracerNames();
  shadowTracers.insert(shadowTracers.begin(), "auto");
  std::string shadowTracerList;
  for (const std::string& t : shadowTracers) shadowTracerList += (shadowTracerList.empty() ? "" : ", ") + t;
  std::vector<std::string> out;
  for (const std::string& m : methods) {
    if (methodTerm(m) == Term::Shadow) {  // unknown names fail here, before any work
      if (tracers.size() != 1 || std::find(shadowTracers.begin(), shadowTracers.end(), tracers[0]) == shadowTracers.end()) {
        throw InputError("--tracer '" + c.tracer + "': method " + m +
                         " takes one tracer of " + shadowTracerList + " (lists are for ao and indirect)");
      }
      out.push_back(m);
    } else if (m == "ao" || m == "indirect") {
      for (const std::string& t : tracers) {
        const std::string tracer = t == "auto" ? "bvh" : t;
        if (!isIndirectTracer(tracer)) {
          throw InputError("--tracer '" + t + "': methods ao and indirect trace on " + indirectTracerList());
        }
        out.push_back(m + "-" + tracer);
      }
    } else {
      const std::string tracer = m.substr(m.find('-') + 1);
      if (!isIndirectTracer(tracer)) throw InputError("method " + m + ": unknown tracer; use " + indirectTracerList());
      out.push_back(m);
    }
  }
  return out;
}

Frame medianFrame(std::vector<Frame> runs) {
  std::sort(runs.begin(), runs.end(), [](const Frame& a, const Frame& b) { return a.stats.totalMs < b.stats.totalMs; });
  Frame median = std::move(runs[runs.size() / 2]);
  median.stats.totalSpreadMs = {runs.front().stats.totalMs, runs.back().stats.totalMs, std::uint32_t(runs.size())};
  return median;
}

std::string referenceFor(const std::string& method) {
  const Term term = methodTerm(method);
  return term == Term::Shadow ? "ref" : std::string(termName(term)) + "-embree";
}

namespace {
// --light-error: what the light's visibility errors changed each covered pixel's shaded value by
// (its shadow weight times |visibility - reference|) added to `sum`; their largest.
double addShadeError(const Frame& light, const Frame& reference, const std::vector<std::uint8_t>& covered,
                     std::vector<double>& sum) {
  double largest = 0.0;
  sum.resize(covered.size(), 0.0);
  for (std::size_t p = 0; p < covered.size(); ++p) {
    if (!covered[p]) continue;
    const double e = double(light.shadowWeight[p]) * std::abs(double(light.visibility[p]) - reference.visibility[p]);
    largest = std::max(largest, e);
    sum[p] += e;
  }
  return largest;
}
}  // namespace

std::optional<MissReport> judgeFrame(Frame& frame, const Frame& reference, bool soft, std::vector<float>* flip) {
  if (!frame.lights.empty()) {  // each light against the reference's same light; the frame over them all
    if (reference.lights.size() != frame.lights.size()) throw std::logic_error("judged against another set of lights");
    frame.stats.imageError =
        compareImages(frame.rgba, reference.rgba, reference.covered, frame.width, frame.height, flip);
    std::vector<float> all, allReference;
    std::vector<std::uint8_t> covered;
    std::vector<double> shadeError;  // --light-error: per pixel, over the lights
    for (std::size_t i = 0; i < frame.lights.size(); ++i) {
      Frame& light = frame.lights[i];
      const Frame& ref = reference.lights[i];
      const float threshold = ref.stats.samplesPerPixel > 1 ? kWrongThresholdSoft : kWrongThresholdHard;
      light.stats.error = compareVisibility(light.visibility, ref.visibility, reference.covered, threshold);
      if (!light.shadowWeight.empty()) {
        light.stats.lightErrorMax = addShadeError(light, ref, reference.covered, shadeError);
      }
      if (!light.pip.empty()) {
        light.stats.pipMissFraction =
            missFraction(light.shadowMapVisibility, ref.visibility, reference.covered, light.pip, threshold);
      }
      frame.stats.lights[i] = light.stats;
      all.insert(all.end(), light.visibility.begin(), light.visibility.end());
      allReference.insert(allReference.end(), ref.visibility.begin(), ref.visibility.end());
      covered.insert(covered.end(), reference.covered.begin(), reference.covered.end());
    }
    frame.stats.error = compareVisibility(all, allReference, covered, soft ? kWrongThresholdSoft : kWrongThresholdHard);
    if (!shadeError.empty()) frame.stats.lightErrorMax = *std::max_element(shadeError.begin(), shadeError.end());
    return std::nullopt;
  }
  const float threshold = soft ? kWrongThresholdSoft : kWrongThresholdHard;
  // ao and indirect are continuous terms: the soft threshold, whatever the light
  const float wrong = frame.stats.term ? kWrongThresholdSoft : threshold;
  frame.stats.error = compareVisibility(frame.visibility, reference.visibility, reference.covered, wrong);
  frame.stats.imageError =
      compareImages(frame.rgba, reference.rgba, reference.covered, frame.width, frame.height, flip);
  if (!frame.shadowWeight.empty()) {
    std::vector<double> shadeError;
    frame.stats.lightErrorMax = addShadeError(frame, reference, reference.covered, shadeError);
  }
  if (frame.pip.empty()) return std::nullopt;
  frame.stats.pipMissFraction =
      missFraction(frame.shadowMapVisibility, reference.visibility, reference.covered, frame.pip, threshold);
  if (soft) frame.stats.penumbraMissFraction = penumbraMissFraction(reference.visibility, reference.covered, frame.pip);
  if (frame.pipWhy.empty()) return std::nullopt;
  MissReport report = explainMisses(frame.shadowMapVisibility, frame.pip, frame.pipWhy, reference.visibility,
                                    reference.covered, threshold);
  frame.stats.missCauses = missCauseCounts(report);
  if (soft) frame.stats.maskRules = explainMask(frame.pip, frame.pipWhy, reference.visibility, reference.covered);
  return report;
}

RunSetup prepareRun(const RunConfig& c, const std::vector<std::string>& methods, const Scene* loaded) {
  for (const std::string& m : expandMethods(c, methods)) makeMethod(m);  // unknown names fail before any work
  if (!std::isfinite(c.lightSize)) throw InputError("--light-size must be a finite number");

  RunSetup s;
  s.settings = c.settings;  // what the declared options set (the others follow)
  // A built-in level's geometry alone may be over the limit: refused before it is built.
  if (const std::optional<std::uint64_t> triangles = loaded ? std::nullopt : builtinTriangleCount(c.scene)) {
    MemoryEstimate geometry;
    geometry.geometry = estimateBytes(s.settings, *triangles, false).geometry;
    requireFits(geometry, s.settings, *triangles);
  }
  s.scene = loaded ? *loaded : loadScene(c.scene);
  for (const std::string& w : s.scene.warnings) std::cerr << "penumbra: " << c.scene << ": " << w << "\n";
  const Bounds bounds = s.scene.bounds();

  std::optional<View> view;
  const glm::dvec3 origin = s.scene.origin;  // options and view files are in world coordinates
  if (!c.viewFile.empty()) view = readViewFile(c.viewFile, origin);
  s.settings.width = view ? std::uint32_t(view->width) : 0;
  s.settings.height = view ? std::uint32_t(view->height) : 0;
  if (!view || c.resolution != "256x256") parseResolution(c.resolution, s.settings.width, s.settings.height);

  if (!c.camera.empty()) s.camera = parseCamera(c.camera, origin);
  else if (view) s.camera = view->camera;
  else if (s.scene.camera) s.camera = *s.scene.camera;
  else {
    s.camera = defaultCamera(bounds);
    std::cout << "camera (default): --camera " << formatCamera(s.camera, origin) << "\n";
  }
  // Lights that carry their own size (a lights file's, a view's "lights", the scene's) keep it unless
  // --light-size is given; specs take --light-size (or the view's light_size).
  for (const std::string& spec : c.lights) s.lights.push_back(parseLight(spec, origin));
  std::size_t sizedByFraction = s.lights.size();
  if (!c.lightsFile.empty()) {
    const std::vector<Light> file = readLightsFile(c.lightsFile, origin);
    s.lights.insert(s.lights.end(), file.begin(), file.end());
  }
  if (s.lights.empty() && view && !view->lights.empty()) s.lights = view->lights;
  if (s.lights.empty() && view) s.lights = {view->light}, sizedByFraction = 1;
  if (s.lights.empty()) s.lights = s.scene.lights;
  if (s.lights.empty()) {
    s.lights = {defaultLight(bounds)};
    sizedByFraction = 1;
    std::cout << "light (default): --light " << formatLight(s.lights.front(), origin) << "\n";
  }
  s.time = c.timeGiven || !view ? c.time : view->time;
  if (!std::isfinite(s.time) || s.time < 0.0) throw InputError("--time must be a number of seconds >= 0");
  if (c.timeGiven && !isAnimated(s.scene)) {
    throw InputError("--time poses animated scenes, but '" + c.scene + "' has no animation (try builtin:courtyard-moving)");
  }
  poseScene(s.scene, s.time);
  s.lightSizeFraction = c.lightSizeGiven || !view ? c.lightSize : view->lightSizeFraction;
  for (std::size_t i = 0; i < s.lights.size(); ++i) {
    if (i < sizedByFraction || c.lightSizeGiven) applyLightSize(s.lights[i], s.lightSizeFraction, bounds);
  }
  if (s.lights.size() > 1 && s.settings.denoise.mode != DenoiseMode::Off) {
    throw InputError("--denoise filters the shadow of one light; this run has " + std::to_string(s.lights.size()) +
                     " lights (give one --light)");
  }

  // A denoised run is judged against the converged reference, not one of its own few samples.
  s.settings.referenceSpp = c.referenceSpp                                ? c.referenceSpp
                            : s.settings.denoise.mode != DenoiseMode::Off ? kConvergedSpp
                                                                          : 0u;
  s.settings.tracer = c.tracer.find(',') == std::string::npos ? c.tracer : "auto";  // a list: ao and indirect only
  if (c.tracer.find(',') == std::string::npos && isIndirectTracer(c.tracer == "auto" ? "bvh" : c.tracer)) {
    s.settings.indirect.tracer = c.tracer == "auto" ? "bvh" : c.tracer;  // bare ao and indirect (bench sweeps it)
  }
  const int ntreeDepth = s.settings.indirect.ntreeDepth, depth = int(s.settings.lineSpace.depth);
  if (ntreeDepth >= depth) {
    throw InputError("--ntree-ls-depth " + std::to_string(ntreeDepth) +
                     ": the N-tree's subdivided nodes are at levels 0.." + std::to_string(depth - 1) +
                     " (--linespace-depth " + std::to_string(depth) + "); choose a smaller D or -1 (d - 1)");
  }
  // Every tracer with an N-tree or a line space takes --linespace-n / --linespace-depth and its budget.
  bool lineSpace = std::find(methods.begin(), methods.end(), "ls") != methods.end();
  for (const std::string& t : c.tracer.empty() ? std::vector<std::string>{} : splitList(c.tracer)) {
    lineSpace = lineSpace || t == "ls" || t == "bvh-ls" || t.rfind("ntree", 0) == 0;
  }
  s.settings.pip.explain = c.explainMisses;

  MemoryEstimate need = estimateBytes(s.settings, s.scene.triangleCount(), lineSpace);
  // the cut-outs' alpha and records: the raster passes' copy and a tracer's (core/cutouts.h); the
  // camera pass's colour textures
  need.textures = 2 * cutoutDataBytes(s.scene) + raster::colorTextureBytes(s.scene);
  if (s.lights.size() > 1) {
    // the lights' sum, and their visibilities a shading batch keeps (ShadePass::recordLight)
    const std::uint64_t batch = std::min<std::uint64_t>(s.lights.size(), ShadePass::kBatchImages);
    need.perPixel += std::uint64_t(s.settings.width) * s.settings.height * (16 + 4 * batch);
    // the lights' maps are kept by face count and resolution: a one-face map's beside a cube's
    // (1/6 more), and coarser footprint resolutions (powers of two below: at most 1/3 more)
    need.lightMaps = need.lightMaps * 14 / 9;
    // and, keeping still lights' maps, each light's own up to --light-maps-memory
    if (s.settings.reuseLightPasses) need.lightMaps += std::uint64_t(s.settings.lightMapsMiB) << 20;
  }
  requireFits(need, s.settings, s.scene.triangleCount());
  if (!c.saveView.empty()) {
    // "light" and light_size hold one light sized by a fraction; every other set goes in "lights".
    const bool ownLights = s.lights.size() > 1 || sizedByFraction == 0;
    writeViewFile(c.saveView,
                  {s.camera, s.lights.front(), s.lightSizeFraction, ownLights ? s.lights : std::vector<Light>{},
                   int(s.settings.width), int(s.settings.height), s.time},
                  origin);
  }
  return s;
}

nlohmann::json describeRun(const RunConfig& c, const RunSetup& s, const gpu::Context& context) {
  nlohmann::json run{{"scene", c.scene},
                     {"triangles", s.scene.triangleCount()},
                     {"load_ms", s.scene.loadMs},
                     {"resolution", {s.settings.width, s.settings.height}},
                     {"camera", formatCamera(s.camera, s.scene.origin)},
                     {"light", formatLight(s.lights.front(), s.scene.origin)},
                     {"lights",
                      [&] {
                        nlohmann::json lights = nlohmann::json::array();
                        for (const Light& l : s.lights)
                          lights.push_back(nlohmann::json(lightToJson(l, s.scene.origin)));
                        return lights;
                      }()},
                     {"origin", {s.scene.origin.x, s.scene.origin.y, s.scene.origin.z}},
                     {"light_size", s.lightSizeFraction},
                     {"time", s.time},
                     {"warmup_frames", c.warmup},
                     {"tracer", c.tracer},
                     {"denoise_frames", c.denoiseFrames},
                     {"warnings", s.scene.warnings},
                     {"device", context.deviceName()},
                     {"driver", context.driverInfo()}};
  recordDeclaredOptions(run, s.settings, renderOptions());  // spp, shadow_map_res, pip/delta, denoise, ...
  return run;
}

void appendCsv(const std::string& path, const std::vector<Frame>& frames, const nlohmann::json& context) {
  const bool fresh = !std::filesystem::exists(path);
  std::ofstream out(path, std::ios::app);
  if (fresh) {
    out << "scene,triangles,width,height,light_size,spp,method,tracer,total_ms,total_min_ms,total_max_ms,runs,pip_fraction,rays_traced,"
           "node_visits_per_ray,wrong_pixel_fraction,rmse,pip_miss_fraction,passes,cpu_threads,device,driver\n";
  }
  auto opt = [](const auto& v) { return v ? std::to_string(*v) : std::string(); };
  for (const Frame& f : frames) {
    const FrameStats& s = f.stats;
    std::string passes;
    for (const auto& [pass, ms] : s.passMs) passes += (passes.empty() ? "" : ";") + pass + "=" + std::to_string(ms);
    out << context["scene"].get<std::string>() << "," << context["triangles"] << "," << f.width << "," << f.height << ","
        << context["light_size"] << "," << s.samplesPerPixel << "," << s.method << "," << s.tracer.value_or("") << "," << s.totalMs << ","
        << (s.totalSpreadMs ? s.totalSpreadMs->minMs : s.totalMs) << "," << (s.totalSpreadMs ? s.totalSpreadMs->maxMs : s.totalMs)
        << "," << (s.totalSpreadMs ? s.totalSpreadMs->runs : 1) << "," << opt(s.pipFraction) << "," << opt(s.raysTraced) << ","
        << (s.nodeVisits && s.raysTraced && *s.raysTraced ? std::to_string(double(*s.nodeVisits) / double(*s.raysTraced)) : "")
        << "," << (s.error ? std::to_string(s.error->wrongPixelFraction) : "") << ","
        << (s.error ? std::to_string(s.error->rmse) : "") << "," << opt(s.pipMissFraction) << "," << passes << ","
        << std::thread::hardware_concurrency() << ",\"" << context["device"].get<std::string>() << "\",\""
        << context["driver"].get<std::string>() << "\"\n";
  }
  if (!out) throw std::runtime_error("cannot append to '" + path + "'");
}

void printSummary(const std::vector<Frame>& frames, std::ostream& out) {
  out << std::left << std::setw(8) << "method" << std::right << std::setw(11) << "total ms" << std::setw(8) << "pip %"
      << std::setw(12) << "rays"
      << std::setw(11) << "wrong %" << std::setw(10) << "rmse" << "   passes (ms)\n";
  for (const Frame& f : frames) {
    const FrameStats& s = f.stats;
    out << std::left << std::setw(8) << s.method << std::right << std::fixed << std::setprecision(1) << std::setw(11)
        << s.totalMs << std::setw(8);
    if (s.pipFraction) out << std::setprecision(2) << 100.0 * *s.pipFraction;
    else out << "-";
    out << std::setw(12) << (s.raysTraced ? std::to_string(*s.raysTraced) : "-");
    if (s.error) {
      out << std::setw(11) << std::setprecision(3) << 100.0 * s.error->wrongPixelFraction << std::setw(10)
          << std::setprecision(4) << s.error->rmse;
    } else {
      out << std::setw(11) << "-" << std::setw(10) << "-";
    }
    out << "  ";
    for (const auto& [pass, ms] : s.passMs) out << " " << pass << "=" << std::setprecision(1) << ms;
    out << "\n";
  }
}

}  // namespace penumbra
