#include "apps/sweep.h"


#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include <sys/utsname.h>
#include <unistd.h>

#include "apps/sweep_progress.h"
#include "core/flip.h"
#include "core/image_io.h"
#include "core/metrics.h"
#include "core/view.h"
#include "hybrid/frame_output.h"
#include "hybrid/method.h"


namespace penumbra {

namespace {

namespace fs = std::filesystem;

// A float option as the user wrote it (0.05, not 0.05000000074505806) for JSON and CSV.
double tidy(float value) {
  const std::string text = shortNumber(value);
  double out = value;
  std::from_chars(text.data(), text.data() + text.size(), out);
  return out;
}

// prepareRun again for a group already checked: its warnings were printed the first time.
RunSetup quietPrepare(const RunConfig& config, const std::string& method) {
  std::ostringstream sink;
  std::streambuf* out = std::cout.rdbuf(sink.rdbuf());
  std::streambuf* err = std::cerr.rdbuf(sink.rdbuf());
  struct Restore {
    std::streambuf *out, *err;
    ~Restore() {
      std::cout.rdbuf(out);
      std::cerr.rdbuf(err);
    }
  } restore{out, err};
  return prepareRun(config, {method});
}

std::string slug(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

// The simulated trace bandwidth, wherever the stats JSON carries it (null when no simulator ran).
nlohmann::json findKey(const nlohmann::json& j, const std::string& key) {
  if (!j.is_object()) return nullptr;
  if (j.contains(key)) return j[key];
  for (const auto& [name, value] : j.items()) {
    nlohmann::json found = findKey(value, key);
    if (!found.is_null()) return found;
  }
  return nullptr;
}

struct Group {
  std::string scene;
  float lightSize = 0.0f;
  RunConfig reference;  // the run options of the group's reference (and base of its configurations)
  std::vector<SweepConfig> configs;
};

std::uint32_t referenceSppOf(const Sweep& sweep, const std::vector<SweepConfig>& configs) {
  if (sweep.referenceSpp) return sweep.referenceSpp;
  if (sweep.base.referenceSpp) return sweep.base.referenceSpp;
  std::uint32_t spp = 0;
  for (const SweepConfig& c : configs) {
    if (const std::string* v = findParam(c.params, "--spp")) spp = std::max<std::uint32_t>(spp, std::stoul(*v));
  }
  return spp ? spp : sweep.base.settings.spp;
}

// Methods ao and indirect are compared with Embree's run of the same rays: the references a
// group needs besides ref, one per term its configurations have.
std::vector<std::string> termReferences(const std::vector<SweepConfig>& configs) {
  std::vector<std::string> out;
  for (const SweepConfig& config : configs) {
    const Term term = methodTerm(config.method);
    const std::string reference = std::string(termName(term)) + "-embree";
    if (term != Term::Shadow && std::find(out.begin(), out.end(), reference) == out.end()) out.push_back(reference);
  }
  return out;
}

}  // namespace

std::string machineDescription() {
  std::string cpu = "unknown CPU";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);) {
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  const double gib = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)) / double(1ull << 30);
  utsname names{};
  uname(&names);
  std::ostringstream out;
  out << cpu << ", " << std::thread::hardware_concurrency() << " threads, " << std::lround(gib) << " GiB, "
      << names.machine;
  return out.str();
}

SweepResult runSweep(const Sweep& sweep) {
  if (sweep.scenes.empty() || sweep.lightSizes.empty()) throw InputError("the sweep needs at least one scene and light size");
  // View files pin each group's camera and light, so every configuration sees exactly the
  // reference's (and default cameras are printed once, not once per configuration).
  const fs::path views = fs::temp_directory_path() / ("penumbra-sweep-" + std::to_string(getpid()));
  fs::create_directories(views);
  struct RemoveViews {
    fs::path dir;
    ~RemoveViews() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } removeViews{views};

  // Everything is checked before the first frame: scenes, light sizes, every parameter value.
  std::vector<Group> groups;
  for (const std::string& scene : sweep.scenes) {
    for (float lightSize : sweep.lightSizes) {
      Group g{scene, lightSize, sweep.base, sweep.configsFor(lightSize)};
      if (g.configs.empty()) throw InputError("the sweep has nothing to run besides the reference; name --methods");
      g.reference.scene = scene;
      g.reference.lightSize = lightSize;
      g.reference.lightSizeGiven = true;
      g.reference.referenceSpp = referenceSppOf(sweep, g.configs);
      g.reference.saveView.clear();
      if (sweep.base.viewFile.empty()) g.reference.saveView = (views / ("group" + std::to_string(groups.size()) + ".json")).string();
      prepareRun(g.reference, {"ref"});
      if (!g.reference.saveView.empty()) g.reference.viewFile = g.reference.saveView;
      g.reference.saveView.clear();
      if (groups.empty() || scene == sweep.scenes.front()) {
        for (const SweepConfig& c : g.configs) {
          RunConfig run = g.reference;
          applyRunOptions(run, c.params);
          quietPrepare(run, c.method);
        }
      }
      groups.push_back(std::move(g));
    }
  }

  SweepResult result;
  result.machine = machineDescription();
  gpu::Context context({.validate = sweep.base.validate});
  result.device = context.deviceName();
  result.driver = context.driverInfo();
  // This shard's configurations (all of them when the sweep is not split), per group.
  std::vector<std::vector<bool>> mine(groups.size());
  std::size_t total = 0, index = 0;
  for (std::size_t gi = 0; gi < groups.size(); ++gi) {
    for (std::size_t j = 0; j < groups[gi].configs.size(); ++j, ++index) {
      mine[gi].push_back(index % sweep.shardCount == sweep.shardIndex);
    }
    const auto count = std::size_t(std::count(mine[gi].begin(), mine[gi].end(), true));
    total += count ? 1 + termReferences(groups[gi].configs).size() + count : 0;
  }
  Progress progress(total, sweep.progress);

  for (std::size_t gi = 0; gi < groups.size(); ++gi) {
    const Group& g = groups[gi];
    if (std::find(mine[gi].begin(), mine[gi].end(), true) == mine[gi].end()) continue;
    if (sweep.skipGroup && sweep.skipGroup(gi)) continue;
    const std::size_t firstRow = result.rows.size();
    std::ostringstream groupName;
    groupName << std::setw(2) << std::setfill('0') << gi << "_" << slug(g.scene) << "_light" << slug(shortNumber(g.lightSize));
    const std::string imagesDir = sweep.imagesDir.empty() ? "" : sweep.imagesDir + "/" + groupName.str();
    const std::string imagesRel = "frames/" + groupName.str() + "/";
    if (!imagesDir.empty()) fs::create_directories(imagesDir);

    std::uint32_t referenceSpp = 0;  // samples per pixel the reference took (1 for point lights)
    auto row = [&](const Frame& f, const nlohmann::json& run, const SweepConfig* config, double referenceMs) {
      const FrameStats& s = f.stats;
      const nlohmann::json stats = s.toJson();
      nlohmann::json params = nlohmann::json::object();
      std::string paramsLabel;
      if (config) {
        for (const auto& [option, value] : config->params) {
          params[option.substr(2)] = value;
          paramsLabel += (paramsLabel.empty() ? "" : " ") + paramText(option, value);
        }
      }
      nlohmann::json passes = nlohmann::json::object();
      for (const auto& [pass, ms] : s.passMs) passes[pass] = ms;
      const double nodesPerRay =
          s.nodeVisits && s.raysTraced && *s.raysTraced ? double(*s.nodeVisits) / double(*s.raysTraced) : 0.0;
      return nlohmann::json{
          {"group", gi},
          {"config", config ? std::ptrdiff_t(config - g.configs.data()) : std::ptrdiff_t(-1)},
          {"scene", g.scene},
          {"triangles", run["triangles"]},
          {"width", f.width},
          {"height", f.height},
          {"light_size", tidy(g.lightSize)},
          {"spp", s.samplesPerPixel},
          {"reference_spp", referenceSpp},
          {"method", s.method},
          {"label", config ? config->label : s.method},
          {"params", params},
          {"params_label", paramsLabel},
          {"tracer", stats["tracer"]},
          {"shadow_map_res", run["shadow_map_res"]},
          {"pcf_kernel", run["pcf_kernel"]},
          {"pip_delta", tidy(run["pip"]["delta"].get<float>())},
          {"msm_maps", run["msm_maps"]},
          {"time_ms", s.totalMs},
          {"time_min_ms", s.totalSpreadMs ? s.totalSpreadMs->minMs : s.totalMs},
          {"time_max_ms", s.totalSpreadMs ? s.totalSpreadMs->maxMs : s.totalMs},
          {"runs", s.totalSpreadMs ? s.totalSpreadMs->runs : 1u},
          {"warmup", g.reference.warmup},
          {"speedup_vs_ref", s.totalMs > 0.0 ? nlohmann::json(referenceMs / s.totalMs) : nlohmann::json(nullptr)},
          {"pip_fraction", stats["pip_fraction"]},
          {"rays_traced", stats["rays_traced"]},
          {"node_visits_per_ray", s.nodeVisits ? nlohmann::json(nodesPerRay) : nlohmann::json(nullptr)},
          {"error", stats["error"]},
          {"flip_mean", findKey(stats, "flip_mean")},
          {"pip_miss_fraction", stats["pip_miss_fraction"]},
          {"penumbra_miss_fraction", stats["penumbra_miss_fraction"]},
          {"trace_bytes_simulated", findKey(stats, "trace_bytes_simulated")},
          {"trace_bytes_per_ray", findKey(stats, "trace_bytes_per_ray")},
          {"passes", passes},
          {"stats", stats},
          {"run", run},
          {"images", nlohmann::json::object()},
          {"machine", result.machine},
          {"cpu_threads", std::thread::hardware_concurrency()},
          {"device", result.device},
          {"driver", result.driver}};
    };

    // Jobs: the reference first, then each configuration, all on the group's one loaded scene.
    const RunSetup refSetup = quietPrepare(g.reference, "ref");
    struct Job {
      const SweepConfig* config;  // null for the reference
      std::string method;
      RunConfig runConfig;
      RunSetup setup;  // its scene stays empty: every job renders refSetup.scene
      nlohmann::json run;
      std::unique_ptr<Renderer> renderer;
      std::vector<Frame> runs;
      std::optional<double> temporalChange;  // with sweep.temporalFrames
      std::optional<double> movingRmse;      // and the mean rmse against the reference's frame over the moving frames
      std::optional<FrameSequence> frames;  // the frames it renders (a sequence with --denoise temporal)
    };
    std::vector<Job> jobs;
    std::vector<std::string> referenceMethods{"ref"};  // and ao's and indirect's, for configurations of theirs
    for (const std::string& reference : termReferences(g.configs)) referenceMethods.push_back(reference);
    for (const std::string& reference : referenceMethods) {
      Job& job = jobs.emplace_back();
      job.config = nullptr;
      job.method = reference;
      job.runConfig = g.reference;
      job.run = describeRun(g.reference, refSetup, context);
    }
    const std::size_t references = jobs.size();
    for (const SweepConfig& config : g.configs) {
      if (!mine[gi][std::size_t(&config - g.configs.data())]) continue;
      RunConfig runConfig = g.reference;
      applyRunOptions(runConfig, config.params);
      RunSetup setup = quietPrepare(runConfig, config.method);
      nlohmann::json run = describeRun(runConfig, setup, context);
      setup.scene = Scene{};
      jobs.push_back({&config, config.method, runConfig, std::move(setup), std::move(run), nullptr, {}, {}});
    }
    auto render = [&](Job& job, std::span<const Light> lights) {
      return job.frames->next(*job.renderer, (job.config ? job.setup : refSetup).camera, lights);
    };
    auto start = [&](Job& job) {
      progress.start(g.scene + " light " + shortNumber(g.lightSize) + ": " + (job.config ? job.config->label : job.method));
      const RunSetup& s = job.config ? job.setup : refSetup;
      job.renderer = std::make_unique<Renderer>(context, refSetup.scene, s.settings);
      job.frames.emplace(job.runConfig, s.settings, job.method);
      for (std::uint32_t i = 0; i < job.frames->warmup(); ++i) render(job, s.lights);
    };
    auto measure = [&](Job& job) { job.runs.push_back(render(job, (job.config ? job.setup : refSetup).lights)); };
    // The mean change between consecutive frames under the slowly circling light (untimed frames),
    // and, for shadow terms, the mean rmse over the frames after the light began to move against
    // the reference's same frame (the reference job runs first): a history that lags shows there.
    std::vector<Frame> movingReference;
    auto temporal = [&](Job& job) {
      if (sweep.temporalFrames < 2) return;
      const RunSetup& s = job.config ? job.setup : refSetup;
      const Bounds bounds = refSetup.scene.bounds();
      const bool reference = !job.config && job.method == "ref";
      const bool judged = job.config && methodTerm(job.method) == Term::Shadow && movingReference.size() == sweep.temporalFrames;
      std::optional<Frame> previous;
      double sum = 0.0, rmse = 0.0;
      for (std::uint32_t i = 0; i < sweep.temporalFrames; ++i) {
        std::vector<Light> lights;
        for (const Light& l : s.lights) lights.push_back(orbitLight(l, bounds, sweep.temporalStepDeg * float(i)));
        Frame frame = render(job, lights);
        if (previous) sum += temporalChange(previous->visibility, frame.visibility, previous->covered, frame.covered);
        if (judged && i > 0) {
          const Frame& ref = movingReference[i];
          rmse += compareVisibility(frame.visibility, ref.visibility, ref.covered, kWrongThresholdSoft).rmse;
        }
        if (reference) movingReference.push_back(frame);
        previous = std::move(frame);
      }
      job.temporalChange = sum / double(sweep.temporalFrames - 1);
      if (judged) job.movingRmse = rmse / double(sweep.temporalFrames - 1);
    };
    if (sweep.interleave) {
      // Round-robin: load on a shared machine falls on every configuration alike.
      for (Job& job : jobs) start(job);
      for (std::uint32_t round = 0; round < sweep.base.repeat; ++round) {
        for (Job& job : jobs) measure(job);
      }
      for (Job& job : jobs) {
        temporal(job);
        job.renderer.reset();
      }
    } else {
      for (Job& job : jobs) {
        start(job);
        for (std::uint32_t i = 0; i < job.runConfig.repeat; ++i) measure(job);
        temporal(job);
        job.renderer.reset();
      }
    }

    std::vector<Frame> referenceFrames;  // jobs [0, references): ref, then ao-embree / indirect-embree
    const bool soft = refSetup.lights.front().size > 0.0f;
    const float threshold = soft ? kWrongThresholdSoft : kWrongThresholdHard;
    const auto orNull = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
    nlohmann::json refRow;
    for (std::size_t j = 0; j < references; ++j) {
      referenceFrames.push_back(medianFrame(std::move(jobs[j].runs)));
      const Frame& reference = referenceFrames.back();
      if (j == 0) referenceSpp = reference.stats.samplesPerPixel;
      nlohmann::json r = row(reference, jobs[j].run, nullptr, reference.stats.totalMs);
      r["config"] = -1 - std::ptrdiff_t(j);  // -1 for ref: rows stay unique per (group, config) for --merge
      r["temporal_change"] = r["ref_temporal_change"] = orNull(jobs[j].temporalChange);
      if (!imagesDir.empty()) {
        writeFrame(imagesDir, reference, jobs[j].run);
        r["images"] = {{"image", imagesRel + jobs[j].method + ".png"}};
      }
      if (j == 0) refRow = r;
      result.rows.push_back(std::move(r));
    }
    auto referenceOf = [&](const Frame& frame) -> const Frame& {
      for (const Frame& r : referenceFrames) {
        if (r.stats.term == frame.stats.term) return r;
      }
      return referenceFrames.front();
    };

    // Images of each method's first configuration in the group (whichever shard measures it).
    auto firstOfMethod = [&](const SweepConfig& c) {
      return &c == &*std::find_if(g.configs.begin(), g.configs.end(), [&](const SweepConfig& o) { return o.method == c.method; });
    };
    for (std::size_t j = references; j < jobs.size(); ++j) {
      const SweepConfig& config = *jobs[j].config;
      const nlohmann::json& run = jobs[j].run;
      Frame frame = medianFrame(std::move(jobs[j].runs));
      jobs[j].runs.clear();
      const Frame& reference = referenceOf(frame);
      // ao and indirect are continuous terms: the soft threshold, whatever the light
      const float wrong = frame.stats.term ? kWrongThresholdSoft : threshold;
      frame.stats.error = compareVisibility(frame.visibility, reference.visibility, reference.covered, wrong);
      const bool picture = !imagesDir.empty() && firstOfMethod(config);
      std::vector<float> flip;
      frame.stats.imageError =
          compareImages(frame.rgba, reference.rgba, reference.covered, frame.width, frame.height, picture ? &flip : nullptr);
      if (!frame.pip.empty()) {
        frame.stats.pipMissFraction =
            missFraction(frame.shadowMapVisibility, reference.visibility, reference.covered, frame.pip, threshold);
        if (soft) frame.stats.penumbraMissFraction = penumbraMissFraction(reference.visibility, reference.covered, frame.pip);
      }
      nlohmann::json r = row(frame, run, &config, reference.stats.totalMs);
      r["temporal_change"] = orNull(jobs[j].temporalChange);
      r["ref_temporal_change"] = refRow["ref_temporal_change"];
      r["moving_rmse"] = orNull(jobs[j].movingRmse);
      // Images of each method's first configuration: the page shows them beside the reference.
      if (picture) {
        writeFrame(imagesDir, frame, run);
        writeHeatmap(imagesDir, frame, reference, soft ? 0.25f : 1.0f);
        writePngRgba8(imagesDir + "/" + config.method + ".flip.png", int(frame.width), int(frame.height),
                      flipHeatmap(flip, reference.covered));
        r["images"] = {{"image", imagesRel + config.method + ".png"}, {"heatmap", imagesRel + config.method + ".heatmap.png"},
                       {"flip", imagesRel + config.method + ".flip.png"}};
        if (!frame.pip.empty()) r["images"]["pip"] = imagesRel + config.method + ".pip.png";
      }
      result.rows.push_back(std::move(r));
    }
    if (sweep.onGroup) {
      sweep.onGroup(gi, nlohmann::json(std::vector<nlohmann::json>(result.rows.begin() + std::ptrdiff_t(firstRow), result.rows.end())));
    }
  }
  const auto messages = context.validationMessages();
  if (!messages.empty()) {
    throw std::runtime_error(std::to_string(messages.size()) + " Vulkan validation message(s) during the sweep, see above");
  }
  return result;
}

}  // namespace penumbra
