#include "core/gltf_animation.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/gltf_accessor.h"

namespace penumbra::gltf {
namespace {

glm::dquat quatXyzw(const double* q) { return glm::normalize(glm::dquat(q[3], q[0], q[1], q[2])); }

glm::dmat4 trs(const glm::dvec3& t, const glm::dquat& r, const glm::dvec3& s) {
  return glm::translate(glm::dmat4(1.0), t) * glm::mat4_cast(r) * glm::scale(glm::dmat4(1.0), s);
}

}  // namespace

glm::dmat4 localTransform(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    glm::dmat4 m;
    std::memcpy(glm::value_ptr(m), node.matrix.data(), sizeof(m));  // both column-major
    return m;
  }
  const glm::dvec3 t = node.translation.size() == 3 ? glm::make_vec3(node.translation.data()) : glm::dvec3(0.0);
  const glm::dquat r = node.rotation.size() == 4 ? quatXyzw(node.rotation.data()) : glm::dquat(1.0, 0.0, 0.0, 0.0);
  const glm::dvec3 s = node.scale.size() == 3 ? glm::make_vec3(node.scale.data()) : glm::dvec3(1.0);
  return trs(t, r, s);
}

NodeAnimations::NodeAnimations(const tinygltf::Model& model, const std::string& path, std::vector<std::string>& warnings) {
  if (model.animations.empty()) return;
  if (model.animations.size() > 1) {
    warnings.push_back("glTF has " + std::to_string(model.animations.size()) + " animations; the first ('" +
                       model.animations[0].name + "') is used");
  }
  const tinygltf::Animation& animation = model.animations[0];
  bool warnedCubic = false;
  for (const tinygltf::AnimationChannel& c : animation.channels) {
    const int path_ = c.target_path == "translation" ? 0 : c.target_path == "rotation" ? 1 : c.target_path == "scale" ? 2 : -1;
    if (path_ < 0) {
      warnings.push_back("glTF animation channel '" + c.target_path + "' (morph weights) is not supported; ignored");
      continue;
    }
    if (c.target_node < 0 || std::size_t(c.target_node) >= model.nodes.size() || c.sampler < 0 ||
        std::size_t(c.sampler) >= animation.samplers.size()) {
      fail(path, "an animation channel names a missing node or sampler", "the file is corrupt; re-export it");
    }
    if (model.nodes[std::size_t(c.target_node)].matrix.size() == 16) {
      fail(path, "node " + std::to_string(c.target_node) + " is animated but has a matrix",
           "animated nodes must use translation/rotation/scale (glTF 2.0 §5.25); re-export it");
    }
    const tinygltf::AnimationSampler& s = animation.samplers[std::size_t(c.sampler)];
    Channel channel;
    channel.node = c.target_node;
    channel.path = path_;
    channel.step = s.interpolation == "STEP";
    channel.times = readFloats(model, s.input, "animation input", path, Kind::Scalar);
    const std::size_t width = path_ == 1 ? 4 : 3;
    channel.values = readFloats(model, s.output, "animation output", path, path_ == 1 ? Kind::Vec4 : Kind::Vec3);
    for (std::size_t k = 0; k < channel.times.size(); ++k) {
      const float t = channel.times[k];
      if (!std::isfinite(t) || t < 0.0f || (k > 0 && !(t > channel.times[k - 1]))) {
        fail(path, "animation key times must be finite, >= 0 and increasing (sampler " + std::to_string(c.sampler) +
             ", key " + std::to_string(k) + ")", "re-export the animation");
      }
    }
    const std::size_t keys = channel.times.size();
    const bool cubic = s.interpolation == "CUBICSPLINE";
    if (keys == 0 || channel.values.size() != keys * width * (cubic ? 3 : 1) ||
        !std::all_of(channel.values.begin(), channel.values.end(), [](float v) { return std::isfinite(v); })) {
      fail(path, "animation sampler " + std::to_string(c.sampler) + " has " + std::to_string(keys) + " key times but " +
           std::to_string(channel.values.size() / width) + " finite output values", "re-export the animation");
    }
    if (cubic) {  // keep each key's value, drop its tangents
      std::vector<float> values;
      for (std::size_t k = 0; k < keys; ++k) {
        values.insert(values.end(), channel.values.begin() + std::ptrdiff_t((3 * k + 1) * width),
                      channel.values.begin() + std::ptrdiff_t((3 * k + 2) * width));
      }
      channel.values = std::move(values);
      if (!warnedCubic) warnings.push_back("glTF CUBICSPLINE animation is interpolated linearly between its keys");
      warnedCubic = true;
    }
    channels_.push_back(std::move(channel));
  }
}

bool NodeAnimations::animates(int node) const {
  return std::any_of(channels_.begin(), channels_.end(), [&](const Channel& c) { return c.node == node; });
}

glm::dvec4 NodeAnimations::sample(const Channel& c, double seconds) const {
  const std::size_t width = c.path == 1 ? 4 : 3;
  const auto value = [&](std::size_t k) {
    glm::dvec4 v(0.0);
    for (std::size_t i = 0; i < width; ++i) v[int(i)] = c.values[k * width + i];
    return v;
  };
  const std::size_t n = c.times.size();
  if (seconds <= c.times.front()) return value(0);
  if (seconds >= c.times.back()) return value(n - 1);
  std::size_t k = std::size_t(std::upper_bound(c.times.begin(), c.times.end(), float(seconds)) - c.times.begin()) - 1;
  if (c.step) return value(k);
  const double f = (seconds - c.times[k]) / (double(c.times[k + 1]) - c.times[k]);
  if (c.path != 1) return glm::mix(value(k), value(k + 1), f);
  const glm::dvec4 a = value(k), b = value(k + 1);
  const glm::dquat q = glm::slerp(glm::dquat(a.w, a.x, a.y, a.z), glm::dquat(b.w, b.x, b.y, b.z), f);
  return {q.x, q.y, q.z, q.w};
}

glm::dmat4 NodeAnimations::localAt(const tinygltf::Node& node, int index, double seconds) const {
  if (!animates(index)) return localTransform(node);
  glm::dvec3 t = node.translation.size() == 3 ? glm::make_vec3(node.translation.data()) : glm::dvec3(0.0);
  glm::dvec4 r = node.rotation.size() == 4 ? glm::make_vec4(node.rotation.data()) : glm::dvec4(0.0, 0.0, 0.0, 1.0);
  glm::dvec3 s = node.scale.size() == 3 ? glm::make_vec3(node.scale.data()) : glm::dvec3(1.0);
  for (const Channel& c : channels_) {
    if (c.node != index) continue;
    const glm::dvec4 v = sample(c, seconds);
    if (c.path == 0) t = glm::dvec3(v);
    else if (c.path == 1) r = v;
    else s = glm::dvec3(v);
  }
  const double rr[4] = {r.x, r.y, r.z, r.w};
  return trs(t, quatXyzw(rr), s);
}

std::vector<double> NodeAnimations::keyTimes(const std::vector<int>& nodes) const {
  std::vector<double> times;
  for (const Channel& c : channels_) {
    if (std::find(nodes.begin(), nodes.end(), c.node) != nodes.end()) times.insert(times.end(), c.times.begin(), c.times.end());
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  return times;
}

std::optional<std::vector<RigidKey>> rigidKeys(const tinygltf::Model& model, const NodeAnimations& animations,
                                               const std::vector<int>& chain, const glm::dvec3& origin,
                                               const std::string& meshName,
                                               std::vector<std::string>& warnings) {
  const std::vector<double> times = animations.keyTimes(chain);
  if (times.empty()) return std::nullopt;
  glm::dmat4 rest(1.0);
  for (int node : chain) rest = rest * localTransform(model.nodes[std::size_t(node)]);
  // A pose moves the mesh's world positions: world(t) * rest^-1. In scene coordinates it is
  // conjugated by the shift to the origin, so a mesh turning far from the world origin turns in place.
  const glm::dmat4 toScene = glm::translate(glm::dmat4(1.0), -origin);
  const glm::dmat4 toRest = glm::inverse(rest) * glm::translate(glm::dmat4(1.0), origin);
  std::vector<RigidKey> keys;
  for (double t : times) {
    glm::dmat4 world(1.0);
    for (int node : chain) world = world * animations.localAt(model.nodes[std::size_t(node)], node, t);
    const glm::dmat4 pose = toScene * world * toRest;
    const glm::dmat3 m(pose);
    const double shear = std::max({std::abs(glm::dot(m[0], m[1])), std::abs(glm::dot(m[1], m[2])), std::abs(glm::dot(m[0], m[2]))});
    const double stretch = std::max({std::abs(glm::length(m[0]) - 1.0), std::abs(glm::length(m[1]) - 1.0),
                                     std::abs(glm::length(m[2]) - 1.0)});
    if (shear > 1e-3 || stretch > 1e-3 || glm::determinant(m) <= 0.0) {
      warnings.push_back("glTF animation of mesh '" + meshName + "' scales or shears it at " + std::to_string(t) +
                         " s; only rigid motion is animated, so it stays static");
      return std::nullopt;
    }
    RigidKey key;
    key.time = float(t);
    key.translation = glm::vec3(pose[3]);
    key.rotation = glm::quat(glm::normalize(glm::quat_cast(m)));
    keys.push_back(key);
  }
  return keys;
}

}  // namespace penumbra::gltf
