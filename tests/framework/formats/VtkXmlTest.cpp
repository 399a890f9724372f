// The VTK XML writers read back independently: tetrahedral grids through the
// project's VTU reader (its own XML, base64 and zlib code), poly data by
// parsing the XML part with tinyxml2 and inflating each appended array, and
// the collection as plain XML.
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include "framework/formats/encoding/Inflate.h"
#include "framework/core/AtomicFile.h"
#include "framework/formats/vtk/VtkSurfaceReader.h"
#include "framework/formats/vtk/VtkXml.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/formats/mesh/VtuWriter.h"
#include "framework/formats/encoding/Base64.h"
#include "framework/formats/surface/SurfaceReader.h"
#include "tests/support/TestSupport.h"
#include "tests/support/VtkAppended.h"
#include "tests/support/ZlibStream.h"

namespace trephine {
namespace {

TEST(VtkXmlTest, ATetrahedralGridReadsBackThroughTheVtuReader) {
  test::TempDir dir;
  // 4,000 tetrahedra sharing nodes along a strip: connectivity (64 KB) in 2 zlib blocks.
  std::vector<Vec3> points;
  std::vector<std::array<int32_t, 4>> tets;
  std::vector<int32_t> labels;
  for (int i = 0; i < 4003; ++i) points.emplace_back(0.1 * i, (i % 2) * 1.5, (i % 3) * 2.25 - 100.0);
  for (int i = 0; i + 3 < 4003; ++i) {
    tets.push_back({i, i + 1, i + 2, i + 3});
    labels.push_back(i % 3 + 1);
  }
  formats::VtkTetGrid grid;
  grid.points = points;
  grid.tets = tets;
  grid.labels = labels;
  formats::VtkDataArray force{"force", 3, {}};
  for (size_t i = 0; i < points.size(); ++i) force.values.insert(force.values.end(), {float(i), 0.5f, -1.0f});
  grid.pointData.push_back(force);
  formats::writeTetGrid(grid, dir / "brain.vtu");
  const TetMesh mesh = formats::readTetMesh(dir / "brain.vtu");
  ASSERT_EQ(mesh.nodeCount(), points.size());
  ASSERT_EQ(mesh.tetCount(), tets.size());
  for (size_t i = 0; i < points.size(); ++i) EXPECT_NEAR((mesh.nodes[i] - points[i]).norm(), 0.0, 2e-5) << i;
  for (size_t t = 0; t < tets.size(); ++t) EXPECT_EQ(mesh.tets[t], tets[t]) << t;
  ASSERT_EQ(mesh.labels.size(), labels.size());
  for (size_t t = 0; t < labels.size(); ++t) EXPECT_EQ(mesh.labels[t], labels[t]);
  // The point array: first in <PointData>, so at offset 0.
  const std::string text = test::readFile(dir / "brain.vtu");
  EXPECT_NE(text.find("<DataArray type=\"Float32\" Name=\"force\" NumberOfComponents=\"3\" format=\"appended\" "
                      "offset=\"0\"/>"),
            std::string::npos);
  const std::vector<float> forces = test::appendedArray<float>(text, 0);
  EXPECT_EQ(forces, force.values);
}

// A mesh file (`trephine mesh --out x.vtu`) goes through the same writer
// with Float64 coordinates: every coordinate and label reads back exactly,
// including values that no float holds (0.1, 1/3, 1e-300, 1e300).
TEST(VtkXmlTest, AMeshFileReadsBackBitForBit) {
  test::TempDir dir;
  TetMesh mesh;
  const double awkward[] = {0.1, 1.0 / 3.0, -1e-300, 1e300, 123456.789012345678, -0.0};
  for (int i = 0; i < 2000; ++i)
    mesh.nodes.emplace_back(awkward[i % 6] + i, awkward[(i + 1) % 6] * (i + 1), std::sqrt(double(i)) - 7.0);
  for (int32_t i = 0; i + 3 < 2000; i += 2) {
    mesh.tets.push_back({i, i + 1, i + 2, i + 3});
    mesh.labels.push_back(i % 7 - 3);
  }
  formats::writeVtuMesh(mesh, dir.path() / "m.vtu");
  const TetMesh read = formats::readTetMesh(dir.path() / "m.vtu");
  ASSERT_EQ(read.nodes.size(), mesh.nodes.size());
  for (size_t i = 0; i < read.nodes.size(); ++i)
    for (int a = 0; a < 3; ++a) EXPECT_EQ(read.nodes[i][a], mesh.nodes[i][a]) << i;
  EXPECT_EQ(read.tets, mesh.tets);
  EXPECT_EQ(read.labels, mesh.labels);

  // A tetrahedron naming a missing node and labels of the wrong count are
  // refused, with the file named and nothing left behind.
  TetMesh bad = mesh;
  bad.tets[3][2] = 2000;
  EXPECT_THROW(formats::writeVtuMesh(bad, dir.path() / "bad.vtu"), FileWriteError);
  bad = mesh;
  bad.labels.pop_back();
  EXPECT_THROW(formats::writeVtuMesh(bad, dir.path() / "bad.vtu"), FileWriteError);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "bad.vtu"));
}

TEST(VtkXmlTest, PolyDataHoldsItsPointsAndCellsInTheAppendedBlocks) {
  test::TempDir dir;
  formats::VtkPolyData data;
  data.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  data.vertices = {3};
  data.lines = {{0, 3}};
  data.triangles = {{0, 1, 2}, {0, 2, 3}};
  data.pointData.push_back({"depth", 1, {0.f, 0.25f, 0.5f, 1.f}});
  formats::writePolyData(data, dir / "tool.vtp");
  const std::string text = test::readFile(dir / "tool.vtp");
  tinyxml2::XMLDocument xml;
  const std::string head = text.substr(0, text.find("<AppendedData")) + "</VTKFile>";
  ASSERT_EQ(xml.Parse(head.c_str()), tinyxml2::XML_SUCCESS) << head;
  const auto* piece = xml.RootElement()->FirstChildElement("PolyData")->FirstChildElement("Piece");
  EXPECT_EQ(piece->IntAttribute("NumberOfPoints"), 4);
  EXPECT_EQ(piece->IntAttribute("NumberOfVerts"), 1);
  EXPECT_EQ(piece->IntAttribute("NumberOfLines"), 1);
  EXPECT_EQ(piece->IntAttribute("NumberOfPolys"), 2);
  auto offsetOf = [&](const char* section, const char* name) {
    for (const auto* a = piece->FirstChildElement(section)->FirstChildElement("DataArray"); a;
         a = a->NextSiblingElement("DataArray"))
      if (!name || (a->Attribute("Name") && std::string(a->Attribute("Name")) == name))
        return uint64_t(a->Unsigned64Attribute("offset"));
    ADD_FAILURE() << section << " " << (name ? name : "");
    return uint64_t(0);
  };
  EXPECT_EQ(test::appendedArray<float>(text, offsetOf("Points", nullptr)),
            (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}));
  EXPECT_EQ(test::appendedArray<int32_t>(text, offsetOf("Polys", "connectivity")), (std::vector<int32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(test::appendedArray<int32_t>(text, offsetOf("Polys", "offsets")), (std::vector<int32_t>{3, 6}));
  EXPECT_EQ(test::appendedArray<int32_t>(text, offsetOf("Lines", "connectivity")), (std::vector<int32_t>{0, 3}));
  EXPECT_EQ(test::appendedArray<int32_t>(text, offsetOf("Verts", "connectivity")), (std::vector<int32_t>{3}));
  EXPECT_EQ(test::appendedArray<float>(text, offsetOf("PointData", "depth")), data.pointData[0].values);
}

TEST(VtkXmlTest, BadDataIsRefusedWithTheFileAndNothingIsLeft) {
  test::TempDir dir;
  formats::VtkPolyData data;
  data.points = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  data.lines = {{0, 2}};
  try {
    formats::writePolyData(data, dir / "bad.vtp");
    ADD_FAILURE() << "no error";
  } catch (const FileWriteError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.vtp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("names point 2 of 2"), std::string::npos) << e.what();
  }
  data.lines.clear();
  data.pointData.push_back({"force", 3, {1, 2, 3}});  // one tuple for two points
  EXPECT_THROW(formats::writePolyData(data, dir / "bad.vtp"), FileWriteError);
  data.pointData.clear();
  data.points[1].x() = NAN;
  EXPECT_THROW(formats::writePolyData(data, dir / "bad.vtp"), FileWriteError);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.vtp"));
}

TEST(VtkXmlTest, TheMultiBlockIndexListsEachFileAtItsBlocksIndex) {
  test::TempDir dir;
  formats::writeMultiBlock({{1, "skull/b00001_00000.vtp"}, {7, "skull/b00007_00012.vtp"}}, dir / "skull.vtm");
  tinyxml2::XMLDocument xml;
  ASSERT_EQ(xml.LoadFile((dir / "skull.vtm").c_str()), tinyxml2::XML_SUCCESS);
  EXPECT_STREQ(xml.RootElement()->Attribute("type"), "vtkMultiBlockDataSet");
  const auto* set = xml.RootElement()->FirstChildElement("vtkMultiBlockDataSet")->FirstChildElement("DataSet");
  EXPECT_EQ(set->IntAttribute("index"), 1);
  EXPECT_STREQ(set->Attribute("file"), "skull/b00001_00000.vtp");
  set = set->NextSiblingElement("DataSet");
  EXPECT_EQ(set->IntAttribute("index"), 7);
  EXPECT_STREQ(set->Attribute("file"), "skull/b00007_00012.vtp");
  EXPECT_EQ(set->NextSiblingElement("DataSet"), nullptr);
}

TEST(VtkXmlTest, TheCollectionListsEachDatasetWithItsTime) {
  test::TempDir dir;
  formats::PvdCollection run;
  run.add(0.0, "brain_0.vtu");
  run.add(1.0 / 30, "tool_0.vtp", 1);
  run.add(0.5, "a&b.vtu");
  run.write(dir / "run.pvd");
  tinyxml2::XMLDocument xml;
  ASSERT_EQ(xml.LoadFile((dir / "run.pvd").c_str()), tinyxml2::XML_SUCCESS);
  const auto* set = xml.RootElement()->FirstChildElement("Collection")->FirstChildElement("DataSet");
  EXPECT_STREQ(set->Attribute("file"), "brain_0.vtu");
  set = set->NextSiblingElement("DataSet");
  EXPECT_DOUBLE_EQ(set->DoubleAttribute("timestep"), 1.0 / 30);
  EXPECT_EQ(set->IntAttribute("part"), 1);
  EXPECT_STREQ(set->NextSiblingElement("DataSet")->Attribute("file"), "a&b.vtu");
}

// The surface reader (trephine view's) reads back what the writer wrote:
// over 32 KiB of points, so several zlib blocks.
TEST(VtkXmlTest, TriangleSurfacesReadBackThroughTheSurfaceReader) {
  test::TempDir dir;
  formats::VtkPolyData surface;
  for (int i = 0; i < 3000; ++i) surface.points.push_back(Vec3(i * 0.25, std::sin(i), -i / 7.0));
  for (int i = 0; i + 2 < 3000; ++i) surface.triangles.push_back({i, i + 1, i + 2});
  surface.lines = {{0, 5}};  // not a triangle: skipped
  formats::writePolyData(surface, dir.path() / "s.vtp");
  const TriangleMesh read = formats::readVtkPolyDataSurface(dir.path() / "s.vtp");
  ASSERT_EQ(read.vertices.size(), surface.points.size());
  for (size_t i = 0; i < read.vertices.size(); ++i)
    EXPECT_LT((read.vertices[i] - surface.points[i]).norm(), 1e-4) << i;  // Float32
  EXPECT_EQ(read.triangles, surface.triangles);

  // A truncated file and a grid are errors that name the file.
  const std::string bytes = test::readFile(dir.path() / "s.vtp");
  std::ofstream(dir.path() / "cut.vtp", std::ios::binary) << bytes.substr(0, bytes.size() - 5000);
  try {
    formats::readVtkPolyDataSurface(dir.path() / "cut.vtp");
    ADD_FAILURE() << "a truncated file was read";
  } catch (const formats::FileReadError& e) {
    EXPECT_NE(std::string(e.what()).find("cut.vtp:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  std::ofstream(dir.path() / "grid.vtp") << "<?xml version=\"1.0\"?><VTKFile type=\"UnstructuredGrid\"/>";
  EXPECT_THROW(formats::readVtkPolyDataSurface(dir.path() / "grid.vtp"), formats::FileReadError);
}

// Files written apart from the project's writer (the fuzzer's seeds, made
// with Python's zlib): a tetrahedron's four faces, zlib blocks and raw.
TEST(VtkXmlTest, TheSurfaceReaderReadsFilesOfAnotherWriterCompressedOrNot) {
  for (const char* name : {"tet.vtp", "tet_raw.vtp"}) {
    const TriangleMesh s =
        formats::readVtkPolyDataSurface(test::sourceDir() / "tests/fuzz/surface_reader_seeds" / name);
    ASSERT_EQ(s.vertices.size(), 4u) << name;
    ASSERT_EQ(s.triangles.size(), 4u) << name;
    EXPECT_EQ(s.vertices[3], Vec3(0, 0, 1)) << name;
    EXPECT_EQ(s.triangles[3], (std::array<int32_t, 3>{1, 2, 3})) << name;
    // The surface reader of `trephine mesh` takes poly data too.
    const TriangleMesh same = formats::readSurface(test::sourceDir() / "tests/fuzz/surface_reader_seeds" / name);
    EXPECT_EQ(same.triangles, s.triangles) << name;
  }
}

// Poly data as ParaView writes it with other settings: ascii arrays, and
// inline base64 binary in big-endian order with 64-bit headers; two pieces,
// the second's points numbered from the first's.
TEST(VtkXmlTest, PolyDataInAsciiAndInlineBinaryReadsTheSame) {
  test::TempDir dir;
  const std::string ascii = R"(<?xml version="1.0"?>
<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian">
<PolyData>
<Piece NumberOfPoints="4" NumberOfPolys="4">
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>
<Polys><DataArray type="Int64" Name="connectivity" format="ascii">0 2 1 0 1 3 0 3 2 1 2 3</DataArray>
<DataArray type="Int64" Name="offsets" format="ascii">3 6 9 12</DataArray></Polys>
</Piece>
<Piece NumberOfPoints="3" NumberOfPolys="1">
<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">5 0 0 6 0 0 5 1 0</DataArray></Points>
<Polys><DataArray type="Int32" Name="connectivity" format="ascii">0 1 2</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">3</DataArray></Polys>
</Piece>
</PolyData>
</VTKFile>
)";
  const TriangleMesh s = formats::readVtkPolyData(dir.path() / "ascii.vtp", ascii);
  ASSERT_EQ(s.vertices.size(), 7u);
  ASSERT_EQ(s.triangles.size(), 5u);
  EXPECT_EQ(s.triangles[4], (std::array<int32_t, 3>{4, 5, 6}));
  EXPECT_EQ(s.vertices[6], Vec3(5, 1, 0));

  // The first piece again, big-endian binary: an 8-byte size header, then the values.
  auto bigEndian = [](const std::vector<uint8_t>& little, size_t width) {
    std::vector<uint8_t> out = little;
    for (size_t i = 0; i + width <= out.size(); i += width) std::reverse(out.begin() + i, out.begin() + i + width);
    return out;
  };
  auto binary = [&](const auto& values) {
    std::vector<uint8_t> bytes(sizeof values[0] * values.size());
    std::memcpy(bytes.data(), values.data(), bytes.size());
    const uint64_t size = bytes.size();
    std::vector<uint8_t> header(8);
    std::memcpy(header.data(), &size, 8);
    std::vector<uint8_t> all = bigEndian(header, 8);
    const std::vector<uint8_t> data = bigEndian(bytes, sizeof values[0]);
    all.insert(all.end(), data.begin(), data.end());
    return formats::encodeBase64(test::asView(all));
  };
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::vector<int64_t> connectivity = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}, offsets = {3, 6, 9, 12};
  const std::string big = "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"BigEndian\" "
                          "header_type=\"UInt64\">\n<PolyData>\n<Piece NumberOfPoints=\"4\" NumberOfPolys=\"4\">\n"
                          "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"binary\">" +
                          binary(xyz) +
                          "</DataArray></Points>\n<Polys><DataArray type=\"Int64\" Name=\"connectivity\" "
                          "format=\"binary\">" +
                          binary(connectivity) + "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"binary\">" +
                          binary(offsets) + "</DataArray></Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n";
  const TriangleMesh b = formats::readVtkPolyData(dir.path() / "big.vtp", big);
  ASSERT_EQ(b.vertices.size(), 4u);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(b.vertices[i], s.vertices[i]) << i;
  const std::vector<std::array<int32_t, 3>> firstPiece(s.triangles.begin(), s.triangles.begin() + 4);
  EXPECT_EQ(b.triangles, firstPiece);

  // A polygon naming a missing point is an error with the file and the line.
  std::string wrong = ascii;
  wrong.replace(wrong.find("0 2 1 0 1 3"), 11, "0 2 9 0 1 3");
  try {
    formats::readVtkPolyData(dir.path() / "wrong.vtp", wrong);
    ADD_FAILURE() << "a missing point was read";
  } catch (const formats::FileReadError& e) {
    EXPECT_NE(std::string(e.what()).find("wrong.vtp:6: polygon 0 refers to point 9"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trephine
