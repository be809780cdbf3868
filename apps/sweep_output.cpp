// What a sweep leaves: bench.csv, tables.md, the summary it prints, and the merge of a split sweep's shards
// (apps/sweep.h).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <optional>
#include <sstream>

#include "apps/sweep.h"

namespace penumbra {

namespace fs = std::filesystem;

nlohmann::json mergeBench(const std::vector<std::string>& dirs, const std::string& outDir) {
  std::optional<nlohmann::json> merged;
  std::vector<bool> seen;
  std::map<std::pair<long, long>, nlohmann::json> rows;  // by (group, configuration; -1 = reference)
  for (const std::string& dir : dirs) {
    const std::string path = dir + "/bench.json";
    std::ifstream in(path);
    if (!in) throw InputError("--merge: no " + path + "; name the output folders of the shards");
    nlohmann::json bench = nlohmann::json::parse(in, nullptr, false);
    if (bench.is_discarded() || !bench.contains("shard") || !bench.contains("rows")) {
      throw InputError("--merge: " + path + " is not the output of bench --shard");
    }
    const nlohmann::json shard = bench["shard"];
    const auto count = shard.value("count", 0u), index = shard.value("index", 0u);
    if (!merged) {
      merged = bench;
      seen.assign(count, false);
    }
    const nlohmann::json& first = (*merged)["shard"];
    if (count != first.value("count", 0u) || shard.value("configurations", 0u) != first.value("configurations", 0u) ||
        bench["description"] != (*merged)["description"] || index < 1 || index > count) {
      throw InputError("--merge: " + path + " is shard " + std::to_string(index) + "/" + std::to_string(count) +
                       " of another sweep than " + dirs.front());
    }
    if (seen[index - 1]) throw InputError("--merge: shard " + std::to_string(index) + " is named twice");
    seen[index - 1] = true;
    for (const nlohmann::json& r : bench["rows"]) rows.emplace(std::make_pair(r["group"].get<long>(), r["config"].get<long>()), r);
  }
  if (!merged) throw InputError("--merge names no folder");
  const auto missing = std::find(seen.begin(), seen.end(), false);
  if (missing != seen.end()) {
    throw InputError("--merge: shard " + std::to_string(missing - seen.begin() + 1) + "/" + std::to_string(seen.size()) +
                     " is missing");
  }
  for (const std::string& dir : dirs) {  // all shards checked: only now write
    if (!fs::exists(dir + "/frames")) continue;
    fs::create_directories(outDir + "/frames");
    fs::copy(dir + "/frames", outDir + "/frames", fs::copy_options::recursive | fs::copy_options::skip_existing);
  }
  nlohmann::json& out = *merged;
  out.erase("shard");
  out["rows"] = nlohmann::json::array();
  for (auto& [key, row] : rows) out["rows"].push_back(std::move(row));
  return out;
}

void writeBenchCsv(const std::string& path, const nlohmann::json& rows) {
  static const char* const columns[] = {
      "scene", "triangles", "width", "height", "light_size", "spp", "reference_spp", "method", "label", "params_label",
      "tracer", "shadow_map_res", "pcf_kernel", "pip_delta", "msm_maps", "time_ms", "time_min_ms", "time_max_ms", "runs",
      "warmup", "speedup_vs_ref", "pip_fraction", "rays_traced", "node_visits_per_ray", "wrong_pixel_fraction", "rmse",
      "mae", "max_error", "flip_mean", "pip_miss_fraction", "penumbra_miss_fraction", "trace_bytes_simulated", "trace_bytes_per_ray", "temporal_change", "ref_temporal_change", "moving_rmse", "passes", "machine",
      "cpu_threads", "device", "driver"};
  auto field = [](const nlohmann::json& v) -> std::string {
    if (v.is_null()) return "";
    std::string text = v.is_string() ? v.get<std::string>() : v.dump();
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
  };
  std::ofstream out(path);
  for (std::size_t i = 0; i < std::size(columns); ++i) out << (i ? "," : "") << columns[i];
  out << "\n";
  for (const nlohmann::json& r : rows) {
    for (std::size_t i = 0; i < std::size(columns); ++i) {
      const std::string c = columns[i];
      nlohmann::json v;
      if (c == "wrong_pixel_fraction" || c == "rmse" || c == "mae") v = r["error"].is_null() ? nullptr : r["error"][c];
      else if (c == "max_error") v = r["error"].is_null() ? nullptr : r["error"]["max"];
      else if (c == "passes") {
        std::string passes;
        for (const auto& [pass, ms] : r["passes"].items()) passes += (passes.empty() ? "" : ";") + pass + "=" + ms.dump();
        v = passes;
      } else v = r.value(c, nlohmann::json());  // a row without the column (older rows, references): empty
      out << (i ? "," : "") << field(v);
    }
    out << "\n";
  }
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

namespace {

// A number with `digits` decimals, or "" for a null or missing field.
std::string cell(const nlohmann::json& v, int digits, double scale = 1.0) {
  if (!v.is_number()) return "";
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v.get<double>() * scale;
  return s.str();
}

double passMs(const nlohmann::json& row, const char* pass) {
  return row["passes"].contains(pass) ? row["passes"][pass].get<double>() : 0.0;
}

}  // namespace

void writeBenchTables(const std::string& path, const nlohmann::json& bench) {
  const nlohmann::json& rows = bench["rows"];
  std::ofstream out(path);
  out << "# " << bench.value("title", "Penumbra bench") << "\n\n"
      << bench.value("device", "") << ", " << bench.value("driver", "") << "; " << bench.value("machine", "") << ".\n\n"
      << bench.value("description", "")
      << "\n\n## Every configuration\n\nms: median frame (min-max); passes: that frame's GPU time per pass; Mrays/s: "
         "rays over the trace pass's GPU time; memory: "
         "the GPU buffers and images its stats list (G-buffer, shadow map, BVH or acceleration structures, ...), "
         "MB.\n\n"
      << "| scene | triangles | res | light | configuration | ms | min-max | PIP % | rays | Mrays/s | wrong % | rmse | "
         "memory MB | passes, ms |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const nlohmann::json& r : rows) {
    std::uint64_t memory = 0;
    if (r.contains("stats") && r["stats"].contains("memory_bytes")) {
      for (const auto& [name, bytes] : r["stats"]["memory_bytes"].items()) memory += bytes.get<std::uint64_t>();
    }
    const double trace = passMs(r, "trace");
    const nlohmann::json rate = r["rays_traced"].is_number() && trace > 0.0
                                    ? nlohmann::json(r["rays_traced"].get<double>() / trace / 1e3)
                                    : nlohmann::json(nullptr);
    const nlohmann::json& error = r["error"].is_null() ? nlohmann::json::object() : r["error"];
    out << "| " << r["scene"].get<std::string>() << " | " << r["triangles"].dump() << " | " << r["width"].dump() << "x"
        << r["height"].dump() << " | " << shortNumber(r["light_size"].get<float>()) << " | "
        << r["label"].get<std::string>() << " | " << cell(r["time_ms"], 2) << " | " << cell(r["time_min_ms"], 2) << "-"
        << cell(r["time_max_ms"], 2) << " | " << cell(r["pip_fraction"], 2, 100.0) << " | "
        << (r["rays_traced"].is_number() ? r["rays_traced"].dump() : "") << " | " << cell(rate, 1) << " | "
        << cell(error.value("wrong_pixel_fraction", nlohmann::json()), 4, 100.0) << " | "
        << cell(error.value("rmse", nlohmann::json()), 4) << " | "
        << (memory ? cell(double(memory), 1, 1e-6) : std::string()) << " |";
    for (const auto& [pass, ms] : r["passes"].items()) out << " " << pass << "=" << cell(ms, 2);
    out << " |\n";
  }

  // Fig. 8: per scene, resolution and light, each srt row with the frt row of the same tracer,
  // samples and denoiser, and the group's sm.
  if (std::any_of(rows.begin(), rows.end(), [](const nlohmann::json& r) { return r["method"] == "srt"; })) {
    out << "\n## Lauterbach et al. 2009, Fig. 8 shape\n\nms, medians. bound: srt's model bound, the sm frame plus "
           "srt's PIP share of frt's trace pass; srt/bound is how far srt is from it.\n\n"
        << "| scene | res | light | spp | tracer | denoise | sm | srt | frt | srt/sm | frt/srt | PIP % | bound | "
           "srt/bound |\n"
        << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    auto denoise = [](const nlohmann::json& r) {
      return r.contains("stats") && r["stats"]["denoise"].is_string() ? r["stats"]["denoise"].get<std::string>()
                                                                      : std::string("off");
    };
    auto ratio = [](double a, double b) { return b > 0.0 ? nlohmann::json(a / b) : nlohmann::json(nullptr); };
    auto sameGroup = [](const nlohmann::json& a, const nlohmann::json& b) {
      return a["scene"] == b["scene"] && a["width"] == b["width"] && a["height"] == b["height"] &&
             a["light_size"] == b["light_size"];
    };
    for (const nlohmann::json& srt : rows) {
      if (srt["method"] != "srt") continue;
      const nlohmann::json *sm = nullptr, *frt = nullptr;
      for (const nlohmann::json& r : rows) {
        if (!sameGroup(r, srt)) continue;
        if (r["method"] == "sm" && !sm) sm = &r;
        if (r["method"] == "frt" && !frt && r["tracer"] == srt["tracer"] && r["spp"] == srt["spp"] &&
            denoise(r) == denoise(srt))
          frt = &r;
      }
      const double srtMs = srt["time_ms"].get<double>();
      const double smMs = sm ? (*sm)["time_ms"].get<double>() : 0.0,
                   frtMs = frt ? (*frt)["time_ms"].get<double>() : 0.0;
      const double pip = srt["pip_fraction"].is_number() ? srt["pip_fraction"].get<double>() : 0.0;
      const double bound = sm && frt ? smMs + pip * passMs(*frt, "trace") : 0.0;
      out << "| " << srt["scene"].get<std::string>() << " | " << srt["width"].dump() << "x" << srt["height"].dump()
          << " | " << shortNumber(srt["light_size"].get<float>()) << " | " << srt["spp"].dump() << " | "
          << (srt["tracer"].is_string() ? srt["tracer"].get<std::string>() : "") << " | " << denoise(srt) << " | "
          << (sm ? cell(smMs, 2) : "") << " | " << cell(srtMs, 2) << " | " << (frt ? cell(frtMs, 2) : "") << " | "
          << (sm ? cell(ratio(srtMs, smMs), 2) : "") << " | " << (frt ? cell(ratio(frtMs, srtMs), 2) : "") << " | "
          << cell(srt["pip_fraction"], 2, 100.0) << " | " << (bound > 0.0 ? cell(bound, 2) : "") << " | "
          << (bound > 0.0 ? cell(ratio(srtMs, bound), 2) : "") << " |\n";
    }
  }
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

void printSweepSummary(const nlohmann::json& rows, std::ostream& out) {
  out << std::left << std::setw(22) << "scene" << std::setw(7) << "light" << std::setw(30) << "configuration" << std::right
      << std::setw(10) << "ms" << std::setw(16) << "min-max" << std::setw(8) << "pip %" << std::setw(10) << "wrong %"
      << std::setw(10) << "rmse" << std::setw(12) << "temporal" << "\n";
  for (const nlohmann::json& r : rows) {
    std::ostringstream spread, pip, wrong, rmse, temporal;
    spread << std::fixed << std::setprecision(1) << r["time_min_ms"].get<double>() << "-" << r["time_max_ms"].get<double>();
    if (r["pip_fraction"].is_null()) pip << "-";
    else pip << std::fixed << std::setprecision(2) << 100.0 * r["pip_fraction"].get<double>();
    if (r["error"].is_null()) wrong << "-", rmse << "-";
    else {
      wrong << std::fixed << std::setprecision(3) << 100.0 * r["error"]["wrong_pixel_fraction"].get<double>();
      rmse << std::fixed << std::setprecision(4) << r["error"]["rmse"].get<double>();
    }
    if (!r.contains("temporal_change") || r["temporal_change"].is_null()) temporal << "-";
    else temporal << std::setprecision(3) << std::scientific << r["temporal_change"].get<double>();
    out << std::left << std::setw(22) << r["scene"].get<std::string>() << std::setw(7) << shortNumber(r["light_size"].get<float>())
        << std::setw(30) << r["label"].get<std::string>() << std::right << std::fixed << std::setprecision(1) << std::setw(10)
        << r["time_ms"].get<double>() << std::setw(16) << spread.str() << std::setw(8) << pip.str() << std::setw(10)
        << wrong.str() << std::setw(10) << rmse.str() << std::setw(12) << temporal.str() << "\n";
  }
}

}  // namespace penumbra
