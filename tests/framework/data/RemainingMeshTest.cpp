// What remains of a tetrahedral mesh as tetrahedra are removed, checked
// against a count from scratch after every removal, in random orders and
// batches until nothing is left: the boundary the changes describe (the
// faces exposed added, the faces taken away removed) is exactly the set of
// faces of alive tetrahedra with no alive neighbour; the nodes freed are
// exactly those whose last alive tetrahedron went; a face is on the boundary
// of at most one alive tetrahedron. Single tetrahedra, random batches and
// connected regions (grown from a random tetrahedron across faces).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "framework/data/RemainingMesh.h"
#include "plugins/tetra_brain/CubePhantom.h"

namespace trephine {
namespace {

using Face = std::pair<int32_t, int>;

std::set<Face> boundaryFromScratch(const TetMesh& mesh, const TetTopology& topology, const RemainingMesh& left) {
  std::set<Face> faces;
  for (int32_t t = 0; t < int32_t(mesh.tetCount()); ++t) {
    if (!left.alive(t)) continue;
    for (int f = 0; f < 4; ++f) {
      const int32_t n = topology.neighbour(t, f);
      if (n == kNoNeighbour || !left.alive(n)) faces.insert({t, f});
    }
  }
  return faces;
}

// A connected region of up to `size` alive tetrahedra grown from `seed` across faces.
std::vector<int32_t> regionFrom(int32_t seed, size_t size, const TetTopology& topology, const RemainingMesh& left) {
  std::vector<int32_t> region{seed};
  std::set<int32_t> seen{seed};
  for (size_t i = 0; i < region.size() && region.size() < size; ++i)
    for (int f = 0; f < 4 && region.size() < size; ++f) {
      const int32_t n = topology.neighbour(region[i], f);
      if (n != kNoNeighbour && left.alive(n) && seen.insert(n).second) region.push_back(n);
    }
  return region;
}

enum class Batches { kOneByOne, kRandom, kRegions };

void removeEverything(Batches batches, uint32_t seed) {
  const TetMesh mesh = tetra::makeCubeMesh(4, 40.0);  // 320 tetrahedra
  const TetTopology topology(mesh);
  RemainingMesh left(mesh, topology);
  std::set<Face> boundary = boundaryFromScratch(mesh, topology, left);
  ASSERT_EQ(boundary.size(), topology.boundaryFaces().size());
  std::vector<int32_t> order(mesh.tetCount());
  for (size_t i = 0; i < order.size(); ++i) order[i] = int32_t(i);
  std::mt19937 random(seed);
  std::shuffle(order.begin(), order.end(), random);
  size_t next = 0, calls = 0;
  std::vector<uint32_t> useBefore(mesh.nodeCount());
  while (left.aliveCount() > 0) {
    std::vector<int32_t> batch;
    if (batches == Batches::kOneByOne) {
      batch = {order[next++]};
    } else if (batches == Batches::kRandom) {
      const size_t size = std::uniform_int_distribution<size_t>(1, 40)(random);
      for (size_t i = 0; i < size && next < order.size(); ++i) batch.push_back(order[next++]);
      // Repeats and already removed ones are skipped.
      if (!batch.empty()) batch.push_back(batch.front());
      if (next > 1) batch.push_back(order[next - 2]);
    } else {
      while (!left.alive(order[next])) ++next;
      batch = regionFrom(order[next], std::uniform_int_distribution<size_t>(1, 60)(random), topology, left);
    }
    for (size_t n = 0; n < mesh.nodeCount(); ++n) useBefore[n] = left.nodeUse(int32_t(n));
    const size_t aliveBefore = left.aliveCount();
    const RemainingMesh::Change change = left.remove(batch);
    ++calls;
    ASSERT_EQ(aliveBefore - left.aliveCount(), change.removedTets.size());
    for (const BoundaryFace& f : change.takenAway) ASSERT_EQ(boundary.erase({f.tet, f.face}), 1u) << "not boundary before";
    for (const BoundaryFace& f : change.exposed) ASSERT_TRUE(boundary.insert({f.tet, f.face}).second) << "already boundary";
    ASSERT_EQ(boundary, boundaryFromScratch(mesh, topology, left)) << "after call " << calls;
    for (const auto& [t, f] : boundary) ASSERT_TRUE(left.onBoundary(t, f));
    std::set<int32_t> freed(change.freedNodes.begin(), change.freedNodes.end());
    ASSERT_EQ(freed.size(), change.freedNodes.size()) << "a node freed twice";
    for (size_t n = 0; n < mesh.nodeCount(); ++n)
      ASSERT_EQ(freed.contains(int32_t(n)), useBefore[n] > 0 && left.nodeUse(int32_t(n)) == 0) << "node " << n;
    ASSERT_EQ(left.validate(), "");
  }
  EXPECT_TRUE(boundary.empty());
  EXPECT_GT(calls, 1u);
  for (size_t n = 0; n < mesh.nodeCount(); ++n) EXPECT_EQ(left.nodeUse(int32_t(n)), 0u);
}

TEST(RemainingMeshTest, OneByOneUntilNothingIsLeft) {
  for (uint32_t seed : {1u, 2u, 3u}) removeEverything(Batches::kOneByOne, seed);
}

TEST(RemainingMeshTest, RandomBatchesWithRepeatsUntilNothingIsLeft) {
  for (uint32_t seed : {4u, 5u, 6u, 7u}) removeEverything(Batches::kRandom, seed);
}

TEST(RemainingMeshTest, ConnectedRegionsUntilNothingIsLeft) {
  for (uint32_t seed : {8u, 9u, 10u, 11u}) removeEverything(Batches::kRegions, seed);
}

TEST(RemainingMeshTest, NothingToRemoveChangesNothing) {
  const TetMesh mesh = tetra::makeCubeMesh(2, 10.0);
  const TetTopology topology(mesh);
  RemainingMesh left(mesh, topology);
  const std::vector<int32_t> outOfRange = {-1, int32_t(mesh.tetCount()), 1 << 30};
  const RemainingMesh::Change change = left.remove(outOfRange);
  EXPECT_TRUE(change.removedTets.empty() && change.exposed.empty() && change.takenAway.empty() &&
              change.freedNodes.empty());
  EXPECT_EQ(left.aliveCount(), mesh.tetCount());
}

}  // namespace
}  // namespace trephine
