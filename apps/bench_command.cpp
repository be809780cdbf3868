#include "apps/bench_command.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <iostream>
#include <sstream>

#include "apps/report.h"
#include "hybrid/frame_output.h"
#include "hybrid/method.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

struct Axis {
  const AxisDef* def;
  std::vector<std::string> values;
};

std::vector<std::string> splitValues(const std::string& list, const std::string& option) {
  std::vector<std::string> items;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) items.push_back(item);
  }
  if (items.empty()) throw InputError(option + " '" + list + "' names nothing; give a comma-separated list");
  return items;
}

bool relevant(const AxisDef& axis, const std::string& method, const RunOptions& partial, const RunConfig& base,
              float lightSize) {
  const std::vector<std::string>& methods = axis.axis.methods;
  if (std::find(methods.begin(), methods.end(), method) == methods.end()) return false;
  if (axis.axis.areaLightOnly && lightSize <= 0.0f) return false;
  if (axis.axis.lineSpaceOnly && method != "ls") {
    const std::string* tracer = findParam(partial, "--tracer");
    return (tracer ? *tracer : base.tracer) == "ls";
  }
  return true;
}


// Method x every relevant axis value; labels name the method and the axes that take several values.
std::vector<SweepConfig> expandConfigs(const std::vector<std::string>& methods, const std::vector<Axis>& axes,
                                       const RunConfig& base, float lightSize) {
  std::vector<SweepConfig> configs;
  for (const std::string& method : methods) {
    std::vector<RunOptions> partial{{}};
    for (const Axis& axis : axes) {
      std::vector<RunOptions> next;
      for (const RunOptions& p : partial) {
        if (!relevant(*axis.def, method, p, base, lightSize)) {
          next.push_back(p);
          continue;
        }
        for (const std::string& v : axis.values) {
          RunOptions q = p;
          q.emplace_back(axis.def->option, v);
          next.push_back(std::move(q));
        }
      }
      partial = std::move(next);
    }
    for (RunOptions& p : partial) {
      std::string label = method;
      for (const auto& [option, value] : p) {
        const auto axis = std::find_if(axes.begin(), axes.end(), [&](const Axis& a) { return option == a.def->option; });
        if (axis != axes.end() && axis->values.size() > 1) label += " " + paramText(option, value);
      }
      configs.push_back({method, std::move(p), label});
    }
  }
  return configs;
}

}  // namespace

BenchCommand::BenchCommand(CLI::App& app) {
  command_ = app.add_subcommand(
      "bench", "Sweep methods x parameters x scenes x light sizes against the Embree reference: bench.csv, bench.json, "
               "report.html with charts and tables");
  base_.outDir = "out/bench";
  base_.repeat = 3;
  addRunOptions(*command_, base_);
  // The run options that become lists here: each configuration gets one value.
  std::vector<std::string> listed{"--scene", "--light-size", "--save-view"};
  for (const AxisDef& axis : sweepAxes()) listed.push_back(axis.option);
  for (const std::string& name : listed) {
    if (CLI::Option* single = command_->get_option_no_throw(name)) command_->remove_option(single);
  }
  command_->add_option("--methods", methods_, "Comma-separated methods, each measured against ref")->capture_default_str();
  command_->add_option("--scenes,--scene", scenes_, "Comma-separated scenes (builtin:NAME[:LEVEL], .gltf/.glb, .obj)")
      ->capture_default_str();
  command_->add_option("--light-sizes,--light-size", lightSizes_,
                       "Comma-separated area-light sizes, fractions of the scene radius (0 = point light)")
      ->capture_default_str();
  axisValues_.resize(sweepAxes().size());
  for (std::size_t i = 0; i < sweepAxes().size(); ++i) command_->add_option(sweepAxes()[i].names, axisValues_[i], sweepAxes()[i].help);
  command_->add_option("--reference-spp", referenceSpp_,
                       "Light samples per pixel of the reference (default: the largest --spp of the sweep)");
  command_->add_option("--temporal-frames", temporalFrames_,
                       "Temporal stability: frames per configuration (and the reference) under a light circling 0.25 "
                       "degrees per frame; rows get the mean frame-to-frame visibility change (0 or 1 = off)")
      ->capture_default_str();
  command_->add_flag("--no-images", noImages_, "Do not write the images of each method's first configuration");
  command_->add_flag("--no-report", noReport_, "Do not run report.py (charts and report.html)");
  command_->add_option("--shard", shard_,
                       "K/N: run configurations K, K+N, K+2N, ... of the sweep (1-based; each with its group's "
                       "reference), for splitting one sweep over several machines");
  command_->add_flag("--resume", resume_,
                     "Keep the results of the scene and light-size groups a killed run of the same sweep finished "
                     "(kept in OUT/rows/ as each group ends) and run only the others");
  command_->add_option("--merge", merge_,
                       "Instead of a sweep: combine the output folders of its N shards (comma-separated) into --out, "
                       "as one run would have written it")
      ->delimiter(',');
}

int BenchCommand::run() {
  if (!merge_.empty()) {
    write(mergeBench(merge_, base_.outDir));
    return 0;
  }
  std::uint32_t shardIndex = 0, shardCount = 1;
  if (!shard_.empty()) {
    const std::size_t slash = shard_.find('/');
    const std::string k = shard_.substr(0, slash), n = slash == std::string::npos ? "" : shard_.substr(slash + 1);
    const auto [kEnd, kErr] = std::from_chars(k.data(), k.data() + k.size(), shardIndex);
    const auto [nEnd, nErr] = std::from_chars(n.data(), n.data() + n.size(), shardCount);
    if (kErr != std::errc() || nErr != std::errc() || kEnd != k.data() + k.size() || nEnd != n.data() + n.size() ||
        shardCount == 0 || shardIndex < 1 || shardIndex > shardCount) {
      throw InputError("--shard '" + shard_ + "' must be K/N with 1 <= K <= N, e.g. --shard 2/4");
    }
    --shardIndex;
  }
  std::vector<std::string> methods;
  for (const std::string& m : splitValues(methods_, "--methods")) {
    makeMethod(m);  // unknown names fail here
    if (m != "ref" && std::find(methods.begin(), methods.end(), m) == methods.end()) methods.push_back(m);
  }
  Sweep sweep;
  sweep.base = base_;
  sweep.scenes = splitValues(scenes_, "--scenes");
  sweep.lightSizes.clear();
  for (const std::string& text : splitValues(lightSizes_, "--light-sizes")) {
    float size = 0.0f;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), size);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(size) || size < 0.0f) {
      throw InputError("--light-sizes: '" + text + "' is not a non-negative number; e.g. --light-sizes 0,0.05,0.1");
    }
    sweep.lightSizes.push_back(size);
  }
  std::vector<Axis> axes;
  for (std::size_t i = 0; i < sweepAxes().size(); ++i) {
    if (axisValues_[i].empty()) continue;
    const std::string name = sweepAxes()[i].names;
    axes.push_back({&sweepAxes()[i], splitValues(axisValues_[i], name.substr(0, name.find(',')))});
    for (const std::string& v : axes.back().values) {  // a bad value fails before any scene loads
      RunConfig probe = base_;
      applyRunOptions(probe, {{sweepAxes()[i].option, v}});
    }
  }
  sweep.configsFor = [methods, axes, base = base_](float lightSize) { return expandConfigs(methods, axes, base, lightSize); };
  sweep.referenceSpp = referenceSpp_;
  sweep.temporalFrames = temporalFrames_;
  sweep.imagesDir = noImages_ ? "" : base_.outDir + "/frames";
  sweep.shardIndex = shardIndex;
  sweep.shardCount = shardCount;

  // Each group's rows are kept in OUT/rows/ as soon as they are final (written under a temporary
  // name, then renamed); --resume takes those of a killed run of the same sweep instead of running
  // their groups again.
  const fs::path rowsDir = fs::path(base_.outDir) / "rows";
  const auto groupFile = [&](std::size_t group) { return rowsDir / ("group" + std::to_string(group) + ".json"); };
  if (resume_ && fs::exists(rowsDir / "sweep.json") &&
      nlohmann::json::parse(std::ifstream(rowsDir / "sweep.json"), nullptr, false) != identity()) {
    throw InputError("--resume: " + base_.outDir + " holds the results of a sweep with other options; give the same "
                     "options, or another --out");
  }
  std::map<std::size_t, nlohmann::json> kept;  // group -> its rows, from the killed run
  sweep.skipGroup = [&](std::size_t group) {
    if (!resume_ || !fs::exists(groupFile(group))) return false;
    kept[group] = nlohmann::json::parse(std::ifstream(groupFile(group)));
    return true;
  };
  bool started = false;
  sweep.onGroup = [&](std::size_t group, const nlohmann::json& rows) {
    if (!started) {  // the first results of this run: a fresh run drops an earlier one's
      if (!resume_) fs::remove_all(rowsDir);
      fs::create_directories(rowsDir);
      writeJson((rowsDir / "sweep.json").string(), identity());
      started = true;
    }
    const fs::path file = groupFile(group), partial = file.string() + ".partial";
    writeJson(partial.string(), rows);
    fs::rename(partial, file);
  };
  SweepResult result = runSweep(sweep);
  if (!kept.empty()) {  // put the kept groups back in their places
    std::map<std::size_t, nlohmann::json> byGroup = kept;
    for (const nlohmann::json& row : result.rows) byGroup[row["group"].get<std::size_t>()].push_back(row);
    result.rows = nlohmann::json::array();
    for (auto& [group, rows] : byGroup) {
      for (nlohmann::json& row : rows) result.rows.push_back(std::move(row));
    }
  }
  std::ostringstream description;
  description << "Release build; " << base_.resolution << " pixels; warm-up " << base_.warmup << " frame(s), median of "
              << base_.repeat << " measured frame(s) (min-max in the tables); errors over covered pixels against the "
              << "Embree reference of the same scene and light (area lights: the reference uses the largest --spp of "
              << "the sweep unless --reference-spp says otherwise). Scenes as named; scaled scenes say in their name "
              << "whether they are tessellation levels or instanced layouts.";
  nlohmann::json bench{{"title", "Penumbra bench"},
                       {"description", description.str()},
                       {"machine", result.machine},
                       {"device", result.device},
                       {"driver", result.driver},
                       {"rows", result.rows}};
  if (!shard_.empty()) {
    std::size_t configurations = 0;  // the whole sweep's, so that a merge can tell shards of another sweep
    for (float size : sweep.lightSizes) configurations += sweep.scenes.size() * sweep.configsFor(size).size();
    bench["shard"] = {{"index", shardIndex + 1}, {"count", shardCount}, {"configurations", configurations}};
  }
  write(bench);
  return 0;
}

nlohmann::json BenchCommand::identity() const {
  nlohmann::json id = nlohmann::json::object();
  for (const CLI::Option* option : command_->get_options()) {
    const std::string name = option->get_name();
    if (option->count() == 0 || name == "--resume" || name == "--out" || name == "--no-report") continue;
    id[name] = option->results();
  }
  return id;
}

void BenchCommand::write(const nlohmann::json& bench) const {
  fs::create_directories(base_.outDir);
  writeJson(base_.outDir + "/bench.json", bench);
  writeBenchCsv(base_.outDir + "/bench.csv", bench["rows"]);
  writeBenchTables(base_.outDir + "/tables.md", bench);
  printSweepSummary(bench["rows"], std::cout);
  if (!noReport_) writeReport("bench", base_.outDir);
  std::cout << "wrote " << base_.outDir << "/ (bench.csv, bench.json, tables.md" << (noReport_ ? "" : ", report.html") << ")\n";
}

}  // namespace penumbra
