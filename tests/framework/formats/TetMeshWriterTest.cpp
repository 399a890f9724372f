// Writing tetrahedral meshes as Medit .mesh: the cube phantom written plain
// and gzipped reads back bit-identical; failed writes name the file and leave
// nothing behind; meshes the readers would refuse are refused before a file
// exists; and `trephine phantom` writes meshes chosen by the file extension.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "plugins/tetra_brain/TetPhantoms.h"
#include "framework/formats/mesh/MeditWriter.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "tests/support/TestSupport.h"

namespace trephine::formats {
namespace {

using test::runProgram;
using test::TempDir;

// The cube's 200 / 7 mm spacing is not a short decimal: a lossy number format would show.
TetMesh cubePhantom() { return tetra::makeTetPhantom("cube?cells=7"); }

std::vector<std::string> directoryEntries(const std::filesystem::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(directory))
    names.push_back(entry.path().filename().string());
  return names;
}

// Same nodes bit for bit, same tetrahedra in the same order; labels as
// written, or all 0 (Medit's reference for "no region") when there were none.
void expectSameMesh(const TetMesh& read, const TetMesh& written) {
  ASSERT_EQ(read.nodeCount(), written.nodeCount());
  for (size_t n = 0; n < written.nodeCount(); ++n)
    for (int axis = 0; axis < 3; ++axis)
      ASSERT_EQ(std::bit_cast<uint64_t>(read.nodes[n][axis]), std::bit_cast<uint64_t>(written.nodes[n][axis]))
          << "node " << n << " axis " << axis << ": " << read.nodes[n][axis] << " vs " << written.nodes[n][axis];
  EXPECT_EQ(read.tets, written.tets);
  if (written.labels.empty())
    EXPECT_EQ(read.labels, std::vector<int32_t>(written.tetCount(), 0));
  else
    EXPECT_EQ(read.labels, written.labels);
}

// Expects writeMeditMesh to fail with a message that starts with the file and
// contains every part.
void expectWriteError(const TetMesh& mesh, const std::filesystem::path& file,
                      std::initializer_list<std::string> parts) {
  try {
    formats::writeMeditMesh(mesh, file);
    ADD_FAILURE() << file << " was written, expected an error";
  } catch (const TetMeshWriteError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.substr(0, file.string().size() + 2), file.string() + ": ") << message;
    for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

TEST(MeditWriter, CubePhantomReadsBackBitIdentical) {
  const TempDir dir;
  const TetMesh cube = cubePhantom();
  ASSERT_EQ(cube.tetCount(), 1715u);
  formats::writeMeditMesh(cube, dir / "cube.mesh");
  const std::string text = test::readFile(dir / "cube.mesh");
  EXPECT_EQ(text.substr(0, 48), "MeshVersionFormatted 2\nDimension 3\nVertices 512\n") << text.substr(0, 60);
  EXPECT_TRUE(text.ends_with("\nEnd\n"));
  expectSameMesh(formats::readTetMesh(dir / "cube.mesh"), cube);
  EXPECT_EQ(directoryEntries(dir.path()), std::vector<std::string>{"cube.mesh"}) << "a temporary file was left";
}

TEST(MeditWriter, GzippedWhenTheNameEndsInGz) {
  const TempDir dir;
  const TetMesh cube = cubePhantom();
  formats::writeMeditMesh(cube, dir / "cube.mesh");
  formats::writeMeditMesh(cube, dir / "cube.mesh.gz");
  const std::string compressed = test::readFile(dir / "cube.mesh.gz");
  ASSERT_GE(compressed.size(), 2u);
  EXPECT_EQ(uint8_t(compressed[0]), 0x1f);
  EXPECT_EQ(uint8_t(compressed[1]), 0x8b);
  EXPECT_LT(compressed.size(), std::filesystem::file_size(dir / "cube.mesh") / 2);
  expectSameMesh(formats::readTetMesh(dir / "cube.mesh.gz"), cube);
}

TEST(MeditWriter, LabelsBecomeReferencesAndExtremeValuesSurvive) {
  const TempDir dir;
  TetMesh mesh = cubePhantom();
  for (size_t t = 0; t < mesh.tetCount(); ++t) mesh.labels.push_back(int32_t(t % 3) - 1);
  mesh.nodes[0] = Vec3(-0.0, std::numeric_limits<double>::denorm_min(), 0.1);
  mesh.nodes[1] = Vec3(std::numeric_limits<double>::max(), -std::numeric_limits<double>::min(), 1.0 / 3.0);
  formats::writeMeditMesh(mesh, dir / "labelled.mesh");
  expectSameMesh(formats::readTetMesh(dir / "labelled.mesh"), mesh);
}

TEST(MeditWriter, MissingDirectoryNamesThePathAndLeavesNothing) {
  const TempDir dir;
  const std::filesystem::path file = dir / "missing/cube.mesh";
  expectWriteError(cubePhantom(), file, {"cannot create", "No such file or directory"});
  EXPECT_TRUE(directoryEntries(dir.path()).empty());
}

TEST(MeditWriter, FailedRenameRemovesTheTemporaryFile) {
  // A directory where the file should go: everything is written, only the rename fails.
  const TempDir dir;
  std::filesystem::create_directory(dir / "taken.mesh");
  expectWriteError(cubePhantom(), dir / "taken.mesh", {"cannot rename the written file into place"});
  EXPECT_EQ(directoryEntries(dir.path()), std::vector<std::string>{"taken.mesh"});
  EXPECT_TRUE(std::filesystem::is_empty(dir / "taken.mesh"));
}

TEST(MeditWriter, MeshesTheReadersWouldRefuseAreNotWritten) {
  const TempDir dir;
  const TetMesh cube = cubePhantom();
  expectWriteError(TetMesh{cube.nodes, {}, {}}, dir / "empty.mesh", {"no tetrahedra"});
  TetMesh labels = cube;
  labels.labels = {1, 2};
  expectWriteError(labels, dir / "labels.mesh", {"2 labels for 1715 tetrahedra"});
  TetMesh corner = cube;
  corner.tets[9][2] = 512;
  expectWriteError(corner, dir / "corner.mesh", {"tetrahedron 9 refers to node 512", "nodes 0 to 511"});
  TetMesh infinite = cube;
  infinite.nodes[4].y() = std::nan("");
  expectWriteError(infinite, dir / "nan.mesh", {"node 4 has a non-finite coordinate"});
  EXPECT_TRUE(directoryEntries(dir.path()).empty());
}

TEST(TrephinePhantomMesh, WritesAMeshTheReaderLoads) {
  const TempDir dir;
  std::string out;
  ASSERT_EQ(runProgram({"phantom", "cube?cells=7", "--out", (dir / "cube.mesh").string()}, &out), 0) << out;
  EXPECT_NE(out.find("512 nodes, 1715 tetrahedra"), std::string::npos) << out;
  EXPECT_EQ(formats::readTetMesh(dir / "cube.mesh").tetCount(), 1715u);
  ASSERT_EQ(runProgram({"phantom", "cube?cells=7&size=50", "--out", (dir / "small.mesh.gz").string()}, &out), 0) << out;
  const TetMesh small = formats::readTetMesh(dir / "small.mesh.gz");
  EXPECT_EQ(small.tetCount(), 1715u);
  EXPECT_EQ(small.nodes.front(), Vec3(-25, -25, -25));
}

TEST(TrephinePhantomMesh, TheExtensionDecidesAndBadOnesAreRefused) {
  const TempDir dir;
  std::string out;
  EXPECT_EQ(runProgram({"phantom", "cube?cells=7", "--out", (dir / "cube.vtk").string()}, &out), 2);
  for (const std::string accepted : {".mesh", ".mesh.gz", ".mha", ".mhd"})
    EXPECT_NE(out.find(accepted), std::string::npos) << out;
  EXPECT_NE(out.find("cube.vtk"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"phantom", "cube?cells=7", "--out", (dir / "cube.mesh").string(), "--raw"}, &out), 2);
  EXPECT_NE(out.find("--raw"), std::string::npos) << out;
  // A tetrahedral key in a volume phantom, and the other way round, name the key.
  EXPECT_EQ(runProgram({"phantom", "cube?cells=7", "--out", (dir / "cube.mha").string()}, &out), 1);
  EXPECT_NE(out.find("cells"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"phantom", "skull?voxel=4", "--out", (dir / "skull.mesh").string()}, &out), 1);
  EXPECT_NE(out.find("unknown phantom 'skull'"), std::string::npos) << out;
  EXPECT_TRUE(directoryEntries(dir.path()).empty());
}

TEST(TrephinePhantomMesh, WithoutArgumentsListsBothKinds) {
  std::string out;
  EXPECT_EQ(runProgram({"phantom"}, &out), 2);
  for (const std::string expected : {"FILE.mesh", "skull?voxel=", "cube?cells=", "brain?tets="})
    EXPECT_NE(out.find(expected), std::string::npos) << out;
}

}  // namespace
}  // namespace trephine::formats
