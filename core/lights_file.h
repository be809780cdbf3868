// Lights as JSON: a lights file (--lights FILE) and a view file's "lights" (core/view.h). A light is
// an object; every field but "light" is optional:
//   {"light": "spot:0,4,0:0,0,0:60",  the spec (core/view.h), in world coordinates
//    "size": 0.5,                     world units: a rect's side, a disk's diameter (default 0)
//    "color": [1, 0.9, 0.8],          linear RGB (default white)
//    "intensity": 2,                  the colour's scale (default 1)
//    "range": 7,                      distance at which its light ends; 0: none (default)
//    "inverse_square": true,          falls off by the inverse square of the distance (default false)
//    "inner_angle": 30}               spot: full cone of full strength, fading to the spec's angle
// A lights file holds an array of them, or an object whose "lights" holds it (a view file).
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "core/scene.h"

namespace penumbra {

// lightFromJson(lightToJson(l, o), o) == l (to 6 digits); fields at their defaults are left out.
nlohmann::ordered_json lightToJson(const Light& light, const glm::dvec3& origin = glm::dvec3(0.0));
// InputError naming the bad field and what it must be.
Light lightFromJson(const nlohmann::json& json, const glm::dvec3& origin = glm::dvec3(0.0));
// The lights of a JSON array of light objects; InputError naming `where` (e.g. "lights file 'x'"),
// the light's index and the field.
std::vector<Light> lightsFromJson(const nlohmann::json& lights, const std::string& where,
                                  const glm::dvec3& origin = glm::dvec3(0.0));
// --lights FILE: InputError naming the file when it is missing, unreadable, not JSON or holds no light.
std::vector<Light> readLightsFile(const std::string& path, const glm::dvec3& origin = glm::dvec3(0.0));

}  // namespace penumbra
