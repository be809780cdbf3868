// Every triangle of the scene by its scene-order index (meshes in order, triangles in order within
// each; BvhTriangle.id and the N-tree's leaf lists use the same index), as the kernels that shade
// a hit read it: vertices for a plane, vertex normals to interpolate (or extrapolate, for the
// candidate line space), and the mesh's base colour. Built by raytrace/scene_triangles.
#ifndef PENUMBRA_SHARED_SCENE_TRIANGLES_H
#define PENUMBRA_SHARED_SCENE_TRIANGLES_H
#include "shared/glsl_cpp.h"
PN_BEGIN

// std430, 64 bytes. Normals: octahedral (octahedralEncode in shared/gbuffer.h) in two snorm16,
// packSnorm2x16 order (x in the low half).
struct SceneTriangle {
  vec3 v0;
  uint normal0;
  vec3 v1;
  uint normal1;
  vec3 v2;
  uint normal2;
  uint mesh;    // index into Scene::meshes
  uint albedo;  // the mesh's base colour, packUnorm4x8 (alpha 1)
  uint pad0, pad1;
};

PN_END
#endif
