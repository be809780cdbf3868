// G-buffer layout written by the camera pass (gbuffer.frag) and read by every later pass.
#ifndef PENUMBRA_SHARED_GBUFFER_H
#define PENUMBRA_SHARED_GBUFFER_H
#include "shared/glsl_cpp.h"
PN_BEGIN
// Attachments, in this order:
//   0 position    RGBA32F: xyz world position, w = 1 where a triangle covers the pixel, 0 elsewhere
//   1 normal      RGBA32F: xyz unit world (shading) normal turned towards the camera, w unused
//   2 albedo      RGBA8:   base colour
//   3 face normal R32UI:   the triangle's own normal, turned towards the camera, octahedral in two
//                          snorm16 (faceNormalEncode): the plane the shadow map sees, where the
//                          shading normal of a smoothed mesh may lean away from it
#define GBUFFER_POSITION 0
#define GBUFFER_NORMAL 1
#define GBUFFER_ALBEDO 2
#define GBUFFER_FACE_NORMAL 3
#define GBUFFER_COUNT 4

// Octahedral map of a unit vector to [-1, 1]^2 and back.
PN_FN vec2 octahedralEncode(vec3 n) {
  float l1 = abs(n.x) + abs(n.y) + abs(n.z);
  float x = n.x / l1, y = n.y / l1;
  if (n.z >= 0.0f) return vec2(x, y);
  return vec2((1.0f - abs(y)) * (x >= 0.0f ? 1.0f : -1.0f), (1.0f - abs(x)) * (y >= 0.0f ? 1.0f : -1.0f));
}
PN_FN vec3 octahedralDecode(vec2 e) {
  float z = 1.0f - abs(e.x) - abs(e.y);
  float t = max(-z, 0.0f);
  return normalize(vec3(e.x + (e.x >= 0.0f ? -t : t), e.y + (e.y >= 0.0f ? -t : t), z));
}

PN_END
#endif
