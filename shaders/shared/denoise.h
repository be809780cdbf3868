// The shadow denoiser (hybrid/denoise_pass.h): push constants of its two kernels and the history
// it keeps per pixel between frames.
#ifndef PENUMBRA_SHARED_DENOISE_H
#define PENUMBRA_SHARED_DENOISE_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// denoise_accumulate.comp's bindings (hybrid/denoise_pass.cpp): the G-buffer's position and normal
// (storage images), FrameData, the frame's visibility and trace flags, the history read and
// written, the temporal result, the blocker distances and the value range of each 8x8 tile.
#define DENOISE_ACCUMULATE_BINDING_POSITION 0
#define DENOISE_ACCUMULATE_BINDING_NORMAL 1
#define DENOISE_ACCUMULATE_BINDING_FRAME 2
#define DENOISE_ACCUMULATE_BINDING_VISIBILITY 3
#define DENOISE_ACCUMULATE_BINDING_FLAGS 4
#define DENOISE_ACCUMULATE_BINDING_HISTORY_IN 5
#define DENOISE_ACCUMULATE_BINDING_HISTORY_OUT 6
#define DENOISE_ACCUMULATE_BINDING_ACCUMULATED 7
#define DENOISE_ACCUMULATE_BINDING_BLOCKERS 8
#define DENOISE_ACCUMULATE_BINDING_RANGES 9
// denoise_spatial.comp's: the same inputs, the temporal result and its tiles' ranges, and the
// visibility it writes.
#define DENOISE_SPATIAL_BINDING_POSITION 0
#define DENOISE_SPATIAL_BINDING_NORMAL 1
#define DENOISE_SPATIAL_BINDING_FRAME 2
#define DENOISE_SPATIAL_BINDING_ACCUMULATED 3
#define DENOISE_SPATIAL_BINDING_FLAGS 4
#define DENOISE_SPATIAL_BINDING_BLOCKERS 5
#define DENOISE_SPATIAL_BINDING_VISIBILITY 6
#define DENOISE_SPATIAL_BINDING_RANGES 7

#define DENOISE_GROUP_SIZE 8             // 8x8 pixels per workgroup, and per tile of the value ranges
#define DENOISE_UNIFORM (0.5 / 65535.0)  // spatial filter: tiles whose values span at most this are left as they are
#define DENOISE_TAPS 3        // spatial filter: (2 * DENOISE_TAPS + 1)^2 taps, spaced to span the radius
#define DENOISE_FOLLOW_BLOCKERS 2  // shadows are followed where at least this many nearby blocker distances are known

// denoise_accumulate.comp, 112 bytes.
struct DenoiseAccumulatePush {
  mat4 previousViewProj;  // the camera of the frame the history holds
  vec4 lightShift;        // xyz: the light's centre now minus in the frame the history holds
  float pixelScale;       // world size of a pixel at unit distance from the camera (2 tan(fovY / 2) / height)
  float maxHistory;       // frames the accumulation averages at most (its 1 / alpha)
  uint useHistory;        // 0: the history is empty (first frame of a sequence, --denoise spatial)
  uint useFlags;          // 1: only pixels with a trace flag are noisy (srt's penumbra mask); 0: every covered pixel
  float clipSigmas;       // > 0: history clipped to the current 5x5 neighbourhood's mean +- this many deviations
  float followSpread;     // the history follows shadows where the nearby blocker distances span at most this fraction of their mean
  uint stillCamera;       // 1: the camera is that of the history's frame
  uint pad0;
};

// denoise_spatial.comp, 32 bytes.
struct DenoiseSpatialPush {
  float pixelScale;
  float maxRadius;      // pixels
  float targetSamples;  // light samples the filter gathers per pixel (with those of earlier frames)
  uint useFlags;
  float widthFraction;  // the radius stays below this fraction of the penumbra's width
  uint skipAgreeing;    // 1: pixels whose taps' tiles agree keep their value (denoise_spatial.comp)
  uint pad0, pad1;
};

// One pixel of the history (std430, 16 bytes): the surface point it saw and its accumulated value.
struct DenoiseHistory {
  vec3 position;    // world
  uint valueCount;  // value in 16-bit fixed point, then frames accumulated (16 bits); frames 0: nothing (uncovered)
};

PN_END
#endif
