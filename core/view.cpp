#include "core/view.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/lights_file.h"

namespace penumbra {

namespace {

constexpr const char* kCameraSyntax = "expected ex,ey,ez:tx,ty,tz[:fovy] (eye, target, vertical fov in degrees "
                                      "strictly between 0 and 180), e.g. 0,3,8:0,0,0:45";
constexpr const char* kLightSyntax =
    "expected dir:dx,dy,dz | point:x,y,z | spot:x,y,z:tx,ty,tz[:angle] | rect:x,y,z:tx,ty,tz | "
    "disk:x,y,z:tx,ty,tz (angle = full cone in degrees strictly between 0 and 180), e.g. disk:5,10,5:0,0,0";

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  for (;;) {
    const std::size_t at = s.find(sep);
    parts.push_back(s.substr(0, at));
    if (at == std::string_view::npos) return parts;
    s.remove_prefix(at + 1);
  }
}

// Thrown inside this file and re-thrown as InputError with the whole spec and its syntax.
struct SpecProblem {
  std::string what;
};

double parseNumber(std::string_view text, const char* what) {
  std::string_view t = trim(text);
  if (t.size() > 1 && t.front() == '+' && t[1] != '-') t.remove_prefix(1);
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (t.empty() || ec == std::errc::invalid_argument || ptr != t.data() + t.size()) {
    throw SpecProblem{"'" + std::string(text) + "' in the " + what + " is not a number"};
  }
  if (ec == std::errc::result_out_of_range || !std::isfinite(value) || !std::isfinite(float(value))) {
    throw SpecProblem{"'" + std::string(text) + "' in the " + what + " is not a finite float"};
  }
  return value;
}

// A world point read in double and stored relative to the scene's origin.
glm::dvec3 parseVec3(std::string_view text, const char* what) {
  const std::vector<std::string_view> parts = split(text, ',');
  if (parts.size() != 3) {
    throw SpecProblem{std::string("the ") + what + " needs 3 comma-separated numbers, got " +
                      std::to_string(parts.size()) + " ('" + std::string(text) + "')"};
  }
  return {parseNumber(parts[0], what), parseNumber(parts[1], what), parseNumber(parts[2], what)};
}

// Relative to the scene's origin; refuses what float cannot hold.
glm::vec3 toScene(const glm::dvec3& world, const glm::dvec3& origin, const char* what) {
  const glm::vec3 local(world - origin);
  if (!std::isfinite(local.x) || !std::isfinite(local.y) || !std::isfinite(local.z)) {
    throw SpecProblem{std::string("the ") + what + " is too far from the scene for float coordinates"};
  }
  return local;
}

// Unit direction from `from` to `to`; refuses coincident points.
glm::vec3 directionBetween(const glm::vec3& from, const glm::vec3& to, const char* what) {
  const glm::vec3 d = to - from;
  const float length = glm::length(d);
  if (!(length > 0.0f)) throw SpecProblem{std::string(what)};
  if (!std::isfinite(length)) throw SpecProblem{"the direction overflows float; use smaller coordinates"};
  return d / length;
}

float parseAngle(std::string_view text, const char* what) {
  const float angle = float(parseNumber(text, what));
  if (!(angle > 0.0f && angle < 180.0f)) {
    throw SpecProblem{std::string("the ") + what + " " + std::string(trim(text)) +
                      " is outside (0, 180) degrees"};
  }
  return angle;
}

// Shortest text that reads back as the same float.
std::string formatNumber(float v) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  return std::string(buffer, result.ptr);
}

// A coordinate in world units: the shortest text that reads back as the same float relative to
// the scene's origin.
std::string formatCoordinate(float local, double origin) {
  if (origin == 0.0) return formatNumber(local);
  char buffer[400];  // fixed notation of any double
  for (int decimals = 0;; ++decimals) {
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, double(local) + origin, std::chars_format::fixed, decimals);
    double world = 0.0;
    std::from_chars(buffer, result.ptr, world);
    if (float(world - origin) == local || decimals == 60) return std::string(buffer, result.ptr);
  }
}

std::string formatVec3(const glm::vec3& v, const glm::dvec3& origin = glm::dvec3(0.0)) {
  return formatCoordinate(v.x, origin.x) + "," + formatCoordinate(v.y, origin.y) + "," + formatCoordinate(v.z, origin.z);
}

// lookAt degenerates when the view is parallel to +y; straight-down or -up views use -z / +z as up.
glm::vec3 upFor(const glm::vec3& forward) {
  if (std::abs(forward.y) < 0.999f) return {0.0f, 1.0f, 0.0f};
  return {0.0f, 0.0f, forward.y < 0.0f ? -1.0f : 1.0f};
}

// Bounds of real scenes; an empty or collapsed box gets a unit sphere at its centre so the
// defaults stay finite.
void sphereOf(const Bounds& bounds, glm::vec3& centre, float& radius) {
  centre = bounds.empty() ? glm::vec3(0.0f) : bounds.center();
  radius = bounds.empty() ? 0.0f : bounds.radius();
  if (!std::isfinite(radius) || !(radius > 0.0f)) radius = 1.0f;
  if (!std::isfinite(centre.x) || !std::isfinite(centre.y) || !std::isfinite(centre.z)) centre = glm::vec3(0.0f);
}

bool hasExtent(LightType type) { return type == LightType::Rect || type == LightType::Disk; }

// The light-size rules shared by applyLightSize and view files; empty when `fraction` is usable.
std::string lightSizeProblem(const Light& light, float fraction) {
  if (!std::isfinite(fraction) || fraction < 0.0f) {
    return "light size " + formatNumber(fraction) +
           " is not a finite non-negative fraction of the scene radius; give e.g. 0.05";
  }
  if (fraction > 0.0f && !hasExtent(light.type)) {
    return "light size " + formatNumber(fraction) + " needs an area light, but the light is '" +
           lightTypeName(light.type) + "'; use a rect:x,y,z:tx,ty,tz or disk:x,y,z:tx,ty,tz light, or light size 0";
  }
  return {};
}

}  // namespace

double shortestDouble(float v) {
  const std::string text = formatNumber(v);
  double out = 0.0;
  std::from_chars(text.data(), text.data() + text.size(), out);
  return out;
}

Camera parseCamera(const std::string& spec, const glm::dvec3& origin) {
  try {
    const std::vector<std::string_view> parts = split(spec, ':');
    if (parts.size() != 2 && parts.size() != 3) {
      throw SpecProblem{"needs 2 or 3 ':'-separated parts, got " + std::to_string(parts.size())};
    }
    Camera camera;
    camera.eye = toScene(parseVec3(parts[0], "eye"), origin, "eye");
    camera.target = toScene(parseVec3(parts[1], "target"), origin, "target");
    const glm::vec3 forward = directionBetween(camera.eye, camera.target, "eye and target coincide");
    camera.up = upFor(forward);
    if (parts.size() == 3) camera.fovYDeg = parseAngle(parts[2], "fovy");
    return camera;
  } catch (const SpecProblem& problem) {
    throw InputError("camera '" + spec + "': " + problem.what + "; " + kCameraSyntax);
  }
}

Patch parsePatch(const std::string& spec, const glm::dvec3& origin) {
  try {
    const std::vector<std::string_view> parts = split(spec, ':');
    if (parts.size() != 3) throw SpecProblem{"needs 3 ':'-separated parts, got " + std::to_string(parts.size())};
    Patch patch;
    patch.corner = toScene(parseVec3(parts[0], "corner"), origin, "corner");
    patch.u = glm::vec3(parseVec3(parts[1], "first edge"));
    patch.v = glm::vec3(parseVec3(parts[2], "second edge"));
    const float lu = glm::length(patch.u), lv = glm::length(patch.v);
    if (!(lu > 0.0f && lv > 0.0f)) throw SpecProblem{"an edge has zero length"};
    if (std::abs(glm::dot(patch.u, patch.v)) > 1e-3f * lu * lv) throw SpecProblem{"the edges are not perpendicular"};
    return patch;
  } catch (const SpecProblem& problem) {
    throw InputError("patch '" + spec + "': " + problem.what + "; use 'x,y,z:ux,uy,uz:vx,vy,vz' (a corner and two perpendicular edges)");
  }
}

std::string formatCamera(const Camera& camera, const glm::dvec3& origin) {
  return formatVec3(camera.eye, origin) + ":" + formatVec3(camera.target, origin) + ":" + formatNumber(camera.fovYDeg);
}

Light parseLight(const std::string& spec, const glm::dvec3& origin) {
  try {
    const std::vector<std::string_view> parts = split(spec, ':');
    const std::string_view type = trim(parts[0]);
    Light light;
    const auto expectParts = [&](std::size_t lo, std::size_t hi) {
      if (parts.size() < lo || parts.size() > hi) {
        throw SpecProblem{"a '" + std::string(type) + "' light needs " +
                          (lo == hi ? std::to_string(lo) : std::to_string(lo) + " or " + std::to_string(hi)) +
                          " ':'-separated parts, got " + std::to_string(parts.size())};
      }
    };
    if (type == "dir") {
      expectParts(2, 2);
      light.type = LightType::Directional;
      light.direction = directionBetween(glm::vec3(0.0f), glm::vec3(parseVec3(parts[1], "direction")),
                                         "the direction has zero length");
    } else if (type == "point") {
      expectParts(2, 2);
      light.type = LightType::Point;
      light.position = toScene(parseVec3(parts[1], "position"), origin, "position");
    } else if (type == "spot" || type == "rect" || type == "disk") {
      light.type = type == "spot" ? LightType::Spot : type == "rect" ? LightType::Rect : LightType::Disk;
      expectParts(3, light.type == LightType::Spot ? 4 : 3);
      light.position = toScene(parseVec3(parts[1], "position"), origin, "position");
      light.direction = directionBetween(light.position, toScene(parseVec3(parts[2], "target"), origin, "target"),
                                         "position and target coincide, so the light has no direction");
      if (parts.size() == 4) light.spotAngleDeg = parseAngle(parts[3], "spot angle");
    } else {
      throw SpecProblem{"unknown light type '" + std::string(type) + "'"};
    }
    return light;
  } catch (const SpecProblem& problem) {
    throw InputError("light '" + spec + "': " + problem.what + "; " + kLightSyntax);
  }
}

std::string formatLight(const Light& light, const glm::dvec3& origin) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on chained operator+ here.
  std::string text = lightTypeName(light.type);
  text += ':';
  switch (light.type) {
    case LightType::Directional: text += formatVec3(light.direction); break;
    case LightType::Point: text += formatVec3(light.position, origin); break;
    case LightType::Spot:
    case LightType::Rect:
    case LightType::Disk: {
      // A target as far out as the position is large keeps the direction's digits after rounding.
      const float reach = std::max(1.0f, glm::length(light.position));
      const glm::vec3 target = light.position + reach * glm::normalize(light.direction);
      text += formatVec3(light.position, origin);
      text += ':';
      text += formatVec3(target, origin);
      if (light.type == LightType::Spot) {
        text += ':';
        text += formatNumber(light.spotAngleDeg);
      }
      break;
    }
  }
  return text;
}

Camera defaultCamera(const Bounds& bounds) {
  glm::vec3 centre;
  float radius;
  sphereOf(bounds, centre, radius);
  Camera camera;
  camera.fovYDeg = 45.0f;
  // The bounding sphere just fits the vertical fov at this distance (5% margin); ~28 degrees up.
  const float distance = 1.05f * radius / std::sin(glm::radians(0.5f * camera.fovYDeg));
  camera.target = centre;
  camera.eye = centre + distance * glm::normalize(glm::vec3(0.7f, 0.65f, 1.0f));
  camera.up = upFor(glm::normalize(camera.target - camera.eye));
  return camera;
}

Light defaultLight(const Bounds& bounds) {
  glm::vec3 centre;
  float radius;
  sphereOf(bounds, centre, radius);
  Light light;
  light.type = LightType::Disk;
  light.size = 0.0f;
  light.position = centre + 2.5f * radius * glm::normalize(glm::vec3(-0.5f, 1.0f, 0.3f));
  light.direction = glm::normalize(centre - light.position);
  return light;
}

Light orbitLight(const Light& light, const Bounds& bounds, float degrees) {
  const glm::vec3 centre = bounds.center();
  const float a = glm::radians(degrees), c = std::cos(a), s = std::sin(a);
  const auto turn = [&](const glm::vec3& v) { return glm::vec3(c * v.x + s * v.z, v.y, -s * v.x + c * v.z); };
  Light out = light;
  out.position = centre + turn(light.position - centre);
  out.direction = glm::normalize(turn(light.direction));
  return out;
}

void applyLightSize(Light& light, float fractionOfRadius, const Bounds& bounds) {
  const std::string problem = lightSizeProblem(light, fractionOfRadius);
  if (!problem.empty()) throw InputError("--light-size: " + problem);
  glm::vec3 centre;
  float radius;
  sphereOf(bounds, centre, radius);
  light.size = fractionOfRadius * radius;
}

nlohmann::json readJsonFile(const std::string& path, const std::string& file, const std::string& expected) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(file + " does not exist or is not a regular file; check the path");
  }
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) throw InputError(file + " cannot be read; check its permissions");
  try {
    return nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file + " is not valid JSON (" + e.what() + "); expected " + expected);
  }
}

View readViewFile(const std::string& path, const glm::dvec3& origin) {
  const std::string file = "view file '" + path + "'";
  const nlohmann::json json = readJsonFile(
      path, file, "{\"camera\": \"...\", \"light\": \"...\", \"light_size\": 0, \"resolution\": [256, 256]}");
  if (!json.is_object()) throw InputError(file + " must hold a JSON object with camera, light and resolution");
  for (const auto& [key, value] : json.items()) {
    if (key != "camera" && key != "light" && key != "light_size" && key != "lights" && key != "resolution" &&
        key != "time") {
      throw InputError(file + " has the unknown field \"" + key +
                       "\"; the fields are camera, light, light_size, lights, resolution and time");
    }
  }
  const auto field = [&](const char* name) -> const nlohmann::json& {
    if (!json.contains(name)) throw InputError(file + " lacks the field \"" + name + "\"");
    return json.at(name);
  };
  const auto fieldError = [&](const char* name, const std::string& why) {
    return InputError(file + ", field \"" + name + "\": " + why);
  };

  View view;
  const nlohmann::json& camera = field("camera");
  if (!camera.is_string()) throw fieldError("camera", "must be a string like \"0,3,8:0,0,0:45\"");
  try {
    view.camera = parseCamera(camera.get<std::string>(), origin);
  } catch (const InputError& e) {
    throw fieldError("camera", e.what());
  }
  const nlohmann::json& light = field("light");
  if (!light.is_string()) throw fieldError("light", "must be a string like \"disk:5,10,5:0,0,0\"");
  try {
    view.light = parseLight(light.get<std::string>(), origin);
  } catch (const InputError& e) {
    throw fieldError("light", e.what());
  }
  if (json.contains("light_size")) {
    const nlohmann::json& size = json.at("light_size");
    if (!size.is_number()) throw fieldError("light_size", "must be a number (fraction of the scene radius)");
    view.lightSizeFraction = size.get<float>();
    const std::string problem = lightSizeProblem(view.light, view.lightSizeFraction);
    if (!problem.empty()) throw fieldError("light_size", problem);
  }
  if (json.contains("lights")) view.lights = lightsFromJson(json.at("lights"), file, origin);
  const nlohmann::json& resolution = field("resolution");
  const auto inRange = [](const nlohmann::json& v) {
    return v.is_number_integer() && v.get<std::int64_t>() >= 1 && v.get<std::int64_t>() <= 16384;
  };
  if (!resolution.is_array() || resolution.size() != 2 || !inRange(resolution[0]) || !inRange(resolution[1])) {
    throw fieldError("resolution", "must be [width, height] with integers in 1..16384, got " + resolution.dump());
  }
  view.width = resolution[0].get<int>();
  view.height = resolution[1].get<int>();
  if (json.contains("time")) {
    const nlohmann::json& time = json.at("time");
    if (!time.is_number() || !std::isfinite(time.get<double>()) || time.get<double>() < 0.0) {
      throw fieldError("time", "must be a number of seconds >= 0, got " + time.dump());
    }
    view.time = time.get<double>();
  }
  return view;
}

void writeViewFile(const std::string& path, const View& view, const glm::dvec3& origin) {
  const std::string file = "view file '" + path + "'";
  if (view.width < 1 || view.width > 16384 || view.height < 1 || view.height > 16384) {
    throw InputError(file + ": resolution " + std::to_string(view.width) + "x" + std::to_string(view.height) +
                     " is outside 1..16384; give a resolution in range");
  }
  const std::string problem = lightSizeProblem(view.light, view.lightSizeFraction);
  if (!problem.empty()) throw InputError(file + ": " + problem);
  nlohmann::ordered_json json;
  json["camera"] = formatCamera(view.camera, origin);
  json["light"] = formatLight(view.light, origin);
  json["light_size"] = shortestDouble(view.lightSizeFraction);
  if (!view.lights.empty()) {
    json["lights"] = nlohmann::ordered_json::array();
    for (const Light& light : view.lights) json["lights"].push_back(lightToJson(light, origin));
  }
  json["resolution"] = {view.width, view.height};
  if (view.time != 0.0) json["time"] = view.time;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << json.dump(2) << "\n";
  out.close();
  if (!out) throw InputError(file + " cannot be written; check that its folder exists and is writable");
}

}  // namespace penumbra
