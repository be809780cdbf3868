// Push constants and workgroup sizes of the raster-side passes.
#ifndef PENUMBRA_SHARED_RASTER_H
#define PENUMBRA_SHARED_RASTER_H
#include "shared/glsl_cpp.h"
PN_BEGIN

#define LOOKUP_GROUP_SIZE 8  // shadow_lookup.comp and shade.comp: 8x8 pixels per workgroup

struct GBufferPush {  // 80 bytes
  mat4 viewProj;
  vec4 cameraPosition;  // xyz; the face normal comes from positions relative to it (small numbers, precise derivatives)
};

struct ShadowMapPush {  // 64 bytes
  mat4 viewProj;
};

PN_END
#endif
