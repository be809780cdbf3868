#include "core/lights_file.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "core/view.h"

namespace penumbra {

namespace {

constexpr const char* kFields = "light, size, color, intensity, range, inverse_square and inner_angle";

float number(const nlohmann::json& json, const char* field, float low, const char* what) {
  const nlohmann::json& v = json.at(field);
  if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < low || !std::isfinite(v.get<float>())) {
    throw InputError(std::string("field \"") + field + "\" must be " + what + ", got " + v.dump());
  }
  return v.get<float>();
}

}  // namespace

nlohmann::ordered_json lightToJson(const Light& light, const glm::dvec3& origin) {
  nlohmann::ordered_json json;  // the spec first, as people read it
  json["light"] = formatLight(light, origin);
  const Light defaults;
  if (light.size != 0.0f) json["size"] = shortestDouble(light.size);
  if (light.color != defaults.color)
    json["color"] = {shortestDouble(light.color.r), shortestDouble(light.color.g), shortestDouble(light.color.b)};
  if (light.intensity != defaults.intensity) json["intensity"] = shortestDouble(light.intensity);
  if (light.range != 0.0f) json["range"] = shortestDouble(light.range);
  if (light.inverseSquare) json["inverse_square"] = true;
  if (light.type == LightType::Spot && light.innerAngleDeg >= 0.0f)
    json["inner_angle"] = shortestDouble(light.innerAngleDeg);
  return json;
}

Light lightFromJson(const nlohmann::json& json, const glm::dvec3& origin) {
  if (!json.is_object())
    throw InputError("a light must be a JSON object like {\"light\": \"point:0,4,0\"}, got " + json.dump());
  for (const auto& [key, value] : json.items()) {
    if (key != "light" && key != "size" && key != "color" && key != "intensity" && key != "range" &&
        key != "inverse_square" && key != "inner_angle") {
      throw InputError("unknown field \"" + key + "\"; a light's fields are " + kFields);
    }
  }
  if (!json.contains("light") || !json.at("light").is_string()) {
    throw InputError("field \"light\" must be a spec string like \"point:0,4,0\"");
  }
  Light light = parseLight(json.at("light").get<std::string>(), origin);
  if (json.contains("size")) {
    light.size = number(json, "size", 0.0f, "a size >= 0 in world units");
    if (light.size > 0.0f && light.type != LightType::Rect && light.type != LightType::Disk) {
      throw InputError("field \"size\" needs an area light (rect or disk), but the light is '" +
                       std::string(lightTypeName(light.type)) + "'");
    }
  }
  if (json.contains("color")) {
    const nlohmann::json& c = json.at("color");
    const auto channel = [](const nlohmann::json& v) {
      return v.is_number() && std::isfinite(v.get<double>()) && v.get<double>() >= 0.0;
    };
    if (!c.is_array() || c.size() != 3 || !channel(c[0]) || !channel(c[1]) || !channel(c[2])) {
      throw InputError("field \"color\" must be [r, g, b] with finite numbers >= 0, got " + c.dump());
    }
    light.color = {c[0].get<float>(), c[1].get<float>(), c[2].get<float>()};
  }
  if (json.contains("intensity")) light.intensity = number(json, "intensity", 0.0f, "a finite number >= 0");
  if (json.contains("range")) light.range = number(json, "range", 0.0f, "a distance >= 0 (0: no range)");
  if (json.contains("inverse_square")) {
    if (!json.at("inverse_square").is_boolean()) throw InputError("field \"inverse_square\" must be true or false");
    light.inverseSquare = json.at("inverse_square").get<bool>();
  }
  if (json.contains("inner_angle")) {
    if (light.type != LightType::Spot) throw InputError("field \"inner_angle\" applies to spot lights only");
    light.innerAngleDeg = number(json, "inner_angle", 0.0f, "a full cone angle in degrees >= 0");
    if (light.innerAngleDeg > light.spotAngleDeg) {
      throw InputError("field \"inner_angle\" (" + json.at("inner_angle").dump() +
                       ") must not exceed the spot's cone angle in its spec");
    }
  }
  return light;
}

std::vector<Light> lightsFromJson(const nlohmann::json& lights, const std::string& where, const glm::dvec3& origin) {
  if (!lights.is_array() || lights.empty()) {
    throw InputError(where + ": \"lights\" must be a non-empty array of light objects (fields: " + kFields + ")");
  }
  std::vector<Light> out;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    try {
      out.push_back(lightFromJson(lights[i], origin));
    } catch (const InputError& e) {
      throw InputError(where + ", light " + std::to_string(i) + ": " + e.what());
    }
  }
  return out;
}

std::vector<Light> readLightsFile(const std::string& path, const glm::dvec3& origin) {
  const std::string file = "lights file '" + path + "'";
  const nlohmann::json json =
      readJsonFile(path, file, "[{\"light\": \"point:0,4,0\", \"range\": 7}, ...] or {\"lights\": [...]}");
  if (json.is_object() && !json.contains("lights")) {
    throw InputError(file + " holds an object without \"lights\"; give an array of light objects");
  }
  return lightsFromJson(json.is_object() ? json.at("lights") : json, file, origin);
}

}  // namespace penumbra
