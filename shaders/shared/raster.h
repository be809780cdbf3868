// Push constants and workgroup sizes of the raster-side passes.
#ifndef PENUMBRA_SHARED_RASTER_H
#define PENUMBRA_SHARED_RASTER_H
#include "shared/glsl_cpp.h"
#include "shared/light.h"
PN_BEGIN

#define LOOKUP_GROUP_SIZE 8  // shadow_lookup.comp and shade.comp: 8x8 pixels per workgroup

// shadow_lookup.comp's bindings (raster/shadow_lookup_pass.cpp).
#define LOOKUP_BINDING_POSITION 0       // G-buffer position
#define LOOKUP_BINDING_NORMAL 1         // G-buffer shading normal
#define LOOKUP_BINDING_SHADOW_MAP 2     // the light's depth map (sampled)
#define LOOKUP_BINDING_FRAME 3          // FrameData
#define LOOKUP_BINDING_VISIBILITY 4     // float per pixel, written
#define LOOKUP_BINDING_SHADOW_TEXELS 5  // the map's texel copy
#define LOOKUP_BINDING_FACE_NORMAL 6    // G-buffer face normal (packed)

// shade.comp's bindings (hybrid/shade_pass.cpp).
#define SHADE_BINDING_POSITION 0
#define SHADE_BINDING_NORMAL 1
#define SHADE_BINDING_ALBEDO 2
#define SHADE_BINDING_FRAME 3
#define SHADE_BINDING_VISIBILITY 4  // float per pixel
#define SHADE_BINDING_COLOR 5       // packed RGBA8 per pixel, written
#define SHADE_BINDING_INDIRECT 6    // vec4 per pixel: rgb one-bounce light, a occlusion
#define SHADE_BINDING_DIRECT 7      // vec4 per pixel: rgb direct light of the frame's lights so far
#define SHADE_BINDING_LIGHTS 8      // a batch of the frame's lights: ShadeLight each
#define SHADE_BINDING_TILES 9       // a batch's lights per tile: tiles + 1 starts, then ShadeLight indices

#define SHADE_TILE 16  // pixels per side of the tiles a batch lists its lights by

// One light of a batch that one shading pass adds (frames of several lights): each light's
// visibility is kept over the rectangle of pixels its range reaches (the image for lights without
// one), row by row from `offset` in the batch's visibility buffer; beyond it the light adds nothing.
struct ShadeLight {  // std430, 128 bytes
  GpuLight light;
  uvec4 rect;   // pixels [xy, zw)
  uint offset;  // of pixel rect.xy in the batch's visibility
  uint traced;  // 1: the batch's trace writes its visibility (FrameData::traceLights), 0: copied there
  uint rays;    // the batch's trace adds the rays it traced to the light
  uint index;   // the light's index among the frame's lights
};

// Push constants of the shading pass: the method's term (hybrid/method.h Term: 0 shadow, 1 ao,
// 2 indirect), the lights it adds, and the pixels it covers.
struct ShadePush {
  uvec2 origin;  // the first pixel of the rectangle the pass covers (the image, or its batch's lights' reach)
  uint term;
  uint batched;  // 0: the frame's one light (FrameData's, visibility per pixel); 1: a batch (ShadeLight)
  uint last;     // 1: writes the image; 0 (a batch before the frame's last): writes the direct light so far
  uint sum;      // 1: adds the direct light of the batches before
  uint tilesX;   // tiles per row of SHADE_BINDING_TILES
  uint pad0;
};

#define GBUFFER_BINDING_COLOR 0  // gbuffer_textured.frag, gbuffer_cutout.frag: the mesh's colour texture (sampled)

struct GBufferPush {  // 80 bytes
  mat4 viewProj;
  vec4 cameraPosition;  // xyz; the face normal comes from positions relative to it (small numbers, precise derivatives)
};

struct ShadowMapPush {  // 64 bytes
  mat4 viewProj;
};

// The cut-out meshes' draws in the camera and light passes (gbuffer_cutout.frag, shadow_map_cutout.*),
// 112 bytes: the pass's matrix (and camera), and the mesh's cut-out (shared/alpha.h) with its
// texture in the alpha words at device address `texels`. The camera pass's textured draws
// (gbuffer_textured.*) take it too, with only the matrix and camera set.
struct CutoutDrawPush {
  mat4 viewProj;
  vec4 cameraPosition;  // the camera pass's
  uvec2 texels;         // (low, high) address of the alpha words, four texels a word
  uint first;           // the texture's first texel there
  uint width;
  uint height;
  float factor;
  float cutoff;
  uint pad0;
};

PN_END
#endif
