// The collision between two tetrahedral meshes through the particle grid
// (thesis section 5.2) against every particle tested against every
// tetrahedron; the penalty response parts them; the experiment's placement
// and sweep.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "plugins/tetra_brain/CubePhantom.h"
#include "plugins/tetra_brain/cell_size/CellSizeExperiment.h"
#include "plugins/tetra_brain/cell_size/TetPairCollision.h"

namespace trephine::tetra {
namespace {

// Every (particle, tet) pair with the particle inside, by brute force.
std::set<std::pair<int32_t, int32_t>> bruteForce(const TetMesh& a, const std::vector<Vec3>& particles) {
  std::set<std::pair<int32_t, int32_t>> pairs;
  for (size_t t = 0; t < a.tets.size(); ++t) {
    const auto& k = a.tets[t];
    const Vec3 &p0 = a.nodes[k[0]], &p1 = a.nodes[k[1]], &p2 = a.nodes[k[2]], &p3 = a.nodes[k[3]];
    const double v = signedVolume(p0, p1, p2, p3);
    for (size_t i = 0; i < particles.size(); ++i) {
      const Vec3& x = particles[i];
      if (signedVolume(x, p1, p2, p3) / v >= 0 && signedVolume(p0, x, p2, p3) / v >= 0 &&
          signedVolume(p0, p1, x, p3) / v >= 0 && signedVolume(p0, p1, p2, x) / v >= 0)
        pairs.insert({int32_t(i), int32_t(t)});
    }
  }
  return pairs;
}

TEST(TetPairCollisionTest, TheGridFindsWhatTestingEveryPairFinds) {
  const TetMesh a = makeBoxMesh({4, 3, 3}, Vec3(0, 0, 0), Vec3(40, 30, 30));
  const TetMesh b = makeBoxMesh({5, 4, 3}, Vec3(0, 0, 0), Vec3(30, 28, 26));
  std::vector<Vec3> particles;
  for (const Vec3& p : b.nodes) particles.push_back(p + Vec3(27.3, 4.1, 3.7));  // overlapping a's far end
  const auto expected = bruteForce(a, particles);
  ASSERT_GT(expected.size(), 5u);
  Box3 bounds;
  for (const Vec3& p : a.nodes) bounds.extend(p);
  for (const Vec3& p : particles) bounds.extend(p);
  for (double cell : {0.7, 3.0, 9.0, 25.0, 200.0}) {
    ParticleGrid grid;
    grid.build(particles, bounds, cell);
    std::vector<Box3> boxes;
    std::vector<ParticleInTet> found;
    const PairCounts counts = findParticlesInTets(a.nodes, a.tets, particles, grid, boxes, found);
    std::set<std::pair<int32_t, int32_t>> pairs;
    for (const ParticleInTet& f : found) {
      pairs.insert({f.particle, f.tet});
      double sum = 0;
      for (double w : f.weights) sum += w;
      EXPECT_NEAR(sum, 1.0, 1e-12);
    }
    EXPECT_EQ(pairs, expected) << "cell " << cell;
    EXPECT_EQ(counts.contacts, expected.size());
    EXPECT_LE(counts.collidingTets, counts.tetsWithParticles);
    EXPECT_LE(counts.barycentricTests, counts.boxTests);
    EXPECT_GE(counts.cellVisits, a.tets.size());  // every tet (all inside the grid) visits a cell at least
  }
}

TEST(TetPairCollisionTest, SmallerCellsVisitMoreCellsAndTestFewerParticles) {
  const TetMesh a = makeBoxMesh({6, 6, 6}, Vec3(0, 0, 0), Vec3(60, 60, 60));
  std::vector<Vec3> particles;
  for (const Vec3& p : a.nodes) particles.push_back(p + Vec3(50, 0, 0));
  Box3 bounds;
  for (const Vec3& p : a.nodes) bounds.extend(p);
  for (const Vec3& p : particles) bounds.extend(p);
  PairCounts previous;
  for (double cell : {40.0, 20.0, 10.0, 5.0}) {
    ParticleGrid grid;
    grid.build(particles, bounds, cell);
    std::vector<Box3> boxes;
    std::vector<ParticleInTet> found;
    const PairCounts counts = findParticlesInTets(a.nodes, a.tets, particles, grid, boxes, found);
    if (previous.cellVisits > 0) {
      EXPECT_GT(counts.cellVisits, previous.cellVisits) << cell;
      EXPECT_LT(counts.boxTests, previous.boxTests) << cell;
      EXPECT_EQ(counts.contacts, previous.contacts) << cell;
    }
    previous = counts;
  }
}

TEST(TetPairCollisionTest, AGridOfTooManyCellsIsRefused) {
  ParticleGrid grid;
  const std::vector<Vec3> points{Vec3(0, 0, 0)};
  EXPECT_THROW(grid.build(points, Box3(Vec3(0, 0, 0), Vec3(1000, 1000, 1000)), 0.01), std::invalid_argument);
  EXPECT_THROW(grid.build(points, Box3(Vec3(0, 0, 0), Vec3(1, 1, 1)), 0.0), std::invalid_argument);
}

TEST(TetPairCollisionTest, ThePenaltyResponsePartsTheCopies) {
  const TetMesh mesh = makeBoxMesh({4, 4, 4}, Vec3(0, 0, 0), Vec3(40, 40, 40));
  TetPairScene scene(mesh, mesh, Vec3(36, 1.3, 2.1));  // 4 mm of overlap along x
  const PairCounts first = scene.step(10.0, 1e-3);
  ASSERT_GT(first.contacts, 0u);
  PairCounts last = first;
  for (int frame = 0; frame < 200 && last.contacts > 0; ++frame) last = scene.step(10.0, 1e-3);
  EXPECT_EQ(last.contacts, 0u) << "the copies still overlap after 200 frames";
  EXPECT_GT(scene.offsetOfB().x() - scene.offsetOfA().x(), 36.0) << "pushed apart along x";
  EXPECT_GT(scene.offsetOfB().y(), 1.3) << "along the line of the centres";
}

TEST(TetPairCollisionTest, TheExperimentPlacesOnePercentAndFindsAZoneAroundItsOptimum) {
  const TetMesh mesh = makeCubeMesh(6, 60.0);
  const CellSizeInputs inputs = measureCellSizeInputs(mesh);
  CellSizeExperimentOptions options;
  options.frames = 2;
  options.rounds = 1;
  const CellSizeExperimentResult result = runCellSizeExperiment(mesh, inputs, options);
  EXPECT_GE(result.collidingFraction, 0.005);
  EXPECT_LE(result.collidingFraction, 0.02);
  ASSERT_EQ(result.samples.size(), 25u);
  EXPECT_LE(result.zoneLow, result.optimal);
  EXPECT_GE(result.zoneHigh, result.optimal);
  EXPECT_GE(result.optimal, result.samples.back().cellSize);  // within the sweep
  EXPECT_LE(result.optimal, result.samples.front().cellSize);
  for (const CellSizeSample& s : result.samples) {
    EXPECT_GT(s.timeUs, 0.0);
    EXPECT_TRUE(std::isfinite(s.fittedUs));
    EXPECT_EQ(s.perFrame.contacts, result.samples.front().perFrame.contacts) << "the same motion at every size";
  }
  EXPECT_GT(result.measuredCollisionFree, 0.0);
  EXPECT_LT(result.measuredCollisionFree, 1.0);
}

}  // namespace
}  // namespace trephine::tetra
