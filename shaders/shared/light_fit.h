// Fitting a light's single map to what the camera sees (raster/light_fit_pass): the receivers'
// bounds in the map's NDC, reduced on the GPU over the G-buffer.
#ifndef PENUMBRA_SHARED_LIGHT_FIT_H
#define PENUMBRA_SHARED_LIGHT_FIT_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// light_fit.comp's bindings (raster/light_fit_pass.cpp).
#define LIGHT_FIT_BINDING_POSITION 0  // G-buffer position (storage image)
#define LIGHT_FIT_BINDING_BOUNDS 1    // LightFitBounds, accumulated

#define LIGHT_FIT_GROUP_SIZE 8  // 8x8 invocations per workgroup ...
#define LIGHT_FIT_BLOCK 4       // ... each reducing a 4x4 block of pixels: lavapipe pays per invocation

struct LightFitPush {  // 80 bytes
  mat4 viewProj;  // the whole-scene map's face
  uint width, height;
  uint pad0, pad1;
};

// Floats as uints whose unsigned order is the floats' order, for atomicMin/atomicMax.
PN_FN uint lightFitOrdered(float f) {
  uint u = floatBitsToUint(f);
  return (u & 0x80000000u) != 0u ? ~u : (u | 0x80000000u);
}
PN_FN float lightFitFloat(uint u) { return uintBitsToFloat((u & 0x80000000u) != 0u ? (u & 0x7fffffffu) : ~u); }

// The reduced bounds, std430: ordered floats (lightFitOrdered) and the receivers counted.
struct LightFitBounds {
  uint minX, minY, maxX, maxY;
  uint receivers;
  uint pad0, pad1, pad2;
};

PN_END
#endif
