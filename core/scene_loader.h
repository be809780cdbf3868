// Loads a scene from a spec: "builtin:NAME[:LEVEL]", a .gltf/.glb file or an .obj file.
// The result is cleaned (cleanScene) and never empty; every failure is an InputError.
#pragma once
#include <string>

#include "core/scene.h"

namespace penumbra {

Scene loadScene(const std::string& spec);

// glTF 2.0 (.gltf, .glb) through tinygltf. External buffers and images are read only from the
// model's own folder: absolute URIs and URIs that climb out with ../ are refused.
// Node transforms are flattened into world space; the first camera and KHR_lights_punctual
// light found in the default scene are kept.
Scene loadGltf(const std::string& path);

// Wavefront OBJ through tinyobjloader (materials' diffuse colour as base colour).
Scene loadObj(const std::string& path);

// Every other format assimp reads (.ply, .stl, .off, .dae, .fbx, .3ds, ...): triangles with their
// node transforms and diffuse colours; lines and points dropped with a note; only the model's
// folder is read. assimpReads(".ext") says whether assimp takes the extension.
Scene loadAssimp(const std::string& path);
bool assimpReads(const std::string& extension);

// Why `reference` (a relative path or URI found inside a model file) would leave `folder`: empty
// when it stays inside, else the reason. Absolute references, ../ climbs and links that resolve
// outside are refused. Shared by the glTF and OBJ loaders.
std::string confinedPathProblem(const std::string& folder, const std::string& reference);

}  // namespace penumbra
