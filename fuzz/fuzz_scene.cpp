// One libFuzzer harness for every way a scene enters (scripts/fuzz.sh): the input is written as a
// file with FUZZ_EXTENSION (.gltf, .glb, .obj) and loaded, or, with FUZZ_BUILTIN, taken as the
// text after "builtin:". The contract under test (core/scene_loader.h): a scene, or an InputError;
// anything else - another exception, a crash, a sanitizer report - is a finding.
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/scene.h"
#include "core/scene_loader.h"

namespace {

#ifdef FUZZ_BUILTIN
// Built-in levels above this build millions of triangles: valid, but too slow to fuzz.
constexpr int kMaxFuzzedLevel = 8;

bool cheapBuiltin(const std::string& spec) {
  const std::size_t colon = spec.rfind(':');
  if (colon == std::string::npos) return true;
  int level = 0;
  const char* begin = spec.data() + colon + 1;
  const auto [end, ec] = std::from_chars(begin, spec.data() + spec.size(), level);
  return ec != std::errc() || level <= kMaxFuzzedLevel;
}
#endif

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string spec;
#ifdef FUZZ_BUILTIN
  if (size > 64) return -1;
  spec = "builtin:" + std::string(reinterpret_cast<const char*>(data), size);
  if (!cheapBuiltin(spec)) return -1;
#else
  // Each input in a folder of its own: the loaders look for buffers and materials beside it.
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = std::filesystem::temp_directory_path() / ("penumbra-fuzz-" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  spec = (dir / ("input" FUZZ_EXTENSION)).string();
  std::ofstream(spec, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
#endif
  try {
    penumbra::loadScene(spec);
  } catch (const penumbra::InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loadScene threw something other than InputError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
