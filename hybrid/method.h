// A method fills the per-pixel visibility buffer (fraction of light visible, 0..1) for one frame
// and reports what it did. Methods compose the shared passes of the FrameContext; each lives in its
// own file, which registers it by name (hybrid/registry.h).
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "hybrid/frame_stats.h"

namespace penumbra {

class FrameContext;
struct RenderSettings;

// What a method's frame holds: the shadow term (visibility), or, for methods ao and indirect, the
// ambient occlusion or one-bounce light they add to the direct light (FrameContext::indirect()).
enum class Term { Shadow, Ao, Indirect };
const char* termName(Term term);

class Method {
 public:
  virtual ~Method() = default;
  // Leaves the frame's visibility in renderer.visibility() and records passes into stats; a
  // method may record the frame's shading at the end of its last submission
  // (FrameContext::recordShade), else it runs in a submission of its own.
  virtual void run(FrameContext& renderer, FrameStats& stats) = 0;
  // What the shared frame data must say for this method.
  virtual std::uint32_t shadowFilter(const RenderSettings&) const { return 0; }  // FILTER_NONE
  virtual std::uint32_t samplesPerPixel(const RenderSettings& settings) const;
  // Methods that run PIP classification expose its flags and sm answer in the Frame.
  virtual bool classifies() const { return false; }
  // Methods that look up the light's centre map (FrameContext::recordShadowMap): the Renderer may fit
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

// Each method file registers its methods by name (hybrid/registry.h).

}  // namespace penumbra
