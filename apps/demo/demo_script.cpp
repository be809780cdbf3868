#include "apps/demo/demo_script.h"

#include <unistd.h>

#include <cstdio>
#include <iomanip>
#include <sstream>
#include <vector>

namespace penumbra::demo {

void addScriptOptions(CLI::App& app, ScriptOptions& o) {
  app.add_option("--frames", o.frames, "Scripted run: render this many frames, then exit (0 = interactive)")
      ->check(CLI::Range(0u, 10000000u));
  app.add_flag("--orbit", o.orbit, "Scripted run: turn the camera about its target by 1.5 degrees per frame");
  app.add_option("--light-path", o.lightPath, "Scripted run: 'circle' turns the light about the scene centre by 1 degree per frame")
      ->capture_default_str()->check(CLI::IsMember({"none", "circle"}));
  app.add_option("--screenshot", o.screenshot, "Write the last presented frame (without the UI) to this PNG");
  app.add_option("--stats-csv", o.statsCsv, "Write one row of stats per frame to this CSV file");
  app.add_flag("--temporal-reference", o.temporalReference,
               "Also render the reference every frame and write its frame-to-frame change (ref_temporal_change)");
  app.add_option("--overlay", o.overlay,
                 "Overlay: none, pip (traced pixels in red), mask (penumbra mask), thin, error, tiles (the tiles the "
                 "penumbra mask's tile test cleared in blue, traced pixels in red, or orange where the tile choice "
                 "traced their tile whole)")
      ->capture_default_str()
      ->check(CLI::IsMember(std::vector<std::string>(kOverlayNames.begin(), kOverlayNames.end())));
  app.add_option("--select-light", o.selectLight,
                 "The light selected at start (0 the first): the one the panel moves, --light-path turns, and the "
                 "overlays and the error show")
      ->capture_default_str();
  app.add_flag("--hide-ui", o.hideUi, "Do not draw the ImGui panels");
}

std::uint64_t residentBytes() {
  unsigned long long size = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%llu %llu", &size, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return std::uint64_t(resident) * std::uint64_t(::sysconf(_SC_PAGESIZE));
}

StatsCsv::StatsCsv(const std::string& path) : path_(path), out_(path, std::ios::trunc) {
  if (!out_) throw InputError("--stats-csv: cannot write '" + path + "'; check the folder exists and is writable");
  out_ << "frame,time_s,method,tracer,total_ms,passes,pip_fraction,rays,memory_bytes,rss_bytes,temporal_change,"
          "ref_temporal_change,refit_ms,sah_growth,rebuilt\n";
}

void StatsCsv::write(const FrameRecord& r) {
  const FrameStats& s = *r.stats;
  auto opt = [](const auto& v) {
    std::ostringstream text;
    if (v) text << std::setprecision(9) << *v;
    return text.str();
  };
  std::string passes;
  for (const auto& [pass, ms] : s.passMs) passes += (passes.empty() ? "" : ";") + pass + "=" + std::to_string(ms);
  std::uint64_t memory = 0;
  for (const auto& [name, bytes] : s.memoryBytes) memory += bytes;
  out_ << r.frame << "," << std::setprecision(9) << r.timeS << "," << s.method << "," << s.tracer.value_or("") << ","
       << s.totalMs << "," << passes << "," << opt(s.pipFraction) << "," << opt(s.raysTraced) << "," << memory << ","
       << r.rssBytes << "," << opt(r.temporalChange) << "," << opt(r.referenceTemporalChange) << ",";
  if (s.refit) {
    out_ << s.refit->ms << "," << s.refit->growth << ","
         << (s.refit->rebuilt ? 1 : 0);
  } else {
    out_ << ",,";
  }
  out_ << "\n";
  out_.flush();  // a run stopped early still leaves its rows
  if (!out_) throw std::runtime_error("cannot write to '" + path_ + "'");
}

}  // namespace penumbra::demo
