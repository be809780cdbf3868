// Procedural scenes selectable as "builtin:NAME" or "builtin:NAME:LEVEL" (LEVEL = tessellation).
// Each comes with its default camera and light.
#pragma once
#include <string>
#include <vector>

#include "core/scene.h"

namespace penumbra {

// courtyard: ground, boxes, columns, a sphere, a torus, a fence of thin bars, thin wires;
//            LEVEL scales curved surfaces and the ground grid (level 8 ~ tens of thousands of
//            triangles; the README lists levels reaching >= 1M).
// wires:     a directional light above a grid of wires thinner than a shadow-map texel over a
//            ground plane (the failure case of shadow maps).
// square:    a square occluder above a plane under a directional light (a known analytic answer).
// room:      a closed box room with a point light inside and a few casters (cube shadow maps).
Scene makeBuiltinScene(const std::string& nameAndLevel);
std::vector<std::string> builtinSceneNames();

}  // namespace penumbra
