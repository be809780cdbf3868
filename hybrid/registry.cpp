#include "hybrid/registry.h"

#include <algorithm>

#include "hybrid/frame_context.h"
#include "raytrace/acceleration_structures.h"

namespace penumbra {

#define PENUMBRA_REGISTER(file) void register_##file(Registry&);
#include "registrations.inc"
#undef PENUMBRA_REGISTER

const Registry& registry() {
  static const Registry all = [] {
    Registry r;
#define PENUMBRA_REGISTER(file) register_##file(r);
#include "registrations.inc"
#undef PENUMBRA_REGISTER
    r.sortByName();
    return r;
  }();
  return all;
}

void Registry::sortByName() {
  const auto byName = [](const auto& a, const auto& b) { return a.first < b.first; };
  std::sort(methods_.begin(), methods_.end(), byName);
  std::sort(tracers_.begin(), tracers_.end(), byName);
}

void Registry::method(const std::string& name, MethodFactory make) { methods_.emplace_back(name, std::move(make)); }

void Registry::methodFamily(const std::string& prefix, Family make) {
  families_.emplace_back(prefix, std::move(make));
}

void Registry::tracer(const std::string& name, TracerEntry entry) { tracers_.emplace_back(name, std::move(entry)); }

std::uint32_t Method::samplesPerPixel(const RenderSettings& settings) const { return settings.spp; }

std::vector<std::string> methodNames() {
  std::vector<std::string> names;
  for (const auto& [name, factory] : registry().methods()) names.push_back(name);
  return names;
}

Term methodTerm(const std::string& name) { return makeMethod(name)->term(); }

std::unique_ptr<Method> makeMethod(const std::string& name) {
  for (const auto& [prefix, make] : registry().families()) {
    if (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0) return make(name.substr(prefix.size()));
  }
  for (const auto& [n, make] : registry().methods()) {
    if (n == name) return make();
  }
  std::string known;
  for (const std::string& n : methodNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown method '" + name + "'; available methods: " + known);
}

std::string resolveTracer(const gpu::Context& context, const std::string& name) {
  return name == "auto" ? defaultTracer(context) : name;
}

std::vector<std::string> tracerNames() {
  std::vector<std::string> names;
  for (const auto& [name, entry] : registry().tracers()) names.push_back(name);
  return names;
}

const TracerEntry& tracerEntry(const std::string& name) {
  for (const auto& [n, entry] : registry().tracers()) {
    if (n == name) return entry;
  }
  std::string known = "auto";
  for (const std::string& n : tracerNames()) known += ", " + n;
  throw InputError("unknown tracer '" + name + "'; use " + known);
}

}  // namespace penumbra
