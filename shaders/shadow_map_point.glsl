// A world point's place in the light's shadow map and the plain (unfiltered) shadow-map answer
// there, shared by the lookup pass and the indirect rays' hits (--hit-light shadow-map). After
// `frame`, the map (`shadowMap`, a sampler2DArray) and its texel copy (`shadowTexels`) are declared
// and light_texels.glsl is included.
#ifndef PENUMBRA_SHADOW_MAP_POINT_GLSL
#define PENUMBRA_SHADOW_MAP_POINT_GLSL

// The view-projection of a face of the light's map. Only cube maps have several; for the others
// the branch is uniform and the matrix is read at a constant offset, once per subgroup. Indexed by
// the per-pixel face, lavapipe gathers its 16 floats lane by lane in every subgroup: ~6 ms of the
// classification and 3 ms of the lookup at 1024^2 (Mesa 25.0).
mat4 faceViewProj(uint face) {
  if (frame.shadow.kind == SHADOW_CUBE) return frame.shadow.viewProj[face];
  return frame.shadow.viewProj[0];
}

// 1 if the receiver at depth `depth` is in front of the occluder stored at texel `t` of `face`.
float litAt(ivec2 t, uint face, float depth) {
  int res = int(frame.shadow.resolution);
  t = clamp(t, ivec2(0), ivec2(res - 1));
  return depth <= LIGHT_TEXEL(shadowMap, shadowTexels, t, face, res) ? 1.0 : 0.0;
}

// Where point p (normal n, facing the light) lands: its face, its texel's world size, the point
// moved off its surface by the normal offset, and that point's NDC and map coordinates (uv in
// [0, 1]^2). False outside the map or beyond its far plane, where nothing that could block was
// rendered.
bool shadowMapPoint(vec3 p, vec3 n, out uint face, out float texel, out vec3 offsetP, out vec3 ndc, out vec2 uv) {
  uint kind = frame.shadow.kind;
  face = shadowFace(kind, frame.shadow.lightPosition, p);
  texel = shadowTexelWorld(kind, frame.shadow.texelWorld, frame.shadow.lightPosition, p);
  offsetP = p + n * (frame.shadow.normalOffset * texel);
  vec4 clip = faceViewProj(face) * vec4(offsetP, 1.0);
  ndc = clip.xyz / clip.w;
  uv = ndc.xy * 0.5 + 0.5;
  return !(clip.w <= 0.0 || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || ndc.z > 1.0);
}

// sm's answer at p (normal n): 0 where the light does not reach the surface, else the one texel's test.
float shadowMapVisibility(vec3 p, vec3 n) {
  if (!lightReaches(frame.light, p, n, frame.light.position.xyz)) return 0.0;
  uint face;
  float texel;
  vec3 offsetP, ndc;
  vec2 uv;
  if (!shadowMapPoint(p, n, face, texel, offsetP, ndc, uv)) return 1.0;
  return litAt(ivec2(floor(uv * float(frame.shadow.resolution))), face, ndc.z);
}

#endif
