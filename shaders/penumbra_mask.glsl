// The penumbra mask of an area light (Lauterbach et al. 2009, 3.2): the union of the splats of the
// shadow map's edge texels, each the light's shape scaled by the edge's depth relative to the
// receiver, gathered per pixel from the edge pyramid (shared/pyramid.h) instead of splatted.
// Included by pip_classify.comp after `frame`, `push` (PipPush), `tiles` (the pyramid),
// linearDepth, rawDepth and axisDepth are declared.

// The penumbra mask's windows on this map for a receiver p (depth d, texel t): window(z) holds the
// texels where an edge no closer to the light than z can lie and still hide part of the light
// from p. Such an edge is on a segment from p to a light point at depth >= z; the segments to the
// light's corners (a disk's bounding square) at depth z project, with p's texel, to a convex hull
// whose bounding box is the window (+1.5 texels). Along a segment clip coordinates are affine and
// w is the depth (ortho: 1), so a corner's point at depth z lands at texel alpha * u + beta, with
// u = 1/z (ortho: z), itself affine in the map's raw depth: a window costs a few multiply-adds.
// Windows shrink as z grows: the cone from p to the light narrows.
struct SplatCone {
  vec2 alpha[4], beta[4];  // per corner: its point at depth parameter u lies at texel alpha * u + beta
  vec2 t;                  // p's texel
  vec2 uOfRaw;             // u = uOfRaw.x + uOfRaw.y * raw depth
  bool unbounded;          // a corner lies behind the map's eye: every window is unbounded
};

SplatCone splatCone(vec3 p, mat4 viewProj, ivec2 t) {
  vec3 tan1 = frame.light.tangent.xyz;
  vec3 tan2 = cross(frame.light.direction.xyz, tan1);
  float h = 0.5 * frame.light.size;
  float halfRes = 0.5 * float(frame.shadow.resolution);
  float near = frame.shadow.nearPlane, far = frame.shadow.farPlane;
  bool ortho = frame.shadow.kind == SHADOW_ORTHO;
  SplatCone cone;
  cone.t = vec2(t);
  cone.uOfRaw = ortho ? vec2(near, far - near) : vec2(1.0 / near, (near - far) / (near * far));
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
    cone.alpha[j] = halfRes * alpha;
    cone.beta[j] = halfRes * beta + halfRes;
  }
  return cone;
}

// window(z) of the raw depth z as an inclusive texel range.
void splatWindow(SplatCone cone, float raw, out ivec2 lo, out ivec2 hi) {
  float u = cone.uOfRaw.x + cone.uOfRaw.y * raw;
  vec2 a = cone.t, b = cone.t;
  for (int j = 0; j < 4; ++j) {
    vec2 e = cone.alpha[j] * u + cone.beta[j];
    a = min(a, e);
    b = max(b, e);
  }
  lo = ivec2(floor(a - 1.5));
  hi = ivec2(ceil(b + 1.5));
}

// .x = 1 when an edge texel whose blocker depth z_e is nearer to the light than the receiver p
// (depth d, texel t) lies in its own window(z_e), i.e. the edge's splat covers the pixel (the
// penumbra mask); .y = 1 when the window of the face's nearest edge leaves the face (a cube seam).
// Searched depth first in the edge pyramid: a tile whose nearest edge z_t lies behind the
// receiver, or whose texels miss window(z_t), holds no such edge (its edges' windows lie inside
// window(z_t)), so only tiles that meet their own window are opened, down to 2x2 texels. The
// face's nearest edge bounds every window, so the search starts from the 2x2 tiles that hold
// that window; it needs no stack (after a tile's last child comes its parent's next sibling) and
// opens children nearest to t first. A search that visits PIP_MAX_TILE_VISITS tiles keeps the
// pixel in the mask.
vec2 edgeWithinReach(vec3 p, mat4 viewProj, ivec2 t, uint face, float d) {
  SplatCone cone = splatCone(p, viewProj, t);
  if (cone.unbounded) return vec2(1.0, 1.0);
  float rawLimit = rawDepth(d - push.depthMargin);  // edges at or behind it cannot shadow p
  uint res = frame.shadow.resolution, faces = frame.shadow.faceCount, levels = push.pyramidLevels;
  // The face's nearest edge bounds every window: the search starts at the level where that window
  // spans at most 2x2 tiles, from those tiles.
  float zTop = tiles[pyramidOffset(res, faces, levels) + face];
  if (zTop >= rawLimit) return vec2(0.0, 0.0);
  ivec2 lo, hi;
  splatWindow(cone, zTop, lo, hi);
  float seam = any(lessThan(lo, ivec2(0))) || any(greaterThanEqual(hi, ivec2(res))) ? 1.0 : 0.0;
  lo = clamp(lo, ivec2(0), ivec2(res - 1));
  hi = clamp(hi, ivec2(0), ivec2(res - 1));
  uint top = 1u;
  while (top < levels && any(greaterThan((hi >> top) - (lo >> top), ivec2(1)))) ++top;
  uint topBase = pyramidOffset(res, faces, top);
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
        float z = tiles[base + (face * uint(dim) + uint(xy.y)) * uint(dim) + uint(xy.x)];
        if (z < rawLimit) {
          splatWindow(cone, z, lo, hi);
          open = all(lessThanEqual(xy << k, hi)) && all(greaterThanEqual(((xy + 1) << k) - 1, lo));
        }
      }
      if (open) {
        if (k == 1u) return vec2(1.0, seam);
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
