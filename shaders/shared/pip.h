// PIP classification (raster/pip_classify_pass): settings and the per-pixel outputs' meaning.
#ifndef PENUMBRA_SHARED_PIP_H
#define PENUMBRA_SHARED_PIP_H
#include "shared/glsl_cpp.h"
PN_BEGIN

#define PIP_GROUP_SIZE 16  // 16x16 pixels per workgroup (8x8: classify 2 ms slower at 1024^2 on lavapipe; the lookup and shade passes, with less work per pixel, stay faster at 8x8)
#define PIP_MASK_TILE_SIZE 8      // the penumbra mask's tile test: pixels per side of its tiles (PipPush::tileTest)
#define PIP_LAYER_TOLERANCE 0.05  // layerOver: a layer must stand this fraction of the margin off the receiver's plane
#define PIP_MAX_TILE_VISITS 256   // penumbra mask: edge-pyramid tiles one pixel's search may read before it gives up (in the mask)

// pip_classify.comp's bindings (raster/pip_classify_pass.cpp binds them).
#define PIP_BINDING_POSITION 0        // G-buffer position (storage image)
#define PIP_BINDING_NORMAL 1          // G-buffer shading normal
#define PIP_BINDING_SHADOW_MAP 2      // the light's depth map (sampled)
#define PIP_BINDING_THIN_MASK 3       // the thin-triangle mask (sampled)
#define PIP_BINDING_FRAME 4           // FrameData
#define PIP_BINDING_VISIBILITY 5      // float per pixel
#define PIP_BINDING_SM_VISIBILITY 6   // float per pixel: the sm answer where flagged
#define PIP_BINDING_TRACE_FLAGS 7     // uint per pixel: PIP_* bits
#define PIP_BINDING_RAY_MAX 8         // float per pixel: the ray's end
#define PIP_BINDING_COUNT 13          // TraceCount of the list PipPush::appendList fills
#define PIP_BINDING_WHY 14            // uint per pixel: PIP_WHY_* (area lights: PIP_MASK_* bits where flagged)
#define PIP_BINDING_FACE_NORMAL 15    // G-buffer face normal (packed)
#define PIP_BINDING_MASK_TILES 16     // uint per PIP_MASK_TILE_SIZE^2 tile of pixels: PIP_TILE_* (PipPush::tileTest)
#define PIP_BINDING_TILE_DOUBT_LAST 17  // uint per tile: the tile choice's counts of the last frame (PIP_TILE_COVERED)
#define PIP_BINDING_TILE_DOUBT 18       // uint per tile: this frame's (zeroed first)

// The penumbra mask's tile test (PipPush::tileTest): what it found for a tile's pixels.
#define PIP_TILE_NONE 0u    // no pixel of the tile searches
#define PIP_TILE_SEARCH 1u  // a blocker may lie within reach of one of them: each searches alone
#define PIP_TILE_CLEAR 2u   // no blocker lies within reach of any of them: none searches
#define PIP_TILE_TRACE 3u   // the tile choice (PipPush::tileTraceBelow) traced every pixel of it: none searches

// The tile choice (PipPush::tileTraceBelow), area lights: per tile of PIP_MASK_TILE_SIZE^2 pixels,
// what its last classification found, as PIP_TILE_COVERED * covered pixels + flagged ones;
// PIP_TILE_TRACED where this frame traced the tile whole instead (the counts carried over).
// Such a tile is classified again every PIP_TILE_REFRESH-th frame (staggered), as views change.
#define PIP_TILE_COVERED 0x10000u
#define PIP_TILE_TRACED 0x80000000u
#define PIP_TILE_REFRESH 8u

// Why a pixel was marked (bits of traceFlags; nonzero = trace it).
#define PIP_EDGE 1u       // depth edge in the 3x3 neighbourhood that can reach the receiver (d-hat test)
#define PIP_THIN 2u       // a conservatively rasterized thin triangle covers the neighbourhood in front
#define PIP_SEAM 4u       // the neighbourhood leaves its cube face: classified conservatively
#define PIP_OUTSIDE 8u    // outside the shadow map: nothing to classify with
#define PIP_PENUMBRA 16u  // area light: a blocker edge within penumbra reach (the splat mask), or the
                          // light straddles the receiver's tangent plane
#define PIP_CONTACT 32u   // the map does not put the receiver in shadow, but another surface lies over it
                          // within the bias: one rising beside it, a step's foot, a strip on it
#define PIP_GAP 64u       // the map puts the receiver in umbra, but the texels around its point hold
                          // different blockers: light may pass through a gap between them narrower
                          // than a texel (the dual of a thin triangle)
// PIP_ACNE: the map puts the receiver in umbra, but its blocker lies within the receiver's own
// depth interval, so it may be the receiver itself (acne the bias left)
#define PIP_ACNE 128u

// Why the classification left a covered pixel unflagged (explained: PipSettings::explain, the miss explainer):
// what went wrong if its sm answer is wrong. The host splits BIAS and FLAT by the sm answer.
#define PIP_WHY_NONE 0u      // flagged (area lights: PIP_MASK_* bits instead), not covered, or not explained
#define PIP_WHY_FACING 1u    // the receiver faces away from the light: dark by rule, no map read
#define PIP_WHY_BIAS 2u      // the map sees the receiver itself (its depth within the receiver's interval
                             // widened by margin and spread): acne (sm dark) or a blocker within bias (sm lit)
#define PIP_WHY_INTERVAL 3u  // a depth edge above the threshold that the receiver's interval did not reach
#define PIP_WHY_DELTA 4u     // a depth edge below the threshold (spread above the margin)
#define PIP_WHY_FLAT 5u      // a flat neighbourhood away from the receiver: a blocker the map lacks
                             // (sm lit) or a gap the map closed (sm dark)
#define PIP_WHY_LIGHT_ERROR 6u  // the light's shadow weighs less than --light-error there (shadowWeight)
#define PIP_WHY_COUNT 7u

// Area lights, explained: for a pixel in the penumbra mask, the bits of every rule that
// puts it there (in `why`, instead of a PIP_WHY_* code); compare --explain-misses counts them
// against the reference (mask_rules).
#define PIP_MASK_EDGE_DOUBT 1u     // the centre map's doubts (PIP_EDGE): a depth edge the receiver's interval reaches
#define PIP_MASK_THIN_DOUBT 2u     // (PIP_THIN) a thin triangle nearer than the receiver in its 3x3 texels
#define PIP_MASK_CONTACT_DOUBT 4u  // (PIP_CONTACT) another surface meets the receiver within the bias
#define PIP_MASK_TANGENT 8u        // part of the light is below the receiver's tangent plane or its face's plane
#define PIP_MASK_OWN_DEPTH 16u     // umbra whose blocker lies within the receiver's own depth interval
// An edge texel's splat covers the pixel (or, in a cube face behind it, a texel lies nearer than the light's extent).
#define PIP_MASK_SPLAT 32u
#define PIP_MASK_SURFACE 64u  // a layer within the bias, or a smooth surface, over a lit receiver
#define PIP_MASK_CORNER 128u  // --penumbra-maps 5: only a corner map's edge splat
#define PIP_MASK_RULES 8u     // the bits above

struct PipPush {  // 64 bytes
  float deltaThreshold;  // depth edge when max |s - s'| exceeds this (world units along the light axis)
  float depthMargin;     // widens the receiver's depth interval [d-hat, d] on both sides (world units)
  uint useThin;          // test the thin-triangle mask
  uint useIntervals;     // write ray intervals (hard shadows only)
  uint pyramidLevels;    // levels of the depth pyramid (area lights)
  uint cornerUnion;      // 1: a corner map's dispatch, which only ORs PIP_PENUMBRA into the flags
  uint appendList;       // 1: also append the flagged pixels to the trace list (no compaction pass)
  uint tileTest;         // 1: area lights, a map of one face: the penumbra mask's tile test ran (maskTile)
  // Device addresses (low, high) of what the classification reads most: the shadow map's and the
  // thin mask's texel copies and the edge pyramid. On lavapipe a load through an address skips the
  // bounds check of a storage-buffer load (soft classification at 1024^2: 70 -> 61 ms).
  uvec2 shadowTexelsAt;
  uvec2 thinTexelsAt;
  uvec2 tilesAt;
  // Area lights, the tile choice: a tile whose last classification left fewer than this many of
  // its covered pixels unflagged is traced whole (all flagged PIP_PENUMBRA, none searches); 0: off.
  uint tileTraceBelow;
  uint tilePhase;  // the frame's count: tiles with (index + tilePhase) % PIP_TILE_REFRESH == 0 classify
};

PN_END
#endif
