// The library's API (include/penumbra/penumbra.h) over the CLI's own pieces: options resolved by
// addRunOptions and prepareRun, frames rendered by a Renderer through FrameSequence, judged by
// judgeFrame, so that a frame here is the CLI's bit for bit.
#include "penumbra/penumbra.h"

#include <map>

#include "apps/run_config.h"
#include "apps/sweep.h"
#include "core/scene_loader.h"
#include "core/view.h"

namespace penumbra::api {
namespace {

// InputError (and the parser's errors) as the API's Error, with the CLI's message.
template <class F>
auto checked(F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw Error(e.what());
  }
}

// The rendered buffers move into the API's frame: no copy after the read-back.
Frame toFrame(penumbra::Frame&& f) {
  return {f.width,
          f.height,
          std::move(f.visibility),
          std::move(f.rgba),
          std::move(f.covered),
          std::move(f.pip),
          f.stats.toJson().dump()};
}

}  // namespace

struct Scene::Impl {
  std::string spec;
  penumbra::Scene scene;
};

Scene::Scene(const std::string& spec)
    : impl_(checked([&] {
        return std::make_shared<const Impl>(Impl{spec, loadScene(spec)});
      })) {}
Scene::~Scene() = default;
const std::string& Scene::spec() const { return impl_->spec; }
std::uint64_t Scene::triangles() const { return impl_->scene.triangleCount(); }

struct Renderer::Impl {
  RunConfig config;
  RunSetup setup;
  gpu::Context context;
  penumbra::Renderer renderer;
  std::map<std::string, FrameSequence> sequences;  // per method: its warm-up done, its next frame

  Impl(const Scene& scene, const RunConfig& c)
      : config(c),
        setup(prepareRun(config, {}, &scene.impl().scene)),
        context({.validate = config.validate}),
        renderer(context, setup.scene, setup.settings) {}

  penumbra::Frame render(const std::string& method) {
    const std::vector<std::string> expanded = expandMethods(config, {method});  // unknown names fail here
    if (expanded.size() != 1)
      throw Error("render takes one method; '" + method + "' with --tracer lists expands to more");
    auto [at, fresh] = sequences.try_emplace(expanded[0], config, setup.settings, expanded[0]);
    FrameSequence& sequence = at->second;
    if (fresh) {
      for (std::uint32_t i = 0; i < sequence.warmup(); ++i) sequence.next(renderer, setup.camera, setup.lights);
    }
    return sequence.next(renderer, setup.camera, setup.lights);
  }

  // As compare measures: --repeat frames, the median one with the spread.
  penumbra::Frame measured(const std::string& method) {
    std::vector<penumbra::Frame> runs;
    for (std::uint32_t i = 0; i < config.repeat; ++i) runs.push_back(render(method));
    return medianFrame(std::move(runs));
  }
};

namespace {

RunConfig configOf(const Scene& scene, const Options& options) {
  RunConfig config;
  config.scene = scene.spec();
  applyRunOptions(config, options);  // the CLI's parser: unknown options and bad values refused alike
  return config;
}

}  // namespace

Renderer::Renderer(const Scene& scene, const Options& options)
    : impl_(checked([&] { return std::make_unique<Impl>(scene, configOf(scene, options)); })) {}
Renderer::~Renderer() = default;

Frame Renderer::render(const std::string& method) {
  return checked([&] { return toFrame(impl_->render(method)); });
}

std::string Renderer::compare(const std::vector<std::string>& methods) {
  return checked([&] {
    const bool soft = impl_->setup.lights.front().size > 0.0f;
    std::map<std::string, penumbra::Frame> references;
    std::vector<penumbra::Frame> frames;
    for (const std::string& m : expandMethods(impl_->config, methods)) {
      const std::string reference = referenceFor(m);
      if (!references.count(reference)) references.emplace(reference, impl_->measured(reference));
      if (m != reference) frames.push_back(impl_->measured(m));
    }
    nlohmann::json metrics{{"scene", describeRun(impl_->config, impl_->setup, impl_->context)},
                           {"methods", nlohmann::json::array()},
                           {"references", nlohmann::json::array()}};
    for (const auto& [name, frame] : references) metrics["references"].push_back(frame.stats.toJson());
    if (references.count("ref")) metrics["reference"] = references.at("ref").stats.toJson();
    for (penumbra::Frame& frame : frames) {
      judgeFrame(frame, references.at(referenceFor(frame.stats.method)), soft, nullptr);
      metrics["methods"].push_back(frame.stats.toJson());
    }
    return metrics.dump();
  });
}

void Renderer::setCamera(const std::string& camera) {
  impl_->setup.camera = checked([&] { return parseCamera(camera, impl_->setup.scene.origin); });
}

void Renderer::setLight(const std::string& light) {
  checked([&] {
    Light parsed = parseLight(light, impl_->setup.scene.origin);
    applyLightSize(parsed, impl_->setup.lightSizeFraction, impl_->setup.scene.bounds());
    impl_->setup.lights = {parsed};
  });
}

std::string Renderer::camera() const { return formatCamera(impl_->setup.camera, impl_->setup.scene.origin); }
std::string Renderer::light() const { return formatLight(impl_->setup.lights.front(), impl_->setup.scene.origin); }

std::string Renderer::settings() const { return describeRun(impl_->config, impl_->setup, impl_->context).dump(); }

}  // namespace penumbra::api
