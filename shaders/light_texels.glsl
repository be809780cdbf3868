// Reading a light's depth map (shadow map, thin mask) in compute passes: from its sampled image,
// or from the copy of its texels in a storage buffer (ShadowMapSettings::reads; on lavapipe a
// sampled fetch costs several storage loads). `texels` is a float[] with one float per texel,
// face after face; q must lie inside the face. The path is fixed per pipeline by specialization
// constant 0 (gpu::SpecializedComputePipeline, true where the maps have texel copies): chosen per
// read, lavapipe runs both, ~3 ms of the classification at 1024^2.
layout(constant_id = 0) const bool kTexelBuffer = false;
#define LIGHT_TEXEL(image, texels, q, face, res) \
  (kTexelBuffer ? texels[(uint(face) * uint(res) + uint((q).y)) * uint(res) + uint((q).x)] \
                : texelFetch(image, ivec3((q), int(face)), 0).r)
