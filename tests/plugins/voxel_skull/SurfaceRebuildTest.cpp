// SkullSurfaceRebuild: a mesh back-end's drilled surface rebuilt off the
// haptic thread, in a second copy the haptic loop adopts. Checked against an
// independent extraction: once the drill stops and the rebuild has caught
// up, both copies hold exactly the isosurface of the codes the skull ends
// with (the same extraction run afresh on them), so no edit was lost or
// applied twice; the haptic loop rebuilt nothing itself; a scene with the
// component runs unchanged on the native back-end (idle, with a note); and
// two readers of the skull's edits (an exporter and the rebuild) each get
// every edit.
#include <gtest/gtest.h>

#include "framework/core/Diagnostics.h"
#include "framework/data/IsoSurface.h"
#include "framework/geometry/ClosestPoint.h"
#include "plugins/voxel_skull/MeshVoxelBackend.h"
#include "plugins/voxel_skull/VoxelSkull.h"
#include "tests/support/TestSupport.h"

#include <random>
#include <unordered_map>

namespace trephine::voxel {
namespace {

// The burr feeds into a cortical half-space (30 mm, 0.5 mm voxels) with the pedal held from
// 0.2 s to 0.7 s; the run goes on to 1.0 s, so the rebuild catches up.
std::string drilledSkull(const std::string& backend, bool rebuild) {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  )" + (backend == "native" ? std::string() : "<RequiredPlugin name=\"" + backend + "\"/>") +
         R"(
  <Node name="patient">
    <VoxelSkull name="skull" file="phantom:halfspace?voxel=0.5&amp;density=1500&amp;size=30" isovalue="400" drill="true" backend=")" +
         backend + R"("/>
    )" + (rebuild ? R"(<SkullSurfaceRebuild name="rebuild" skull="@skull" rate="200"/>)" : "") + R"(
  </Node>
  <ScriptedDevice name="device" record="false" path="drill-in" target="@/patient/skull" direction="0 0 -1"
                  tipOffset="2.5" standoff="3" speed="20" depth="2" feedSpeed="2.0" buttonTimes="0.2 0.7"/>
  <PointshellTool name="burr" radius="2.5" angleStep="10" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@/patient/skull" sweep="cylinder" drillButton="1"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" damping="0.002" maxForce="3.3"/>
</Node>)";
}

std::unique_ptr<Simulation> load(const std::string& xml, Diagnostics& d, double duration = 1.0) {
  SimulationOptions options;
  options.duration = duration;
  return test::loadScene(xml, d, options);
}

void expectSameSurface(const TriangleBlocks& a, const TriangleBlocks& b, const std::string& what) {
  ASSERT_EQ(a.blockCount(), b.blockCount()) << what;
  size_t differing = 0;
  for (size_t i = 0; i < a.blockCount(); ++i) {
    const TriangleMesh &x = a.block(i), &y = b.block(i);
    differing += x.vertices != y.vertices || x.triangles != y.triangles;
  }
  EXPECT_EQ(differing, 0u) << what << ": blocks that differ from a fresh extraction of the final codes";
}

TEST(SurfaceRebuildTest, BothCopiesEndAsTheIsosurfaceOfTheDrilledCodes) {
#ifndef TREPHINE_HAS_MESH_BACKENDS
  GTEST_SKIP() << "the bullet plugin is not built";
#endif
  // Bullet alone stands for the mesh back-ends in this process: Embree's
  // worker threads trip LeakSanitizer's tracer under the sanitizer build
  // (the Embree path is the same adapter, run by the program's tests).
  Diagnostics d;
  auto simulation = load(drilledSkull("bullet", true), d);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  ASSERT_TRUE(simulation->complete());
  const auto* skull = dynamic_cast<const VoxelSkull*>(simulation->scene().findComponent("/patient/skull"));
  ASSERT_NE(skull, nullptr);
  EXPECT_GT(test::componentCounter(*simulation, "VoxelSkull", "removed_bone_mm3"), 0.3) << "it drilled";
  const MeshVoxelBackend* mesh = skull->meshBackend();
  ASSERT_NE(mesh, nullptr);
  ASSERT_TRUE(mesh->keepsSecondCopy());
  // The independent check: the same extraction, afresh, on the final codes.
  BlockedIsoSurface fresh;
  fresh.build(skull->grid());
  expectSameSurface(mesh->surface(0), fresh, "copy 0");
  expectSameSurface(mesh->surface(1), fresh, "copy 1");
  // Every edit went to the rebuild, and the haptic loop rebuilt nothing: each
  // block rebuild was the rebuild's (its copies alternate).
  const double rebuilds = test::componentCounter(*simulation, "SkullSurfaceRebuild", "rebuilds");
  EXPECT_GE(rebuilds, 4);
  EXPECT_EQ(test::componentCounter(*simulation, "SkullSurfaceRebuild", "edits_dropped"), 0);
  EXPECT_GT(test::componentCounter(*simulation, "SkullSurfaceRebuild", "edits_followed"), 0);
  EXPECT_EQ(test::componentCounter(*simulation, "VoxelSkull", "surface_copies"), 2);
  const HapticStats s = simulation->hapticLog().stats();
  EXPECT_EQ(s.nanFrames, 0u);
  EXPECT_EQ(s.forceReversals, 0u);
}

TEST(SurfaceRebuildTest, TheSurfaceLagsTheDrillByNoMoreThanTheRebuildsPeriod) {
#ifndef TREPHINE_HAS_MESH_BACKENDS
  GTEST_SKIP() << "the bullet plugin is not built";
#endif
  // The same drilling with the blocks rebuilt in the haptic frame: the
  // removal may differ only by what a few frames of lag change (the burr
  // meets bone already cut for up to 5 ms), not by a lost region.
  Diagnostics d1, d2;
  auto deferred = load(drilledSkull("bullet", true), d1);
  auto inFrame = load(drilledSkull("bullet", false), d2);
  ASSERT_TRUE(deferred && inFrame) << test::messages(d1) << test::messages(d2);
  deferred->run();
  inFrame->run();
  const double a = test::componentCounter(*deferred, "VoxelSkull", "removed_bone_mm3");
  const double b = test::componentCounter(*inFrame, "VoxelSkull", "removed_bone_mm3");
  RecordProperty("removed_deferred_mm3", std::to_string(a));
  RecordProperty("removed_in_frame_mm3", std::to_string(b));
  EXPECT_GT(b, 0.3);
  EXPECT_NEAR(a, b, 0.1 * b);
  EXPECT_EQ(test::componentCounter(*inFrame, "VoxelSkull", "surface_copies"), 1);
  EXPECT_GT(test::componentCounter(*inFrame, "VoxelSkull", "rebuilt_blocks"), 0);
}

TEST(SurfaceRebuildTest, OnTheNativeBackEndTheSceneRunsAndTheRebuildIsIdle) {
  Diagnostics d;
  auto simulation = load(drilledSkull("native", true), d, 0.5);
  ASSERT_TRUE(simulation) << test::messages(d);
  EXPECT_EQ(d.errorCount(), 0);
  EXPECT_NE(test::messages(d).find("uses the native back-end, which reads the drilled codes themselves, so this "
                                   "component does nothing"),
            std::string::npos)
      << test::messages(d);
  simulation->run();
  EXPECT_TRUE(simulation->complete());
  EXPECT_EQ(test::componentCounter(*simulation, "SkullSurfaceRebuild", "idle"), 1);
  EXPECT_EQ(test::componentCounter(*simulation, "SkullSurfaceRebuild", "rebuilds"), 0);
}

TEST(SurfaceRebuildTest, TwoRebuildsOfOneSkullAreRefused) {
#ifndef TREPHINE_HAS_MESH_BACKENDS
  GTEST_SKIP() << "the bullet plugin is not built";
#endif
  std::string xml = drilledSkull("bullet", true);
  const std::string rebuild = R"(<SkullSurfaceRebuild name="rebuild" skull="@skull" rate="200"/>)";
  xml.insert(xml.find(rebuild), R"(<SkullSurfaceRebuild name="again" skull="@skull" rate="100"/>)");
  Diagnostics d;
  EXPECT_FALSE(load(xml, d));
  EXPECT_NE(test::messages(d).find("another component already rebuilds the surface of /patient/skull"),
            std::string::npos)
      << test::messages(d);
}

TEST(SurfaceRebuildTest, EveryReaderOfTheEditsGetsEveryEdit) {
  // Two readers on one skull (an exporter and a rebuild, say): each queue
  // receives every lowered code, in order (one reader used to replace the other).
  Diagnostics d;
  auto simulation = load(drilledSkull("native", false), d, 0.8);
  ASSERT_TRUE(simulation) << test::messages(d);
  auto* skull = const_cast<VoxelSkull*>(
      dynamic_cast<const VoxelSkull*>(simulation->scene().findComponent("/patient/skull")));
  ASSERT_NE(skull, nullptr);
  auto first = std::make_shared<ChangeQueue<VoxelEdit>>(size_t(1) << 20);
  auto second = std::make_shared<ChangeQueue<VoxelEdit>>(size_t(1) << 20);
  skull->recordEdits(first);
  skull->recordEdits(second);
  simulation->run();
  std::vector<VoxelEdit> a, b;
  first->drain([&](const VoxelEdit& e) { a.push_back(e); });
  second->drain([&](const VoxelEdit& e) { b.push_back(e); });
  EXPECT_GT(a.size(), 10u);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].voxel, b[i].voxel) << i;
    ASSERT_EQ(a[i].code, b[i].code) << i;
  }
  // The last edit of each voxel is its final code.
  std::unordered_map<int64_t, VoxelCode> last;
  for (const VoxelEdit& e : a) last[e.voxel] = e.code;
  for (const auto& [voxel, code] : last) EXPECT_EQ(skull->grid().codes[voxel], code) << voxel;
}

TEST(SegmentTriangleDistanceTest, MatchesADenseSamplingOfBoth) {
  // Random segments and triangles (some crossing, some degenerate): the
  // distance is never above the closest pair found by sampling both densely,
  // and within the sampling's resolution of it.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto point = [&] { return Vec3(u(random), u(random), u(random)); };
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 p = point(), q = trial % 10 == 0 ? p : point();
    const Vec3 a = point(), b = point(), c = trial % 17 == 0 ? a : point();
    const double d = segmentTriangleDistance(p, q, a, b, c);
    double sampled = std::numeric_limits<double>::infinity();
    constexpr int kAlong = 60;
    for (int i = 0; i <= kAlong; ++i) {
      const Vec3 x = p + (double(i) / kAlong) * (q - p);
      sampled = std::min(sampled, (closestOnTriangle(x, a, b, c) - x).norm());
    }
    ASSERT_LE(d, sampled + 1e-12) << trial;
    // The sampling steps along the segment by |pq| / 60: within that of the truth.
    ASSERT_GE(d, sampled - (q - p).norm() / kAlong - 1e-12) << trial;
  }
  // A segment through a triangle's face: 0; one parallel above it: its height.
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(segmentTriangleDistance({0.2, 0.2, -1}, {0.2, 0.2, 1}, a, b, c), 0.0);
  EXPECT_NEAR(segmentTriangleDistance({-1, 0.2, 0.3}, {2, 0.2, 0.3}, a, b, c), 0.3, 1e-12);
}

}  // namespace
}  // namespace trephine::voxel
