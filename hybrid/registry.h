// Methods and shadow tracers by name. Each method file (hybrid/*_method.cpp) and each tracer file
// (hybrid/tracers/*.cpp) registers what it provides in a function register_<file name>(Registry&);
// the build lists the files present (hybrid/CMakeLists.txt) and registry.cpp calls them all, so
// adding a method or a tracer is one new file and touches no central one.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/scene.h"
#include "gpu/context.h"
#include "hybrid/frame_stats.h"
#include "hybrid/method.h"
#include "raytrace/shadow_tracer.h"

namespace penumbra {

struct RenderSettings;

using MethodFactory = std::function<std::unique_ptr<Method>()>;

struct TracerEntry {
  std::string help;  // what it is, for --help: "GPU compute BVH"
  std::function<std::unique_ptr<ShadowTracer>(const gpu::Context&, const Scene&, const RenderSettings&)> make;
  // What every frame that traced on it reports: its one-time build, memory and notes.
  std::function<void(const ShadowTracer&, const RenderSettings&, FrameStats&)> report;
};

class Registry {
 public:
  using Family = std::function<std::unique_ptr<Method>(const std::string&)>;
  void method(const std::string& name, MethodFactory make);
  // Methods named prefix + anything: make gets the rest of the name (ao-<tracer>).
  void methodFamily(const std::string& prefix, Family make);
  void tracer(const std::string& name, TracerEntry entry);

  const std::vector<std::pair<std::string, MethodFactory>>& methods() const { return methods_; }
  const std::vector<std::pair<std::string, Family>>& families() const { return families_; }
  const std::vector<std::pair<std::string, TracerEntry>>& tracers() const { return tracers_; }

 private:
  friend const Registry& registry();
  void sortByName();
  std::vector<std::pair<std::string, MethodFactory>> methods_;
  std::vector<std::pair<std::string, Family>> families_;
  std::vector<std::pair<std::string, TracerEntry>> tracers_;
};

const Registry& registry();  // everything registered, sorted by name

// The tracer "auto" stands for on this device (defaultTracer: rq on a GPU with ray queries, else
// bvh); other names stay.
std::string resolveTracer(const gpu::Context& context, const std::string& name);
// The shadow tracers, sorted by name ("auto" is not one: resolveTracer maps it).
std::vector<std::string> tracerNames();
// InputError for an unknown name, listing the known ones.
const TracerEntry& tracerEntry(const std::string& name);

}  // namespace penumbra
