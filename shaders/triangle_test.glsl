// The robust ray/triangle test of every compute tracer (bvh_traverse.glsl, and the line space's
// exact shadows in linespace_traverse.glsl): Embree's watertight origin-shifted Pluecker edge
// tests, so rays that hit a shared edge or vertex find a triangle exactly when they do in the
// reference. Included by traversal code (not compiled on its own); safe to include twice.
#ifndef PENUMBRA_TRIANGLE_TEST_GLSL
#define PENUMBRA_TRIANGLE_TEST_GLSL
#include "shared/bvh.h"

// Embree evaluates its robust test with fused multiply-adds on CPUs that have them (every x86 CPU
// with AVX2); doing the same, operation for operation, makes the edge decisions agree with the
// reference bit for bit there, even for grazing rays where any rounding difference would flip
// them. `precise` keeps the compiler from fusing or reordering anything else.
vec3 bvhCross(vec3 a, vec3 b) {
  precise vec3 r = vec3(fma(a.y, b.z, -(a.z * b.y)), fma(a.z, b.x, -(a.x * b.z)), fma(a.x, b.y, -(a.y * b.x)));
  return r;
}

float bvhDot(vec3 a, vec3 b) {
  precise float r = fma(a.x, b.x, fma(a.y, b.y, a.z * b.z));
  return r;
}

// Each coordinate of the normal from whichever of two cross products loses less to cancellation
// (the one whose subtracted product is smaller), as Embree's robust mode computes it.
vec3 bvhStableNormal(vec3 a, vec3 b, vec3 c) {
  precise vec3 abTerm = vec3(a.z * b.y, a.x * b.z, a.y * b.x);
  precise vec3 bcTerm = vec3(b.z * c.y, b.x * c.z, b.y * c.x);
  precise vec3 ab = vec3(fma(a.y, b.z, -abTerm.x), fma(a.z, b.x, -abTerm.y), fma(a.x, b.y, -abTerm.z));
  precise vec3 bc = vec3(fma(b.y, c.z, -bcTerm.x), fma(b.z, c.x, -bcTerm.y), fma(b.x, c.y, -bcTerm.z));
  return mix(bc, ab, lessThan(abs(abTerm), abs(bcTerm)));
}

// Ray distance to triangle `tri` if the ray hits it within [tMin, tMax], else a negative value;
// `bary` gets the hit's barycentrics (u, v) of v1 and v2, as Embree reports them (its U, V, W
// edge functions over their sum).
float bvhTriangleHit(BvhTriangle tri, vec3 origin, vec3 dir, float tMin, float tMax, out vec2 bary) {
  precise vec3 v0 = tri.v0 - origin;
  precise vec3 v1 = tri.v1 - origin;
  precise vec3 v2 = tri.v2 - origin;
  precise vec3 e0 = v2 - v0;
  precise vec3 e1 = v0 - v1;
  precise vec3 e2 = v1 - v2;
  // Edge functions: each uses only its edge's two vertices, so neighbours agree on shared edges.
  precise float u = bvhDot(bvhCross(e0, v2 + v0), dir);
  precise float v = bvhDot(bvhCross(e1, v0 + v1), dir);
  precise float w = bvhDot(bvhCross(e2, v1 + v2), dir);
  precise float eps = 1.1920929e-7f * abs(u + v + w);  // float epsilon relative to the sum, as Embree
  bary = vec2(0.0f);
  if (!(min(u, min(v, w)) >= -eps || max(u, max(v, w)) <= eps)) return -1.0f;
  precise vec3 n = bvhStableNormal(e0, e1, e2);
  precise float den = 2.0f * bvhDot(n, dir);
  if (den == 0.0f) return -1.0f;  // the ray lies in the triangle's plane
  precise float t = (2.0f * bvhDot(v0, n)) / den;
  if (!(t >= tMin && t <= tMax)) return -1.0f;
  bary = vec2(u, v) / (u + v + w);
  return t;
}

float bvhTriangleHit(BvhTriangle tri, vec3 origin, vec3 dir, float tMin, float tMax) {
  vec2 bary;
  return bvhTriangleHit(tri, origin, dir, tMin, tMax, bary);
}

#endif  // PENUMBRA_TRIANGLE_TEST_GLSL
