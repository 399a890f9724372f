// `trephine mesh`: a surface, a ball or a labelled image to a tetrahedral
// mesh file at a count, and clear errors.
#include <gtest/gtest.h>

#include <set>

#include "framework/formats/mesh/TetMeshReader.h"
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
  const TetMesh fromSurface = formats::readTetMesh(dir / "tet.mesh");
  EXPECT_NEAR(double(fromSurface.tetCount()), 2000.0, 0.05 * 2000) << out;
  ASSERT_EQ(runProgram({"mesh", "phantom:sphere?radius=10", "--tets", "3000", "--out", (dir / "ball.vtu").string()}, &out),
            0)
      << out;
  EXPECT_NEAR(double(formats::readTetMesh(dir / "ball.vtu").tetCount()), 3000.0, 0.03 * 3000) << out;
  // At a size instead of a count: larger cells, fewer tetrahedra.
  ASSERT_EQ(runProgram({"mesh", "phantom:sphere?radius=10", "--size", "4", "--out", (dir / "coarse.mesh").string()}, &out),
            0)
      << out;
  EXPECT_LT(formats::readTetMesh(dir / "coarse.mesh").tetCount(), 3000u) << out;
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

// A segmentation as NRRD (unsigned 8-bit, 1 mm voxels): a ball of label 42
// inside a ball of label 3, and a block of label 7 apart.
// `specks`: single voxels of label 9 on a 4-voxel lattice outside the balls
// and the block (as a segmentation's stray voxels), some 200 at n = 34.
std::string segmentation(int n, bool fractional = false, bool specks = false) {
  std::string header = "NRRD0004\ntype: " + std::string(fractional ? "float" : "uchar") +
                       "\ndimension: 3\nsizes: " + std::to_string(n) + " " + std::to_string(n) + " " +
                       std::to_string(n) + "\nspacings: 1 1 1\nencoding: raw\nendian: little\n\n";
  std::string data;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double r = Vec3(i - 14.5, j - 14.5, k - 14.5).norm();
        int label = r < 6 ? 42 : r < 12 ? 3 : (i > n - 6 && j > n - 6 && k > n - 6) ? 7 : 0;
        if (specks && label == 0 && r > 13 && i % 4 == 1 && j % 4 == 1 && k % 4 == 1) label = 9;
        if (fractional) {
          const float value = label + 0.5f;
          data.append(reinterpret_cast<const char*>(&value), 4);
        } else {
          data.push_back(char(label));
        }
      }
  return header + data;
}

TEST(MeshCommandTest, ALabelledImageMeshesWithItsLabels) {
  test::TempDir dir;
  dir.write("labels.nrrd", segmentation(34));
  std::string out;
  ASSERT_EQ(runProgram({"mesh", (dir / "labels.nrrd").string(), "--labels", "3,42", "--tets", "3000", "--out",
                        (dir / "head.mesh").string()},
                       &out),
            0)
      << out;
  const TetMesh mesh = formats::readTetMesh(dir / "head.mesh");
  EXPECT_NEAR(double(mesh.tetCount()), 3000.0, 0.05 * 3000) << out;
  std::set<int32_t> labels(mesh.labels.begin(), mesh.labels.end());
  EXPECT_EQ(labels, (std::set<int32_t>{3, 42})) << out;
  EXPECT_NE(out.find("tetrahedra per label: 3: "), std::string::npos) << out;
  // Without --labels every non-zero label is meshed.
  ASSERT_EQ(runProgram({"mesh", (dir / "labels.nrrd").string(), "--size", "3", "--out", (dir / "all.vtu").string()},
                       &out),
            0)
      << out;
  const TetMesh all = formats::readTetMesh(dir / "all.vtu");
  labels = std::set<int32_t>(all.labels.begin(), all.labels.end());
  EXPECT_EQ(labels, (std::set<int32_t>{3, 7, 42})) << out;
  // Errors: a label no voxel holds, values that are no labels, a bad list,
  // labels for a surface.
  EXPECT_EQ(runProgram({"mesh", (dir / "labels.nrrd").string(), "--labels", "5", "--tets", "1000", "--out",
                        (dir / "x.mesh").string()},
                       &out),
            1);
  EXPECT_NE(out.find("labels.nrrd: no voxel holds label 5 of --labels"), std::string::npos) << out;
  dir.write("density.nrrd", segmentation(20, true));
  EXPECT_EQ(runProgram({"mesh", (dir / "density.nrrd").string(), "--tets", "1000", "--out", (dir / "x.mesh").string()},
                       &out),
            1);
  EXPECT_NE(out.find("holds 0.5"), std::string::npos) << out;
  EXPECT_NE(out.find("expected a segmentation"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"mesh", (dir / "labels.nrrd").string(), "--labels", "3,,4", "--tets", "1000", "--out",
                        (dir / "x.mesh").string()},
                       &out),
            2);
  EXPECT_NE(out.find("--labels takes labels of 1 and up"), std::string::npos) << out;
  dir.write("tet.off", kTetrahedron);
  EXPECT_EQ(runProgram({"mesh", (dir / "tet.off").string(), "--labels", "3", "--tets", "1000", "--out",
                        (dir / "x.mesh").string()},
                       &out),
            2);
  EXPECT_NE(out.find("--labels is for a labelled image"), std::string::npos) << out;
}

// A segmentation's stray voxels: each is meshed on its own, whatever the
// cell size, so the count asked for cannot be met and the command says why;
// --min-region gives them the label around them (here, outside) and the
// count is met.
TEST(MeshCommandTest, SpecksOfALabelSetAFloorThatMinRegionRemoves) {
  test::TempDir dir;
  dir.write("specks.nrrd", segmentation(34, false, true));
  std::string out;
  ASSERT_EQ(runProgram({"mesh", (dir / "specks.nrrd").string(), "--tets", "3000", "--out",
                        (dir / "specks.mesh").string()},
                       &out),
            0)
      << out;
  const TetMesh floor = formats::readTetMesh(dir / "specks.mesh");
  EXPECT_GT(double(floor.tetCount()), 1.1 * 3000) << out;
  EXPECT_NE(out.find("regions have fewer than 27 voxels"), std::string::npos) << out;
  EXPECT_NE(out.find("--min-region 27"), std::string::npos) << out;
  ASSERT_EQ(runProgram({"mesh", (dir / "specks.nrrd").string(), "--tets", "3000", "--min-region", "27", "--out",
                        (dir / "merged.mesh").string()},
                       &out),
            0)
      << out;
  const TetMesh merged = formats::readTetMesh(dir / "merged.mesh");
  EXPECT_NEAR(double(merged.tetCount()), 3000.0, 0.05 * 3000) << out;
  const std::set<int32_t> labels(merged.labels.begin(), merged.labels.end());
  EXPECT_EQ(labels, (std::set<int32_t>{3, 7, 42})) << "the specks are outside now: " << out;
  EXPECT_NE(out.find("had fewer than 27 voxels"), std::string::npos) << out;
  EXPECT_EQ(out.find("note:"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"mesh", (dir / "specks.nrrd").string(), "--tets", "3000", "--min-region", "0", "--out",
                        (dir / "x.mesh").string()},
                       &out),
            2);
  EXPECT_NE(out.find("--min-region takes a voxel count"), std::string::npos) << out;
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
