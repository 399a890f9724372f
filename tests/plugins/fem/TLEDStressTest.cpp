// The elements' von Mises stress (what a viewer colours the brain by) against
// closed forms of the decoupled neo-Hookean material under homogeneous
// deformations, applied to every node of a mesh whose elements lie every way:
//   uniaxial stretch F = diag(l, 1, 1):  sigma_vM = mu l^(-5/3) (l^2 - 1);
//   simple shear F = I + g e_x e_y^T:     sigma_vM = mu g sqrt(3 + g^2);
// a rigid rotation: zero; and a material per element is each element's own.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "tests/plugins/fem/FemTestSupport.h"

namespace trephine::fem {
namespace {

using test::kBrain;

const TetMesh& box() {
  static const TetMesh mesh = tetra::makeBoxMesh({5, 4, 3}, Vec3(-3, 2, 1), Vec3(17, 14, 10));
  return mesh;
}

// The von Mises stress of every element (kPa) with every node at F X + c.
std::vector<float> stressUnder(const TLEDModel& model, const Mat3& F) {
  TLEDState state(model);
  std::vector<Vec3> u;
  for (const Vec3& X : box().nodes) u.push_back((F - Mat3::Identity()) * X + Vec3(4, -2, 7));
  state.setDisplacements(u, u);
  std::vector<float> out(model.elementCount(), NAN);
  state.vonMisesStress(out);
  return out;
}

const double kMu = ElasticModuli::fromYoung(kBrain.youngModulus, kBrain.poissonRatio).mu;

TEST(TLEDStressTest, UniaxialStretchGivesTheClosedForm) {
  const TLEDModel model = test::modelOf(box());
  for (double l : {0.8, 0.97, 1.0, 1.02, 1.3}) {
    const double expected = kMu * std::pow(l, -5.0 / 3.0) * (l * l - 1);
    for (float s : stressUnder(model, Eigen::Vector3d(l, 1, 1).asDiagonal().toDenseMatrix()))
      ASSERT_NEAR(s, std::abs(expected), 1e-5 * kMu + 1e-6 * std::abs(expected)) << "stretch " << l;
  }
}

TEST(TLEDStressTest, SimpleShearGivesTheClosedForm) {
  const TLEDModel model = test::modelOf(box());
  for (double g : {0.01, 0.1, 0.5}) {
    Mat3 F = Mat3::Identity();
    F(0, 1) = g;
    const double expected = kMu * g * std::sqrt(3 + g * g);
    for (float s : stressUnder(model, F)) ASSERT_NEAR(s, expected, 1e-5 * kMu) << "shear " << g;
  }
}

TEST(TLEDStressTest, ARigidRotationIsUnstressed) {
  const TLEDModel model = test::modelOf(box());
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, -1).normalized()).toRotationMatrix();
  for (float s : stressUnder(model, R)) ASSERT_NEAR(s, 0.0, 1e-9 * kMu);
}

TEST(TLEDStressTest, EachElementHasItsOwnMaterialInTheMeshOrder) {
  TLEDModel model = test::modelOf(box());
  // A stiffer material on every third element (the model stores them in its
  // own order: the output must come back in the mesh's).
  std::vector<int32_t> stiff;
  for (int32_t e = 0; e < int32_t(box().tets.size()); e += 3) stiff.push_back(e);
  ElementMaterial hard = kBrain;
  hard.youngModulus = 4 * kBrain.youngModulus;
  model.assignMaterial(stiff, hard);
  const double l = 1.1, expected = kMu * std::pow(l, -5.0 / 3.0) * (l * l - 1);
  const std::vector<float> s = stressUnder(model, Eigen::Vector3d(l, 1, 1).asDiagonal().toDenseMatrix());
  for (size_t e = 0; e < s.size(); ++e)
    ASSERT_NEAR(s[e], (e % 3 == 0 ? 4 : 1) * expected, 1e-5 * expected) << "element " << e;
}

}  // namespace
}  // namespace trephine::fem
