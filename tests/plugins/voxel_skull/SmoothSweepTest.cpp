// The line and cylinder sweeps on the smooth surface (VoxelSkull::sweep: all
// probe lines advance together half a voxel a step, the first step where a
// line enters bone ends the sweep, its crossing refined to 1e-5 mm) against a
// brute-force reference written from the sweep's contract: each probe line
// sampled every 1/40 of a voxel, the same start rules (a front line that
// starts in bone blocks at once unless the tool's centre is buried; other
// lines pass the bone they start in), the nearest entry taken.
//
// The sweep may miss bone only where the reference's first entry is a sliver
// the half-voxel samples can straddle (a grazing chord shorter than one
// step); it must never block where no line is in bone, nor before the
// reference's entry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "framework/core/Node.h"
#include "framework/geometry/FrontRings.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/geometry/ShellSampling.h"
#include "plugins/voxel_skull/Phantoms.h"
#include "plugins/voxel_skull/SolidGrid.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

constexpr double kRadius = 2.5;  // mm, burr radius
constexpr double kVoxel = 1.0;   // mm, the phantom's voxels

struct Reference {
  bool blocked = false, startsInside = false;
  double freeFraction = 2.0;
  double entryRun = 0;  // fraction of the path the entered line stays in bone after its entry
  int line = -1;
};

struct ProbeLine {
  Vec3 offset;
  bool front;
};

std::vector<ProbeLine> probeLines(const Vec3& u, SweepProbe probe) {
  std::vector<ProbeLine> lines = {{kRadius * u, true}};
  if (probe == SweepProbe::Cylinder)
    forEachFrontRingPoint(u, kRadius, kVoxel, [&](const Vec3& offset, bool front) {
      lines.push_back({offset, front});
      return false;
    });
  return lines;
}

// The contract, by fine sampling (1/40 voxel) and bisection, on the plain
// interpolation (no occupancy cells).
Reference reference(const voxel::SolidGrid& grid, const SweepQuery& q) {
  Reference r;
  const Vec3 path = q.to - q.from;
  const double length = path.norm();
  const Vec3 u = path / length;
  const bool buried = grid.codeAt(q.from) > grid.isoCode;
  const auto solid = [&](const Vec3& p) { return grid.codeAt(p) > grid.isoCode; };
  const std::vector<ProbeLine> lines = probeLines(u, q.probe);
  for (const ProbeLine& line : lines)
    if (solid(q.from + line.offset) && line.front && !buried) {
      r.blocked = r.startsInside = true;
      r.freeFraction = 0;
      return r;
    }
  const int samples = int(std::ceil(length / (kVoxel / 40))) + 1;
  for (size_t j = 0; j < lines.size(); ++j) {
    const Vec3 a = q.from + lines[j].offset;
    bool skipping = solid(a);
    double previous = 0;
    for (int k = 1; k <= samples; ++k) {
      const double t = double(k) / samples;
      if (!solid(a + t * path)) {
        skipping = false;
        previous = t;
        continue;
      }
      if (skipping) continue;
      double lo = previous, hi = t;
      for (int i = 0; i < 50; ++i) (solid(a + 0.5 * (lo + hi) * path) ? hi : lo) = 0.5 * (lo + hi);
      if (hi < r.freeFraction) {
        r.freeFraction = hi;
        r.line = int(j);
        double end = hi;
        while (end <= 1.0 && solid(a + end * path)) end += 1.0 / samples;
        r.entryRun = end - hi;
      }
      break;
    }
  }
  r.blocked = r.freeFraction <= 1.0;
  return r;
}

// A VoxelSkull on its own (its queries called directly), with a 466-point
// even shell of the burr reserved, as PointshellTool makes it.
struct LoadedSkull {
  std::unique_ptr<Simulation> simulation;
  ShellContactTarget* skull = nullptr;
  std::vector<ShellPoint> shell;
};

LoadedSkull loadSkull(const std::string& file, double isovalue) {
  LoadedSkull loaded;
  Diagnostics d;
  loaded.simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <VoxelSkull name="skull" file=")" + file + R"(" isovalue=")" + std::to_string(isovalue) + R"("/>
</Node>)",
                                      d);
  if (!loaded.simulation) {
    ADD_FAILURE() << test::messages(d);
    return loaded;
  }
  loaded.skull = dynamic_cast<ShellContactTarget*>(loaded.simulation->scene().findComponent("/skull"));
  for (const Vec3& u : evenDirections(466)) loaded.shell.push_back({kRadius * u, -u});
  if (loaded.skull) loaded.skull->reserveShell(loaded.shell);
  return loaded;
}

class SmoothSweepTest : public ::testing::TestWithParam<SweepProbe> {};

TEST_P(SmoothSweepTest, AgreesWithFineSamplingOfEveryProbeLine) {
  const LoadedSkull loaded = loadSkull("phantom:skull?voxel=1.0", 400.0);
  ShellContactTarget* skull = loaded.skull;
  ASSERT_NE(skull, nullptr);
  const std::vector<ShellPoint>& shell = loaded.shell;

  DensityVolume volume = voxel::makeSkullPhantom(kVoxel);
  const voxel::SolidGrid grid = voxel::SolidGrid::of(volume, 400.0, true);  // no cells: the plain interpolation

  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Vec3 centre = grid.corner + 0.5 * Vec3(grid.nx * grid.spacing.x(), grid.ny * grid.spacing.y(),
                                               grid.nz * grid.spacing.z());
  int queries = 0, blocked = 0, startsInside = 0, agreeing = 0, slivers = 0;
  while (queries < 400) {
    // A start near the bone's outer surface (from 1 mm inside to 4 mm out),
    // a move of 0.01 to 6 mm in a random direction: grazing, entering, leaving.
    Vec3 ray(normal(rng), normal(rng), normal(rng));
    ray.normalize();
    Vec3 p = centre + 150.0 * ray;
    while ((p - centre).norm() > 1.0 && !(grid.codeAt(p) > grid.isoCode)) p -= 0.05 * ray;
    if ((p - centre).norm() <= 1.0) continue;
    // Half of the moves lean towards the bone, so that many enter it.
    Vec3 move = Vec3(normal(rng), normal(rng), normal(rng)).normalized() - (queries % 2 ? 1.5 : 0.0) * ray;
    move.normalize();
    SweepQuery q;
    q.from = p + (kRadius - 1.0 + 5.0 * uniform(rng)) * ray;
    q.to = q.from + std::pow(10.0, -2.0 + 2.78 * uniform(rng)) * move;
    q.probe = GetParam();
    q.leadingRadius = kRadius;
    q.shell = shell;
    ++queries;

    const SweepResult got = skull->sweep(q);
    const Reference want = reference(grid, q);
    const double length = (q.to - q.from).norm();
    const double tolerance = 2e-5 / length;  // the sweep's 1e-5 mm, and the reference's own
    ASSERT_EQ(got.startsInside, want.startsInside) << "query " << queries;
    blocked += want.blocked;
    startsInside += want.startsInside;
    if (got.blocked) {
      // It blocks only where bone is: the contact point is in bone, and no
      // earlier than the reference's first entry.
      EXPECT_TRUE(grid.codeAt(got.contactPoint) > grid.isoCode || got.startsInside) << "query " << queries;
      ASSERT_GE(got.freeFraction, want.freeFraction - tolerance) << "query " << queries;
    }
    if (got.blocked == want.blocked && (!got.blocked || std::abs(got.freeFraction - want.freeFraction) <= tolerance)) {
      ++agreeing;
      continue;
    }
    // Otherwise the reference's entry must be a sliver shorter than the sweep's step.
    const int steps = std::max(1, int(std::ceil(length / (0.5 * kVoxel))));
    ASSERT_TRUE(want.blocked) << "query " << queries << ": blocked at " << got.freeFraction << " of " << length
                              << " mm, the reference free";
    EXPECT_LT(want.entryRun, 1.0 / steps) << "query " << queries << ": missed " << want.entryRun * length
                                           << " mm of bone (entry at " << want.freeFraction << ", sweep "
                                           << (got.blocked ? got.freeFraction : 2.0) << ")";
    ++slivers;
  }
  // The random queries must exercise both outcomes, and agree almost always.
  EXPECT_GT(blocked - startsInside, queries / 20) << "blocked on the way (a crossing refined)";
  EXPECT_GT(startsInside, 0);
  EXPECT_LT(blocked, queries * 4 / 5);
  EXPECT_GE(agreeing, queries * 98 / 100) << slivers << " slivers";
  std::printf("%d queries: %d blocked (%d at the start), %d agreeing, %d slivers\n", queries, blocked, startsInside,
              agreeing, slivers);
}

// The overlap test of a displayed proxy (VoxelSkull::overlaps: its shell
// pulled one voxel in and thinned to points about a voxel apart): a burr sunk
// into a half-space by 1.3 voxels or more is seen at every orientation, one
// sunk less than a voxel never.
TEST(VoxelOverlapTest, ABurrSunkMoreThanAVoxelIsSeenAndOneGrazingIsNot) {
  const LoadedSkull loaded = loadSkull("phantom:halfspace?voxel=0.5", 500.0);
  ShellContactTarget* skull = loaded.skull;
  ASSERT_NE(skull, nullptr);
  const std::vector<ShellPoint>& shell = loaded.shell;
  const double h = 0.5;  // mm, the voxel; the half-space's top face is z = 0
  std::mt19937_64 rng(9);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial) {
    const Quat q = Quat(normal(rng), normal(rng), normal(rng), normal(rng)).normalized();
    // Sunk by `sunk`, the inset shell's lowest point is sunk - h into the bone:
    // 1.3 h leaves a cap of 1.3 mm across below the top face, which points
    // about a voxel apart cannot miss.
    for (const double sunk : {1.3 * h, 2.0 * h, 3.0 * h})
      EXPECT_TRUE(skull->overlaps({Vec3(0.3, -0.2, kRadius - sunk), q}, shell)) << sunk << " mm in, trial " << trial;
    for (const double sunk : {0.7 * h, 0.0, -h})
      EXPECT_FALSE(skull->overlaps({Vec3(0.3, -0.2, kRadius - sunk), q}, shell)) << sunk << " mm in, trial " << trial;
  }
}

INSTANTIATE_TEST_SUITE_P(Probes, SmoothSweepTest, ::testing::Values(SweepProbe::Line, SweepProbe::Cylinder),
                         [](const auto& info) { return info.param == SweepProbe::Line ? "line" : "cylinder"; });

}  // namespace
}  // namespace trephine
