// The surface readers (OFF, OBJ, STL, PLY) on the same closed box written in
// each format, their errors, the winding-number inside test, and meshing a
// surface at a count.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <fstream>

#include "framework/meshing/TetMeshing.h"
#include "framework/meshing/SurfaceSolid.h"
#include "framework/formats/surface/SurfaceReader.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "tests/support/TestSupport.h"

namespace trephine::formats {
namespace {

// A box [0, 2] x [0, 3] x [0, 4] as 8 corners and 6 quads, normals out.
const std::vector<Vec3> kCorners = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 3, 0), Vec3(0, 3, 0),
                                    Vec3(0, 0, 4), Vec3(2, 0, 4), Vec3(2, 3, 4), Vec3(0, 3, 4)};
const std::vector<std::array<int, 4>> kQuads = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};

std::string offText() {
  std::string s = "OFF\n# a box\n8 6 0\n";
  for (const Vec3& p : kCorners) s += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  for (const auto& q : kQuads) s += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " + std::to_string(q[3]) + "\n";
  return s;
}

std::string objText() {
  std::string s = "# a box\no box\n";
  for (const Vec3& p : kCorners) s += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
  s += "vn 0 0 1\n";
  // Corners counted from 1, with normals, and the last face counted back from the end.
  for (size_t f = 0; f + 1 < kQuads.size(); ++f)
    s += "f " + std::to_string(kQuads[f][0] + 1) + "//1 " + std::to_string(kQuads[f][1] + 1) + "//1 " +
         std::to_string(kQuads[f][2] + 1) + " " + std::to_string(kQuads[f][3] + 1) + "\n";
  const auto& q = kQuads.back();
  s += "f " + std::to_string(q[0] - 8) + " " + std::to_string(q[1] - 8) + " " + std::to_string(q[2] - 8) + " " +
       std::to_string(q[3] - 8) + "\n";
  return s;
}

std::vector<std::array<Vec3, 3>> boxTriangles() {
  std::vector<std::array<Vec3, 3>> t;
  for (const auto& q : kQuads) {
    t.push_back({kCorners[size_t(q[0])], kCorners[size_t(q[1])], kCorners[size_t(q[2])]});
    t.push_back({kCorners[size_t(q[0])], kCorners[size_t(q[2])], kCorners[size_t(q[3])]});
  }
  return t;
}

std::string asciiStl() {
  std::string s = "solid box\n";
  for (const auto& t : boxTriangles()) {
    s += "facet normal 0 0 0\n outer loop\n";
    for (const Vec3& p : t) s += "  vertex " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
    s += " endloop\nendfacet\n";
  }
  return s + "endsolid box\n";
}

std::string binaryStl() {
  std::string s(80, ' ');
  s.replace(0, 5, "solid");  // binary files often start so: the content decides
  const auto triangles = boxTriangles();
  const uint32_t n = uint32_t(triangles.size());
  s.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 0};
    s.append(reinterpret_cast<const char*>(normal), 12);
    for (const Vec3& p : t)
      for (int a = 0; a < 3; ++a) {
        const float f = float(p[a]);
        s.append(reinterpret_cast<const char*>(&f), 4);
      }
    s.append(2, '\0');
  }
  return s;
}

std::string plyText(const std::string& format) {
  std::string s = "ply\nformat " + format + " 1.0\ncomment a box\nelement vertex 8\nproperty float x\nproperty float y\n"
                  "property float z\nproperty uchar red\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n";
  const bool big = format == "binary_big_endian";
  const auto put = [&](auto value) {
    auto bytes = std::bit_cast<std::array<char, sizeof(value)>>(value);
    if (big) std::reverse(bytes.begin(), bytes.end());
    s.append(bytes.data(), bytes.size());
  };
  for (const Vec3& p : kCorners) {
    if (format == "ascii") {
      s += std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + " 255\n";
    } else {
      for (int a = 0; a < 3; ++a) put(float(p[a]));
      put(uint8_t(255));
    }
  }
  for (const auto& q : kQuads) {
    if (format == "ascii") {
      s += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " + std::to_string(q[3]) + "\n";
    } else {
      put(uint8_t(4));
      for (int c : q) put(int32_t(c));
    }
  }
  return s;
}

// The box as read: 8 vertices, 12 triangles, volume 24 with normals out.
void expectBox(const TriangleMesh& s, const std::string& what) {
  EXPECT_EQ(s.vertices.size(), 8u) << what;
  EXPECT_EQ(s.triangles.size(), 12u) << what;
  const SurfaceSolid solid(s);
  EXPECT_NEAR(solid.volume(), 24.0, 1e-9) << what;
  EXPECT_NEAR(solid.area(), 2 * (6 + 8 + 12), 1e-9) << what;
}

TEST(SurfaceReaderTest, EachFormatGivesTheSameBox) {
  test::TempDir dir;
  dir.write("box.off", offText());
  dir.write("box.obj", objText());
  dir.write("box.stl", asciiStl());
  dir.write("box_binary.stl", binaryStl());
  dir.write("box_ascii.ply", plyText("ascii"));
  dir.write("box_little.ply", plyText("binary_little_endian"));
  dir.write("box_big.ply", plyText("binary_big_endian"));
  for (const char* name : {"box.off", "box.obj", "box.stl", "box_binary.stl", "box_ascii.ply", "box_little.ply", "box_big.ply"})
    expectBox(formats::readSurface(dir / name), name);
}

std::string errorOf(const test::TempDir& dir, const std::string& name, const std::string& content) {
  dir.write(name, content);
  try {
    formats::readSurface(dir / name);
  } catch (const TetMeshReadError& e) {
    return e.what();
  }
  return "(read without error)";
}

TEST(SurfaceReaderTest, BadFilesAreErrorsThatSayWhereAndWhat) {
  test::TempDir dir;
  std::string m = errorOf(dir, "cut.off", offText().substr(0, 60));
  EXPECT_NE(m.find("cut.off:"), std::string::npos) << m;
  m = errorOf(dir, "index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  EXPECT_NE(m.find("index.off:6: face 0 names vertex 7 of 3"), std::string::npos) << m;
  m = errorOf(dir, "two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
  EXPECT_NE(m.find("two.obj:3: the face has 2 corners; expected 3 or more"), std::string::npos) << m;
  m = errorOf(dir, "ahead.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  EXPECT_NE(m.find("ahead.obj:4: the face names vertex 4 but 3 vertices are read so far"), std::string::npos) << m;
  m = errorOf(dir, "nan.obj", "v 0 0 nan\n");
  EXPECT_NE(m.find("nan.obj:1:"), std::string::npos) << m;
  std::string stl = binaryStl();
  m = errorOf(dir, "short.stl", stl.substr(0, stl.size() - 7));
  EXPECT_NE(m.find("short.stl: the header counts 12 triangles"), std::string::npos) << m;
  m = errorOf(dir, "format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n");
  EXPECT_NE(m.find("format.ply:2: unknown format"), std::string::npos) << m;
  std::string ply = plyText("binary_little_endian");
  m = errorOf(dir, "cut.ply", ply.substr(0, ply.size() - 9));
  EXPECT_NE(m.find("cut.ply: the binary data ends"), std::string::npos) << m;
  // A vertex index that is no whole number within int32 (the fuzzer's: 2e117).
  const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n";
  m = errorOf(dir, "huge.ply", header + "3 0 1 2" + std::string(117, '2') + "\n");
  EXPECT_NE(m.find("huge.ply"), std::string::npos) << m;
  EXPECT_NE(m.find("face 0 lists the vertex index 2.2"), std::string::npos) << m;
  m = errorOf(dir, "half.ply", header + "3 0 1 1.5\n");
  EXPECT_NE(m.find("face 0 lists the vertex index 1.5 (expected a whole number)"), std::string::npos) << m;
  m = errorOf(dir, "what.xyz", "1 2 3\n");
  EXPECT_NE(m.find("what.xyz: not a surface this program reads"), std::string::npos) << m;
  m = errorOf(dir, "empty.obj", "# nothing\nv 0 0 0\n");
  EXPECT_NE(m.find("empty.obj: the surface has no triangle"), std::string::npos) << m;
}

TEST(SurfaceSolidTest, TheWindingNumberIsOneInsideAndZeroOutsideOnEdgesAndCornersToo) {
  test::TempDir dir;
  dir.write("box.off", offText());
  const SurfaceSolid solid(formats::readSurface(dir / "box.off"));
  EXPECT_EQ(solid.windingNumber(Vec3(1, 1.5, 2)), 1);
  EXPECT_EQ(solid.windingNumber(Vec3(3, 1.5, 2)), 0);
  EXPECT_EQ(solid.windingNumber(Vec3(1, 1.5, 5)), 0);
  EXPECT_EQ(solid.windingNumber(Vec3(1, 1.5, -1)), 0);
  // Below the diagonals the quads were split along, and below a corner shared
  // by several triangles: counted once.
  EXPECT_EQ(solid.windingNumber(Vec3(1, 1.5, 1)), 1);
  EXPECT_EQ(solid.windingNumber(Vec3(2.0 / 3.0 * 1.5, 1.5 * 1.5 / 1.5, 3)), 1);
  EXPECT_EQ(solid.windingNumber(Vec3(0, 0, 2)), solid.windingNumber(Vec3(0, 0, 2)));
  for (double x = 0.05; x < 2; x += 0.1)
    for (double y = 0.05; y < 3; y += 0.1) EXPECT_EQ(solid.windingNumber(Vec3(x, y, 3.9)), 1) << x << " " << y;
}

TEST(SurfaceSolidTest, APartThroughAnotherCountsTwiceAndAnOpenSurfaceIsRefused) {
  // Two boxes, the second shifted into the first: one surface passing through itself.
  TriangleMesh two;
  for (int copy = 0; copy < 2; ++copy) {
    const int32_t base = int32_t(two.vertices.size());
    for (const Vec3& p : kCorners) two.vertices.push_back(p + Vec3(copy, 0, 0));
    for (const auto& q : kQuads) {
      two.triangles.push_back({base + q[0], base + q[1], base + q[2]});
      two.triangles.push_back({base + q[0], base + q[2], base + q[3]});
    }
  }
  const SurfaceSolid solid(two);
  EXPECT_EQ(solid.windingNumber(Vec3(0.5, 1, 1)), 1);
  EXPECT_EQ(solid.windingNumber(Vec3(1.5, 1, 1)), 2);
  EXPECT_EQ(solid.windingNumber(Vec3(2.5, 1, 1)), 1);
  TriangleMesh open = two;
  open.triangles.pop_back();
  try {
    SurfaceSolid refused(open);
    ADD_FAILURE() << "an open surface was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not closed: 3 edges"), std::string::npos) << e.what();
  }
}

TEST(SurfaceSolidTest, ABoxSurfaceMeshesToTheCountAndFillsTheBox) {
  test::TempDir dir;
  dir.write("box.obj", objText());
  const SurfaceSolid surface(formats::readSurface(dir / "box.obj"));
  const TetMesh mesh = meshImplicitSolid(surface.solid(), 3000);
  EXPECT_NEAR(double(mesh.tetCount()), 3000.0, 0.03 * 3000) << mesh.tetCount();
  double volume = 0;
  for (const TetIndices& t : mesh.tets)
    volume += signedVolume(mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]], mesh.nodes[t[3]]);
  EXPECT_NEAR(volume, 24.0, 0.03 * 24) << "the box's volume";
  for (const Vec3& p : mesh.nodes) {
    EXPECT_GE(p.minCoeff(), -1e-3);
    EXPECT_LE(p.x(), 2 + 1e-3);
    EXPECT_LE(p.y(), 3 + 1e-3);
    EXPECT_LE(p.z(), 4 + 1e-3);
  }
}

}  // namespace
}  // namespace trephine::formats
