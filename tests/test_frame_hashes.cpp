// Frames that must not change under a refactor: a fixed set of scenes x methods x tracers, each
// frame's outputs (visibility, coverage, PIP flags, sm answer, shaded image) and machine-independent
// counts (rays, traversal steps) hashed and compared with tests/frame_hashes.txt. The file was
// recorded once on the device it names; on another device (another driver, CPU or GPU, whose float
// results may round differently) the comparison is skipped and says so.
// Record anew only for a change meant to alter frames:
//   PENUMBRA_RECORD_FRAME_HASHES=1 build/bin/frame_hash_tests
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render_fixture.h"

namespace penumbra::test {
namespace {

const std::string kFile = std::string(PENUMBRA_SOURCE_DIR) + "/tests/frame_hashes.txt";

struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    for (std::size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  }
  template <typename T>
  void add(const std::vector<T>& v) {
    add(v.data(), v.size() * sizeof(T));
  }
  void add(std::uint64_t v) { add(&v, sizeof v); }
};

std::string hashOf(const Frame& frame) {
  Fnv f;
  f.add(frame.visibility);
  f.add(frame.covered);
  f.add(frame.rgba);
  f.add(frame.pip);
  f.add(frame.shadowMapVisibility);
  f.add(frame.stats.raysTraced.value_or(0));
  f.add(frame.stats.pipPixels.value_or(0));
  f.add(frame.stats.nodeVisits.value_or(0));
  f.add(frame.stats.triangleTests.value_or(0));
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(f.h));
  return text;
}

struct Case {
  std::string scene;
  float lightSize;  // 0: the scene's light as it is (hard shadows)
  std::vector<std::string> methods;
  std::string tracer;
};

std::vector<Case> cases() {
  const std::vector<std::string> shadow{"sm", "pcf", "pcss", "msm", "srt", "frt", "ref", "ls"};
  std::vector<std::string> soft = shadow;
  soft.push_back("bitmask");
  return {
      {"builtin:courtyard", 0.0f, shadow, "bvh"},
      {"builtin:courtyard", 0.1f, soft, "bvh"},
      {"builtin:wires", 0.0f, {"sm", "srt", "frt"}, "bvh"},
      {"builtin:room", 0.0f, {"sm", "srt", "frt"}, "bvh"},          // a point light's cube map
      {"builtin:room", 0.05f, {"srt", "frt"}, "bvh"},
      {"builtin:foliage", 0.0f, {"srt", "frt"}, "bvh"},
      {"builtin:courtyard", 0.0f, {"srt", "frt"}, "rq"},
      {"builtin:courtyard", 0.1f, {"srt", "frt"}, "rq"},
      {"builtin:courtyard", 0.0f, {"srt"}, "embree"},
      {"builtin:courtyard", 0.0f, {"srt"}, "ls"},
      {"builtin:courtyard", 0.0f, {"ao", "indirect"}, "bvh"},
  };
}

std::string deviceKey() {
  const gpu::Context& context = validatedContext();
  return context.deviceName() + " | " + context.driverInfo();
}

// key "scene light tracer method" -> hash
std::map<std::string, std::string> renderAll() {
  std::map<std::string, std::string> hashes;
  for (const Case& c : cases()) {
    if (c.tracer == "rq" && !validatedContext().rayQuery()) continue;
    RenderSettings settings = smallSettings(128, 1024);
    settings.tracer = c.tracer;
    settings.spp = 8;
    SceneRun run(c.scene, settings);
    if (c.lightSize > 0.0f) run.light.size = c.lightSize * run.scene.bounds().radius();
    for (const std::string& method : c.methods) {
      std::ostringstream key;
      key << c.scene << " " << c.lightSize << " " << c.tracer << " " << method;
      hashes[key.str()] = hashOf(run.render(method));
    }
  }
  return hashes;
}

TEST(FrameHashes, EveryFrameIsTheRecordedOne) {
  const std::map<std::string, std::string> hashes = renderAll();
  expectValidationSilent();
  if (std::getenv("PENUMBRA_RECORD_FRAME_HASHES")) {
    std::ofstream out(kFile);
    out << "device " << deviceKey() << "\n";
    for (const auto& [key, hash] : hashes) out << hash << " " << key << "\n";
    GTEST_SKIP() << "recorded " << hashes.size() << " frames in " << kFile;
  }
  std::ifstream in(kFile);
  ASSERT_TRUE(in) << kFile << " is missing";
  std::string line;
  std::getline(in, line);
  const std::string recordedDevice = line.substr(std::strlen("device "));
  if (recordedDevice != deviceKey()) {
    GTEST_SKIP() << "frames were recorded on '" << recordedDevice << "', this is '" << deviceKey() << "'";
  }
  std::map<std::string, std::string> recorded;
  while (std::getline(in, line)) {
    if (line.size() > 17) recorded[line.substr(17)] = line.substr(0, 16);
  }
  EXPECT_EQ(recorded.size(), hashes.size()) << "the recorded set and the rendered set differ";
  for (const auto& [key, hash] : hashes) {
    const auto it = recorded.find(key);
    ASSERT_NE(it, recorded.end()) << "no recorded frame for " << key;
    EXPECT_EQ(it->second, hash) << "the frame of " << key << " changed";
  }
}

}  // namespace
}  // namespace penumbra::test
