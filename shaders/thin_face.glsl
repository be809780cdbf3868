// One triangle on one light face, shared by the selection pass (thin_select.comp) and the
// conservative raster (thin_triangles.geom), so both apply the same test: near-plane clipping and
// the thin criterion (see thin_triangles.geom for the reasoning). Needs `push` (ThinTrianglePush).

vec2 texel(vec4 c) { return (c.xy / c.w * 0.5 + 0.5) * push.resolution; }

// Corners c0..c2 in the face's clip space, w0..w2 in world space. True when the triangle is thin
// (or of a cut-out mesh) and its texel-space bounds reach the face; then q0..q3 is the near-clipped
// polygon (a triangle repeats its last corner), `behind` counts the corners clipped off and `thin`
// says whether it is thin.
bool thinOnFace(vec4 c0, vec4 c1, vec4 c2, vec3 w0, vec3 w1, vec3 w2, out vec4 q0, out vec4 q1, out vec4 q2,
                out vec4 q3, out uint behind, out bool thin) {
  bool b0 = c0.z < 0.0;
  bool b1 = c1.z < 0.0;
  bool b2 = c2.z < 0.0;
  behind = uint(b0) + uint(b1) + uint(b2);
  q0 = c0; q1 = c1; q2 = c2; q3 = c2;
  thin = false;
  if (behind == 3u) return false;
  if (behind > 0u) {
    // Rotate so that `a` is the odd corner: the one behind, or the one in front.
    bool odd0 = behind == 1u ? b0 : !b0;
    bool odd1 = behind == 1u ? b1 : !b1;
    vec4 a = odd0 ? c0 : (odd1 ? c1 : c2);
    vec4 b = odd0 ? c1 : (odd1 ? c2 : c0);
    vec4 d = odd0 ? c2 : (odd1 ? c0 : c1);
    vec4 ab = mix(a, b, a.z / (a.z - b.z));
    vec4 da = mix(d, a, d.z / (d.z - a.z));
    if (behind == 1u) {
      q0 = ab; q1 = b; q2 = d; q3 = da;
    } else {
      q0 = a; q1 = ab; q2 = da; q3 = da;
    }
  }
  if (!(min(min(q0.w, q1.w), min(q2.w, q3.w)) > 0.0)) return false;

  float res = push.resolution;
  vec2 p0 = texel(q0), p1 = texel(q1), p2 = texel(q2), p3 = texel(q3);
  if (behind == 0u) {
    thin = thinTriangle(p0, p1, p2, push.maxWidthTexels, push.minAspect);
  } else {
    vec3 e0 = w1 - w0;
    vec3 e1 = w2 - w1;
    vec3 e2 = w0 - w2;
    float size = push.texelWorld * max(max(q0.w, q1.w), max(q2.w, q3.w));
    float longest = sqrt(max(dot(e0, e0), max(dot(e1, e1), dot(e2, e2)))) / size;
    thin = thinMeasure(longest, length(cross(e0, e2)) / (size * size), push.maxWidthTexels, push.minAspect);
  }
  // A cut-out triangle may hold holes finer than a texel anywhere inside it (its texture's), which
  // the map cannot show: the mask keeps it wherever its alpha changes (thin_cutout.glsl).
  if (!thin && push.cutouts == 0u) return false;
  vec2 lo = min(min(p0, p1), min(p2, p3));
  vec2 hi = max(max(p0, p1), max(p2, p3));
  return !(hi.x <= 0.0 || hi.y <= 0.0 || lo.x >= res || lo.y >= res);  // else it touches no texel
}
