// TLED against closed forms: the kernel against the scalar neo-Hookean
// formulas, uniaxial stretch against the material's stress-strain curve,
// energy conservation, rigid motions, inverted elements, the critical time
// step, determinism (the cantilever: TLEDConvergenceTest).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "tests/plugins/fem/FemTestSupport.h"

namespace trephine::fem {
namespace {

using tetra::makeBoxMesh;

using test::kBrain;
using test::modelOf;

// The reference: the scalar formulas of NeoHookean.h on one element.
std::array<Vec3, 4> referenceForces(const std::array<Vec3, 4>& X, const std::array<Vec3, 4>& x,
                                    const ElasticModuli& m) {
  Mat3 D, d;
  for (int a = 0; a < 3; ++a) {
    D.col(a) = X[a + 1] - X[0];
    d.col(a) = x[a + 1] - x[0];
  }
  const Mat3 F = d * D.inverse();
  const double V = D.determinant() / 6;
  const Mat3 P = neoHookeanStress(F, m);
  const Mat3 G = D.inverse();  // row a: gradient of N_(a+1)
  std::array<Vec3, 4> f;
  f[0] = Vec3::Zero();
  for (int a = 0; a < 3; ++a) {
    f[a + 1] = V * P * G.row(a).transpose();
    f[0] -= f[a + 1];
  }
  return f;
}

// The kernel's forces on one element per case, deformed by a random F scaled
// to a chosen J (near rest: the fast root; far from it: the exact one),
// against the scalar formulas; `tolerance` from the reference forces' scale
// and the element's stress terms (below).
void expectKernelForcesMatchTheFormulas(ElementPrecision precision, ElementLoopIsa isa, double relativeToForces,
                                        double relativeToTerms) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  const ElasticModuli moduli = ElasticModuli::fromYoung(kBrain.youngModulus, kBrain.poissonRatio);
  for (double targetJ : {1.0, 0.97, 1.05, 0.62, 1.58, 0.3, 2.5, 6.0}) {
    for (int trial = 0; trial < 20; ++trial) {
      std::array<Vec3, 4> X{Vec3(0, 0, 0), Vec3(3, 0.2, 0.1), Vec3(0.5, 2.5, -0.3), Vec3(0.2, 0.4, 2.8)};
      for (Vec3& p : X) p += 0.3 * Vec3(unit(random), unit(random), unit(random));
      Mat3 F = Mat3::Identity() + 0.15 * Mat3::NullaryExpr([&](Eigen::Index, Eigen::Index) { return unit(random); });
      F *= std::cbrt(targetJ / F.determinant());
      std::array<Vec3, 4> x;
      for (int a = 0; a < 4; ++a) x[a] = F * X[a] + Vec3(1, 2, 3);
      const TetMesh mesh{{X.begin(), X.end()}, {TetIndices{0, 1, 2, 3}}, {}};
      TLEDModel model = modelOf(mesh);
      TLEDState state(model);
      model.setElementPrecision(precision);
      model.setElementLoopIsa(isa);
      std::vector<Vec3> u(4), forces(4);
      for (int a = 0; a < 4; ++a) u[a] = x[a] - X[a];
      state.setDisplacements(u, u);
      state.internalForces(forces);
      const auto expected = referenceForces(X, x, moduli);
      double scale = 0;
      for (const Vec3& f : expected) scale = std::max(scale, f.norm());
      // The terms whose difference is the force: the isochoric stress and the
      // stress on the cofactor, each times V |grad N| (rounding loses a few
      // units of the last place of these, not of their difference).
      Mat3 D;
      for (int a = 0; a < 3; ++a) D.col(a) = X[a + 1] - X[0];
      const double J = F.determinant(), volume = D.determinant() / 6;
      const double terms = volume * D.inverse().norm() *
                           (moduli.mu * std::pow(J, -2.0 / 3) * F.norm() +
                            (moduli.kappa * std::abs(J - 1) +
                             moduli.mu * F.squaredNorm() * std::pow(std::max(J, kMinIsochoricJ), -5.0 / 3) / 3) *
                                (J * F.inverse()).norm());
      for (int a = 0; a < 4; ++a)
        EXPECT_LT((forces[a] - expected[a]).norm(), relativeToForces * std::max(scale, 1.0) + relativeToTerms * terms)
            << elementLoopName(isa) << ", J " << targetJ << " node " << a << ": " << forces[a].transpose() << " vs "
            << expected[a].transpose();
    }
  }
}

// The element loop's versions this processor can run (the portable one at least).
std::vector<ElementLoopIsa> availableIsas() {
  std::vector<ElementLoopIsa> isas;
  for (ElementLoopIsa isa : {ElementLoopIsa::kPortable, ElementLoopIsa::kAvx2, ElementLoopIsa::kAvx512})
    if (elementLoopAvailable(isa)) isas.push_back(isa);
  return isas;
}

TEST(TLEDModelTest, KernelForcesMatchTheScalarNeoHookeanFormulas) {
  for (ElementLoopIsa isa : availableIsas()) expectKernelForcesMatchTheFormulas(ElementPrecision::kDouble, isa, 1e-12, 0);
}

TEST(TLEDModelTest, InSinglePrecisionKernelForcesMatchTheFormulasToFloatRounding) {
  // A float carries 6e-8 relative; the worst case here loses 3 to 8 units of
  // it (measured: 2e-7 fails, 5e-7 holds); 1e-6 is 16 units.
  for (ElementLoopIsa isa : availableIsas()) expectKernelForcesMatchTheFormulas(ElementPrecision::kSingle, isa, 0, 1e-6);
}

// On a mesh, where elements share nodes and several chunks run: every
// version's node forces against the portable version's, at a random
// deformation. The versions differ in the order of additions only.
TEST(TLEDModelTest, EveryInstructionSetGivesThePortableNodeForcesOnAMesh) {
  const TetMesh mesh = makeBoxMesh({7, 6, 5}, Vec3::Zero(), Vec3(20, 16, 12));  // over 1,000 elements: many chunks
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<Vec3> u(mesh.nodeCount());
  for (Vec3& d : u) d = Vec3(unit(random), unit(random), unit(random)) * 0.4 + Vec3(5, -3, 2);
  for (ElementPrecision precision : {ElementPrecision::kDouble, ElementPrecision::kSingle}) {
    std::vector<Vec3> expected(mesh.nodeCount()), forces(mesh.nodeCount());
    TLEDModel model = modelOf(mesh);
    TLEDState state(model);
    model.setElementPrecision(precision);
    model.setElementLoopIsa(ElementLoopIsa::kPortable);
    state.setDisplacements(u, u);
    state.internalForces(expected);
    double scale = 0;
    for (const Vec3& f : expected) scale = std::max(scale, f.norm());
    ASSERT_GT(scale, 1.0);  // mN: a real deformation
    const double tolerance = precision == ElementPrecision::kDouble ? 1e-12 : 1e-5;
    for (ElementLoopIsa isa : availableIsas()) {
      model.setElementLoopIsa(isa);
      state.internalForces(forces);
      double worst = 0;
      for (size_t i = 0; i < forces.size(); ++i) worst = std::max(worst, (forces[i] - expected[i]).norm());
      EXPECT_LT(worst, tolerance * scale) << elementLoopName(isa) << (precision == ElementPrecision::kDouble ? " double" : " single");
    }
  }
}

TEST(TLEDModelTest, AnInstructionSetTheProcessorLacksIsRefused) {
  TLEDModel model = modelOf(makeBoxMesh({1, 1, 1}, Vec3::Zero(), Vec3::Constant(1)));
  EXPECT_EQ(model.elementLoopIsa(), bestElementLoopIsa());
  for (ElementLoopIsa isa : {ElementLoopIsa::kPortable, ElementLoopIsa::kAvx2, ElementLoopIsa::kAvx512}) {
    if (elementLoopAvailable(isa))
      EXPECT_NO_THROW(model.setElementLoopIsa(isa));
    else
      EXPECT_THROW(model.setElementLoopIsa(isa), std::invalid_argument);
  }
}

// Uniaxial stretch lambda along x with free lateral faces: F = diag(lambda,
// t, t) with t from P22 = 0, found here by bisection on the closed form.
double uniaxialNominalStress(double lambda, const ElasticModuli& m) {
  const auto P = [&](double t) {
    Mat3 F = Mat3::Identity();
    F(0, 0) = lambda;
    F(1, 1) = F(2, 2) = t;
    return neoHookeanStress(F, m);
  };
  double low = 0.2, high = 2.0;  // P22 rises with t
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    (P(mid)(1, 1) > 0 ? high : low) = mid;
  }
  return P(0.5 * (low + high))(0, 0);
}

void expectUniaxialStretchFollowsTheCurveWithinOnePercent(ElementPrecision precision) {
  const double L = 10;  // mm
  const TetMesh mesh = makeBoxMesh({4, 4, 4}, Vec3::Zero(), Vec3::Constant(L));
  const ElasticModuli moduli = ElasticModuli::fromYoung(kBrain.youngModulus, kBrain.poissonRatio);
  for (double lambda : {0.8, 0.9, 1.1, 1.3, 1.5}) {
    TLEDModel model = modelOf(mesh);
    TLEDState state(model);
    model.setElementPrecision(precision);
    // Symmetry planes x = 0, y = 0, z = 0; the face x = L pulled to lambda L.
    std::vector<int32_t> pulled;
    for (size_t i = 0; i < mesh.nodeCount(); ++i) {
      const Vec3& X = mesh.nodes[i];
      unsigned axes = (X.x() == 0 ? 1u : 0u) | (X.y() == 0 ? 2u : 0u) | (X.z() == 0 ? 4u : 0u);
      if (axes) model.fixNode(int32_t(i), Vec3::Zero(), axes);
      if (X.x() == L) pulled.push_back(int32_t(i));
    }
    // Dynamic relaxation: damping about twice the lowest frequency (c / L ~ 630 rad/s).
    // The face is pulled over the first 2000 steps (a jump would crush the
    // elements next to it), then held.
    model.setTimeStep(0.9 * model.criticalTimeStep(), 2000);
    for (int step = 1; step <= 5000; ++step) {
      const double share = std::min(1.0, step / 2000.0);
      for (int32_t i : pulled) model.fixNode(i, Vec3(share * (lambda - 1) * L, 0, 0), 1u);
      state.step();
    }
    std::vector<Vec3> forces(mesh.nodeCount());
    state.internalForces(forces);
    double reaction = 0;  // mN: what holds the pulled face
    for (int32_t i : pulled) reaction += forces[i].x();
    const double expected = uniaxialNominalStress(lambda, moduli) * L * L;  // kPa mm^2 = mN
    EXPECT_NEAR(reaction / expected, 1.0, 0.01) << "stretch " << lambda << ": " << reaction << " mN against "
                                                << expected << " mN";
  }
}

TEST(TLEDModelTest, UniaxialStretchOfACubeFollowsTheNeoHookeanCurveWithinOnePercent) {
  expectUniaxialStretchFollowsTheCurveWithinOnePercent(ElementPrecision::kDouble);
}

TEST(TLEDModelTest, InSinglePrecisionUniaxialStretchFollowsTheCurveWithinOnePercent) {
  expectUniaxialStretchFollowsTheCurveWithinOnePercent(ElementPrecision::kSingle);
}

// `relative`: of the force of a 1% strain on a cell face, E 0.01 h^2 = 30 mN;
// `drift`: mm, how far a node may wander in 200 steps released.
void expectARigidMotionProducesNoForce(ElementPrecision precision, double relative, double drift) {
  const TetMesh mesh = makeBoxMesh({3, 3, 3}, Vec3::Zero(), Vec3::Constant(30));
  TLEDModel model = modelOf(mesh);
  TLEDState state(model);
  model.setElementPrecision(precision);
  const Mat3 R = Eigen::AngleAxisd(0.9, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<Vec3> u(mesh.nodeCount()), forces(mesh.nodeCount());
  for (size_t i = 0; i < u.size(); ++i) u[i] = R * mesh.nodes[i] + Vec3(40, -7, 3) - mesh.nodes[i];
  state.setDisplacements(u, u);
  state.internalForces(forces);
  for (const Vec3& f : forces) EXPECT_LT(f.norm(), relative * 30) << f.transpose();
  // Released at rest, it stays where it is.
  model.setTimeStep(0.5 * model.criticalTimeStep(), 0);
  for (int step = 0; step < 200; ++step) state.step();
  for (size_t i = 0; i < u.size(); ++i) EXPECT_LT((state.displacement(int32_t(i)) - u[i]).norm(), drift);
}

TEST(TLEDModelTest, ARigidMotionProducesNoForce) {
  expectARigidMotionProducesNoForce(ElementPrecision::kDouble, 1e-9, 1e-9);
}

TEST(TLEDModelTest, InSinglePrecisionARigidMotionProducesNoForceBeyondFloatRounding) {
  // F = R to 6e-8: the stress of a strain of about 1e-7, 1e-5 of a 1% strain's.
  // Each step rounds afresh: undamped, the nodes wander by about 1e-6 of the
  // 10 mm cells (1e-5 mm in 200 steps); 1e-4 mm bounds it.
  expectARigidMotionProducesNoForce(ElementPrecision::kSingle, 1e-5, 1e-4);
}

TEST(TLEDModelTest, AnInvertedElementGivesFiniteRestoringForcesAndIsCounted) {
  const std::vector<Vec3> nodes{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  const TetMesh mesh{nodes, {TetIndices{0, 1, 2, 3}}, {}};
  for (double z : {0.0, -0.5, -3.0}) {  // flat (J = 0), inverted, far inverted
    TLEDModel model = modelOf(mesh);
    TLEDState state(model);
    for (int32_t i = 0; i < 3; ++i) model.fixNode(i);
    std::vector<Vec3> u(4, Vec3::Zero()), forces(4);
    u[3] = Vec3(0, 0, z - 1);
    state.setDisplacements(u, u);
    state.internalForces(forces);
    for (const Vec3& f : forces) EXPECT_TRUE(f.allFinite()) << "z " << z;
    // The internal force on the apex points down (it resists): released, it moves up.
    EXPECT_LT(forces[3].z(), 0) << "z " << z;
    model.setTimeStep(0.5 * model.criticalTimeStep(), 0);
    state.step();
    EXPECT_EQ(state.invertedNow(), 1u) << "z " << z;  // J <= 0
    EXPECT_EQ(state.counts().farFromRest, 1u);
    EXPECT_GT(state.displacement(3).z(), z - 1) << "z " << z;
    EXPECT_TRUE(state.displacement(3).allFinite());
  }
}

// Total energy of a free cube released from a smooth deformation, no damping:
// at step n, the strain energy of u_n plus the kinetic energy of the central
// velocity (u_(n+1) - u_(n-1)) / (2 dt), second-order accurate as the scheme.
TEST(TLEDModelTest, WithoutDampingEnergyIsConservedWithinOnePercentOver10000Steps) {
  const TetMesh mesh = makeBoxMesh({4, 4, 4}, Vec3::Zero(), Vec3::Constant(20));
  const size_t n = mesh.nodeCount();
  TLEDModel model = modelOf(mesh);
  TLEDState state(model);
  TLEDState probe(model);  // a second state of the model: the strain energy of a past one
  std::vector<Vec3> u(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3& X = mesh.nodes[i];
    u[i] = Vec3(0.15 * X.x() * std::sin(X.y() / 12), -0.1 * X.y(), 0.05 * X.z() * X.x() / 20);
  }
  state.setDisplacements(u, u);
  const double dt = 0.5 * model.criticalTimeStep();
  model.setTimeStep(dt, 0);
  const double initial = state.strainEnergy();
  ASSERT_GT(initial, 0);
  std::vector<Vec3> before = u, now = u;
  double worst = 0, largestKinetic = 0;
  for (int step = 1; step <= 10000; ++step) {
    state.step();
    if (step % 10 == 0) {
      double kinetic = 0;  // uJ
      for (size_t i = 0; i < n; ++i)
        kinetic += 0.5 * model.mass(int32_t(i)) * ((state.displacement(int32_t(i)) - before[i]) / (2 * dt)).squaredNorm();
      probe.setDisplacements(now, now);
      largestKinetic = std::max(largestKinetic, kinetic);
      worst = std::max(worst, std::abs(probe.strainEnergy() + kinetic - initial) / initial);
    }
    before.swap(now);
    for (size_t i = 0; i < n; ++i) now[i] = state.displacement(int32_t(i));
  }
  EXPECT_GT(largestKinetic, 0.5 * initial);  // it did oscillate
  EXPECT_LT(worst, 0.01);
}

TEST(TLEDModelTest, TheCriticalTimeStepSeparatesStableFromDivergent) {
  const TetMesh mesh = makeBoxMesh({4, 4, 4}, Vec3::Zero(), Vec3::Constant(20));
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<Vec3> u(mesh.nodeCount());
  for (Vec3& v : u) v = 1e-3 * Vec3(unit(random), unit(random), unit(random));  // every mode excited
  const auto largestAfter = [&](double factor) {
    TLEDModel model = modelOf(mesh);
    TLEDState state(model);
    state.setDisplacements(u, u);
    model.setTimeStep(factor * model.criticalTimeStep(), 0);
    for (int step = 0; step < 3000; ++step) state.step();
    double largest = 0;
    for (size_t i = 0; i < u.size(); ++i) {
      const double d = state.displacement(int32_t(i)).norm();
      if (!(d <= largest)) largest = d;  // a NaN stays
    }
    return largest;
  };
  // At the bound: bounded. At 1.5 times it: diverges (to infinity, or NaN),
  // so the bound is within a factor 1.5 of the mesh's true limit.
  EXPECT_LT(largestAfter(1.0), 1e-2);
  const double beyond = largestAfter(1.5);
  EXPECT_FALSE(beyond < 1e3) << beyond;
}

TEST(TLEDModelTest, StepsAreDeterministic) {
  const TetMesh mesh = makeBoxMesh({3, 3, 3}, Vec3::Zero(), Vec3::Constant(20));
  const auto run = [&] {
    TLEDModel model = modelOf(mesh);
    TLEDState state(model);
    for (int32_t i = 0; i < 4; ++i) model.fixNode(i);
    model.setBodyAcceleration(Vec3(0, 0, -9810));
    state.setExternalForce(50, Vec3(1, 2, -3));
    model.setTimeStep(0.8 * model.criticalTimeStep(), 50);
    for (int step = 0; step < 500; ++step) state.step();
    std::vector<Vec3> positions(mesh.nodeCount());
    state.writePositions(positions);
    return positions;
  };
  const auto a = run(), b = run();
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(std::memcmp(a[i].data(), b[i].data(), sizeof(Vec3)), 0);
}

TEST(TLEDModelTest, WrittenShapesReportTheLargestDisplacementAndTheLargestMove) {
  // Checked against the positions written, node by node.
  const TetMesh mesh = makeBoxMesh({3, 3, 3}, Vec3::Zero(), Vec3::Constant(20));
  TLEDModel model = modelOf(mesh);
  TLEDState state(model);
  for (int32_t i = 0; i < 4; ++i) model.fixNode(i);
  model.setBodyAcceleration(Vec3(0, 0, -9810));
  model.setTimeStep(0.8 * model.criticalTimeStep(), 50);
  std::vector<Vec3> positions = mesh.nodes, before;
  for (int frame = 0; frame < 20; ++frame) {
    for (int step = 0; step < 3; ++step) state.step();
    before = positions;
    const TLEDState::WrittenShape shape = state.writePositions(positions);
    double displacement = 0, move = 0;
    for (size_t i = 0; i < positions.size(); ++i) {
      displacement = std::max(displacement, (positions[i] - mesh.nodes[i]).norm());
      move = std::max(move, (positions[i] - before[i]).norm());
    }
    EXPECT_NEAR(shape.largestDisplacement, displacement, 1e-12);
    EXPECT_NEAR(shape.largestMove, move, 1e-12);
  }
  EXPECT_GT(state.writePositions(positions).largestDisplacement, 0.0);  // it did move
  // Over a shape that is not finite (a diverged one) the move is unknown, the displacement is not.
  positions[7] = Vec3::Constant(NAN);
  const TLEDState::WrittenShape shape = state.writePositions(positions);
  EXPECT_TRUE(std::isfinite(shape.largestDisplacement));
  EXPECT_EQ(shape.largestMove, INFINITY);
}

TEST(TLEDModelTest, AtRestWithoutLoadNothingIsComputedAndTheAnswerIsTheComputedOne) {
  const TetMesh mesh = makeBoxMesh({3, 3, 3}, Vec3::Zero(), Vec3::Constant(20));
  TLEDModel model = modelOf(mesh);
  TLEDState state(model);
  for (int32_t i = 0; i < 4; ++i) model.fixNode(i);  // held at zero: no load
  model.setTimeStep(0.8 * model.criticalTimeStep(), 50);
  for (int step = 0; step < 100; ++step) state.step();
  EXPECT_EQ(state.steps(), 100u);
  EXPECT_EQ(state.restingSteps(), 100u);
  for (size_t i = 0; i < mesh.nodeCount(); ++i) EXPECT_EQ(state.displacement(int32_t(i)), Vec3::Zero());
  // The same 100 steps computed (a state set by hand is not known to be rest):
  // rest to rounding, which is what the skipped steps answered.
  TLEDModel computedModel = modelOf(mesh);
  TLEDState computed(computedModel);
  for (int32_t i = 0; i < 4; ++i) computedModel.fixNode(i);
  computedModel.setTimeStep(0.8 * computedModel.criticalTimeStep(), 50);
  const std::vector<Vec3> zero(mesh.nodeCount(), Vec3::Zero());
  computed.setDisplacements(zero, zero);
  for (int step = 0; step < 100; ++step) computed.step();
  EXPECT_EQ(computed.restingSteps(), 0u);
  for (size_t i = 0; i < mesh.nodeCount(); ++i) EXPECT_LT(computed.displacement(int32_t(i)).norm(), 1e-12);
  // A load ends the rest at the next step; back at rest with the load still on, it goes on computing.
  state.setExternalForce(50, Vec3(0, 0, -10));
  state.step();
  EXPECT_EQ(state.restingSteps(), 100u);
  EXPECT_LT(state.displacement(50).z(), 0.0);
  state.resetToRest();
  state.step();
  EXPECT_EQ(state.restingSteps(), 100u);
  // Without it, at rest again: nothing computed.
  state.clearExternalForces();
  state.resetToRest();
  state.step();
  EXPECT_EQ(state.restingSteps(), 101u);
  // Gravity and a held displacement are loads too.
  model.setBodyAcceleration(Vec3(0, 0, -9810));
  state.step();
  EXPECT_EQ(state.restingSteps(), 101u);
  model.setBodyAcceleration(Vec3::Zero());
  state.resetToRest();
  model.fixNode(60, Vec3(0.1, 0, 0));
  state.step();
  EXPECT_EQ(state.restingSteps(), 101u);
}

TEST(TLEDModelTest, ANodesOwnDampingDecaysItsEnergyAsExpMinusCtOverM) {
  // One element, three nodes held, the apex released from a small
  // displacement, no mass-proportional damping: damping c on the apex alone
  // is proportional to its mass, so every mode's energy decays as
  // exp(-c t / m) (lightly damped: c / (2 m omega) is about 4e-4 here).
  const std::vector<Vec3> nodes{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  const TetMesh mesh{nodes, {TetIndices{0, 1, 2, 3}}, {}};
  TLEDModel model = modelOf(mesh);
  TLEDState state(model), probe(model);  // probe: a second state of the model, the strain energy of a past one
  for (int32_t i = 0; i < 3; ++i) model.fixNode(i);
  const double m = model.mass(3), rate = 20;  // kg, 1/s
  state.setNodeDamping(3, rate * m);
  std::vector<Vec3> now(4, Vec3::Zero());
  now[3] = Vec3(1e-3, -2e-3, 1.5e-3);
  state.setDisplacements(now, now);
  // A tenth of the critical step: the central-velocity energy then wobbles
  // with the step by a few 1e-4 (it is second order in omega dt).
  const double dt = 0.1 * model.criticalTimeStep();
  model.setTimeStep(dt, 0);
  std::vector<Vec3> before = now;
  // Steps on; returns the energy of the state before the last step: its
  // strain energy and the kinetic energy of the central velocity (uJ).
  const auto stepAndMeasure = [&](int steps) {
    double energy = 0;
    for (int step = 0; step < steps; ++step) {
      state.step();
      if (step == steps - 1) {
        probe.setDisplacements(now, now);
        energy = probe.strainEnergy() +
                 0.5 * m * ((state.displacement(3) - before[3]) / (2 * dt)).squaredNorm();
      }
      before = now;
      for (int32_t i = 0; i < 4; ++i) now[i] = state.displacement(i);
    }
    return energy;
  };
  const double start = stepAndMeasure(1);
  const int steps = int(std::round(0.1 / dt));
  const double end = stepAndMeasure(steps);
  EXPECT_NEAR(end / start, std::exp(-rate * steps * dt), 0.01 * std::exp(-rate * steps * dt));
  // Removed, the energy stays.
  state.setNodeDamping(3, 0);
  EXPECT_EQ(state.dampedNodes(), 0u);
  EXPECT_NEAR(stepAndMeasure(steps) / end, 1.0, 0.01);
}

// The model is fixed while a state moves on it: two states of one model,
// stepped in turn under different loads, end where each would alone on a
// model of its own, to the bit; and a copy of a state replays its steps.
TEST(TLEDModelTest, StatesOfOneModelMoveIndependentlyAndACopyReplaysExactly) {
  const TetMesh mesh = makeBoxMesh({3, 3, 3}, Vec3::Zero(), Vec3::Constant(20));
  const auto setUp = [&](TLEDModel& model) {
    for (int32_t i = 0; i < 4; ++i) model.fixNode(i);
    model.setBodyAcceleration(Vec3(0, 0, -9810));
    model.setTimeStep(0.8 * model.criticalTimeStep(), 50);
  };
  const auto load = [](TLEDState& state, double scale) {
    state.setExternalForce(50, scale * Vec3(1, 2, -3));
    state.setNodeDamping(40, scale * 1e-3);
  };
  const auto shape = [&](const TLEDState& state) {
    std::vector<Vec3> positions(mesh.nodeCount());
    state.writePositions(positions);
    return positions;
  };
  TLEDModel shared = modelOf(mesh), aloneA = modelOf(mesh), aloneB = modelOf(mesh);
  for (TLEDModel* model : {&shared, &aloneA, &aloneB}) setUp(*model);
  TLEDState a(shared), b(shared), onlyA(aloneA), onlyB(aloneB);
  load(a, 1);
  load(onlyA, 1);
  load(b, -2);
  load(onlyB, -2);
  for (int step = 0; step < 300; ++step) {
    a.step();
    b.step();
    onlyA.step();
    onlyB.step();
  }
  EXPECT_EQ(shape(a), shape(onlyA));
  EXPECT_EQ(shape(b), shape(onlyB));
  EXPECT_NE(shape(a), shape(b)) << "the loads differ: so must the shapes";
  // A copy made mid-run (velocity, loads and counts included) replays the rest.
  TLEDState copy = a;
  for (int step = 0; step < 200; ++step) {
    a.step();
    copy.step();
  }
  EXPECT_EQ(shape(copy), shape(a));
  EXPECT_EQ(copy.steps(), 500u);
  EXPECT_EQ(copy.kineticEnergy(), a.kineticEnergy());
}

TEST(TLEDModelTest, LumpedMassesSumToTheBodysMass) {
  const TetMesh mesh = makeBoxMesh({3, 4, 5}, Vec3::Zero(), Vec3(30, 20, 10));
  const TLEDModel model = modelOf(mesh);
  EXPECT_NEAR(model.totalMass(), kBrain.density * 30 * 20 * 10, 1e-15);
}

}  // namespace
}  // namespace trephine::fem
