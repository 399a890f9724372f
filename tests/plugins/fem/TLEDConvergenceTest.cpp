// TLED's convergence on a bending problem: a cantilever under gravity
// against Euler-Bernoulli as the mesh is refined, and the damped dynamic
// cantilever against the static solution of its mesh. Numerical checks of
// the material and the integrator (seconds of arithmetic), so they are left
// out of the sanitizer runs (label "numerics"); the other FEM tests run the
// same code there.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "tests/plugins/fem/FemTestSupport.h"

namespace trephine::fem {
namespace {

using tetra::makeBoxMesh;

using test::kBrain;
using test::modelOf;

// A cantilever along x (length 100 mm, square section 10 mm) clamped at
// x = 0 under its own weight, at a small acceleration so that the strain stays
// small (Euler-Bernoulli: tip deflection 3 rho g L^4 / (2 E h^2) = 0.5 mm).
struct Cantilever {
  static constexpr double L = 100, h = 10, g = 10;  // mm, mm, mm/s^2
  TetMesh mesh;
  std::vector<char> clamped;
  explicit Cantilever(int cellsAcross)
      : mesh(makeBoxMesh({10 * cellsAcross, cellsAcross, cellsAcross}, Vec3(0, -h / 2, -h / 2), Vec3(L, h / 2, h / 2))) {
    for (const Vec3& X : mesh.nodes) clamped.push_back(X.x() == 0);
  }
  static double eulerBernoulli() { return -3 * kBrain.density * g * std::pow(L, 4) / (2 * kBrain.youngModulus * h * h); }
  double meanTip(const std::function<double(size_t)>& deflection) const {
    double sum = 0;
    int count = 0;
    for (size_t i = 0; i < mesh.nodeCount(); ++i)
      if (mesh.nodes[i].x() == L) sum += deflection(i), ++count;
    return sum / count;
  }
};

// The static deflection from the kernel's own forces: K u = m g solved by
// conjugate gradients (Jacobi preconditioned), K v the difference quotient of
// the internal forces along v at rest (the small-strain stiffness).
double staticTipDeflection(const Cantilever& beam) {
  const TLEDModel model = modelOf(beam.mesh);
  const size_t m = beam.mesh.nodeCount();
  using Vector = std::vector<Vec3>;
  Vector plus(m), forcePlus(m);
  // The forces at rest are zero, so one evaluation gives the derivative (to
  // a relative 1e-6 at a displacement of 1e-6 mm).
  const auto stiffness = [&](const Vector& v, Vector& out) {
    double largest = 1e-300;
    for (const Vec3& x : v) largest = std::max(largest, x.cwiseAbs().maxCoeff());
    const double epsilon = 1e-6 / largest;  // mm of the largest entry
    for (size_t i = 0; i < m; ++i) plus[i] = epsilon * v[i];
    model.internalForcesAt(plus, forcePlus);
    for (size_t i = 0; i < m; ++i) out[i] = beam.clamped[i] ? Vec3::Zero() : Vec3(forcePlus[i] / epsilon);
  };
  // Jacobi: the diagonal of the linear-elastic element stiffness, from the mesh.
  const ElasticModuli moduli = ElasticModuli::fromYoung(kBrain.youngModulus, kBrain.poissonRatio);
  Vector diagonal(m, Vec3::Zero());
  for (const TetIndices& t : beam.mesh.tets) {
    Mat3 D;
    for (int a = 0; a < 3; ++a) D.col(a) = beam.mesh.nodes[t[a + 1]] - beam.mesh.nodes[t[0]];
    const Mat3 G = D.inverse();
    const double V = D.determinant() / 6;
    std::array<Vec3, 4> g;
    for (int a = 0; a < 3; ++a) g[a + 1] = G.row(a).transpose();
    g[0] = -(g[1] + g[2] + g[3]);
    for (int a = 0; a < 4; ++a)
      diagonal[t[a]] += V * ((moduli.lambda() + moduli.mu) * g[a].cwiseProduct(g[a]) +
                             Vec3::Constant(moduli.mu * g[a].squaredNorm()));
  }
  const auto dot = [](const Vector& a, const Vector& b) {
    double s = 0;
    for (size_t i = 0; i < a.size(); ++i) s += a[i].dot(b[i]);
    return s;
  };
  Vector x(m, Vec3::Zero()), r(m), z(m), p(m), Ap(m);
  for (size_t i = 0; i < m; ++i)
    r[i] = beam.clamped[i] ? Vec3::Zero() : Vec3(0, 0, -model.mass(int32_t(i)) * Cantilever::g);
  const double bb = dot(r, r);
  const auto precondition = [&] {
    for (size_t i = 0; i < m; ++i) z[i] = r[i].cwiseQuotient(diagonal[i]);
  };
  precondition();
  p = z;
  double rz = dot(r, z);
  // To a residual 1e-7 of the load: the deflection to about as much, far below the 5% asked.
  for (int iteration = 0; iteration < 5000 && dot(r, r) > 1e-14 * bb; ++iteration) {
    stiffness(p, Ap);
    const double alpha = rz / dot(p, Ap);
    for (size_t i = 0; i < m; ++i) x[i] += alpha * p[i], r[i] -= alpha * Ap[i];
    precondition();
    const double next = dot(r, z);
    for (size_t i = 0; i < m; ++i) p[i] = z[i] + (next / rz) * p[i];
    rz = next;
  }
  EXPECT_LE(dot(r, r), 1e-14 * bb) << "conjugate gradients did not converge";
  return beam.meanTip([&](size_t i) { return x[i].z(); });
}

TEST(TLEDConvergenceTest, ACantileverUnderGravityConvergesToEulerBernoulli) {
  // Linear tetrahedra are stiff in bending: the error falls with the square
  // of the element size (here 32%, 11% and 4% with 2, 4 and 7 cells across).
  const double exact = Cantilever::eulerBernoulli();
  double previousError = INFINITY;
  for (int cells : {2, 4, 7}) {
    const double tip = staticTipDeflection(Cantilever(cells));
    const double error = std::abs(tip / exact - 1);
    std::printf("%d cells across: tip %.4f mm, Euler-Bernoulli %.4f mm, error %.1f%%\n", cells, tip, exact, 100 * error);
    EXPECT_LT(error, previousError) << cells << " cells across";
    previousError = error;
  }
  EXPECT_LT(previousError, 0.05) << "7 cells across";
}

class DampedCantilever : public ::testing::TestWithParam<ElementPrecision> {};

// In double and in single precision: the strains here are about 1e-4, where
// a float's stress carries about 1e-3 of relative rounding.
TEST_P(DampedCantilever, SettlesOnItsStaticDeflectionWithinOnePercent) {
  const Cantilever beam(2);
  const double expected = staticTipDeflection(beam);
  TLEDModel model = modelOf(beam.mesh);
  model.setElementPrecision(GetParam());
  TLEDState state(model);
  for (size_t i = 0; i < beam.mesh.nodeCount(); ++i)
    if (beam.clamped[i]) model.fixNode(int32_t(i));
  model.setBodyAcceleration(Vec3(0, 0, -Cantilever::g));
  // The first bending mode is at 3.5 (h / L^2) sqrt(E / (12 rho)) = 5.6 rad/s; damping twice that.
  model.setTimeStep(0.9 * model.criticalTimeStep(), 11);
  const int steps = int(std::ceil(4.0 / model.timeStep()));  // 4 s
  for (int step = 0; step < steps; ++step) state.step();
  const double tip = beam.meanTip([&](size_t i) { return state.displacement(int32_t(i)).z(); });
  std::printf("tip %.6f mm, static %.6f mm, error %.3f%%\n", tip, expected, 100 * std::abs(tip / expected - 1));
  EXPECT_NEAR(tip / expected, 1.0, 0.01) << tip << " mm against " << expected << " mm";
}

INSTANTIATE_TEST_SUITE_P(Precisions, DampedCantilever,
                         ::testing::Values(ElementPrecision::kDouble, ElementPrecision::kSingle),
                         [](const auto& info) { return info.param == ElementPrecision::kSingle ? "single" : "double"; });

}  // namespace
}  // namespace trephine::fem
