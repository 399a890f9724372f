// Hard cases of the tetrahedral brain: points on faces, edges and vertices,
// degenerate tetrahedra, a sharp ridge, tools much smaller and larger than the
// tetrahedra, a mesh far from the origin, a tool deep inside.
#include <gtest/gtest.h>

#include "tests/plugins/tetra_brain/TetTestShapes.h"
#include "tests/support/TestSupport.h"

namespace trephine::tetra {
namespace {

using shapes::cubeBrain;
using shapes::sphereShell;

TEST(TetraBrainTest, PointsOnFacesEdgesAndVerticesAreCountedOnce) {
  TetraBrain brain;
  cubeBrain(brain, 2);  // nodes at -100, 0, 100 on each axis: faces, edges and vertices at 0
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(0, 0, 50), Vec3(0, 30, 50), Vec3(20, 30, 0), Vec3(-100, -100, -100)}) {
    const int32_t tet = shapes::native(brain).locate(p);
    ASSERT_GE(tet, 0) << p.transpose();
    // The tet reported is the lowest-numbered tet that holds the point.
    for (int32_t t = 0; t < tet; ++t) {
      const TetIndices& k = brain.mesh().tets[t];
      const auto& n = brain.mesh().nodes;
      const double tolerance = -1e-12 * signedVolume(n[k[0]], n[k[1]], n[k[2]], n[k[3]]);
      const bool holds = signedVolume(p, n[k[1]], n[k[2]], n[k[3]]) >= tolerance &&
                         signedVolume(n[k[0]], p, n[k[2]], n[k[3]]) >= tolerance &&
                         signedVolume(n[k[0]], n[k[1]], p, n[k[3]]) >= tolerance &&
                         signedVolume(n[k[0]], n[k[1]], n[k[2]], p) >= tolerance;
      EXPECT_FALSE(holds) << "tet " << t << " holds " << p.transpose() << " before " << tet;
    }
  }
  EXPECT_EQ(shapes::native(brain).locate(Vec3(0, 0, 100.001)), -1);
  // A shell whose points sit on shared faces: each counted once, contact consistent.
  std::vector<ShellPoint> shell = {{Vec3(0, 0, 0), Vec3(0, 0, 1)}, {Vec3(0, 50, 0), Vec3(0, 0, 1)}};
  ContactMemory memory_brain_shell = brain.reserveShell(shell);
  const ShellContact c = brain.collide(Pose{Vec3(0, 0, 95), Quat::Identity()}, shell, false, memory_brain_shell);
  EXPECT_EQ(c.points, 2);
  EXPECT_GT(c.normal.z(), 0.99);
  EXPECT_NEAR(c.penetration, 5.0, 1e-9);
}

TEST(TetraBrainTest, DegenerateTetrahedraAreReportedAndHoldNoPoint) {
  TetMesh mesh = makeCubeMesh(1);
  mesh.nodes.push_back(Vec3(0, 0, 100));  // on the top face
  const int32_t top = int32_t(mesh.nodes.size()) - 1;
  mesh.tets.push_back({0, 1, 2, 3});  // zero volume: four corners of the bottom face
  mesh.tets.push_back({mesh.tets[0][0], mesh.tets[0][1], mesh.tets[0][2], top});  // a sliver/duplicate user
  TetraBrain brain;
  brain.setMesh(mesh);
  EXPECT_GE(brain.report().degenerateTets, 1u);
  const std::vector<ShellPoint> shell = sphereShell(2.5, 200);
  ContactMemory memory_brain_shell = brain.reserveShell(shell);
  for (double z : {-99.0, 0.0, 99.0}) {
    const ShellContact c = brain.collide(Pose{Vec3(1, 2, z), Quat::Identity()}, shell, false, memory_brain_shell);
    EXPECT_TRUE(c.normal.allFinite());
    EXPECT_TRUE(std::isfinite(c.penetration));
  }
}

TEST(TetraBrainTest, SharpRidgeFallsBackToTheNearestFace) {
  // A ridge: two tets whose top faces meet at a sharp edge along y (a roof, 90 degrees).
  TetMesh mesh;
  mesh.nodes = {Vec3(-10, -10, 0), Vec3(10, -10, 0), Vec3(-10, 10, 0),
                Vec3(10, 10, 0),   Vec3(0, -10, 10), Vec3(0, 10, 10)};
  mesh.tets = {{0, 2, 4, 1}, {1, 2, 4, 5}, {1, 2, 5, 3}};
  TetraBrain brain;
  brain.setMesh(mesh);
  const std::vector<ShellPoint> shell = sphereShell(2.0, 300);
  ContactMemory memory_brain_shell = brain.reserveShell(shell);
  // The sphere pressed straight down onto the ridge line.
  const ShellContact c = brain.collide(Pose{Vec3(0, 0, 11.0), Quat::Identity()}, shell, false, memory_brain_shell);
  ASSERT_GT(c.points, 0);
  EXPECT_TRUE(c.normal.allFinite());
  EXPECT_NEAR(c.normal.norm(), 1.0, 1e-9);
  EXPECT_GT(c.normal.z(), 0.5) << "the ridge pushes the tool up";
  EXPECT_GT(c.penetration, 0.0);
}

TEST(TetraBrainTest, ToolsSmallerAndLargerThanTheTetrahedraMeasureTheSameDepth) {
  for (const auto& [cells, radius] : {std::pair{1, 2.5}, std::pair{7, 2.5}, std::pair{60, 10.0}, std::pair{60, 1.0}}) {
    TetraBrain brain;
    cubeBrain(brain, cells);
    const std::vector<ShellPoint> shell = sphereShell(radius, 466);
    ContactMemory memory_brain_shell = brain.reserveShell(shell);
    // Pressed 0.8 mm into the top face (z = 100).
    const ShellContact c = brain.collide(Pose{Vec3(3, -7, 100 + radius - 0.8), Quat::Identity()}, shell, false, memory_brain_shell);
    EXPECT_NEAR(c.penetration, 0.8, 0.05) << cells << " cells, radius " << radius;
    EXPECT_GT(c.normal.z(), 0.999) << cells << " cells, radius " << radius;
  }
}

TEST(TetraBrainTest, AMeshFarFromTheOriginGivesTheSameContact) {
  const Vec3 far(1e5, -2e5, 3e5);  // mm: 100 to 300 m away
  TetraBrain near, away;
  cubeBrain(near, 13);
  cubeBrain(away, 13, far);
  const std::vector<ShellPoint> shell = sphereShell(2.5, 466);
  ContactMemory memory_near_shell = near.reserveShell(shell);
  ContactMemory memory_away_shell = away.reserveShell(shell);
  const Vec3 centre(11.3, -4.7, 101.7);
  const ShellContact a = near.collide(Pose{centre, Quat::Identity()}, shell, false, memory_near_shell);
  const ShellContact b = away.collide(Pose{centre + far, Quat::Identity()}, shell, false, memory_away_shell);
  EXPECT_EQ(a.points, b.points);
  EXPECT_NEAR(a.penetration, b.penetration, 1e-6);
  EXPECT_NEAR((a.normal - b.normal).norm(), 0.0, 1e-9);
}

TEST(TetraBrainTest, ToolDeepInsideMeasuresToTheNearestBoundaryFace) {
  // Algorithm 2 only measures to boundary faces of the colliding tetrahedra; 12 mm
  // under the top of a fine mesh they have none, so the nearest boundary face is used.
  TetraBrain brain;
  cubeBrain(brain, 22);  // 9 mm cells
  const std::vector<ShellPoint> shell = sphereShell(2.5, 466);
  ContactMemory memory_brain_shell = brain.reserveShell(shell);
  const ShellContact c = brain.collide(Pose{Vec3(1, 1, 100 - 12), Quat::Identity()}, shell, false, memory_brain_shell);
  EXPECT_EQ(c.points, 466);
  EXPECT_NEAR(c.penetration, 12 + 2.5, 0.1) << "the deepest point, below the top face";
  EXPECT_GT(c.normal.z(), 0.99);
  EXPECT_EQ(test::counter(brain, "deep_fallbacks"), 466.0) << "every point measured to the mesh's nearest face";
}

TEST(TetraBrainTest, TheThesisSearchesFindTheSameContactsAsTheGrid) {
  // A tool smaller than the tetrahedra: the first colliding tet and two rings of
  // neighbours hold every colliding point, so the thesis's scans agree with the grid.
  const std::vector<ShellPoint> shell = sphereShell(2.5, 211);
  for (const Vec3& centre : {Vec3(3, -7, 101.7), Vec3(-60, 40, 100.5), Vec3(99.5, 0, 30)}) {
    ShellContact results[3];
    int k = 0;
    for (const char* search : {"grid", "first-tetrahedron", "previous-contact"}) {
      TetraBrain brain;
      ASSERT_TRUE(brain.findField("search")->assign(search, {}, {}) == std::nullopt);
      cubeBrain(brain, 13);
      ContactMemory memory_brain_shell = brain.reserveShell(shell);
      results[k++] = brain.collide(Pose{centre, Quat::Identity()}, shell, false, memory_brain_shell);
    }
    for (int i = 1; i < 3; ++i) {
      EXPECT_EQ(results[i].points, results[0].points) << centre.transpose() << " search " << i;
      EXPECT_NEAR(results[i].penetration, results[0].penetration, 1e-12) << centre.transpose();
    }
    EXPECT_GT(results[0].points, 0) << centre.transpose();
  }
}

TEST(TetraBrainTest, ScaleConvertsTheFilesUnitToMillimetres) {
  // The same cube phantom read as if in centimetres: every length ten times.
  auto averageEdge = [](const std::string& scale) {
    Diagnostics d;
    auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <TetraBrain name="brain" file="phantom:cube?cells=7" translation="5 0 0" )" +
                                          scale + R"(/>
</Node>)",
                                      d);
    EXPECT_TRUE(simulation) << test::messages(d);
    return simulation ? test::componentCounter(*simulation, "TetraBrain", "average_edge_mm") : 0.0;
  };
  EXPECT_NEAR(averageEdge(R"(scale="10")"), 10 * averageEdge(""), 1e-9);
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <TetraBrain name="brain" file="phantom:cube?cells=7" scale="-1"/>
</Node>)",
                               d));
  EXPECT_NE(test::messages(d).find("inline.xml:3:"), std::string::npos) << test::messages(d);
}

TEST(TetraBrainTest, BadMeshSourcesAreLoadErrorsAtTheAttribute) {
  auto errors = [](const std::string& file, const std::string& extra = "") {
    const std::string xml = R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <TetraBrain name="brain" file=")" +
                            file + "\" " + extra + R"(/>
</Node>)";
    Diagnostics d;
    EXPECT_FALSE(test::loadScene(xml, d)) << file;
    return test::messages(d);
  };
  std::string m = errors("phantom:cube?cells=0");
  EXPECT_NE(m.find("inline.xml:3:"), std::string::npos) << m;
  EXPECT_NE(m.find("phantom key 'cells' must be in [1, 200]"), std::string::npos) << m;
  m = errors("phantom:torus");
  EXPECT_NE(m.find("unknown phantom 'torus' (cube, bar, brain, sphere)"), std::string::npos) << m;
  test::TempDir dir;
  dir.write("broken.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices\n2\n0 0 0 0\n");
  m = errors((dir / "broken.mesh").string());
  EXPECT_NE(m.find("broken.mesh"), std::string::npos) << m;
  EXPECT_NE(m.find("inline.xml:3:"), std::string::npos) << m;
  // An inverted tetrahedron refused on request, with its index.
  dir.write("inverted.mesh",
            "MeshVersionFormatted 1\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
            "Tetrahedra\n1\n1 3 2 4 0\nEnd\n");
  m = errors((dir / "inverted.mesh").string(), R"(inverted="refuse")");
  EXPECT_NE(m.find("1 tetrahedra with negative volume (first: 0)"), std::string::npos) << m;
}

}  // namespace
}  // namespace trephine::tetra
