// The penumbra mask's tiles of PIP_MASK_TILE_SIZE^2 pixels, included by pip_classify.comp before
// its main (not compiled on its own): their verdicts (PIP_TILE_*), the tile choice (traceWhole,
// countTile: PipPush::tileTraceBelow) and the tile test (maskTile: PipPush::tileTest), which uses
// the classification's own functions (mapPoint, splatCone, withinReach, mapPlane).
#ifndef PENUMBRA_PIP_TILES_GLSL
#define PENUMBRA_PIP_TILES_GLSL
layout(std430, binding = PIP_BINDING_MASK_TILES) buffer MaskTiles { uint maskTiles[]; };
uint tileIndex(uvec2 tile) { return tile.y * ((frame.width + PIP_MASK_TILE_SIZE - 1u) / PIP_MASK_TILE_SIZE) + tile.x; }
layout(std430, binding = PIP_BINDING_TILE_DOUBT_LAST) readonly buffer TileDoubtLast { uint tileDoubtLast[]; };
layout(std430, binding = PIP_BINDING_TILE_DOUBT) buffer TileDoubt { uint tileDoubt[]; };

// The tile choice: whether this frame traces `tile` whole (PipPush::tileTraceBelow).
bool traceWhole(uint tile) {
  if (push.tileTraceBelow == 0u || (tile + push.tilePhase) % PIP_TILE_REFRESH == 0u) return false;
  uint last = tileDoubtLast[tile] & ~PIP_TILE_TRACED;
  uint covered = last / PIP_TILE_COVERED, flagged = last % PIP_TILE_COVERED;
  return covered > 0u && covered - flagged < push.tileTraceBelow;
}

// The tile choice's counts for the next frame (PIP_BINDING_TILE_DOUBT): a tile traced whole
// carries its last ones over; the others add up their pixels, one atomic per subgroup and tile.
void countTile(uint tile, uvec2 pix, bool covered, bool flagged, bool traced) {
  if (traced) {
    if (all(equal(pix % PIP_MASK_TILE_SIZE, uvec2(0u)))) tileDoubt[tile] = tileDoubtLast[tile] | PIP_TILE_TRACED;
    return;
  }
  uint v = (covered ? PIP_TILE_COVERED : 0u) + (flagged ? 1u : 0u);
  for (;;) {  // the lanes' tiles in turn (one on lavapipe's 8-wide subgroups, two on 32-wide ones)
    uint first = subgroupBroadcastFirst(tile);
    if (tile == first) {
      uint sum = subgroupAdd(v);
      if (subgroupElect() && sum != 0u) atomicAdd(tileDoubt[tile], sum);
      break;
    }
  }
}

// The penumbra mask's tile test: one search for the receivers of a tile of PIP_MASK_TILE_SIZE^2
// pixels together, in a map of one face; returns PIP_TILE_*. Each receiver's windows lie within
// the tile's: per corner the bounds of their alphas and betas (SplatCone), of their texels and of
// their depths (the farthest bounds the blockers that count); the surface channel's plane is the
// highest of the lit receivers' (MapPlane's gLo, gHi) with their least tol. Where that search finds
// no blocker, none of theirs would: the tile is clear and none of its pixels searches.
// The receivers: those classify() may search for, the covered pixels the light reaches inside
// the map with the light above their tangent and face planes (all of them where explained),
// whatever doubts already put them in the mask.
// One invocation per tile, which reads the tile's pixels in turn: on lavapipe (courtyard, 1024^2,
// light 0.1, tiles of 16x16) this dispatch took ~19 ms, and a workgroup per tile with an invocation
// per pixel, meeting in shared memory over barriers, ~100 ms. On a GPU the latter may be the faster.
// Tiles of 8x8 clear more pixels than of 16x16 (courtyard 48% -> 58% of the tiles' pixels) for ~2 ms
// more: classify and the test ~6-8 ms less at 1024^2 on the courtyard, FZK-Haus and USS Truman
// close; 4x4, ~3 ms more than 8x8. Clearing each channel on its own saved nothing (the bunny seen
// close clears its edges in half its tiles, the surface in 15%): where the tile's edge search finds
// nothing, a pixel's is cheap.
uint maskTile(uvec2 tile) {
  GpuLight light = frame.light;
  float halfExtent = light.type == LIGHT_RECT ? light.size * 0.70710678 : light.size * 0.5;
  int res = int(frame.shadow.resolution);
  mat4 viewProj = faceViewProj(0u);
  SplatCone cone;
  for (int j = 0; j < 4; ++j) {
    cone.alphaLo[j] = cone.betaLo[j] = vec2(3.0e38);
    cone.alphaHi[j] = cone.betaHi[j] = vec2(-3.0e38);
  }
  cone.tLo = vec2(3.0e38);
  cone.tHi = vec2(-3.0e38);
  cone.uOfRaw = coneDepthOfRaw();
  cone.unbounded = false;
  MapPlane highest = MapPlane(-3.0e38, 3.0e38, vec2(0.0), vec2(3.0e38), vec2(-3.0e38), 0.0, planeDepthOfRaw());
  float farthest = -3.0e38;
  bool any = false, lit = false;
  for (uint k = 0u; k < PIP_MASK_TILE_SIZE * PIP_MASK_TILE_SIZE; ++k) {
    ivec2 pix = ivec2(tile * PIP_MASK_TILE_SIZE + uvec2(k % PIP_MASK_TILE_SIZE, k / PIP_MASK_TILE_SIZE));
    if (pix.x >= int(frame.width) || pix.y >= int(frame.height)) continue;
    if (!inLightRect(frame.lightRectMin, frame.lightRectMax, uint(pix.x), uint(pix.y))) continue;
    vec4 position = imageLoad(gPosition, pix);
    if (position.w == 0.0) continue;
    vec3 p = position.xyz, n = imageLoad(gNormal, pix).xyz, nf = faceNormalAt(pix);
    if (!lightReaches(light, p, n, light.position.xyz)) continue;
    if (frame.lightError > 0.0 && shadowWeight(light, p, n) < frame.lightError) continue;
    float facing = min(dot(n, light.position.xyz - p), dot(nf, light.position.xyz - p));
    if (!kExplain && facing < halfExtent) continue;  // PIP_MASK_TANGENT holds: no search
    MapPoint m = mapPoint(p, n);
    if (!m.inside) continue;
    SplatCone c = splatCone(m.offsetP, viewProj, m.t);
    if (c.unbounded) return PIP_TILE_SEARCH;
    for (int j = 0; j < 4; ++j) {
      cone.alphaLo[j] = min(cone.alphaLo[j], c.alphaLo[j]);
      cone.alphaHi[j] = max(cone.alphaHi[j], c.alphaHi[j]);
      cone.betaLo[j] = min(cone.betaLo[j], c.betaLo[j]);
      cone.betaHi[j] = max(cone.betaHi[j], c.betaHi[j]);
    }
    cone.tLo = min(cone.tLo, c.tLo);
    cone.tHi = max(cone.tHi, c.tHi);
    farthest = max(farthest, axisDepth(m.clip));
    any = true;
    if (m.clip.z / m.clip.w > LIGHT_TEXEL(shadowMap, shadowTexels, clamp(m.t, ivec2(0), ivec2(res - 1)), 0u, res)) {
      continue;  // dark in the map: only the edge channel searches
    }
    MapPlane q = mapPlane(p, nf, m.texel, viewProj);
    if (!all(lessThan(abs(q.gLo), vec2(1e30)))) return PIP_TILE_SEARCH;  // edge-on: its search is unbounded
    if (!lit) highest.e0 = q.e0;  // the tile's plane is measured from its first lit receiver's texel
    lit = true;
    highest.s0 = max(highest.s0, q.s0 + dot(q.gLo, highest.e0 - q.e0));
    highest.gLo = min(highest.gLo, q.gLo);
    highest.gHi = max(highest.gHi, q.gHi);
    highest.tol = min(highest.tol, q.tol);
  }
  if (!any) return PIP_TILE_NONE;
  if (withinReach(cone, 0u, farthest, PYRAMID_EDGES, kNoPlane).x > 0.0) return PIP_TILE_SEARCH;
  highest.raw0 = (highest.s0 - highest.sOfRaw.x) / highest.sOfRaw.y;
  if (lit && withinReach(cone, 0u, farthest, PYRAMID_SURFACE, highest).x > 0.0) return PIP_TILE_SEARCH;
  return PIP_TILE_CLEAR;
}

#endif
