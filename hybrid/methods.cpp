// The method registry: names to factories, nothing else.
#include <map>

#include "core/scene.h"
#include "hybrid/method.h"
#include "hybrid/renderer.h"

namespace penumbra {
namespace {

const std::map<std::string, std::function<std::unique_ptr<Method>()>>& registry() {
  static const std::map<std::string, std::function<std::unique_ptr<Method>()>> methods{
      {"sm", [] { return makeShadowMapMethod(ShadowMapFilter::None); }},
      {"pcf", [] { return makeShadowMapMethod(ShadowMapFilter::Pcf); }},
      {"pcss", [] { return makeShadowMapMethod(ShadowMapFilter::Pcss); }},
      {"msm", [] { return makeMultiMapMethod(); }},
      {"ref", [] { return makeReferenceMethod(); }},
      {"srt", [] { return makeTracedMethod(true); }},
      {"frt", [] { return makeTracedMethod(false); }},
      {"ls", [] { return makeTracedMethod(false, "ls"); }},  // frt on the line-space tracer
      {"bitmask", [] { return makeBitmaskMethod(); }},
      {"ao", [] { return makeIndirectMethod(Term::Ao); }},
      {"indirect", [] { return makeIndirectMethod(Term::Indirect); }},
  };
  return methods;
}

}  // namespace

std::uint32_t Method::samplesPerPixel(const RenderSettings& settings) const { return settings.spp; }

std::vector<std::string> methodNames() {
  std::vector<std::string> names;
  for (const auto& [name, factory] : registry()) names.push_back(name);
  return names;
}

Term methodTerm(const std::string& name) { return makeMethod(name)->term(); }

std::unique_ptr<Method> makeMethod(const std::string& name) {
  // ao-<tracer>, indirect-<tracer>: the method on that tracer
  for (const auto& [prefix, term] : {std::pair{"ao-", Term::Ao}, std::pair{"indirect-", Term::Indirect}}) {
    const std::string p = prefix;
    if (name.size() > p.size() && name.compare(0, p.size(), p) == 0) return makeIndirectMethod(term, name.substr(p.size()));
  }
  const auto it = registry().find(name);
  if (it == registry().end()) {
    std::string known;
    for (const std::string& n : methodNames()) known += (known.empty() ? "" : ", ") + n;
    throw InputError("unknown method '" + name + "'; available methods: " + known);
  }
  return it->second();
}

}  // namespace penumbra
