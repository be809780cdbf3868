// G-buffer layout written by the camera pass (gbuffer.frag) and read by every later pass.
#ifndef PENUMBRA_SHARED_GBUFFER_H
#define PENUMBRA_SHARED_GBUFFER_H
// Attachments, in this order:
//   0 position RGBA32F: xyz world position, w = 1 where a triangle covers the pixel, 0 elsewhere
//   1 normal   RGBA32F: xyz unit world normal turned towards the camera, w unused
//   2 albedo   RGBA8:   base colour
#define GBUFFER_POSITION 0
#define GBUFFER_NORMAL 1
#define GBUFFER_ALBEDO 2
#define GBUFFER_COUNT 3
#endif
