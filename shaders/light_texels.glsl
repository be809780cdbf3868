// Reading a light's depth map (shadow map, thin mask) in compute passes: from its sampled image,
// or from the copy of its texels in a storage buffer (ShadowMapSettings::reads; on lavapipe a
// sampled fetch costs several storage loads). `texels` is a float[] with one float per texel,
// face after face; q must lie inside the face.
#define LIGHT_TEXEL(useBuffer, image, texels, q, face, res) \
  ((useBuffer) ? texels[(uint(face) * uint(res) + uint((q).y)) * uint(res) + uint((q).x)] \
               : texelFetch(image, ivec3((q), int(face)), 0).r)
