// Elements taken out of a TLED model (resection) leave it as if they had
// never been meshed: against a model built from the remaining elements alone
// (the same nodes), the internal forces at random displacements, the lumped
// masses, the held nodes (those left without an element) and 300 steps under
// the same loads agree to rounding, for random removals in several batches,
// in double and single precision; removed elements stay out when materials
// or mass scaling are applied again.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "tests/plugins/fem/FemTestSupport.h"

namespace trephine::fem {
namespace {

using test::kBrain;

struct Removal {
  TetMesh mesh;
  std::vector<int32_t> removed;  // mesh indices
  TetMesh remaining;             // the same nodes, the other elements
};

Removal randomRemoval(uint32_t seed, double fraction) {
  Removal r;
  r.mesh = tetra::makeBoxMesh({4, 3, 3}, Vec3::Zero(), Vec3(40, 30, 30));
  std::mt19937 random(seed);
  std::vector<int32_t> order(r.mesh.tetCount());
  for (size_t i = 0; i < order.size(); ++i) order[i] = int32_t(i);
  std::shuffle(order.begin(), order.end(), random);
  r.removed.assign(order.begin(), order.begin() + std::ptrdiff_t(fraction * double(order.size())));
  const std::set<int32_t> gone(r.removed.begin(), r.removed.end());
  r.remaining.nodes = r.mesh.nodes;
  for (size_t e = 0; e < r.mesh.tetCount(); ++e)
    if (!gone.contains(int32_t(e))) r.remaining.tets.push_back(r.mesh.tets[e]);
  return r;
}

void expectAsIfNeverMeshed(uint32_t seed, ElementPrecision precision) {
  const Removal r = randomRemoval(seed, 0.4);
  TLEDModel cut(r.mesh.nodes, r.mesh.tets, std::span(&kBrain, 1));
  TLEDModel fresh(r.remaining.nodes, r.remaining.tets, std::span(&kBrain, 1));
  cut.setElementPrecision(precision);
  fresh.setElementPrecision(precision);
  const double dt = 0.5 * fresh.criticalTimeStep();
  cut.setTimeStep(dt, 10);
  fresh.setTimeStep(dt, 10);
  // In three batches, with a repeat and an index out of range.
  const size_t third = r.removed.size() / 3;
  std::vector<int32_t> first(r.removed.begin(), r.removed.begin() + std::ptrdiff_t(third));
  first.push_back(first.front());
  first.push_back(-3);
  EXPECT_EQ(cut.removeElements(first), third);
  EXPECT_EQ(cut.removeElements(std::span(r.removed).subspan(third, third)), third);
  EXPECT_EQ(cut.removeElements(std::span(r.removed).subspan(2 * third)), r.removed.size() - 2 * third);
  EXPECT_EQ(cut.removedCount(), r.removed.size());
  for (const int32_t e : r.removed) ASSERT_TRUE(cut.removed(e));
  // Masses and held nodes.
  for (int32_t n = 0; n < int32_t(r.mesh.nodeCount()); ++n) {
    EXPECT_NEAR(cut.mass(n), fresh.mass(n), 1e-12 * fresh.mass(n) + 1e-18) << "node " << n;
    EXPECT_EQ(cut.isFixed(n, 0), fresh.isFixed(n, 0)) << "node " << n;
  }
  // Internal forces at random displacements (a few percent strain).
  std::mt19937 random(seed + 100);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<Vec3> u(r.mesh.nodeCount()), a(u.size()), b(u.size());
  for (Vec3& v : u) v = 0.5 * Vec3(unit(random), unit(random), unit(random));
  cut.internalForcesAt(u, a);
  fresh.internalForcesAt(u, b);
  double largest = 0;
  for (const Vec3& f : b) largest = std::max(largest, f.norm());
  const double tolerance = (precision == ElementPrecision::kSingle ? 1e-5 : 1e-12) * largest;
  for (size_t n = 0; n < u.size(); ++n) ASSERT_LT((a[n] - b[n]).norm(), tolerance) << "node " << n;
  // Steps under the same loads.
  TLEDState cutState(cut), freshState(fresh);
  for (int32_t n = 0; n < int32_t(r.mesh.nodeCount()); n += 7) {
    cutState.setExternalForce(n, Vec3(3, -2, 5));
    freshState.setExternalForce(n, Vec3(3, -2, 5));
  }
  for (int step = 0; step < 300; ++step) {
    cutState.step();
    freshState.step();
  }
  double moved = 0;
  for (int32_t n = 0; n < int32_t(r.mesh.nodeCount()); ++n) moved = std::max(moved, freshState.displacement(n).norm());
  EXPECT_GT(moved, 1e-3) << "the loads moved the mesh";
  for (int32_t n = 0; n < int32_t(r.mesh.nodeCount()); ++n)
    ASSERT_LT((cutState.displacement(n) - freshState.displacement(n)).norm(),
              (precision == ElementPrecision::kSingle ? 1e-5 : 1e-10) * moved)
        << "node " << n;
}

TEST(ElementRemovalTest, RemovedElementsLeaveTheModelAsIfNeverMeshed) {
  for (uint32_t seed : {1u, 2u, 3u}) expectAsIfNeverMeshed(seed, ElementPrecision::kDouble);
}

TEST(ElementRemovalTest, InSinglePrecisionToo) { expectAsIfNeverMeshed(4, ElementPrecision::kSingle); }

TEST(ElementRemovalTest, RemovedElementsStayOutOfMaterialsAndMassScaling) {
  const Removal r = randomRemoval(5, 0.3);
  TLEDModel cut(r.mesh.nodes, r.mesh.tets, std::span(&kBrain, 1));
  TLEDModel fresh(r.remaining.nodes, r.remaining.tets, std::span(&kBrain, 1));
  cut.removeElements(r.removed);
  // Every element, removed ones included, given another material; then
  // scaled for a step below the critical one.
  std::vector<int32_t> all(r.mesh.tetCount());
  for (size_t e = 0; e < all.size(); ++e) all[e] = int32_t(e);
  std::vector<int32_t> allFresh(r.remaining.tetCount());
  for (size_t e = 0; e < allFresh.size(); ++e) allFresh[e] = int32_t(e);
  const ElementMaterial denser{2e-6, 45, 0.4};
  cut.assignMaterial(all, denser);
  fresh.assignMaterial(allFresh, denser);
  const double dt = 2 * fresh.criticalTimeStep();
  EXPECT_EQ(cut.scaleMassForStep(dt), fresh.scaleMassForStep(dt));
  EXPECT_NEAR(cut.totalMass(), fresh.totalMass(), 1e-12 * fresh.totalMass());
  EXPECT_NEAR(cut.addedMass(), fresh.addedMass(), 1e-12 * fresh.totalMass());
  EXPECT_DOUBLE_EQ(cut.criticalTimeStep(), fresh.criticalTimeStep());
  EXPECT_DOUBLE_EQ(cut.unscaledCriticalTimeStep(), fresh.unscaledCriticalTimeStep());
}

}  // namespace
}  // namespace trephine::fem
