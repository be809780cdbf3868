// Candidate line-space lookup (Keul et al. 2018, Alg. 1 and 2), included by candidate_rays.comp
// and bvh_ls_traverse.glsl, and usable from any kernel (not compiled on its own).
// The includer:
//   - puts a CsParams (shared/candidates.h) in its push constants or a uniform and defines
//     CS_PARAMS to name it (e.g. `#define CS_PARAMS push.cs`) before including this file;
//   - binds the buffers at CS_BINDING_BOXES, _BITS and _OFFSETS (defaults 5, 6, 7; define any of
//     them first to move it); the packed candidates and the scene's triangles are read through the
//     addresses in CS_PARAMS (GL_EXT_buffer_reference and _uvec2 enabled);
//   - may read csCandidateTests (plane tests of the calling invocation) for its statistics.
// csHit clips the ray's infinite line to the line space's box (a ray starting inside still uses the
// line's entry, as in the paper), finds the directed shaft of its entry and exit patches, and
// intersects the shaft's candidate triangle as an infinite plane.
#ifndef PENUMBRA_CANDIDATE_LOOKUP_GLSL
#define PENUMBRA_CANDIDATE_LOOKUP_GLSL
#include "shared/candidates.h"
#include "shared/gbuffer.h"
#include "shared/linespace.h"
#include "shared/scene_triangles.h"

#ifndef CS_PARAMS
#error "define CS_PARAMS (a CsParams) before including candidate_lookup.glsl"
#endif

layout(std430, binding = CS_BINDING_BOXES) readonly buffer CsBoxes { CsBox csBoxes[]; };
layout(std430, binding = CS_BINDING_BITS) readonly buffer CsBits { uint csBits[]; };
layout(std430, binding = CS_BINDING_OFFSETS) readonly buffer CsOffsets { uint csOffsets[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer CsCandidateArray { uint v[]; };
#define csCandidates CsCandidateArray(CS_PARAMS.candidates).v
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer CsSceneTriangleArray { SceneTriangle v[]; };
#define csSceneTriangles CsSceneTriangleArray(CS_PARAMS.triangles).v

uint csCandidateTests = 0u;  // candidate planes tested by the calling invocation

// The infinite line origin + t * dir against box [lo, hi]: entry and exit distances and faces
// (face = 2 * axis + side, shared/linespace.h). False when the line misses the box or only
// touches it. A direction component of 0 leaves that axis's slab unbounded (if the origin is in it).
bool csClip(vec3 lo, vec3 hi, vec3 origin, vec3 dir, out float tEnter, out float tExit, out uint faceIn,
            out uint faceOut) {
  tEnter = -3.0e38f;
  tExit = 3.0e38f;
  faceIn = 0u;
  faceOut = 1u;
  for (uint axis = 0u; axis < 3u; ++axis) {
    float o = lsComponent(origin, axis), d = lsComponent(dir, axis);
    float l = lsComponent(lo, axis), h = lsComponent(hi, axis);
    if (d == 0.0f) {
      if (o < l || o > h) return false;
      continue;
    }
    float t0 = (l - o) / d, t1 = (h - o) / d;
    // Positive direction: in through the low face (side 0), out through the high one.
    uint sideIn = d > 0.0f ? 0u : 1u;
    float tNear = min(t0, t1), tFar = max(t0, t1);
    if (tNear > tEnter) {
      tEnter = tNear;
      faceIn = 2u * axis + sideIn;
    }
    if (tFar < tExit) {
      tExit = tFar;
      faceOut = 2u * axis + 1u - sideIn;
    }
  }
  return tEnter > -3.0e38f && tEnter < tExit && faceIn != faceOut;  // a zero direction has no line
}

// The candidate of directed shaft `shaft` of line space `ls` (sparse lookup), or CS_NONE.
uint csCandidate(uint ls, uint shaft) {
  uint w = csBoxes[ls].wordBase + shaft / 32u, b = shaft % 32u;
  uint word = csBits[w];
  if ((word & (1u << b)) == 0u) return CS_NONE;
  return csCandidates[csDataIndex(csOffsets[w], word, b)];
}

// The vertex normals of `tri` interpolated at point p of its plane (extrapolated outside the
// triangle) by the plane's barycentrics, normalized, and the face normal turned to the vertex
// normals' side. Returns false where the interpolated normal vanishes or the triangle is degenerate.
bool csTriangleNormals(SceneTriangle tri, vec3 p, out vec3 shading, out vec3 face) {
  vec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
  vec3 ng = cross(e1, e2);
  float area2 = dot(ng, ng);
  shading = vec3(0.0f, 0.0f, 1.0f);
  face = shading;
  if (!(area2 > 0.0f)) return false;
  vec3 rel = p - tri.v0;
  float b1 = dot(cross(rel, e2), ng) / area2;
  float b2 = dot(cross(e1, rel), ng) / area2;
  float b0 = 1.0f - b1 - b2;
  vec3 n0 = octahedralDecode(unpackSnorm2x16(tri.normal0));
  vec3 n1 = octahedralDecode(unpackSnorm2x16(tri.normal1));
  vec3 n2 = octahedralDecode(unpackSnorm2x16(tri.normal2));
  face = ng * inversesqrt(area2);
  if (dot(n0 + n1 + n2, face) < 0.0f) face = -face;
  vec3 n = b0 * n0 + b1 * n1 + b2 * n2;
  float len = length(n);
  if (!(len > 1.0e-6f)) return false;
  shading = n / len;
  return true;
}

// The ray origin + t * dir (t in [tMin, tMax]) against line space `ls`: the candidate of the shaft
// its line passes through, as an infinite plane, hit within the part of the line inside the box;
// the hit is dropped where the extrapolated normal leans more than CS_PARAMS.cosMaxDeviation
// allows from the face normal (the shaft only grazes the surface's edge). On a hit: t, the
// triangle (scene order) and the shading normal (vertex normals' side, not turned to the ray).
bool csHit(uint ls, vec3 origin, vec3 dir, float tMin, float tMax, out float t, out uint triangle, out vec3 normal) {
  t = -1.0f;
  triangle = CS_NONE;
  normal = vec3(0.0f, 0.0f, 1.0f);
  CsBox box = csBoxes[ls];
  float tEnter, tExit;
  uint faceIn, faceOut;
  if (!csClip(box.lo, box.hi, origin, dir, tEnter, tExit, faceIn, faceOut)) return false;
  float lo = max(tMin, tEnter), hi = min(tMax, tExit);
  if (lo > hi) return false;
  uint n = CS_PARAMS.n;
  vec3 extent = max(box.hi - box.lo, vec3(1.0e-30f));
  uint patchIn = lsPatch((origin + tEnter * dir - box.lo) / extent, faceIn, n);
  uint patchOut = lsPatch((origin + tExit * dir - box.lo) / extent, faceOut, n);
  uint candidate = csCandidate(ls, csShaft(faceIn, patchIn, faceOut, patchOut, n));
  if (candidate == CS_NONE) return false;
  ++csCandidateTests;
  SceneTriangle tri = csSceneTriangles[candidate];
  vec3 ng = cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
  float den = dot(ng, dir);
  if (den == 0.0f) return false;  // the line lies in (or parallel to) the plane
  float tPlane = dot(ng, tri.v0 - origin) / den;
  if (!(tPlane >= lo && tPlane <= hi)) return false;
  vec3 face;
  if (!csTriangleNormals(tri, origin + tPlane * dir, normal, face)) return false;
  if (dot(normal, face) < CS_PARAMS.cosMaxDeviation) return false;
  t = tPlane;
  triangle = candidate;
  return true;
}
#endif  // PENUMBRA_CANDIDATE_LOOKUP_GLSL
