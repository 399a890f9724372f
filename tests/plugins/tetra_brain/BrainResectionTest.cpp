// A brain resected until nothing is left, the mesh, the collision and the
// FEM following every removal: random tetrahedra and connected regions are
// removed through BrainResection (which takes with them the pieces they cut
// loose, the flaps and the spikes), each change goes to the native back-end
// and to a TLED model, and after every change:
//  - the remaining mesh holds its invariants (RemainingMesh::validate);
//  - no face is shared by three alive tetrahedra, no alive tetrahedron is
//    inverted or degenerate (the mesh's own: none is made);
//  - beside a removal no alive tetrahedron is held by one face or less, no
//    node by two tetrahedra or less, and every face-connected piece that a
//    removal touched holds at least loosePieceLimit() tetrahedra;
//  - the back-end finds the centroid of every alive tetrahedron in it and of
//    no removed one;
//  - the FEM stepped under random loads on the remaining surface stays
//    finite, its removed elements exert nothing, and every node left without
//    an element is held where it is.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"
#include "plugins/tetra_brain/BrainResection.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "plugins/tetra_brain/NativeTetBackend.h"

namespace trephine::tetra {
namespace {

TissueTable oneTissue(const TetMesh& mesh) {
  TissueTable table;
  EXPECT_FALSE(table.declare({"brain", 1, 0.05, 0.03, false}, mesh.labels).has_value());
  return table;
}

Vec3 centroid(const TetMesh& mesh, int32_t tet) {
  Vec3 c = Vec3::Zero();
  for (int32_t n : mesh.tets[size_t(tet)]) c += mesh.nodes[size_t(n)];
  return c / 4;
}

// The face-connected piece of `seed` among alive tetrahedra (up to `limit`).
size_t pieceSize(int32_t seed, const TetTopology& topology, const RemainingMesh& left, size_t limit) {
  std::vector<int32_t> piece{seed};
  std::set<int32_t> seen{seed};
  for (size_t i = 0; i < piece.size() && piece.size() < limit; ++i)
    for (int f = 0; f < 4; ++f) {
      const int32_t n = topology.neighbour(piece[i], f);
      if (n != kNoNeighbour && left.alive(n) && seen.insert(n).second) piece.push_back(n);
    }
  return piece.size();
}

enum class Batches { kRandom, kRegions };

void resectUntilEmpty(Batches batches, uint32_t seed) {
  TetMesh mesh = makeBoxMesh({6, 5, 4}, Vec3::Zero(), Vec3(60, 50, 40));  // 600 tetrahedra
  mesh.labels.assign(mesh.tetCount(), 1);
  const TetTopology topology(mesh);
  const TissueTable tissues = oneTissue(mesh);
  BrainResection resection(mesh, topology, tissues);
  NativeTetBackend backend;
  backend.bind({&mesh, &topology, {}});
  ASSERT_FALSE(backend.followRemovals().has_value());
  const fem::ElementMaterial material{1e-6, 30.0, 0.3};
  fem::TLEDModel model(mesh.nodes, mesh.tets, std::span(&material, 1));
  model.setTimeStep(0.5 * model.criticalTimeStep(), 50);
  fem::TLEDState state(model);
  std::vector<Vec3> positions(mesh.nodeCount());

  std::mt19937 rng(seed);
  std::uniform_int_distribution<int32_t> anyTet(0, int32_t(mesh.tetCount()) - 1);
  std::uniform_real_distribution<double> unit(-1, 1);
  int rounds = 0;
  size_t fragmentsSeen = 0;
  while (resection.remaining().aliveCount() > 0 && rounds < 1000) {
    ++rounds;
    // What the tools' responses would queue: random tetrahedra, or a region.
    std::vector<int32_t> chosen;
    if (batches == Batches::kRandom) {
      for (int k = 0; k < 7; ++k) chosen.push_back(anyTet(rng));
    } else {
      int32_t start = anyTet(rng);
      while (!resection.remaining().alive(start)) start = anyTet(rng);
      chosen = {start};
      for (size_t i = 0; i < chosen.size() && chosen.size() < 12; ++i)
        for (int f = 0; f < 4; ++f) {
          const int32_t n = topology.neighbour(chosen[i], f);
          if (n != kNoNeighbour && resection.remaining().alive(n) &&
              std::find(chosen.begin(), chosen.end(), n) == chosen.end())
            chosen.push_back(n);
        }
    }
    resection.queue(chosen);
    std::set<int32_t> removedNow;
    std::vector<int32_t> elements;
    for (RemainingMesh::Change c = resection.removeNext(); !c.removedTets.empty(); c = resection.removeNext()) {
      backend.removeTets(c);
      removedNow.insert(c.removedTets.begin(), c.removedTets.end());
      elements.assign(c.removedTets.begin(), c.removedTets.end());
      model.removeElements(elements);
    }
    const RemainingMesh& left = resection.remaining();
    ASSERT_EQ(left.validate(), "") << "round " << rounds;
    size_t boundary = 0;
    for (int32_t t = 0; t < int32_t(mesh.tetCount()); ++t)
      for (int f = 0; f < 4; ++f) boundary += left.onBoundary(t, f);
    ASSERT_EQ(resection.boundaryFaces(), boundary) << "round " << rounds;
    for (size_t n = 0; n < mesh.nodeCount(); ++n) {
      bool held = false;
      for (int32_t t = 0; t < int32_t(mesh.tetCount()) && !held; ++t)
        for (int f = 0; f < 4 && !held; ++f)
          if (left.onBoundary(t, f))
            for (int32_t m : faceNodes(mesh.tets[size_t(t)], f)) held = held || m == int32_t(n);
      ASSERT_EQ(resection.onSurface(int32_t(n)), held) << "node " << n << ", round " << rounds;
    }
    for (int32_t t : removedNow) ASSERT_FALSE(left.alive(t));
    // Beside this round's removal: no flap, no spike, no small loose piece.
    for (int32_t t : removedNow)
      for (int f = 0; f < 4; ++f) {
        const int32_t n = topology.neighbour(t, f);
        if (n == kNoNeighbour || !left.alive(n)) continue;
        int held = 0;
        for (int g = 0; g < 4; ++g) {
          const int32_t m = topology.neighbour(n, g);
          held += m != kNoNeighbour && left.alive(m);
        }
        ASSERT_GE(held, 2) << "a flap beside the removal, round " << rounds;
        ASSERT_GE(pieceSize(n, topology, left, resection.loosePieceLimit()), resection.loosePieceLimit())
            << "a loose piece beside the removal, round " << rounds;
      }
    for (int32_t t : removedNow)
      for (int32_t node : mesh.tets[size_t(t)]) {
        const uint32_t use = left.nodeUse(node);
        ASSERT_TRUE(use == 0 || use > BrainResection::kSpikeUse) << "a spike's node, round " << rounds;
      }
    // The collision: every alive tetrahedron's centroid in it, no removed one's.
    for (int32_t t = 0; t < int32_t(mesh.tetCount()); ++t) {
      const int32_t found = backend.locate(centroid(mesh, t));
      if (left.alive(t)) {
        ASSERT_EQ(found, t) << "round " << rounds;
      } else {
        ASSERT_EQ(found, -1) << "round " << rounds;
      }
    }
    // The FEM: random loads on alive nodes, a few steps, all finite; a node
    // without an element stays where it was left.
    state.clearExternalForces();
    for (size_t n = 0; n < mesh.nodeCount(); ++n)
      if (left.nodeUse(int32_t(n)) > 0 && unit(rng) > 0.8)
        state.setExternalForce(int32_t(n), 50.0 * Vec3(unit(rng), unit(rng), unit(rng)));
    for (int s = 0; s < 20; ++s) state.step();
    const auto shape = state.writePositions(positions);
    ASSERT_TRUE(std::isfinite(shape.largestDisplacement)) << "round " << rounds;
    for (size_t n = 0; n < mesh.nodeCount(); ++n)
      if (left.nodeUse(int32_t(n)) == 0) {
        ASSERT_LT((positions[n] - mesh.nodes[n]).norm(), 1e-12) << "node " << n;
      }
    fragmentsSeen = resection.fragments() + resection.looseTets();
  }
  EXPECT_EQ(resection.remaining().aliveCount(), 0u);
  EXPECT_EQ(model.removedCount(), mesh.tetCount());
  // The pieces, flaps and spikes were exercised, not only the chosen tetrahedra.
  EXPECT_GT(fragmentsSeen, 0u);
  // Nothing left: the FEM exerts nothing anywhere.
  std::vector<Vec3> forces(mesh.nodeCount());
  state.internalForces(forces);
  for (const Vec3& f : forces) EXPECT_EQ(f.norm(), 0.0);
}

TEST(BrainResectionTest, RandomRemovalsUntilNothingIsLeft) {
  for (uint32_t seed : {11u, 12u, 13u}) {
    SCOPED_TRACE(seed);
    resectUntilEmpty(Batches::kRandom, seed);
    if (HasFatalFailure()) return;
  }
}

TEST(BrainResectionTest, ConnectedRegionsUntilNothingIsLeft) {
  for (uint32_t seed : {21u, 22u, 23u}) {
    SCOPED_TRACE(seed);
    resectUntilEmpty(Batches::kRegions, seed);
    if (HasFatalFailure()) return;
  }
}

TEST(BrainResectionTest, ALoosePieceGoesWithTheCutThatFreedIt) {
  // A bar three cells long: removing the middle cell's tetrahedra leaves two
  // pieces of 5 tetrahedra each (fewer than the limit of this small mesh):
  // both go with the cut.
  TetMesh mesh = makeBoxMesh({3, 1, 1}, Vec3::Zero(), Vec3(30, 10, 10));
  mesh.labels.assign(mesh.tetCount(), 1);
  const TetTopology topology(mesh);
  const TissueTable tissues = oneTissue(mesh);
  BrainResection resection(mesh, topology, tissues);
  std::vector<int32_t> middle;
  for (int32_t t = 0; t < int32_t(mesh.tetCount()); ++t)
    if (std::abs(centroid(mesh, t).x() - 15) < 5) middle.push_back(t);
  ASSERT_EQ(middle.size(), 5u);
  resection.queue(middle);
  size_t removed = 0;
  for (RemainingMesh::Change c = resection.removeNext(); !c.removedTets.empty(); c = resection.removeNext())
    removed += c.removedTets.size();
  EXPECT_EQ(removed, mesh.tetCount());
  EXPECT_EQ(resection.remaining().aliveCount(), 0u);
}

}  // namespace
}  // namespace trephine::tetra
