// Renders a scene's shadows with sm and srt, compares both with the Embree reference, and prints
// what each got wrong and what srt traced:  shadow_report [SCENE [WxH]]
#include <cstdio>
#include <string>

#include <penumbra/penumbra.h>

int main(int argc, char** argv) {
  const std::string scene = argc > 1 ? argv[1] : "builtin:square";
  const std::string res = argc > 2 ? argv[2] : "64x64";
  try {
    const penumbra::api::Scene loaded(scene);
    penumbra::api::Renderer renderer(loaded, {{"--res", res}, {"--srt-choice", "off"}});
    const penumbra::api::Frame srt = renderer.render("srt");
    std::size_t covered = 0, traced = 0, lit = 0;
    for (std::size_t i = 0; i < srt.visibility.size(); ++i) {
      covered += srt.covered[i];
      traced += srt.pip[i] != 0;
      lit += srt.covered[i] && srt.visibility[i] > 0.5f;
    }
    std::printf("%s: %llu triangles, %ux%u, srt traced %zu of %zu covered pixels, %zu lit\n", scene.c_str(),
                static_cast<unsigned long long>(loaded.triangles()), srt.width, srt.height, traced, covered, lit);
    std::printf("%s\n", renderer.compare({"sm", "srt"}).c_str());  // metrics.json's object
  } catch (const penumbra::api::Error& e) {
    std::fprintf(stderr, "shadow_report: %s\n", e.what());
    return 2;
  }
  return 0;
}
