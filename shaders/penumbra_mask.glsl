// The penumbra mask of an area light (Lauterbach et al. 2009, 3.2): the union of the splats of the
// shadow map's edge texels, each the light's shape scaled by the edge's depth relative to the
// receiver, gathered per pixel from the edge pyramid (shared/pyramid.h) instead of splatted.
// Included by pip_classify.comp after `frame`, `push` (PipPush), `tiles` (the pyramid), the
// shadow map's reads (LIGHT_TEXEL), linearDepth, rawDepth, axisDepth and MapPlane are declared.

// The penumbra mask's windows on this map for a receiver p (depth d, texel t): window(z) holds the
// texels where an edge no closer to the light than z can lie and still hide part of the light
// from p. Such an edge is on a segment from p to a light point at depth >= z; the segments to the
// light's corners (a disk's bounding square) at depth z project, with p's texel, to a convex hull
// whose bounding box, widened by a texel's reach, is the window. Along a segment clip coordinates
// are affine and w is the depth (ortho: 1), so a corner's point at depth z lands at texel
// alpha * u + beta, with u = 1/z (ortho: z), itself affine in the map's raw depth: a window costs
// a few multiply-adds.
// Windows shrink as z grows: the cone from p to the light narrows.
// A tile's cone (maskTile in pip_tiles.glsl) bounds the windows of several receivers: the bounds of their
// alphas and betas per corner, and of their texels (one receiver: lo = hi).
struct SplatCone {
  vec2 alphaLo[4], alphaHi[4];  // per corner: its point at depth parameter u lies at texel alpha * u + beta,
  vec2 betaLo[4], betaHi[4];    // alpha and beta within these bounds
  vec2 tLo, tHi;                // p's texel
  vec2 uOfRaw;                  // u = uOfRaw.x + uOfRaw.y * raw depth
  bool unbounded;               // a corner lies behind the map's eye: every window is unbounded
};

// u of the raw depth: u = coneDepthOfRaw().x + coneDepthOfRaw().y * raw.
vec2 coneDepthOfRaw() {
  float near = frame.shadow.nearPlane, far = frame.shadow.farPlane;
  return frame.shadow.kind == SHADOW_ORTHO ? vec2(near, far - near) : vec2(1.0 / near, (near - far) / (near * far));
}

SplatCone splatCone(vec3 p, mat4 viewProj, ivec2 t) {
  vec3 tan1 = frame.light.tangent.xyz;
  vec3 tan2 = cross(frame.light.direction.xyz, tan1);
  float h = 0.5 * frame.light.size;
  float halfRes = 0.5 * float(frame.shadow.resolution);
  bool ortho = frame.shadow.kind == SHADOW_ORTHO;
  SplatCone cone;
  cone.tLo = vec2(t);
  cone.tHi = vec2(t);
  cone.uOfRaw = coneDepthOfRaw();
  cone.unbounded = false;
  vec4 cp = viewProj * vec4(p, 1.0);
  float dp = axisDepth(cp);
  for (int j = 0; j < 4; ++j) {
    vec3 q = frame.light.position.xyz + h * ((j & 1) != 0 ? tan1 : -tan1) + h * ((j & 2) != 0 ? tan2 : -tan2);
    vec4 cq = viewProj * vec4(q, 1.0);
    float dq = axisDepth(cq);
    vec2 alpha = vec2(0.0), beta;
    if (dp > dq) {
      // the point at depth z: cp + (dp - z) k, with k = (cq - cp) / (dp - dq)
      vec2 k = (cq.xy - cp.xy) / (dp - dq);
      vec2 far0 = cp.xy + dp * k;
      alpha = ortho ? -k : far0;
      beta = ortho ? far0 : -k;
    } else {  // p is no farther than the corner: the corner itself
      cone.unbounded = cone.unbounded || cq.w <= 1e-6 * dp;
      beta = cq.xy / cq.w;
    }
    cone.alphaLo[j] = cone.alphaHi[j] = halfRes * alpha;
    cone.betaLo[j] = cone.betaHi[j] = halfRes * beta + halfRes;
  }
  return cone;
}

// window(z) of the raw depth z as an inclusive texel range, widened by pad texels.
void splatWindow(SplatCone cone, float raw, float pad, out ivec2 lo, out ivec2 hi) {
  float u = cone.uOfRaw.x + cone.uOfRaw.y * raw;
  vec2 a = cone.tLo, b = cone.tHi;
  for (int j = 0; j < 4; ++j) {
    vec2 e0 = cone.alphaLo[j] * u, e1 = cone.alphaHi[j] * u;  // u may be negative (orthographic)
    a = min(a, min(e0, e1) + cone.betaLo[j]);
    b = max(b, max(e0, e1) + cone.betaHi[j]);
  }
  lo = ivec2(floor(a - pad));
  hi = ivec2(ceil(b + pad));
}

// p's plane (in mapPlane's depth measure) at its highest over the texel centres of the tile xy of
// level k (1 texel at k = 0). A tile's plane (maskTile) is the highest of its receivers'.
float planeMaxOver(MapPlane plane, ivec2 xy, uint k) {
  float halfSpan = 0.5 * float((1 << k) - 1);
  vec2 toCentre = vec2(xy << k) + 0.5 + halfSpan - plane.e0;
  vec2 rise = max(plane.gLo * toCentre, plane.gHi * toCentre) + halfSpan * max(abs(plane.gLo), abs(plane.gHi));
  return plane.s0 + rise.x + rise.y;
}

// Whether the surface fit of the tile xy of level k >= 2 (at `fit` in the pyramid) allows a texel
// over p's plane by more than its tol: the fit's plane, lowered by its `below`, rises over p's
// plane somewhere over the tile's texel centres. Compared in raw depth, where both are affine.
bool fitOver(MapPlane plane, ivec2 xy, uint k, uint fit) {
  vec2 g = vec2(tiles[fit + PYRAMID_FIT_GRADIENT], tiles[fit + PYRAMID_FIT_GRADIENT + 1u]);
  vec2 toCentre = vec2(xy << k) + float(1 << (k - 1u)) - plane.e0;
  vec2 gLo = plane.gLo / plane.sOfRaw.y, gHi = plane.gHi / plane.sOfRaw.y;  // p's plane per texel in raw depth
  vec2 rise = max(gLo * toCentre, gHi * toCentre);
  float atCentre = tiles[fit + PYRAMID_FIT_CENTRE] - tiles[fit + PYRAMID_FIT_BELOW] - (plane.raw0 + rise.x + rise.y);
  vec2 dg = max(abs(g - gLo), abs(g - gHi));
  return atCentre - 0.5 * float((1 << k) - 1) * (dg.x + dg.y) < -plane.tol / plane.sOfRaw.y;
}

// Whether a texel of the 2x2 tile xy (level 1) is nearer than rawLimit, over p's plane by more than
// its tol, and in its own window.
bool texelOverWithinReach(SplatCone cone, MapPlane plane, ivec2 xy, uint face, float rawLimit) {
  int res = int(frame.shadow.resolution);
  for (int j = 0; j < 4; ++j) {
    ivec2 c = 2 * xy + ivec2(j & 1, j >> 1);
    if (any(greaterThanEqual(c, ivec2(res)))) continue;
    float z = LIGHT_TEXEL(shadowMap, shadowTexels, c, face, res);
    if (z >= rawLimit || plane.sOfRaw.x + plane.sOfRaw.y * z >= planeMaxOver(plane, c, 0u) - plane.tol) continue;
    ivec2 lo, hi;
    splatWindow(cone, z, 0.5, lo, hi);
    if (all(lessThanEqual(c, hi)) && all(greaterThanEqual(c, lo))) return true;
  }
  return false;
}

// .x = 1 when a blocker of the channel's kind lies where its splat covers the receiver p (depth d;
// cone = splatCone(p, ...) at its texel t), i.e. in its own window: the penumbra mask; .y = 1 when the window of the face's
// nearest one leaves the face (a cube seam).
//  - PYRAMID_EDGES: an edge texel whose blocker depth z_e is nearer to the light than p, in
//    window(z_e).
//  - PYRAMID_SURFACE: any texel nearer than p and over p's plane (mapPlane) by more than its tol,
//    in its window; a tile opens only where its surface fit (fitOver) also allows such a texel. A
//    smooth surface rising over p (an ear's curl) hides part of a light wholly above p's plane
//    without an edge in the map; a texel of p's own plane, or of a surface curving away below it,
//    cannot.
// Searched depth first in the pyramid: a tile whose nearest depth z_t lies behind the receiver,
// or (surface) is nowhere over p's plane in the tile, or whose texels miss window(z_t), holds no
// such blocker (its texels' windows lie inside window(z_t)), so only tiles that meet their own
// window are opened, down to 2x2 texels (surface: then to its texels). The face's nearest blocker
// bounds every window, so the search starts from the 2x2 tiles that hold that window; it needs no
// stack (after a tile's last child comes its parent's next sibling) and opens children nearest to
// t first. A search that visits PIP_MAX_TILE_VISITS tiles keeps the pixel in the mask.
vec2 withinReach(SplatCone cone, uint face, float d, uint channel, MapPlane plane) {
  if (cone.unbounded) return vec2(1.0, 1.0);
  ivec2 t = ivec2(floor(0.5 * (cone.tLo + cone.tHi)));
  bool surface = channel == PYRAMID_SURFACE;
  // A texel's footprint reaches half a texel from its centre; an edge texel's blocker reaches its
  // silhouette, which runs within a texel of it (depth_pyramid.comp), as does a thin triangle on it.
  float pad = surface ? 0.5 : 1.0;
  if (surface && !all(lessThan(max(abs(plane.gLo), abs(plane.gHi)), vec2(1e30)))) return vec2(1.0, 0.0);  // edge-on
  float rawLimit = rawDepth(d - push.depthMargin);  // blockers at or behind it cannot shadow p
  uint res = frame.shadow.resolution, faces = frame.shadow.faceCount, levels = push.pyramidLevels;
  // The face's nearest blocker bounds every window: the search starts at the level where that
  // window spans at most 2x2 tiles, from those tiles.
  float zTop = tiles[2u * (pyramidOffset(res, faces, levels) + face) + channel];
  if (zTop >= rawLimit) return vec2(0.0, 0.0);
  ivec2 lo, hi;
  splatWindow(cone, zTop, pad, lo, hi);
  float seam = any(lessThan(lo, ivec2(0))) || any(greaterThanEqual(hi, ivec2(res))) ? 1.0 : 0.0;
  lo = clamp(lo, ivec2(0), ivec2(res - 1));
  hi = clamp(hi, ivec2(0), ivec2(res - 1));
  uint top = 1u;
  while (top < levels && any(greaterThan((hi >> top) - (lo >> top), ivec2(1)))) ++top;
  uint topBase = pyramidOffset(res, faces, top);
  uint fitBase = 2u * pyramidOffset(res, faces, levels + 1u) - PYRAMID_FIT_FLOATS * pyramidOffset(res, faces, 2u);
  ivec2 firstRoot = lo >> top, lastRoot = hi >> top;
  int visits = 0;
  for (int root = 0; root < 4; ++root) {
    ivec2 xy = firstRoot + ivec2(root & 1, root >> 1);
    if (any(greaterThan(xy, lastRoot))) continue;
    uint k = top, base = topBase;
    for (; visits < PIP_MAX_TILE_VISITS; ++visits) {
      int dim = int(pyramidDim(res, k));
      bool open = false;
      if (xy.x < dim && xy.y < dim) {  // a map whose size is no power of two has tiles cut at its edge
        uint tile = base + (face * uint(dim) + uint(xy.y)) * uint(dim) + uint(xy.x);
        float z = tiles[2u * tile + channel];
        bool nearer = z < rawLimit;  // and for the surface channel over p's plane somewhere in the tile:
        if (nearer && surface) {
          nearer = plane.sOfRaw.x + plane.sOfRaw.y * z < planeMaxOver(plane, xy, k) - plane.tol &&
                   (k < 2u || fitOver(plane, xy, k, fitBase + PYRAMID_FIT_FLOATS * tile));
        }
        if (nearer) {
          splatWindow(cone, z, pad, lo, hi);
          open = all(lessThanEqual(xy << k, hi)) && all(greaterThanEqual(((xy + 1) << k) - 1, lo));
        }
      }
      if (open && k == 1u) {
        if (!surface || texelOverWithinReach(cone, plane, xy, face, rawLimit)) return vec2(1.0, seam);
        open = false;
      }
      if (open) {
        --k;  // on to its first child
        base -= faces * pyramidDim(res, k) * pyramidDim(res, k);
        xy = 2 * xy + ((t >> k) & 1);
        continue;
      }
      // On to the next tile: up from last children, then the parent's next child.
      while (k < top && ((xy ^ (t >> k)) & 1) == ivec2(1, 1)) {
        dim = int(pyramidDim(res, k));
        base += faces * uint(dim * dim);
        ++k;
        xy >>= 1;
      }
      if (k == top) break;
      ivec2 order = (xy ^ (t >> k)) & 1;  // (0,0) (1,0) (0,1) (1,1)
      order = order.x == 0 ? ivec2(1, order.y) : ivec2(0, 1);
      xy = (xy & ~1) | (order ^ ((t >> k) & 1));
    }
    if (visits == PIP_MAX_TILE_VISITS) return vec2(1.0, seam);
  }
  return vec2(0.0, seam);
}
