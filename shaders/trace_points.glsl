// The shading points of a shadow-ray kernel (after `frame` and `traceCount` are declared; the
// kernel enables GL_EXT_buffer_reference and _uvec2 for point_list.glsl):
// the compacted list, or - when the frame traces in place (frt on a GPU tracer) - every covered
// pixel of FrameData's light rectangle read from the G-buffer, enumerated in the compaction's tile
// order so that a warp still traces neighbouring pixels. The dispatch covers traceCount.groupsX
// groups either way. traceShadows is the kernel's work: one light (FrameData's), or a batch of them.
#include "shared/compact.h"
#include "shared/raster.h"
#include "shared/trace.h"
#include "point_list.glsl"
layout(binding = TRACE_BINDING_POSITION, rgba32f) uniform readonly image2D gPosition;
layout(binding = TRACE_BINDING_NORMAL, rgba32f) uniform readonly image2D gNormal;

// This invocation's point: dispatches wider than one row of workgroups (an in-place trace of a
// frame over 4M pixels) continue in further rows.
uint tracePointIndex() {
  return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * TRACE_GROUP_SIZE + gl_LocalInvocationID.x;
}

// The index-th point, or false when there is none (past the list, off the image, or sky).
bool tracePoint(uint index, out ShadingPoint point) {
  if (frame.traceInPlace == 0u) {
    if (index >= traceCount.count || index >= frame.traceCapacity) return false;  // the host refuses an overfull list
    point = pointList[index];
    return true;
  }
  uvec2 lo = frame.lightRectMin, hi = frame.lightRectMax;
  if (hi == uvec2(0u)) hi = uvec2(frame.width, frame.height);
  uvec2 pix = lo + compactPixel(index, compactTilesX(hi.x - lo.x));
  if (pix.x >= hi.x || pix.y >= hi.y || pix.x >= frame.width || pix.y >= frame.height) return false;
  vec4 position = imageLoad(gPosition, ivec2(pix));
  if (position.w == 0.0) return false;
  point.position = position.xyz;
  point.pixel = pix.y * frame.width + pix.x;
  point.normal = imageLoad(gNormal, ivec2(pix)).xyz;
  point.spp = frame.spp;
  point.rayMax = 0.0;
  point.pad0 = point.pad1 = point.pad2 = 0u;
  return true;
}

layout(buffer_reference, std430, buffer_reference_align = 16) buffer TraceLights { ShadeLight v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer TraceTiles { uint v[]; };

// The point's visibility of `light`: traced, or - in a trace in place, where the light's shadow
// changes the pixel's shade by less than --light-error (shadowWeight) - unshadowed by the rule,
// without a ray (a compacted list holds no such point: the classification kept the map's answer).
float slightOrTraced(ShadingPoint point, GpuLight light, uvec2 blockers, inout uint rays) {
  if (frame.traceInPlace != 0u && frame.lightError > 0.0 &&
      shadowWeight(light, point.position, point.normal) < frame.lightError) {
    if (blockers != uvec2(0u)) BlockerDistances(blockers).v[point.pixel] = 0.0;  // none known
    return lightReaches(light, point.position, point.normal, light.position.xyz) ? 1.0 : 0.0;
  }
  return shadowVisibility(point, light, blockers, rays);
}

// The invocation's point traced to FrameData's light into visibility[point.pixel]; or, in the trace
// of a batch of lights (FrameData::traceLights), to each light its tile lists that the batch
// traces, into that light's part of the batch's visibility, the rays counted per light. Adds the rays traced to `rays`.
void traceShadows(inout uint rays) {
  uint index = tracePointIndex();
  ShadingPoint point;
  bool valid = tracePoint(index, point);
  if (frame.traceLights == uvec2(0u)) {
    if (valid) visibility[point.pixel] = slightOrTraced(point, frame.light, frame.blockers, rays);
    return;
  }
  // The rectangle starts at a tile's corner and is whole tiles wide, so that a workgroup (two
  // compaction tiles side by side) lies in one SHADE_TILE tile: its lights' loop is uniform.
  uvec2 pix = frame.lightRectMin + compactPixel(index, compactTilesX(frame.lightRectMax.x - frame.lightRectMin.x));
  TraceLights lights = TraceLights(frame.traceLights);
  TraceTiles tiles = TraceTiles(frame.traceTiles);
  uint tile = (pix.y / SHADE_TILE) * frame.traceTilesX + pix.x / SHADE_TILE;
  uint first = tiles.v[tile], end = tiles.v[tile + 1u];
  for (uint i = first; i < end; ++i) {
    uint k = tiles.v[i];
    uvec4 rect = lights.v[k].rect;
    uint lightRays = 0u;
    if (lights.v[k].traced != 0u && all(greaterThanEqual(pix, rect.xy)) && all(lessThan(pix, rect.zw))) {
      // an uncovered pixel as a light's own trace leaves it (FrameContext::recordUnclassified)
      bool wholeImage = rect == uvec4(0u, 0u, frame.width, frame.height);
      GpuLight light = lights.v[k].light;
      point.spp = lightSampleCount(light, frame.spp);  // FrameData::spp: the method's samples per pixel
      float visible = valid ? slightOrTraced(point, light, uvec2(0u), lightRays) : wholeImage ? 1.0f : 0.0f;
      visibility[lights.v[k].offset + (pix.y - rect.y) * (rect.z - rect.x) + pix.x - rect.x] = visible;
    }
    rays += lightRays;
    lightRays = subgroupAdd(lightRays);
    if (subgroupElect() && lightRays != 0u) atomicAdd(lights.v[k].rays, lightRays);
  }
}
