// The penumbra command as a user meets it: help for every command, one clear line and a non-zero
// exit for bad input with no partial output, the promised files, and reproducible views.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "core/image_io.h"
#include "gpu/timer.h"
#include "hybrid/frame_output.h"
#include "raster/shadow_map_pass.h"
#include "hybrid/registry.h"
#include "render_fixture.h"

namespace fs = std::filesystem;

namespace {

using penumbra::test::slurp;
using Result = penumbra::test::CliResult;
using Cli = penumbra::test::CliTest;

TEST_F(Cli, HelpForEveryCommand) {
  for (const auto& [command, option] : {std::pair{"render", "--method"}, std::pair{"compare", "--methods"}}) {
    const Result r = run(std::string(command) + " --help");
    EXPECT_EQ(r.exitCode, 0) << command;
    EXPECT_NE(r.out.find(option), std::string::npos) << command;
    EXPECT_NE(r.out.find("--scene"), std::string::npos) << command;
  }
  EXPECT_EQ(run("--help").exitCode, 0);
  const Result render = run("render --help");
  for (const char* option : {"--ls-shadows", "--linespace-n"}) EXPECT_NE(render.out.find(option), std::string::npos) << option;
}

// docs/options.md is what `penumbra options` prints from the declarations, so the reference stays
// true; every declared option is in it.
TEST_F(Cli, OptionsPageIsTheDeclarationsOutput) {
  const std::filesystem::path page = std::filesystem::path(PENUMBRA_SOURCE_DIR) / "docs" / "options.md";
  if (!std::filesystem::exists(PENUMBRA_SOURCE_DIR)) GTEST_SKIP() << "no source tree here (the bundle's clean root)";
  const Result r = run("options");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.out, slurp(page))
      << "docs/options.md is stale; regenerate it: build/bin/penumbra options > docs/options.md";
  for (const penumbra::Option<penumbra::RenderSettings>& o : penumbra::renderOptions().all()) {
    EXPECT_NE(r.out.find("`" + o.name.substr(0, o.name.find(',')) + "`"), std::string::npos) << o.name;
  }
}

TEST_F(Cli, BadInputIsOneClearLineAndNoOutput) {
  const std::string out = (dir_ / "out").string();
  const std::pair<std::string, std::string> cases[] = {
      {"render --method sm --scene /nonexistent/model.glb", "not found"},
      {"render --method nosuch --scene builtin:square", "unknown method"},
      {"render --method sm --scene builtin:nosuch", "nosuch"},
      {"render --method sm --scene builtin:square --res 12by4", "--res"},
      {"render --method sm --scene builtin:square --light-size 0.1", "rect"},
      {"render --method sm --scene builtin:square --light spot:1,2", "spot:1,2"},
      {"render --method sm --scene builtin:square --spp 0", "--spp"},
      {"render --method sm --scene builtin:square --pcf-kernel 7x7", "--pcf-kernel"},
      {"render --method sm --scene builtin:square --view /nonexistent/view.json", "view.json"},
      {"compare --methods , --scene builtin:square", "--methods"},
      {"compare --methods srt --tracer nosuch --scene builtin:square", "--tracer"},
      {"compare --methods ao --tracer ls --scene builtin:square", "--tracer"},
      {"compare --methods srt,ao --tracer bvh,embree --scene builtin:square", "lists are for ao and indirect"},
      {"render --method ao --indirect-rays 0 --scene builtin:square", "--indirect-rays"},
      {"render --method ao --ao-radius -1 --scene builtin:square", "--ao-radius"},
      {"tune --scene builtin:square --methods sm,ao --max-error 0.1", "apart from the shadow methods"},
      {"render --method srt --ray-intervals maybe --scene builtin:square", "--ray-intervals"},
      {"render --method srt --thin-width -1 --scene builtin:square", "--thin-width"},
      {"render --method ls --ls-shadows maybe --scene builtin:square", "--ls-shadows"},
      {"render --method srt --tracer ls --ls-shadows Exact --scene builtin:square",
       "'Exact' is not one of binary, exact"},
      {"render --method ls --linespace-n 3 --scene builtin:square", "--linespace-n '3'"},
      {"render --method ao --tracer ntree-ls --ntree-ls-depth 3 --scene builtin:square", "--ntree-ls-depth 3"},
      {"render --method ls --linespace-budget -5 --scene builtin:square", "--linespace-budget '-5'"},
      {"render --method bitmask --scene builtin:courtyard --light-size 0.1 --bitmask-receivers a,b,c,d,e",
       "names more than 4"},
      {"bench --scenes builtin:square --methods sm --shard 3/2", "--shard"},
      {"bench --merge /nonexistent/shard1,/nonexistent/shard2", "--merge"},
      {"render --method bitmask --scene builtin:courtyard", "area light"},
      {"render --method bitmask --scene builtin:courtyard --light-size 0.1 --bitmask-receivers nosuch", "nosuch"},
      {"visibility --scene builtin:square --from 0,1,0:1,0,0:0,0,1 --to 0,0,0:1,0,0:0,0,1 --samples 8x4", "--samples"},
      {"visibility --scene builtin:square --from 0,1,0:1,0,0:1,0,1 --to 0,0,0:1,0,0:0,0,1", "perpendicular"},
  };
  // Refused before allocating, naming the limit applied (half of this machine's memory) and the option
  // that lowers the largest term; each where its estimate is over that limit: the 16384^2 frame with
  // 16384^2 maps needs over 60 GB, the maps alone over 25 GB, courtyard:512's geometry over 17 GB.
  std::vector<std::pair<std::string, std::string>> refused;
  const std::uint64_t memory = std::uint64_t(sysconf(_SC_PHYS_PAGES)) * std::uint64_t(sysconf(_SC_PAGE_SIZE));
  const auto refusedBelow = [&](std::uint64_t gb, const std::string& args, const std::string& mention) {
    if (memory / 2 < gb * 1'000'000'000ull) {
      refused.emplace_back(args, mention);
    } else {
      std::cout << "not refused on this machine (" << (memory >> 30) << " GiB): " << args << "\n";
    }
  };
  refusedBelow(60, "render --method sm --scene builtin:square --res 16384x16384 --shadow-map-res 16384", "lower --res");
  refusedBelow(25, "render --method sm --scene builtin:square --res 64x64 --shadow-map-res 16384", "lower --shadow-map-res");
  refusedBelow(25, "render --method sm --scene builtin:square --res 64x64 --shadow-map-res 16384", "half of this machine's");
  refusedBelow(17, "render --method sm --scene builtin:courtyard:512", "73741720 triangles");  // before it is built
  std::vector<std::pair<std::string, std::string>> all(std::begin(cases), std::end(cases));
  all.insert(all.end(), refused.begin(), refused.end());
  for (const auto& [args, mention] : all) {
    const Result r = run(args + " --out " + out);
    EXPECT_NE(r.exitCode, 0) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ":\n" << r.err;
    EXPECT_EQ(r.err.rfind("penumbra: ", 0), 0u) << args << ": " << r.err;
    EXPECT_NE(r.err.find(mention), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << args << " left partial output";
  }
}

// penumbra visibility: the fraction of unblocked pairs, printed and in visibility.json, with its images.
TEST_F(Cli, VisibilityWritesTheFractionAndItsImages) {
  const std::string out = (dir_ / "vis").string();
  const Result r = run("visibility --scene builtin:courtyard --from=-2,3,-2:4,0,0:0,0,4 --to=-3,0,-3:6,0,0:0,0,6 "
                       "--samples 8x8 --validate --out " + out);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("unblocked pairs"), std::string::npos) << r.out;
  const auto json = nlohmann::json::parse(slurp(dir_ / "vis" / "visibility.json"));
  EXPECT_EQ(json["pairs"].get<std::uint64_t>(), 64u * 64u);
  const double fraction = json["unblocked_fraction"].get<double>();
  EXPECT_GT(fraction, 0.2);  // the courtyard's casters block some pairs, not most
  EXPECT_LT(fraction, 1.0);
  EXPECT_TRUE(fs::exists(dir_ / "vis" / "visibility.png"));
  EXPECT_TRUE(fs::exists(dir_ / "vis" / "mask.png"));
}

TEST_F(Cli, RenderWritesImagesVisibilityAndStats) {
  const Result r = run("render --method pcf --scene builtin:square --res 64x48 --shadow-map-res 256 --validate --out " +
                       (dir_ / "out").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  for (const char* file : {"pcf.png", "pcf.visibility.exr", "pcf.visibility.png", "pcf.stats.json"}) {
    EXPECT_TRUE(fs::exists(dir_ / "out" / file)) << file;
  }
  int w = 0, h = 0;
  EXPECT_EQ(penumbra::readExrGray((dir_ / "out" / "pcf.visibility.exr").string(), w, h).size(), 64u * 48u);
  EXPECT_EQ(w, 64);
  const auto stats = nlohmann::json::parse(slurp(dir_ / "out" / "pcf.stats.json"));
  EXPECT_EQ(stats["method"], "pcf");
  EXPECT_TRUE(stats["tracer"].is_null());
  EXPECT_TRUE(stats["pip_fraction"].is_null());
  double passes = 0.0;  // the frame's passes fit in its total
  for (const auto& [name, ms] : stats["time_ms"].items()) {
    if (name.rfind("total", 0) != 0 && name != "runs") passes += ms.get<double>();
  }
  EXPECT_GT(passes, 0.0);
  EXPECT_LE(passes, stats["time_ms"]["total"].get<double>() * 1.001 + 0.01);
  EXPECT_TRUE(stats["time_ms"].contains("shadow_map"));
  EXPECT_EQ(stats["context"]["resolution"], nlohmann::json::array({64, 48}));
}

TEST_F(Cli, CompareWritesMetricsAndHeatmaps) {
  const Result r = run("compare --methods sm,pcf --scene builtin:square --res 64x64 --shadow-map-res 512 --no-report --out " +
                       (dir_ / "out").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto metrics = nlohmann::json::parse(slurp(dir_ / "out" / "metrics.json"));
  EXPECT_EQ(metrics["reference"]["method"], "ref");
  EXPECT_EQ(metrics["reference"]["tracer"], "embree");
  EXPECT_GT(metrics["reference"]["rays_traced"].get<long>(), 0);
  EXPECT_GT(metrics["reference"]["setup_ms"]["embree_build"].get<double>(), 0.0) << "build time survives the warm-up frame";
  ASSERT_EQ(metrics["methods"].size(), 2u);
  for (const auto& m : metrics["methods"]) {
    const std::string name = m["method"];
    EXPECT_TRUE(fs::exists(dir_ / "out" / (name + ".heatmap.png"))) << name;
    EXPECT_TRUE(fs::exists(dir_ / "out" / (name + ".png"))) << name;
    for (const char* field : {"rmse", "mae", "max", "wrong_pixel_fraction"}) {
      EXPECT_TRUE(m["error"][field].is_number()) << name << " " << field;
    }
    EXPECT_LT(m["error"]["wrong_pixel_fraction"].get<double>(), 0.05) << name;
  }
  EXPECT_TRUE(fs::exists(dir_ / "out" / "ref.png"));
  // Written in a staging folder beside it and moved in whole: none is left behind.
  for (const fs::directory_entry& e : fs::directory_iterator(dir_)) {
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
  }
}

// ao and indirect on a list of tracers, each against its own Embree reference (same rays).
TEST_F(Cli, CompareAoAndIndirectAgainstTheirOwnReferences) {
  const Result r = run("compare --methods ao,indirect,sm --tracer bvh --scene builtin:courtyard:2 --res 48x48 "
                       "--indirect-rays 4 --no-report --out " + (dir_ / "out").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto metrics = nlohmann::json::parse(slurp(dir_ / "out" / "metrics.json"));
  ASSERT_EQ(metrics["references"].size(), 3u);
  std::set<std::string> references;
  for (const auto& ref : metrics["references"]) references.insert(ref["method"].get<std::string>());
  EXPECT_EQ(references, (std::set<std::string>{"ao-embree", "indirect-embree", "ref"}));
  ASSERT_EQ(metrics["methods"].size(), 3u);
  for (const auto& m : metrics["methods"]) {
    const std::string name = m["method"];
    EXPECT_TRUE(fs::exists(dir_ / "out" / (name + ".heatmap.png"))) << name;
    if (name == "sm") continue;
    EXPECT_EQ(m["tracer"], "bvh") << name;
    EXPECT_EQ(m["error"]["wrong_pixel_fraction"].get<double>(), 0.0) << name << ": the same rays as its reference";
  }
}

// Every GPU tracer of ao and indirect in one compare (issue 19: ntree, ntree-ls): each against its
// term's reference, with its heatmap; the exact ones (bvh, ntree) equal it.
TEST_F(Cli, CompareAoAndIndirectOnEveryTracer) {
  const Result r = run("compare --scene builtin:courtyard:2 --res 48x48 --methods ao,indirect --tracer "
                       "bvh,bvh-ls,ntree,ntree-ls --indirect-rays 4 --no-report --out " + (dir_ / "out").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto metrics = nlohmann::json::parse(slurp(dir_ / "out" / "metrics.json"));
  ASSERT_EQ(metrics["methods"].size(), 8u);
  for (const auto& m : metrics["methods"]) {
    const std::string name = m["method"];
    EXPECT_TRUE(fs::exists(dir_ / "out" / (name + ".heatmap.png"))) << name;
    if (m["tracer"] == "bvh" || m["tracer"] == "ntree") {
      EXPECT_EQ(m["error"]["wrong_pixel_fraction"].get<double>(), 0.0) << name << ": exact";
    }
  }
}

// A sweep split in shards (bench --shard K/N, issue 20) and merged gives the rows of one run, in
// its order, with the same fields and images; a merge missing a shard, or mixing sweeps, is refused.
TEST_F(Cli, BenchShardsMergeIntoOneRun) {
  const std::string sweep = "bench --scenes builtin:square --methods sm,pcf --pcf-kernel 3x3,5x5 --res 32x32 --repeat 1 "
                            "--warmup 0 --temporal-frames 0 --no-report";
  const fs::path one = dir_ / "one", a = dir_ / "a", b = dir_ / "b", merged = dir_ / "merged";
  ASSERT_EQ(run(sweep + " --out " + one.string()).exitCode, 0);
  ASSERT_EQ(run(sweep + " --shard 1/2 --out " + a.string()).exitCode, 0);
  ASSERT_EQ(run(sweep + " --shard 2/2 --out " + b.string()).exitCode, 0);
  const Result m = run("bench --no-report --merge " + a.string() + "," + b.string() + " --out " + merged.string());
  ASSERT_EQ(m.exitCode, 0) << m.err;
  const auto whole = nlohmann::json::parse(slurp(one / "bench.json")), parts = nlohmann::json::parse(slurp(merged / "bench.json"));
  const auto shardA = nlohmann::json::parse(slurp(a / "bench.json"));
  EXPECT_LT(shardA["rows"].size(), whole["rows"].size());  // a shard measures only its share
  ASSERT_EQ(parts["rows"].size(), whole["rows"].size());
  for (std::size_t i = 0; i < whole["rows"].size(); ++i) {
    const auto &w = whole["rows"][i], &p = parts["rows"][i];
    EXPECT_EQ(p["label"], w["label"]) << i;
    EXPECT_EQ(p["images"], w["images"]) << i;
    for (const auto& [key, value] : w.items()) EXPECT_TRUE(p.contains(key)) << i << " " << key;
    for (const char* exact : {"pip_fraction", "rays_traced", "error"}) EXPECT_EQ(p[exact], w[exact]) << i << " " << exact;
  }
  EXPECT_FALSE(parts.contains("shard"));
  EXPECT_TRUE(fs::exists(merged / "bench.csv"));
  for (const auto& r : whole["rows"]) {
    for (const auto& [kind, image] : r["images"].items()) EXPECT_TRUE(fs::exists(merged / image.get<std::string>())) << image;
  }
  const Result missing = run("bench --no-report --merge " + a.string() + " --out " + (dir_ / "m2").string());
  EXPECT_NE(missing.exitCode, 0);
  EXPECT_NE(missing.err.find("shard 2/2 is missing"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir_ / "m2")) << "a refused merge writes nothing";
  const Result twice = run("bench --no-report --merge " + a.string() + "," + a.string() + " --out " + (dir_ / "m3").string());
  EXPECT_NE(twice.err.find("named twice"), std::string::npos) << twice.err;
}

// bench's tables.md (readable where no Python is, e.g. on a GPU machine): a Fig. 8 row per srt
// configuration whose model bound is the sm frame plus srt's PIP share of frt's trace pass, as
// recomputed here from bench.json.
TEST_F(Cli, BenchTablesHoldFig8WithTheModelBound) {
  const fs::path out = dir_ / "out";
  const Result r = run("bench --scenes builtin:courtyard --methods sm,srt,frt --tracer bvh --res 64x64 --repeat 1 --warmup 0 "
                       "--temporal-frames 0 --no-report --no-images --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto bench = nlohmann::json::parse(slurp(out / "bench.json"));
  const nlohmann::json *sm = nullptr, *srt = nullptr, *frt = nullptr;
  for (const auto& row : bench["rows"]) {
    if (row["method"] == "sm") sm = &row;
    if (row["method"] == "srt") srt = &row;
    if (row["method"] == "frt") frt = &row;
  }
  ASSERT_TRUE(sm && srt && frt);
  const double bound = (*sm)["time_ms"].get<double>() +
                       (*srt)["pip_fraction"].get<double>() * (*frt)["passes"]["trace"].get<double>();
  const std::string tables = slurp(out / "tables.md");
  const std::size_t fig8 = tables.find("## Lauterbach et al. 2009, Fig. 8 shape");
  ASSERT_NE(fig8, std::string::npos) << tables;
  const std::size_t row = tables.find("| builtin:courtyard | 64x64 | 0 | 1 | bvh | off |", fig8);
  ASSERT_NE(row, std::string::npos) << tables;
  std::vector<std::string> cells;
  std::stringstream line(tables.substr(row + 1, tables.find('\n', row) - row - 1));
  for (std::string c; std::getline(line, c, '|');) cells.push_back(c.substr(1, c.size() - 2));
  ASSERT_GE(cells.size(), 13u) << line.str();
  EXPECT_NEAR(std::stod(cells[6]), (*sm)["time_ms"].get<double>(), 0.006);  // sm, srt, frt, ..., bound
  EXPECT_NEAR(std::stod(cells[7]), (*srt)["time_ms"].get<double>(), 0.006);
  EXPECT_NEAR(std::stod(cells[8]), (*frt)["time_ms"].get<double>(), 0.006);
  EXPECT_NEAR(std::stod(cells[12]), bound, 0.006);
  EXPECT_NE(tables.find("| builtin:courtyard | " + (*srt)["triangles"].dump() + " | 64x64 | 0 | srt |"), std::string::npos)
      << "every configuration's row";
}

// penumbra device: the device the renderer uses and what each `auto` setting resolves to there,
// as the library itself resolves them; the same JSON in --out.
TEST_F(Cli, DeviceNamesItsDeviceAndAutoChoices) {
  const Result r = run("device --validate --out " + (dir_ / "device.json").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto info = nlohmann::json::parse(r.out);
  EXPECT_EQ(info, nlohmann::json::parse(slurp(dir_ / "device.json")));
  penumbra::gpu::Context& context = penumbra::test::validatedContext();
  const auto& device = info["device"];
  EXPECT_EQ(device["name"], context.deviceName());
  EXPECT_EQ(device["driver"], context.driverInfo());
  EXPECT_EQ(device["ray_query"], context.rayQuery());
  EXPECT_EQ(device["auto"]["tracer"], penumbra::resolveTracer(context, "auto"));
  EXPECT_EQ(device["auto"]["shadow_reads"], penumbra::raster::bufferReads(context, {}) ? "buffer" : "texture");
  EXPECT_EQ(device["auto"]["timer"], penumbra::gpu::toString(penumbra::gpu::defaultTimerMode(context)));
  EXPECT_EQ(device["limits"]["max_storage_buffer_range"], context.storageBufferRange());
  EXPECT_TRUE(info["validation_messages"].empty());
  bool listed = false;
  for (const auto& d : info["devices"]) listed |= d["name"] == device["name"] && d["unusable"].is_null();
  EXPECT_TRUE(listed) << info["devices"];
}

// bench --resume (issue 20): a sweep killed after its first group keeps that group's results
// (its rows come back exactly, times included) and runs only the rest; other options are refused.
TEST_F(Cli, BenchResumesAKilledSweep) {
  const fs::path out = dir_ / "out";
  const std::string sweep = "bench --scenes builtin:square,builtin:wires --methods sm --res 32x32 --repeat 1 --warmup 0 "
                            "--temporal-frames 0 --no-report --no-images --out " + out.string();
  ASSERT_EQ(run(sweep).exitCode, 0);
  const auto first = nlohmann::json::parse(slurp(out / "bench.json"))["rows"];
  ASSERT_EQ(first.size(), 4u);  // per group: the reference and sm
  fs::remove(out / "rows" / "group1.json");  // killed during the second group
  fs::remove(out / "bench.json");
  const Result resumed = run(sweep + " --resume");
  ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
  const auto rows = nlohmann::json::parse(slurp(out / "bench.json"))["rows"];
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0], first[0]);
  EXPECT_EQ(rows[1], first[1]);
  EXPECT_EQ(rows[2]["group"], 1);
  EXPECT_EQ(rows[3]["scene"], "builtin:wires");
  EXPECT_TRUE(fs::exists(out / "rows" / "group1.json"));
  const Result other = run("bench --scenes builtin:square,builtin:wires --methods sm,pcf --res 32x32 --repeat 1 --warmup 0 "
                           "--temporal-frames 0 --no-report --no-images --resume --out " + out.string());
  EXPECT_NE(other.exitCode, 0);
  EXPECT_NE(other.err.find("other options"), std::string::npos) << other.err;
}

// A run's output folder is written whole or not at all (issue 20): what a run that stops before
// commit() wrote disappears, and committing moves every file, in subfolders too.
TEST_F(Cli, StagedOutputIsWholeOrNothing) {
  const fs::path out = dir_ / "staged";
  {
    penumbra::StagedOutput staged(out.string());
    std::ofstream(staged.path() + "/a.png") << "a";
    EXPECT_FALSE(fs::exists(out));
  }  // not committed: a failed or interrupted run
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator{}), 0);
  {
    penumbra::StagedOutput staged(out.string() + "/");
    fs::create_directories(staged.path() + "/charts");
    std::ofstream(staged.path() + "/charts/c.png") << "c";
    std::ofstream(staged.path() + "/metrics.json") << "{}";
    staged.commit();
  }
  EXPECT_EQ(slurp(out / "charts" / "c.png"), "c");
  EXPECT_EQ(slurp(out / "metrics.json"), "{}");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator{}), 1);  // out only
}

TEST_F(Cli, SavedViewReproducesTheImageBitForBit) {
  const std::string view = (dir_ / "view.json").string();
  const std::string common = " --method sm --scene builtin:courtyard:2 --shadow-map-res 512";
  ASSERT_EQ(run("render" + common + " --res 80x60 --save-view " + view + " --out " + (dir_ / "a").string()).exitCode, 0);
  ASSERT_TRUE(fs::exists(view));
  const Result r = run("render --view " + view + common + " --out " + (dir_ / "b").string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  int w = 0, h = 0;
  const auto a = penumbra::readExrGray((dir_ / "a" / "sm.visibility.exr").string(), w, h);
  const auto b = penumbra::readExrGray((dir_ / "b" / "sm.visibility.exr").string(), w, h);
  EXPECT_EQ(w, 80);
  EXPECT_EQ(a, b);
}

}  // namespace
