// The camera pass's fragment stage (gbuffer.frag, gbuffer_textured.frag, gbuffer_cutout.frag). The
// includer declares the push constants `push` (cameraPosition).
#include "shared/gbuffer.h"
layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec3 worldNormal;
layout(location = 2) in vec3 albedo;
layout(location = 3) in vec3 fromCamera;
layout(location = GBUFFER_POSITION) out vec4 outPosition;
layout(location = GBUFFER_NORMAL) out vec4 outNormal;
layout(location = GBUFFER_ALBEDO) out vec4 outAlbedo;
layout(location = GBUFFER_FACE_NORMAL) out uint outFaceNormal;
// `texel`: the colour texture's, linear (white without one), times the mesh's base colour.
void gbufferFragment(vec3 texel) {
  vec3 n = normalize(worldNormal);
  // Scenes are drawn two-sided: the shading normal faces the viewer.
  if (dot(n, push.cameraPosition.xyz - worldPosition) < 0.0) n = -n;
  // The triangle's plane: two screen-space derivatives of the position lie in it (helper lanes
  // extrapolate the same triangle), taken relative to the camera so far-away scenes keep their digits.
  vec3 face = cross(dFdx(fromCamera), dFdy(fromCamera));
  face = dot(face, face) > 0.0 ? normalize(face) : n;
  if (dot(face, fromCamera) > 0.0) face = -face;
  outPosition = vec4(worldPosition, 1.0);
  outNormal = vec4(n, 0.0);
  outAlbedo = vec4(albedo * texel, 1.0);
  outFaceNormal = packSnorm2x16(octahedralEncode(face));
}
