// The scene's Light in the layout every pass and the reference tracer consume.
#pragma once
#include "core/scene.h"
#include "shared/light.h"

namespace penumbra {

// rayEpsilon: shadow-ray origin offset along the normal, as a fraction of the scene radius.
shared::GpuLight toGpuLight(const Light& light, const Bounds& bounds, float rayEpsilonFraction = 1e-4f);

}  // namespace penumbra
