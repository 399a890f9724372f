// The CGAL-meshed brain phantom: tet counts near the target, orientation,
// compact node numbering, size and shape (base, fissure, filled volume),
// determinism and the refused targets. Small targets keep it fast under ASan.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "plugins/tetra_brain/BrainPhantom.h"

namespace trephine::tetra {
namespace {

class BrainPhantomTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    small_ = new TetMesh(makeBrainPhantom(3500));
    medium_ = new TetMesh(makeBrainPhantom(22000));
  }
  static void TearDownTestSuite() {
    delete small_;
    delete medium_;
  }
  static std::vector<const TetMesh*> meshes() { return {small_, medium_}; }

  static TetMesh* small_;
  static TetMesh* medium_;
};
TetMesh* BrainPhantomTest::small_ = nullptr;
TetMesh* BrainPhantomTest::medium_ = nullptr;

double tetVolume(const TetMesh& mesh, const TetIndices& t) {
  return signedVolume(mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]], mesh.nodes[t[3]]);
}

// Highest z (mm) at which the vertical line through (x, y) meets the mesh: the
// largest crossing of the line with a face of a tet, or -infinity if none.
double topAlongVertical(const TetMesh& mesh, double x, double y) {
  double top = -std::numeric_limits<double>::infinity();
  constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  for (const TetIndices& t : mesh.tets) {
    for (const auto& f : kFaces) {
      const Vec3& a = mesh.nodes[t[f[0]]];
      const Vec3& b = mesh.nodes[t[f[1]]];
      const Vec3& c = mesh.nodes[t[f[2]]];
      // Barycentric coordinates of (x, y) in the face projected onto z = 0.
      const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
      if (std::abs(det) < 1e-12) continue;
      const double u = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / det;
      const double v = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / det;
      if (u < 0 || v < 0 || u + v > 1) continue;
      top = std::max(top, a.z() + u * (b.z() - a.z()) + v * (c.z() - a.z()));
    }
  }
  return top;
}

TEST_F(BrainPhantomTest, CountsAreWithinTenPercentOfTheTarget) {
  EXPECT_NEAR(static_cast<double>(small_->tetCount()), 3500.0, 350.0);
  EXPECT_NEAR(static_cast<double>(medium_->tetCount()), 22000.0, 2200.0);
}

TEST_F(BrainPhantomTest, EveryTetIsPositiveAndLabelledOne) {
  for (const TetMesh* mesh : meshes()) {
    ASSERT_EQ(mesh->labels.size(), mesh->tetCount());
    for (size_t i = 0; i < mesh->tetCount(); ++i) {
      for (int32_t node : mesh->tets[i]) {
        ASSERT_GE(node, 0);
        ASSERT_LT(static_cast<size_t>(node), mesh->nodeCount());
      }
      // 1e-3 mm^3: far below the smallest Mesh_3 tet here (about 0.5 mm^3).
      ASSERT_GT(tetVolume(*mesh, mesh->tets[i]), 1e-3) << "tet " << i;
      ASSERT_EQ(mesh->labels[i], 1);
    }
  }
}

TEST_F(BrainPhantomTest, EveryNodeBelongsToATet) {
  for (const TetMesh* mesh : meshes()) {
    std::vector<bool> used(mesh->nodeCount(), false);
    for (const TetIndices& t : mesh->tets)
      for (int32_t node : t) used[node] = true;
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
  }
}

TEST_F(BrainPhantomTest, HasAdultBrainSizeWithAFlatBase) {
  for (const TetMesh* mesh : meshes()) {
    Vec3 low = Vec3::Constant(std::numeric_limits<double>::infinity()), high = -low;
    for (const Vec3& p : mesh->nodes) {
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
      // Boundary nodes lie on the implicit surface, the others inside it (mm).
      ASSERT_LT(brainPhantomDistance(p), 0.05) << p.transpose();
    }
    const Vec3 size = high - low, centre = 0.5 * (high + low);
    EXPECT_NEAR(size.x(), 140.0, 4.0);  // left-right
    EXPECT_NEAR(size.y(), 170.0, 4.0);  // posterior-anterior
    EXPECT_NEAR(size.z(), 115.0, 4.0);  // height
    EXPECT_LT(centre.norm(), 2.0);
    EXPECT_NEAR(low.z(), kBrainBaseZ, 0.01);
  }
}

// The mesh fills the implicit body: its volume matches the body's volume
// counted on a 2 mm grid, so no part is missing and no fissure is bridged.
TEST_F(BrainPhantomTest, FillsTheImplicitBody) {
  constexpr double h = 2.0;  // mm
  double bodyVolume = 0;
  for (double x = -75 + h / 2; x < 75; x += h)
    for (double y = -90 + h / 2; y < 90; y += h)
      for (double z = -60 + h / 2; z < 60; z += h)
        if (brainPhantomDistance(Vec3(x, y, z)) < 0) bodyVolume += h * h * h;
  for (const TetMesh* mesh : meshes()) {
    double volume = 0;
    for (const TetIndices& t : mesh->tets) volume += tetVolume(*mesh, t);
    EXPECT_NEAR(volume / bodyVolume, 1.0, mesh == small_ ? 0.04 : 0.02) << mesh->tetCount() << " tets";
  }
}

// The longitudinal fissure splits the top of the brain but not the body: the
// mesh starts lower on the mid-sagittal plane than 20 mm to either side, and
// no node lies in the groove.
TEST_F(BrainPhantomTest, LongitudinalFissureSeparatesTheHemispheresAtTheTop) {
  for (const TetMesh* mesh : meshes()) {
    for (double y : {-40.0, 0.0, 40.0}) {
      const double middle = topAlongVertical(*mesh, 0.0, y);
      const double left = topAlongVertical(*mesh, -20.0, y), right = topAlongVertical(*mesh, 20.0, y);
      EXPECT_LT(middle, std::min(left, right) - 15.0) << mesh->tetCount() << " tets, y = " << y;
      // The hemispheres stay joined below the fissure.
      EXPECT_NEAR(middle, kBrainFissureBottomZ, 3.0) << mesh->tetCount() << " tets, y = " << y;
    }
    for (const Vec3& p : mesh->nodes) {
      // Between the straight walls, above the rounded bottom (mm).
      const double wallsBottom = kBrainFissureBottomZ + 0.5 * kBrainFissureWidth;
      const bool inGroove = std::abs(p.x()) < 0.5 * kBrainFissureWidth - 0.1 && p.z() > wallsBottom;
      ASSERT_FALSE(inGroove) << p.transpose();
    }
  }
}

TEST_F(BrainPhantomTest, SameTargetGivesTheSameMesh) {
  const TetMesh again = makeBrainPhantom(3500);
  ASSERT_EQ(again.nodeCount(), small_->nodeCount());
  ASSERT_EQ(again.tetCount(), small_->tetCount());
  for (size_t i = 0; i < again.nodeCount(); ++i) ASSERT_EQ(again.nodes[i], small_->nodes[i]) << "node " << i;
  for (size_t i = 0; i < again.tetCount(); ++i) ASSERT_EQ(again.tets[i], small_->tets[i]) << "tet " << i;
  EXPECT_EQ(again.labels, small_->labels);
}

TEST(BrainPhantom, RefusesTargetsOutsideTheRange) {
  for (int target : {-1, 0, 99, 2000001}) {
    try {
      makeBrainPhantom(target);
      ADD_FAILURE() << target << " was accepted";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find("[100, 2000000]"), std::string::npos) << error.what();
      EXPECT_NE(std::string(error.what()).find(std::to_string(target)), std::string::npos) << error.what();
    }
  }
}

}  // namespace
}  // namespace trephine::tetra
