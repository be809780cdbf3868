// Compaction (hybrid/compact_pass): per-pixel trace flags -> dense, pixel-ordered ShadingPoints.
#ifndef PENUMBRA_SHARED_COMPACT_H
#define PENUMBRA_SHARED_COMPACT_H
#include "shared/glsl_cpp.h"
PN_BEGIN

#define COMPACT_GROUP_SIZE 256

#define COMPACT_FLAGGED 0u      // pixels with traceFlags[pixel] != 0 (srt)
#define COMPACT_ALL_COVERED 1u  // every covered pixel (frt)

struct CompactPush {
  uint mode;        // COMPACT_FLAGGED / COMPACT_ALL_COVERED
  uint pixelCount;  // width * height
  uint pad0, pad1;
};

PN_END
#endif
