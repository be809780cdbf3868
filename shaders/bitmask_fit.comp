#version 450
// Bitmask visibility sampling: fits the receiver's map to its visible part, so that its texels are
// spent where the camera looks (on a large ground most of the mesh's rectangle is off screen).
// Pass 0 (per pixel): the bounds, in the mesh rectangle's [0, 1]^2 coordinates, of the covered
// pixels that lie on the receiver (as bitmask_resolve.comp tests them), by atomic min/max on the
// coordinates' bits (ordered as unsigned integers for non-negative floats). Pass 1 (one
// invocation): the frame's rectangle narrowed to those bounds, widened by a texel on each side;
// left as it is when no pixel is on the receiver.
#extension GL_GOOGLE_include_directive : require
#include "shared/bitmask.h"
layout(local_size_x = BITMASK_GROUP_SIZE, local_size_y = BITMASK_GROUP_SIZE) in;
layout(binding = BITMASK_FIT_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = BITMASK_FIT_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;
layout(std430, binding = BITMASK_FIT_BINDING_FRAME) buffer Bitmask { BitmaskFrame bitmask; };
layout(std430, binding = BITMASK_FIT_BINDING_BOUNDS) buffer Bounds { uint bounds[4]; };  // min u, min v, max u, max v (float bits)
layout(push_constant) uniform Push { uint apply; };

void main() {
  if (apply != 0u) {
    if (gl_GlobalInvocationID.xy != uvec2(0u)) return;
    vec2 lo = vec2(uintBitsToFloat(bounds[0]), uintBitsToFloat(bounds[1]));
    vec2 hi = vec2(uintBitsToFloat(bounds[2]), uintBitsToFloat(bounds[3]));
    if (any(greaterThan(lo, hi))) return;
    vec2 extent = vec2(bitmask.axisU.w, bitmask.axisV.w);
    vec2 size = (hi - lo) * extent;
    vec2 pad = max(size, extent * 1e-6) / float(bitmask.resolution);
    vec2 from = lo * extent - pad;
    bitmask.origin.xyz += from.x * bitmask.axisU.xyz + from.y * bitmask.axisV.xyz;
    bitmask.axisU.w = size.x + 2.0 * pad.x;
    bitmask.axisV.w = size.y + 2.0 * pad.y;
    return;
  }
  ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pix, imageSize(gPosition)))) return;
  vec4 position = imageLoad(gPosition, pix);
  if (position.w == 0.0) return;
  vec2 uv = receiverUv(bitmask, position.xyz);
  // A height field's surface is not mapped yet: any height from the plane to its top will do.
  float top = bitmask.field.x != 0.0 ? bitmask.field.y : 0.0;
  if (!onReceiver(bitmask, position.xyz, imageLoad(gNormal, pix).xyz, uv, 0.5 * top, 0.5 * top)) return;
  atomicMin(bounds[0], floatBitsToUint(uv.x));
  atomicMin(bounds[1], floatBitsToUint(uv.y));
  atomicMax(bounds[2], floatBitsToUint(uv.x));
  atomicMax(bounds[3], floatBitsToUint(uv.y));
}
