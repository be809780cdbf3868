// Poses the scene's animated meshes (Scene::animations, rigid keyframes) at a time. The renderer
// is told with Renderer::sceneMoved(), which re-uploads the raster geometry and refits the ray
// tracers' dynamic BVHs.
#pragma once
#include <glm/glm.hpp>

#include "core/scene.h"

namespace penumbra {

bool isAnimated(const Scene& scene);
double animationPeriod(const Scene& scene);  // seconds until every animation repeats (longest); 0 if static
// The animation's transform at `seconds` (looped over its period).
glm::mat4 poseAt(const MeshAnimation& animation, double seconds);
// Writes the pose at `seconds` into the animated meshes' positions and normals. Throws InputError
// for a non-finite time or an animation that names a missing mesh or does not match its rest pose.
void poseScene(Scene& scene, double seconds);
// Registers mesh `mesh` as animated with `keys` (its current positions become the rest pose) and
// marks it dynamic.
void animateMesh(Scene& scene, std::size_t mesh, std::vector<RigidKey> keys);

}  // namespace penumbra
