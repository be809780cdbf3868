// Edge pyramid over a light's faces (raster/depth_pyramid_pass), the penumbra mask's source: an
// edge texel is the near side of a depth edge (a texel of its 3x3 neighbourhood lies farther by
// more than the threshold, the hard shadows' edge test), its blocker depth the minimum depth
// there, or a thin triangle touches it (the thin mask's 3x3 opening undoes its dilation).
// Level k >= 1 holds, per tile of 2^k x 2^k texels, two raw NDC depths: the minimum blocker depth
// of its edge texels (1 = none) and the minimum depth of all its texels (the surface channel: the
// mask's search for a smooth surface rising over a lit receiver, which has no edge). One storage
// buffer: levels 1..count, each faceCount * dim(k)^2 tiles, face-major, a tile's two channels
// side by side (index 2 * tile + PYRAMID_EDGES or PYRAMID_SURFACE); then, for levels 2..count,
// each tile's surface fit (pyramidFitIndex): a plane through its texels' raw depths, z(c) =
// centre + dot(gradient, c - the tile's centre) in texel coordinates, and how far below it the
// nearest of them lies (every texel's raw depth >= the plane's there - below). The mask's surface
// search skips a tile whose texels the fit puts nowhere over the receiver's plane: the receiver's
// own surface, flat or gently curved, which the minimum alone lets through tile by tile.
#ifndef PENUMBRA_SHARED_PYRAMID_H
#define PENUMBRA_SHARED_PYRAMID_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// depth_pyramid.comp's bindings (raster/depth_pyramid_pass.cpp).
#define PYRAMID_BINDING_SHADOW_MAP 0     // the light's depth map (sampled)
#define PYRAMID_BINDING_THIN_MASK 1      // the thin-triangle mask (sampled; the map again without one)
#define PYRAMID_BINDING_TILES 2          // the pyramid, written
#define PYRAMID_BINDING_SHADOW_TEXELS 3  // the map's texel copy
#define PYRAMID_BINDING_THIN_TEXELS 4    // the mask's texel copy (the map's without one)

#define PYRAMID_GROUP_SIZE 8
#define PYRAMID_MAX_LEVELS 15
#define PYRAMID_EDGES 0u
#define PYRAMID_SURFACE 1u

PN_FN uint pyramidDim(uint resolution, uint level) { return (resolution + (1u << level) - 1u) >> level; }

// Index of the first tile of `level` (>= 1) in the buffer, in tiles (two floats each).
PN_FN uint pyramidOffset(uint resolution, uint faceCount, uint level) {
  uint offset = 0u;
  for (uint k = 1u; k < level; ++k) offset += faceCount * pyramidDim(resolution, k) * pyramidDim(resolution, k);
  return offset;
}

#define PYRAMID_FIT_CENTRE 0u
#define PYRAMID_FIT_GRADIENT 1u  // x, y: raw depth per texel
#define PYRAMID_FIT_BELOW 3u
#define PYRAMID_FIT_FLOATS 4u

// Index of the first float of the fit of tile `tile` (counted from the first of `level` >= 2).
PN_FN uint pyramidFitIndex(uint resolution, uint faceCount, uint levels, uint level, uint tile) {
  uint fits = pyramidOffset(resolution, faceCount, level) - pyramidOffset(resolution, faceCount, 2u) + tile;
  return 2u * pyramidOffset(resolution, faceCount, levels + 1u) + PYRAMID_FIT_FLOATS * fits;
}

struct PyramidPush {  // 48 bytes
  uint level;       // the level this dispatch writes (>= 1)
  uint resolution;  // of level 0
  uint faceCount;
  uint useThin;     // thin-triangle texels are edges too
  uint kind;        // SHADOW_* of the map, for linear depths
  float nearPlane, farPlane;
  float deltaThreshold;  // linear depth edge threshold (as PipPush.deltaThreshold)
  uint levels;      // the pyramid's level count (where the fits start)
  uint pad1, pad2, pad3;
};

PN_END
#endif
