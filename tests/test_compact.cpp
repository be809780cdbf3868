// Compaction against a CPU reference on a real G-buffer (builtin:courtyard:2): tile order,
// positions and normals bit-identical to the G-buffer readback, spp from the frame, rayMax copied,
// the count and the indirect dispatch size. Sizes cross mask-word (32 pixels), subgroup and block
// (8192 pixels) boundaries, and the largest one gives the block scan more blocks than invocations.
#include <gtest/gtest.h>

#include <cstring>
#include <iostream>
#include <memory>
#include <random>
#include <span>

#include "core/camera.h"
#include "core/scene_loader.h"
#include "hybrid/compact_pass.h"
#include "raster/gbuffer_pass.h"
#include "raster/scene_geometry.h"
#include "render_fixture.h"
#include "shared/compact.h"
#include "shared/frame.h"
#include "shared/shading_point.h"
#include "shared/trace.h"

namespace penumbra::test {
namespace {

using shared::ShadingPoint;
using shared::TraceCount;
using Flags = std::vector<std::uint32_t>;

const Scene& courtyard() {
  static const Scene scene = loadScene("builtin:courtyard:2");
  return scene;
}

struct Result {
  TraceCount count;
  std::vector<ShadingPoint> points;
};

// The courtyard's G-buffer at one size (read back), a CompactPass and its inputs.
struct CompactRig {
  static constexpr std::uint32_t kSpp = 3;
  std::uint32_t width, height;
  raster::SceneGeometry geometry;
  raster::GBufferPass gbuffer;
  CompactPass pass;
  gpu::Buffer flags, rayMax, frame;
  std::vector<glm::vec4> positions, normals;
  std::vector<float> rayMaxValues;

  CompactRig(std::uint32_t w, std::uint32_t h)
      : width(w),
        height(h),
        geometry(validatedContext(), courtyard()),
        gbuffer(validatedContext(), courtyard(), w, h),
        pass(validatedContext(), w, h),
        flags(validatedContext(), CompactPass::inputBytes(w, h), vk::BufferUsageFlagBits::eStorageBuffer, "test flags"),
        rayMax(validatedContext(), CompactPass::inputBytes(w, h), vk::BufferUsageFlagBits::eStorageBuffer,
               "test rayMax"),
        frame(validatedContext(), sizeof(shared::FrameData), vk::BufferUsageFlagBits::eStorageBuffer, "test frame") {
    const Scene& scene = courtyard();
    const ViewMatrices view = cameraMatrices(*scene.camera, scene.bounds(), int(w), int(h));
    validatedContext().submitAndWait([&](const vk::raii::CommandBuffer& cmd) {
      gbuffer.record(cmd, geometry, view, scene.camera->eye);
      gbuffer.recordReadback(cmd);
    });
    positions = gbuffer.positions();
    normals = gbuffer.normals();
    // Distinct per pixel, with some zeros (rays to the light), so a misplaced copy shows.
    rayMaxValues.resize(positions.size());
    for (std::size_t i = 0; i < rayMaxValues.size(); ++i)
      rayMaxValues[i] = i % 7 == 0 ? 0.0f : 0.25f + float(i) * 1e-3f;
    rayMax.upload(std::span<const float>(rayMaxValues));
    shared::FrameData data{};
    data.width = w;
    data.height = h;
    data.spp = kSpp;
    pass.describeList(data);  // the scatter writes the list through its address
    frame.upload(std::span<const shared::FrameData>(&data, 1));
  }

  std::size_t pixels() const { return positions.size(); }
  bool covered(std::size_t i) const { return positions[i].w != 0.0f; }

  Result run(const Flags& values, std::uint32_t mode) {
    flags.upload(std::span<const std::uint32_t>(values));
    validatedContext().submitAndWait(
        [&](const vk::raii::CommandBuffer& cmd) { pass.record(cmd, gbuffer, flags, rayMax, frame, mode); });
    Result r;
    r.count = pass.count().download<TraceCount>(1).front();
    r.points = pass.points().download<ShadingPoint>(std::min<std::size_t>(r.count.count, pixels()));
    return r;
  }

  std::vector<ShadingPoint> reference(const Flags& values, std::uint32_t mode) const {
    std::vector<ShadingPoint> out;
    // Tile order (shared/compact.h), written out here independently of compactPixel.
    std::vector<std::size_t> order;
    for (std::uint32_t ty = 0; ty < height; ty += COMPACT_TILE_H)
      for (std::uint32_t tx = 0; tx < width; tx += COMPACT_TILE_W)
        for (std::uint32_t y = ty; y < std::min(ty + COMPACT_TILE_H, height); ++y)
          for (std::uint32_t x = tx; x < std::min(tx + COMPACT_TILE_W, width); ++x) order.push_back(std::size_t(y) * width + x);
    EXPECT_EQ(order.size(), pixels());
    for (std::size_t i : order) {
      if (!covered(i)) continue;  // a flag on an uncovered pixel is ignored
      if ((mode & COMPACT_MODE_MASK) == COMPACT_FLAGGED && values[i] == 0) continue;
      ShadingPoint p{};
      p.position = glm::vec3(positions[i]);
      p.pixel = std::uint32_t(i);
      p.normal = glm::vec3(normals[i]);
      p.spp = kSpp;
      p.rayMax = rayMaxValues[i];
      out.push_back(p);
    }
    return out;
  }

  // Runs the pass and expects exactly the reference list, bit for bit.
  void check(const Flags& values, std::uint32_t mode) {
    const std::vector<ShadingPoint> expected = reference(values, mode);
    const Result got = run(values, mode);
    ASSERT_EQ(got.count.count, expected.size());
    EXPECT_EQ(got.count.groupsX, (expected.size() + TRACE_GROUP_SIZE - 1) / TRACE_GROUP_SIZE);
    EXPECT_EQ(got.count.groupsY, 1u);
    EXPECT_EQ(got.count.groupsZ, 1u);
    for (std::size_t i = 0; i < expected.size(); ++i) {
      if (std::memcmp(&got.points[i], &expected[i], sizeof(ShadingPoint)) != 0) {
        ADD_FAILURE() << "point " << i << " differs: got pixel " << got.points[i].pixel << " spp " << got.points[i].spp
                      << " rayMax " << got.points[i].rayMax << ", expected pixel " << expected[i].pixel << " rayMax "
                      << expected[i].rayMax;
        return;
      }
    }
  }
};

// One rig at a time: the parameterized sizes each build their own; the timing test reuses 1024^2.
CompactRig& rigFor(std::uint32_t width, std::uint32_t height) {
  // Dynamically initialized after the context (which CompactRig's constructor makes), so destroyed first.
  static std::unique_ptr<CompactRig> rig = std::make_unique<CompactRig>(width, height);
  if (rig->width != width || rig->height != height) {
    rig.reset();
    rig = std::make_unique<CompactRig>(width, height);
  }
  return *rig;
}

Flags randomFlags(std::size_t n, double density, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Flags f(n);
  for (auto& v : f) v = u(rng) < density ? 1u + rng() % 1000u : 0u;  // any nonzero value means trace
  return f;
}

struct Pattern {
  const char* name;
  Flags flags;
};

std::vector<Pattern> patterns(std::size_t n) {
  std::vector<Pattern> out;
  out.push_back({"none", Flags(n, 0u)});
  out.push_back({"all", Flags(n, 1u)});
  out.push_back({"random 1%", randomFlags(n, 0.01, 1234u)});
  out.push_back({"random 50%", randomFlags(n, 0.5, 5678u)});
  Flags everyOther(n, 0u);
  for (std::size_t i = 0; i < n; i += 2) everyOther[i] = 0xffffffffu;
  out.push_back({"every other", everyOther});
  Flags last(n, 0u);
  last.back() = 1u;
  out.push_back({"last only", last});
  return out;
}

struct Size {
  std::uint32_t width, height;
};
void PrintTo(const Size& s, std::ostream* os) { *os << s.width << "x" << s.height; }

class CompactSizes : public ::testing::TestWithParam<Size> {};

TEST_P(CompactSizes, MatchesCpuReference) {
  CompactRig& s = rigFor(GetParam().width, GetParam().height);
  for (const Pattern& p : patterns(s.pixels())) {
    SCOPED_TRACE(p.name);
    s.check(p.flags, COMPACT_FLAGGED);
  }
  {
    SCOPED_TRACE("all covered (flags ignored)");
    s.check(randomFlags(s.pixels(), 0.3, 42u), COMPACT_ALL_COVERED);
  }
  {
    // The shared-memory scan is the fallback for drivers whose subgroups do not tile a workgroup.
    SCOPED_TRACE("shared-memory scan");
    s.check(randomFlags(s.pixels(), 0.5, 99u), COMPACT_FLAGGED | COMPACT_SHARED_SCAN);
    s.check(Flags(s.pixels(), 0u), COMPACT_ALL_COVERED | COMPACT_SHARED_SCAN);
  }
  expectValidationSilent();
}

// 91x91 and 2000x1300 end one pixel / partway into a block; 2000x1300 has 318 blocks, more than
// the block scan's 256 invocations (runs of two, the last one short).
INSTANTIATE_TEST_SUITE_P(Compact, CompactSizes,
                         ::testing::Values(Size{1, 1}, Size{7, 5}, Size{91, 91}, Size{1000, 3}, Size{256, 256},
                                           Size{1024, 1024}, Size{2000, 1300}),
                         [](const auto& info) {
                           return std::to_string(info.param.width) + "x" + std::to_string(info.param.height);
                         });

TEST(Compact, AllCoveredListsExactlyTheCoveredPixels) {
  CompactRig& s = rigFor(256, 256);
  std::size_t covered = 0;
  for (std::size_t i = 0; i < s.pixels(); ++i) covered += s.covered(i);
  ASSERT_GT(covered, 0u);
  ASSERT_LT(covered, s.pixels()) << "the view should show some sky, or the coverage test proves nothing";
  const Result r = s.run(Flags(s.pixels(), 0u), COMPACT_ALL_COVERED);
  ASSERT_EQ(r.count.count, covered);
  for (const ShadingPoint& p : r.points) EXPECT_TRUE(s.covered(p.pixel));
  expectValidationSilent();
}

TEST(Compact, FlagsOnUncoveredPixelsAreIgnored) {
  CompactRig& s = rigFor(256, 256);
  Flags uncoveredOnly(s.pixels(), 0u);
  for (std::size_t i = 0; i < s.pixels(); ++i) uncoveredOnly[i] = s.covered(i) ? 0u : 1u;
  const Result r = s.run(uncoveredOnly, COMPACT_FLAGGED);
  EXPECT_EQ(r.count.count, 0u);
  EXPECT_EQ(r.count.groupsX, 0u);
  expectValidationSilent();
}

TEST(Compact, GroupsXRoundsUpToTraceGroups) {
  CompactRig& s = rigFor(256, 256);
  for (std::uint32_t k : {0u, 1u, 63u, 64u, 65u, 128u, 129u}) {
    Flags f(s.pixels(), 0u);
    std::uint32_t flagged = 0;
    for (std::size_t i = 0; i < s.pixels() && flagged < k; ++i) {
      if (s.covered(i)) f[i] = 1u, ++flagged;
    }
    const Result r = s.run(f, COMPACT_FLAGGED);
    EXPECT_EQ(r.count.count, k);
    EXPECT_EQ(r.count.groupsX, (k + TRACE_GROUP_SIZE - 1) / TRACE_GROUP_SIZE) << k << " points";
  }
  expectValidationSilent();
}

TEST(Compact, RejectsBadInput) {
  gpu::Context& context = validatedContext();
  EXPECT_THROW(CompactPass(context, 0, 5), std::invalid_argument);
  EXPECT_THROW(CompactPass(context, 65536, 65536), std::invalid_argument);
  CompactRig& s = rigFor(7, 5);
  const gpu::Buffer small(context, 16, vk::BufferUsageFlagBits::eStorageBuffer, "test small");
  const raster::GBufferPass other(context, Scene{}, 5, 7);
  auto recordWith = [&](const raster::GBufferPass& g, const gpu::Buffer& f, const gpu::Buffer& r, std::uint32_t mode) {
    context.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { s.pass.record(cmd, g, f, r, s.frame, mode); });
  };
  EXPECT_THROW(recordWith(other, s.flags, s.rayMax, COMPACT_FLAGGED), std::invalid_argument);
  EXPECT_THROW(recordWith(s.gbuffer, small, s.rayMax, COMPACT_FLAGGED), std::invalid_argument);
  EXPECT_THROW(recordWith(s.gbuffer, s.flags, small, COMPACT_FLAGGED), std::invalid_argument);
  EXPECT_THROW(recordWith(s.gbuffer, s.flags, s.rayMax, 7u), std::invalid_argument);
  EXPECT_THROW(recordWith(s.gbuffer, s.flags, s.rayMax, COMPACT_FLAGGED | 0x10000u), std::invalid_argument);
  expectValidationSilent();
}

// A list larger than one buffer of the device may hold is refused when recording (a renderer makes
// the pass for every image size; only the methods that trace record it). Exercised on any device
// through a context whose buffers hold at most 1 MiB, where 256x256 points (2 MiB) do not fit.
TEST(Compact, RefusesAListOverOneBuffer) {
  gpu::Context limited({.validate = true, .printMessages = true, .bufferBytesLimit = 1u << 20});
  const std::uint32_t size = 256;
  ASSERT_GT(std::uint64_t(size) * size * sizeof(ShadingPoint), limited.maxBufferBytes());
  const CompactPass pass(limited, size, size);
  const raster::GBufferPass gbuffer(limited, Scene{}, size, size);
  const gpu::Buffer input(limited, CompactPass::inputBytes(size, size), vk::BufferUsageFlagBits::eStorageBuffer, "test input");
  gpu::Buffer frame(limited, sizeof(shared::FrameData), vk::BufferUsageFlagBits::eStorageBuffer, "test frame");
  shared::FrameData data{};
  data.width = size;
  data.height = size;
  pass.describeList(data);
  frame.upload(std::span<const shared::FrameData>(&data, 1));
  std::string message;
  try {
    limited.submitAndWait([&](const vk::raii::CommandBuffer& cmd) { pass.record(cmd, gbuffer, input, input, frame, COMPACT_FLAGGED); });
  } catch (const std::invalid_argument& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("over the 1048576 bytes one buffer of this device holds"), std::string::npos) << message;
  EXPECT_TRUE(limited.validationMessages().empty());
}

}  // namespace
}  // namespace penumbra::test
