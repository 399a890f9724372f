// The native back-end following removals answers as if the removed
// tetrahedra had never been meshed: after every removal (random batches and
// connected regions, in several orders, until nothing is left) its location,
// depth, contact, sweep and ray-cast answers are compared with those of a
// back-end built from scratch on the remaining tetrahedra alone, at random
// points and poses over the whole mesh. Both of the thesis's penetration
// methods and the thesis's scans as well as the grid search.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "framework/data/RemainingMesh.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "plugins/tetra_brain/NativeTetBackend.h"
#include "tests/plugins/tetra_brain/TetTestShapes.h"

namespace trephine::tetra {
namespace {

// The remaining tetrahedra as a mesh of their own (same nodes, the alive
// tetrahedra in their order, so the lowest index still wins on shared faces).
TetMesh remainingAlone(const TetMesh& mesh, const RemainingMesh& left, std::vector<int32_t>& fromOriginal) {
  TetMesh out;
  out.nodes = mesh.nodes;
  fromOriginal.assign(mesh.tetCount(), -1);
  for (int32_t t = 0; t < int32_t(mesh.tetCount()); ++t)
    if (left.alive(t)) {
      fromOriginal[size_t(t)] = int32_t(out.tets.size());
      out.tets.push_back(mesh.tets[size_t(t)]);
    }
  return out;
}

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

struct Checked {
  int points = 0, contacts = 0, blocked = 0;
};

// Every query of `following` against `fresh` at random places in `box`.
void compareQueries(NativeTetBackend& following, NativeTetBackend& fresh, const std::vector<int32_t>& fromOriginal,
                    std::span<const ShellPoint> shell, const Box3& box, std::mt19937& rng, Checked& checked,
                    const std::string& where) {
  std::uniform_real_distribution<double> u(0, 1);
  auto randomPoint = [&] {
    return Vec3(box.min().x() + u(rng) * box.sizes().x(), box.min().y() + u(rng) * box.sizes().y(),
                box.min().z() + u(rng) * box.sizes().z());
  };
  for (int i = 0; i < 60; ++i) {
    const Vec3 p = randomPoint();
    const int32_t a = following.locate(p), b = fresh.locate(p);
    ASSERT_EQ(a < 0 ? -1 : fromOriginal[size_t(a)], b) << where << " locate at " << p.transpose();
    Vec3 na, nb;
    const double da = following.depthBelowSurface(p, na), db = fresh.depthBelowSurface(p, nb);
    ASSERT_NEAR(da, db, 1e-9) << where << " depth at " << p.transpose();
    checked.points += a >= 0;
  }
  for (int i = 0; i < 40; ++i) {
    const Pose pose{randomPoint(), Quat::UnitRandom()};
    int32_t startA = 0, startB = 0;
    const TetContact ca = following.collide(pose, shell, false, startA);
    const TetContact cb = fresh.collide(pose, shell, false, startB);
    ASSERT_EQ(ca.contact.points, cb.contact.points) << where << " contact at " << pose.position.transpose();
    ASSERT_EQ(ca.contact.primitives, cb.contact.primitives) << where;
    ASSERT_NEAR(ca.contact.penetration, cb.contact.penetration, 1e-9) << where;
    ASSERT_LT((ca.contact.normal - cb.contact.normal).norm(), 1e-9) << where;
    ASSERT_EQ(ca.tets.size(), cb.tets.size());
    for (size_t k = 0; k < ca.tets.size(); ++k) ASSERT_EQ(fromOriginal[size_t(ca.tets[k])], cb.tets[k]);
    checked.contacts += ca.contact.points > 0;
    SweepQuery sweep{randomPoint(), randomPoint(), Quat::Identity(), SweepProbe::Line, 1.0, shell};
    const SweepResult sa = following.sweep(sweep), sb = fresh.sweep(sweep);
    ASSERT_EQ(sa.blocked, sb.blocked) << where << " sweep " << sweep.from.transpose() << " to " << sweep.to.transpose();
    ASSERT_EQ(sa.startsInside, sb.startsInside) << where;
    ASSERT_NEAR(sa.freeFraction, sb.freeFraction, 1e-12) << where;
    checked.blocked += sa.blocked;
    const Vec3 direction = (sweep.to - sweep.from).normalized();
    const auto ra = following.raycast(sweep.from, direction, 80.0), rb = fresh.raycast(sweep.from, direction, 80.0);
    ASSERT_EQ(ra.has_value(), rb.has_value()) << where;
    if (ra) {
      ASSERT_NEAR(ra->distance, rb->distance, 1e-9) << where;
    }
  }
}

enum class Batches { kRandom, kRegions };

void removeUntilEmpty(Batches batches, TetQueryOptions options, uint32_t seed) {
  const TetMesh mesh = makeCubeMesh(4, 40.0);  // 320 tetrahedra, a 40 mm cube
  const TetTopology topology(mesh);
  RemainingMesh left(mesh, topology);
  NativeTetBackend following;
  following.bind({&mesh, &topology, options});
  ASSERT_FALSE(following.followRemovals().has_value());
  const std::vector<ShellPoint> shell = shapes::sphereShell(4.0, 80);
  following.reserveShell(shell);
  Box3 box;
  for (const Vec3& p : mesh.nodes) box.extend(p);
  box = Box3(box.min() - Vec3::Constant(6), box.max() + Vec3::Constant(6));
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int32_t> anyTet(0, int32_t(mesh.tetCount()) - 1);
  Checked checked;
  int round = 0;
  while (left.aliveCount() > 0) {
    std::vector<int32_t> batch;
    if (batches == Batches::kRandom) {
      for (int k = 0; k < 25; ++k) batch.push_back(anyTet(rng));
    } else {
      int32_t start = anyTet(rng);
      while (!left.alive(start)) start = anyTet(rng);
      batch = regionFrom(start, 30, topology, left);
    }
    following.removeTets(left.remove(batch));
    if (left.aliveCount() == 0) break;
    std::vector<int32_t> fromOriginal;
    const TetMesh alone = remainingAlone(mesh, left, fromOriginal);
    const TetTopology aloneTopology(alone);
    NativeTetBackend fresh;
    fresh.bind({&alone, &aloneTopology, options});
    fresh.reserveShell(shell);
    compareQueries(following, fresh, fromOriginal, shell, box, rng, checked,
                   "round " + std::to_string(round) + " (" + std::to_string(left.aliveCount()) + " left)");
    if (::testing::Test::HasFatalFailure()) return;
    ++round;
  }
  // The comparison saw inside points, contacts and blocked sweeps, not only misses.
  EXPECT_GT(checked.points, 100);
  EXPECT_GT(checked.contacts, 50);
  EXPECT_GT(checked.blocked, 50);
  // Nothing left: nothing to touch.
  EXPECT_EQ(following.locate(Vec3(20, 20, 20)), -1);
  int32_t start = 0;
  EXPECT_EQ(following.collide({Vec3(20, 20, 20), Quat::Identity()}, shell, false, start).contact.points, 0);
}

TEST(NativeRemovalTest, RandomBatchesAnswerAsTheRemainingMeshAlone) {
  for (uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE(seed);
    removeUntilEmpty(Batches::kRandom, {}, seed);
  }
}

TEST(NativeRemovalTest, ConnectedRegionsAnswerAsTheRemainingMeshAlone) {
  for (uint32_t seed : {4u, 5u}) {
    SCOPED_TRACE(seed);
    removeUntilEmpty(Batches::kRegions, {}, seed);
  }
}

TEST(NativeRemovalTest, TheThesisSearchAndAlgorithm2FollowToo) {
  TetQueryOptions options;
  options.search = TetQueryOptions::Search::kFirstTetrahedron;
  options.algorithm2 = true;
  removeUntilEmpty(Batches::kRegions, options, 7);
}

TEST(NativeRemovalTest, WithoutFollowingRemovalsNothingChanges) {
  // A back-end not told to follow keeps the whole mesh.
  const TetMesh mesh = makeCubeMesh(4, 40.0);
  const TetTopology topology(mesh);
  RemainingMesh left(mesh, topology);
  NativeTetBackend backend;
  backend.bind({&mesh, &topology, {}});
  const size_t boundaryOnly = backend.faces().size();
  EXPECT_EQ(boundaryOnly, topology.boundaryFaces().size());
  const int32_t inside = backend.locate(Vec3(20, 20, 20));
  ASSERT_GE(inside, 0);
  std::vector<int32_t> all(mesh.tetCount());
  for (size_t t = 0; t < all.size(); ++t) all[t] = int32_t(t);
  backend.removeTets(left.remove(all));
  EXPECT_EQ(backend.locate(Vec3(20, 20, 20)), inside);
  // Following from then on lists the same faces in its grid (the first boundary's).
  ASSERT_FALSE(backend.followRemovals().has_value());
  EXPECT_EQ(backend.faces().size(), boundaryOnly);
}

}  // namespace
}  // namespace trephine::tetra
