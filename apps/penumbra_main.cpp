// penumbra: command-line front end. `render` runs one method, `compare` runs the Embree reference
// and several methods and measures each against it. Every input is checked before any output is
// written; errors print one line on stderr and exit with a non-zero code.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "apps/bench_command.h"
#include "apps/declared_options.h"
#include "apps/device_command.h"
#include "apps/report.h"
#include "apps/run_config.h"
#include "apps/tune_command.h"
#include "apps/visibility_command.h"
#include "core/image_io.h"
#include "core/metrics.h"
#include "core/miss_explainer.h"
#include "hybrid/frame_output.h"
#include "hybrid/method.h"

using namespace penumbra;

namespace {

int runCommand(const RunConfig& config, const std::vector<std::string>& requested, bool compare) {
  const RunSetup setup = prepareRun(config, requested);
  std::vector<std::string> methods;
  std::vector<std::string> references;  // compare: one per term, in the order the methods need them
  for (const std::string& m : expandMethods(config, requested)) {
    const std::string reference = referenceFor(m);
    if (compare && std::find(references.begin(), references.end(), reference) == references.end()) {
      references.push_back(reference);
    }
    if (!compare || m != reference) methods.push_back(m);
  }
  gpu::Context context({.validate = config.validate});
  Renderer renderer(context, setup.scene, setup.settings);

  auto measured = [&](const std::string& method) {
    FrameSequence sequence(config, setup.settings, method);
    for (std::uint32_t i = 0; i < sequence.warmup(); ++i) sequence.next(renderer, setup.camera, setup.lights);
    std::vector<Frame> runs;
    for (std::uint32_t i = 0; i < config.repeat; ++i)
      runs.push_back(sequence.next(renderer, setup.camera, setup.lights));
    return medianFrame(std::move(runs));
  };
  std::vector<Frame> frames;
  for (const std::string& reference : references) frames.push_back(measured(reference));
  for (const std::string& method : methods) frames.push_back(measured(method));
  // compare: frames[referenceOf[i]] is frame i's reference
  std::vector<std::size_t> referenceOf(frames.size(), 0);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::string reference = referenceFor(frames[i].stats.method);
    for (std::size_t r = 0; r < references.size(); ++r) {
      if (references[r] == reference) referenceOf[i] = r;
    }
  }

  nlohmann::json context_json = describeRun(config, setup, context);
  const bool soft = setup.lights.front().size > 0.0f;
  const float threshold = soft ? kWrongThresholdSoft : kWrongThresholdHard;
  const float heatmapScale = soft ? 0.25f : 1.0f;
  std::vector<std::vector<float>> flipMaps(frames.size());  // per method: FLIP of its image vs the reference's
  std::vector<std::optional<MissReport>> missReports(frames.size());  // --explain-misses
  if (compare) {
    for (std::size_t i = references.size(); i < frames.size(); ++i) {
      missReports[i] = judgeFrame(frames[i], frames[referenceOf[i]], soft, &flipMaps[i]);
    }
  }

  // Everything rendered: only now write, into a staging folder that becomes the output folder whole.
  StagedOutput out(config.outDir);
  const std::string& dir = out.path();
  for (const Frame& frame : frames) writeFrame(dir, frame, context_json);
  if (compare) {
    nlohmann::json metrics{{"scene", context_json}, {"reference", frames[0].stats.toJson()}, {"methods", nlohmann::json::array()}};
    // Methods ao and indirect have references of their own (the first is also "reference").
    metrics["references"] = nlohmann::json::array();
    for (std::size_t r = 0; r < references.size(); ++r) metrics["references"].push_back(frames[r].stats.toJson());
    metrics["scene"]["wrong_pixel_threshold"] = threshold;
    if (references.size() > 1 || references.front() != "ref") metrics["scene"]["wrong_pixel_threshold_ao_indirect"] = kWrongThresholdSoft;
    metrics["scene"]["heatmap_full_scale"] = heatmapScale;
    metrics["scene"]["flip_pixels_per_degree"] = FlipSettings{}.pixelsPerDegree;
    for (std::size_t i = references.size(); i < frames.size(); ++i) {
      const Frame& reference = frames[referenceOf[i]];
      writeHeatmap(dir, frames[i], reference, heatmapScale);
      if (missReports[i]) {
        writePngRgba8(dir + "/" + frames[i].stats.method + ".misses.png", int(frames[i].width),
                      int(frames[i].height), missImage(*missReports[i], reference.covered));
      }
      writePngRgba8(dir + "/" + frames[i].stats.method + ".flip.png", int(frames[i].width),
                    int(frames[i].height), flipHeatmap(flipMaps[i], reference.covered));
      metrics["methods"].push_back(frames[i].stats.toJson());
    }
    writeJson(dir + "/metrics.json", metrics);
    if (!config.csv.empty()) appendCsv(config.csv, frames, context_json);
    if (!config.noReport) writeReport("compare", dir);  // report.html: images, metrics, chart
  }
  out.commit();
  printSummary(frames, std::cout);
  std::cout << "wrote " << config.outDir << "/\n";

  const auto messages = context.validationMessages();
  if (!messages.empty()) {
    std::cerr << "penumbra: " << messages.size() << " Vulkan validation message(s), see above\n";
    return 3;
  }
  return 0;
}

// A run that ran out of memory the estimate did not foresee: what to lower, exit 2.
int outOfMemory(const char* what) {
  std::cerr << "penumbra: out of " << what << "; lower --res, --shadow-map-res or --spp, or use a smaller scene\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Penumbra: hybrid selective ray-traced shadows (shadow maps + ray tracing where they may be wrong)"};
  app.require_subcommand(1);
  RunConfig config;

  CLI::App* render = app.add_subcommand("render", "Render one method: DIR/<method>.png, .visibility.exr/.png, .stats.json");
  std::string method;
  render->add_option("--method", method, "Method: " + [] {
    std::string s;
    for (const auto& n : methodNames()) s += (s.empty() ? "" : ", ") + n;
    return s;
  }())->required();
  addRunOptions(*render, config);

  CLI::App* compare = app.add_subcommand("compare", "Render the Embree reference and each method; write heatmaps and metrics.json");
  std::string methodList = "sm,pcf";
  compare->add_option("--methods", methodList, "Comma-separated methods to compare with ref")->capture_default_str();
  compare->add_option("--csv", config.csv, "Append one row per method (with machine, driver and device) to this CSV file");
  compare->add_option("--reference-spp", config.referenceSpp, "Light samples per pixel of the reference (default: --spp; 256 with --denoise)");
  compare->add_flag("--no-report", config.noReport, "Do not run report.py (report.html and its chart)");
  compare->add_flag("--explain-misses", config.explainMisses,
                    "Count why the classification left out each pixel sm gets wrong (miss_causes in metrics.json; "
                    "hard shadows) and draw them (<method>.misses.png); area lights: which rule put each pixel in "
                    "the penumbra mask and whether the reference has it in penumbra, lit or dark (mask_rules)");
  addRunOptions(*compare, config);
  BenchCommand bench(app);
  TuneCommand tune(app);
  VisibilityCommand visibility(app);
  DeviceCommand device(app);
  CLI::App* options = app.add_subcommand(
      "options", "Print every pass's, method's and tracer's option as Markdown: docs/options.md is this output");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "penumbra: " << e.what() << " (see --help)\n";
    return 2;
  }
  try {
    if (render->parsed()) return runCommand(config, {method}, false);
    if (bench.parsed()) return bench.run();
    if (tune.parsed()) return tune.run();
    if (visibility.parsed()) return visibility.run();
    if (device.parsed()) return device.run();
    if (options->parsed()) {
      std::cout << "# Options of the passes, methods and tracers\n\n"
                   "Each pass, method and tracer declares its options once, beside its settings (`core/options.h`); "
                   "`render`, `compare`, `bench` and `tune` take them, `metrics.json` records them under their key, "
                   "and `bench` sweeps a comma-separated list of values for those that name methods. This page is "
                   "the output of `build/bin/penumbra options`, and a test keeps it so. Scene, camera, light, "
                   "tracer and measuring options, with examples: [cli.md](cli.md).\n"
                << declaredOptionsMarkdown(renderOptions(), RunConfig{}.settings);
      return 0;
    }
    return runCommand(config, splitList(methodList), true);
  } catch (const vk::OutOfDeviceMemoryError&) {  // beyond what the estimate foresaw
    return outOfMemory("device memory");
  } catch (const vk::OutOfHostMemoryError&) {
    return outOfMemory("host memory");
  } catch (const std::bad_alloc&) {
    return outOfMemory("memory");
  } catch (const std::exception& e) {
    std::cerr << "penumbra: " << e.what() << "\n";
    return 2;
  }
}
