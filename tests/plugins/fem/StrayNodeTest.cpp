// A mesh file with a node that no tetrahedron holds (a stray vertex far from
// the body): the load names it, and it changes nothing of how the body
// deforms or when the FEM counts as diverged.
#include <gtest/gtest.h>

#include "tests/plugins/fem/FemFailureScenes.h"
#include "tests/plugins/fem/FemScenes.h"
#include "tests/support/TestSupport.h"

namespace trephine::fem {
namespace {

const Vec3 kStray(1000, 1000, 1000);  // mm, 1.7 m from a 20 mm cube

TEST(StrayNodeTest, TheLoadWarnsNamingTheNodeAndWhereItIs) {
  test::TempDir dir;
  const auto mesh = scenes::writeCube(dir / "stray.mesh", &kStray);
  Diagnostics d;
  ASSERT_TRUE(test::loadScene(scenes::cubePressScene(mesh), d)) << test::messages(d);
  const std::string m = test::messages(d);
  EXPECT_NE(m.find("warning: file of TetraBrain 'brain': 1 node is used by no tetrahedron and ignored: node 343"),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("at (1000, 1000, 1000) mm"), std::string::npos) << m;
}

TEST(StrayNodeTest, AStrayNodeChangesNothingOfWhenTheFemCountsAsDiverged) {
  // The same press on the same cube, with and without the stray node: the FEM
  // diverges in both (the cube cannot carry the probe's point load) and the
  // shapes handed to the collision go as far from rest in both. Counted with
  // the stray node, the body's size was 1.7 m and shapes torn 1.5 m apart
  // reached the collision.
  test::TempDir dir;
  double largest[2] = {0, 0};
  for (int withStray = 0; withStray < 2; ++withStray) {
    const auto mesh = scenes::writeCube(dir / "cube.mesh", withStray ? &kStray : nullptr);
    auto simulation = scenes::runFor(scenes::cubePressScene(mesh), 1.0, dir / ("out" + std::to_string(withStray)));
    ASSERT_TRUE(simulation);
    EXPECT_GT(test::componentCounter(*simulation, "TLEDForceField", "non_finite_ticks"), 0) << "it diverges";
    largest[withStray] = test::componentCounter(*simulation, "TLEDForceField", "largest_displacement_mm");
  }
  EXPECT_GT(largest[0], 1.0);
  EXPECT_LT(largest[1], 1.5 * largest[0]) << "without the stray node: " << largest[0] << " mm";
}

}  // namespace
}  // namespace trephine::fem
