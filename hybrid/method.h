// A method fills the per-pixel visibility buffer (fraction of light visible, 0..1) for one frame
// and reports what it did. Methods compose the shared passes the Renderer owns; each lives in its
// own file, and the registry only maps names to factories.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "hybrid/frame_stats.h"

namespace penumbra {

class Renderer;
struct RenderSettings;

// What a method's frame holds: the shadow term (visibility), or, for methods ao and indirect, the
// ambient occlusion or one-bounce light they add to the direct light (Renderer::indirect()).
enum class Term { Shadow, Ao, Indirect };
const char* termName(Term term);

class Method {
 public:
  virtual ~Method() = default;
  // Leaves the frame's visibility in renderer.visibility() and records passes into stats.
  virtual void run(Renderer& renderer, FrameStats& stats) = 0;
  // Records what works on the finished visibility, in the shading pass's submission, before it.
  virtual void recordBeforeShade(Renderer&, const vk::raii::CommandBuffer&, FrameStats&) {}
  // What the shared frame data must say for this method.
  virtual std::uint32_t shadowFilter(const RenderSettings&) const { return 0; }  // FILTER_NONE
  virtual std::uint32_t samplesPerPixel(const RenderSettings& settings) const;
  // Methods that run PIP classification expose its flags and sm answer in the Frame.
  virtual bool classifies() const { return false; }
  // Methods that look up the light's centre map (Renderer::recordShadowMap): the Renderer may fit
  // that map to the view first (RenderSettings::fitLightToView).
  virtual bool readsShadowMap() const { return false; }
  // Methods whose pixels all use one light-sample pattern (GpuLight::sharedPattern): every method
  // does with RenderSettings::sharedSamples.
  virtual bool sharedSamplePattern() const { return false; }
  virtual Term term() const { return Term::Shadow; }
};

std::unique_ptr<Method> makeMethod(const std::string& name);  // InputError for unknown names
Term methodTerm(const std::string& name);                      // makeMethod(name)->term()
std::vector<std::string> methodNames();

// Factories, one per method file.
enum class ShadowMapFilter { None, Pcf, Pcss };
std::unique_ptr<Method> makeShadowMapMethod(ShadowMapFilter filter);  // sm (None), pcf (Pcf), pcss (Pcss)
std::unique_ptr<Method> makeMultiMapMethod();  // msm: average of settings.msmMaps light-sample maps
std::unique_ptr<Method> makeReferenceMethod();              // ref: Embree, every covered pixel
// srt (selective = true), frt; `tracer` overrides the settings' tracer (method ls: frt on "ls")
std::unique_ptr<Method> makeTracedMethod(bool selective, const std::string& tracer = {});
std::unique_ptr<Method> makeBitmaskMethod();  // bitmask: visibility sampling on a planar receiver
// ao and indirect (term Ao or Indirect) on `tracer` (empty: settings.indirect.tracer; embree: the reference)
std::unique_ptr<Method> makeIndirectMethod(Term term, const std::string& tracer = {});

}  // namespace penumbra
