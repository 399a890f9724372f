// `trephine mesh`: a surface or a ball to a tetrahedral mesh file at a
// count, and clear errors.
#include <gtest/gtest.h>

#include "plugins/tetra_brain/io/TetMeshReader.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using test::runProgram;

// A closed tetrahedron's surface, normals out.
constexpr const char* kTetrahedron = "OFF\n4 4 0\n0 0 0\n10 0 0\n0 10 0\n0 0 10\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

TEST(MeshCommandTest, ASurfaceAndABallMeshToTheCountAsked) {
  test::TempDir dir;
  dir.write("tet.off", kTetrahedron);
  std::string out;
  ASSERT_EQ(runProgram({"mesh", (dir / "tet.off").string(), "--tets", "2000", "--out", (dir / "tet.mesh").string()}, &out),
            0)
      << out;
  const tetra::TetMesh fromSurface = tetra::readTetMesh(dir / "tet.mesh");
  EXPECT_NEAR(double(fromSurface.tetCount()), 2000.0, 0.05 * 2000) << out;
  ASSERT_EQ(runProgram({"mesh", "phantom:sphere?radius=10", "--tets", "3000", "--out", (dir / "ball.vtu").string()}, &out),
            0)
      << out;
  EXPECT_NEAR(double(tetra::readTetMesh(dir / "ball.vtu").tetCount()), 3000.0, 0.03 * 3000) << out;
  // At a size instead of a count: larger cells, fewer tetrahedra.
  ASSERT_EQ(runProgram({"mesh", "phantom:sphere?radius=10", "--size", "4", "--out", (dir / "coarse.mesh").string()}, &out),
            0)
      << out;
  EXPECT_LT(tetra::readTetMesh(dir / "coarse.mesh").tetCount(), 3000u) << out;
}

TEST(MeshCommandTest, TheSameSurfaceGivesTheSameFile) {
  test::TempDir dir;
  dir.write("tet.off", kTetrahedron);
  std::string out;
  for (const char* name : {"a.mesh", "b.mesh"})
    ASSERT_EQ(runProgram({"mesh", (dir / "tet.off").string(), "--tets", "1500", "--out", (dir / name).string()}, &out), 0)
        << out;
  const std::string a = test::readFile(dir / "a.mesh");
  EXPECT_GT(a.size(), 1000u);
  EXPECT_EQ(a, test::readFile(dir / "b.mesh")) << "seeded: byte-identical";
}

TEST(MeshCommandTest, BadArgumentsAndSurfacesAreClearErrors) {
  test::TempDir dir;
  dir.write("tet.off", kTetrahedron);
  const std::string tet = (dir / "tet.off").string();
  std::string out;
  EXPECT_EQ(runProgram({"mesh", tet, "--tets", "2000"}, &out), 2);
  EXPECT_NE(out.find("--out OUT is required"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"mesh", tet, "--tets", "2000", "--size", "1", "--out", "x.mesh"}, &out), 2);
  EXPECT_EQ(runProgram({"mesh", tet, "--tets", "2000", "--out", "x.stl"}, &out), 2);
  EXPECT_NE(out.find("--out must end in .mesh, .mesh.gz or .vtu"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"mesh", tet, "--tets", "12", "--out", "x.mesh"}, &out), 2);
  // Three faces of the four: a hole.
  dir.write("open.off", "OFF\n4 3 0\n0 0 0\n10 0 0\n0 10 0\n0 0 10\n3 0 2 1\n3 0 1 3\n3 0 3 2\n");
  EXPECT_EQ(runProgram({"mesh", (dir / "open.off").string(), "--tets", "500", "--out", (dir / "o.mesh").string()}, &out), 1);
  EXPECT_NE(out.find("not closed: 3 edges belong to one triangle only"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"mesh", (dir / "nothere.obj").string(), "--tets", "500", "--out", (dir / "o.mesh").string()}, &out), 1);
  EXPECT_NE(out.find("nothere.obj"), std::string::npos) << out;
}

}  // namespace
}  // namespace trephine
