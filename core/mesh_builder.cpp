#include "core/mesh_builder.h"

#include <cmath>
#include <numbers>

namespace penumbra::mesh {

namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

std::uint32_t addVertex(Mesh& m, const glm::vec3& p, const glm::vec3& n) {
  m.positions.push_back(p);
  m.normals.push_back(n);
  return std::uint32_t(m.positions.size() - 1);
}

void addTriangle(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) { m.indices.insert(m.indices.end(), {a, b, c}); }

// Right-handed unit frame (e1, e2, axis): cross(e1, e2) == axis, so angles grow counter-clockwise
// seen from the tip of `axis`.
void frameAround(const glm::vec3& axis, glm::vec3& e1, glm::vec3& e2) {
  const glm::vec3 helper = std::abs(axis.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
  e1 = glm::normalize(glm::cross(helper, axis));
  e2 = glm::cross(axis, e1);
}

}  // namespace

void addQuad(Mesh& m, const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, const glm::vec3& p3,
             const glm::vec3& facing) {
  const glm::vec3 n = glm::normalize(facing);
  const std::uint32_t a = addVertex(m, p0, n), b = addVertex(m, p1, n), c = addVertex(m, p2, n),
                      d = addVertex(m, p3, n);
  if (glm::dot(glm::cross(p1 - p0, p2 - p0), n) >= 0.0f) {
    addTriangle(m, a, b, c);
    addTriangle(m, a, c, d);
  } else {
    addTriangle(m, a, c, b);
    addTriangle(m, a, d, c);
  }
}

void addGrid(Mesh& m, const glm::vec3& origin, const glm::vec3& u, const glm::vec3& v, int nu, int nv,
             const glm::vec3& facing) {
  const glm::vec3 n = glm::normalize(facing);
  const bool flip = glm::dot(glm::cross(u, v), n) < 0.0f;
  const std::uint32_t first = std::uint32_t(m.positions.size());
  m.positions.reserve(m.positions.size() + std::size_t(nu + 1) * std::size_t(nv + 1));
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      addVertex(m, origin + (float(i) / float(nu)) * u + (float(j) / float(nv)) * v, n);
    }
  }
  m.indices.reserve(m.indices.size() + 3 * gridTriangles(nu, nv));
  const auto at = [&](int i, int j) { return first + std::uint32_t(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (flip) {
        addTriangle(m, a, c, b);
        addTriangle(m, a, d, c);
      } else {
        addTriangle(m, a, b, c);
        addTriangle(m, a, c, d);
      }
    }
  }
}

void addBox(Mesh& m, const glm::vec3& centre, const glm::vec3& halfX, const glm::vec3& halfY,
            const glm::vec3& halfZ, bool inward) {
  const glm::vec3 axes[3] = {halfX, halfY, halfZ};
  for (int a = 0; a < 3; ++a) {
    const glm::vec3& s = axes[(a + 1) % 3];
    const glm::vec3& t = axes[(a + 2) % 3];
    for (float sign : {1.0f, -1.0f}) {
      const glm::vec3 faceCentre = centre + sign * axes[a];
      const glm::vec3 outward = sign * axes[a];
      addQuad(m, faceCentre - s - t, faceCentre + s - t, faceCentre + s + t, faceCentre - s + t,
              inward ? -outward : outward);
    }
  }
}

void addYawedBox(Mesh& m, const glm::vec3& centre, const glm::vec3& half, float yawDeg) {
  const float yaw = glm::radians(yawDeg);
  const glm::vec3 x{std::cos(yaw), 0.0f, -std::sin(yaw)};
  const glm::vec3 z{std::sin(yaw), 0.0f, std::cos(yaw)};
  addBox(m, centre, half.x * x, glm::vec3(0.0f, half.y, 0.0f), half.z * z);
}

void addCylinder(Mesh& m, const glm::vec3& base, const glm::vec3& top, float radius, int segments) {
  const glm::vec3 axis = glm::normalize(top - base);
  glm::vec3 e1, e2;
  frameAround(axis, e1, e2);
  const auto radial = [&](int i) {
    const float angle = kTwoPi * float(i % segments) / float(segments);
    return std::cos(angle) * e1 + std::sin(angle) * e2;
  };
  // Sides: a bottom/top vertex pair per segment boundary, smooth radial normals.
  const std::uint32_t side = std::uint32_t(m.positions.size());
  for (int i = 0; i <= segments; ++i) {
    const glm::vec3 r = radial(i);
    addVertex(m, base + radius * r, r);
    addVertex(m, top + radius * r, r);
  }
  for (int i = 0; i < segments; ++i) {
    const std::uint32_t b0 = side + 2 * i, t0 = b0 + 1, b1 = b0 + 2, t1 = b0 + 3;
    addTriangle(m, b0, b1, t1);
    addTriangle(m, b0, t1, t0);
  }
  // Caps: fans around a centre vertex with their own flat normals.
  for (const bool isTop : {true, false}) {
    const glm::vec3 c = isTop ? top : base;
    const glm::vec3 n = isTop ? axis : -axis;
    const std::uint32_t centreIndex = addVertex(m, c, n);
    for (int i = 0; i <= segments; ++i) addVertex(m, c + radius * radial(i), n);
    for (int i = 0; i < segments; ++i) {
      const std::uint32_t r0 = centreIndex + 1 + i, r1 = r0 + 1;
      if (isTop) {
        addTriangle(m, centreIndex, r0, r1);
      } else {
        addTriangle(m, centreIndex, r1, r0);
      }
    }
  }
}

void addSphere(Mesh& m, const glm::vec3& centre, float radius, int segments, int rings) {
  const std::uint32_t north = addVertex(m, centre + glm::vec3(0.0f, radius, 0.0f), {0.0f, 1.0f, 0.0f});
  const std::uint32_t south = addVertex(m, centre - glm::vec3(0.0f, radius, 0.0f), {0.0f, -1.0f, 0.0f});
  // Latitude rows 1..rings-1, each with a duplicated seam vertex.
  const std::uint32_t first = std::uint32_t(m.positions.size());
  for (int j = 1; j < rings; ++j) {
    const float polar = std::numbers::pi_v<float> * float(j) / float(rings);
    for (int i = 0; i <= segments; ++i) {
      const float azimuth = kTwoPi * float(i % segments) / float(segments);
      const glm::vec3 n{std::sin(polar) * std::cos(azimuth), std::cos(polar), std::sin(polar) * std::sin(azimuth)};
      addVertex(m, centre + radius * n, n);
    }
  }
  const auto at = [&](int j, int i) { return first + std::uint32_t((j - 1) * (segments + 1) + i); };
  // Azimuth grows towards +z from +x, i.e. clockwise seen from above: (row j, i), (j, i+1),
  // (j+1, i+1) is counter-clockwise seen from outside.
  for (int i = 0; i < segments; ++i) {
    addTriangle(m, north, at(1, i + 1), at(1, i));
    addTriangle(m, at(rings - 1, i), at(rings - 1, i + 1), south);
  }
  for (int j = 1; j + 1 < rings; ++j) {
    for (int i = 0; i < segments; ++i) {
      addTriangle(m, at(j, i), at(j, i + 1), at(j + 1, i + 1));
      addTriangle(m, at(j, i), at(j + 1, i + 1), at(j + 1, i));
    }
  }
}

void addTorus(Mesh& m, const glm::vec3& centre, const glm::vec3& axis, float major, float minor,
              int majorSegments, int minorSegments) {
  const glm::vec3 a = glm::normalize(axis);
  glm::vec3 e1, e2;
  frameAround(a, e1, e2);
  const std::uint32_t first = std::uint32_t(m.positions.size());
  for (int i = 0; i <= majorSegments; ++i) {
    const float u = kTwoPi * float(i % majorSegments) / float(majorSegments);
    const glm::vec3 radial = std::cos(u) * e1 + std::sin(u) * e2;
    for (int j = 0; j <= minorSegments; ++j) {
      const float v = kTwoPi * float(j % minorSegments) / float(minorSegments);
      const glm::vec3 n = std::cos(v) * radial + std::sin(v) * a;
      addVertex(m, centre + major * radial + minor * n, n);
    }
  }
  const auto at = [&](int i, int j) { return first + std::uint32_t(i * (minorSegments + 1) + j); };
  // d/du x d/dv points outward for the (e1, e2, axis) frame.
  for (int i = 0; i < majorSegments; ++i) {
    for (int j = 0; j < minorSegments; ++j) {
      addTriangle(m, at(i, j), at(i + 1, j), at(i + 1, j + 1));
      addTriangle(m, at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
}

}  // namespace penumbra::mesh
