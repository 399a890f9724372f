// Tetrahedral mesh files: a cube cut into five tetrahedra written by hand in
// every supported format and variant (TetGen 0- and 1-based, Medit, Gmsh
// legacy, 2.x, 4.0 and 4.1 (and files Gmsh wrote), VTK legacy ASCII and binary, VTK XML ascii, base64
// and appended raw or base64 data, with and without zlib, gzip), read back and compared; the format found from
// the content whatever the file's name; every kind of error naming the file
// and the place; and the real meshes of ../shared/data with the counts
// their provenance files give.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include "framework/formats/mesh/TetMeshReader.h"
#include "tests/support/TestSupport.h"
#include "tests/support/ZlibStream.h"

namespace trephine::formats {
namespace {

using test::TempDir;
using Bytes = std::string;

// ---------------------------------------------------------------------------
// The reference mesh and comparisons.

// A 10 x 10 x 10.125 mm box (coordinates exact in float and double) cut into
// four corner tetrahedra and the middle one, labelled 5 and 6 like grey and
// white matter.
TetMesh cube() {
  TetMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.nodes.emplace_back(i & 1 ? 8.5 : -1.5, i & 2 ? 12.25 : 2.25, i & 4 ? 110.125 : 100.0);
  mesh.tets = {{0, 1, 2, 4}, {1, 3, 2, 7}, {1, 4, 5, 7}, {2, 6, 4, 7}, {1, 2, 4, 7}};
  mesh.labels = {5, 5, 6, 6, 5};
  return mesh;
}

// Same tetrahedra over the same points (node order may differ), same labels
// when `labelled`, none otherwise.
void expectCube(const TetMesh& mesh, bool labelled) {
  const TetMesh expected = cube();
  ASSERT_EQ(mesh.nodeCount(), expected.nodeCount());
  ASSERT_EQ(mesh.tetCount(), expected.tetCount());
  for (size_t t = 0; t < expected.tetCount(); ++t) {
    for (size_t k = 0; k < 4; ++k) {
      ASSERT_GE(mesh.tets[t][k], 0);
      ASSERT_LT(size_t(mesh.tets[t][k]), mesh.nodeCount());
      EXPECT_EQ(mesh.nodes[size_t(mesh.tets[t][k])], expected.nodes[size_t(expected.tets[t][k])])
          << "tetrahedron " << t << " corner " << k;
    }
  }
  if (labelled)
    EXPECT_EQ(mesh.labels, expected.labels);
  else
    EXPECT_TRUE(mesh.labels.empty());
}

// Expects formats::readTetMesh(file) to fail with a message that starts with the file
// name (and a line when `line` > 0) and contains every part.
void expectError(const std::filesystem::path& file, size_t line, std::initializer_list<std::string> parts) {
  try {
    const TetMesh mesh = formats::readTetMesh(file);
    ADD_FAILURE() << file << " was read (" << mesh.tetCount() << " tetrahedra), expected an error";
  } catch (const TetMeshReadError& error) {
    const std::string message = error.what();
    const std::string start = file.string() + (line > 0 ? ":" + std::to_string(line) + ": " : std::string(": "));
    EXPECT_EQ(message.substr(0, start.size()), start) << message;
    for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string xyz(const Vec3& p) { return number(p.x()) + " " + number(p.y()) + " " + number(p.z()); }

// ---------------------------------------------------------------------------
// Bytes: gzip, zlib, base64, packed binary numbers.

std::filesystem::path writeBytes(const std::filesystem::path& file, const Bytes& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return file;
}

Bytes deflated(const Bytes& data, int windowBits) {
  const std::vector<uint8_t> out = test::zlibStream(data, test::ZlibWrapper(windowBits));
  return Bytes(out.begin(), out.end());
}

Bytes gzipped(const Bytes& data) { return deflated(data, 15 + 16); }
Bytes zlibbed(const Bytes& data) { return deflated(data, 15); }

Bytes base64(const Bytes& data) {
  static const char* const kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  Bytes out;
  for (size_t i = 0; i < data.size(); i += 3) {
    uint32_t group = uint32_t(uint8_t(data[i])) << 16;
    if (i + 1 < data.size()) group |= uint32_t(uint8_t(data[i + 1])) << 8;
    if (i + 2 < data.size()) group |= uint32_t(uint8_t(data[i + 2]));
    out += kAlphabet[(group >> 18) & 63];
    out += kAlphabet[(group >> 12) & 63];
    out += i + 1 < data.size() ? kAlphabet[(group >> 6) & 63] : '=';
    out += i + 2 < data.size() ? kAlphabet[group & 63] : '=';
  }
  return out;
}

template <typename T>
void put(Bytes& out, T value, bool bigEndian) {
  using Bits = std::conditional_t<
      sizeof(T) == 1, uint8_t,
      std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
  const auto bits = std::bit_cast<Bits>(value);
  for (size_t b = 0; b < sizeof(T); ++b)
    out.push_back(char(uint8_t(bits >> (8 * (bigEndian ? sizeof(T) - 1 - b : b)))));
}

template <typename T>
Bytes packed(const std::vector<double>& values, bool bigEndian) {
  Bytes out;
  for (const double v : values) put<T>(out, static_cast<T>(v), bigEndian);
  return out;
}

// ---------------------------------------------------------------------------
// Writers of the cube in each format, by the format descriptions.

std::string tetgenNode(int base, bool attributesAndMarkers) {
  const TetMesh mesh = cube();
  std::string text =
      "# cube nodes\n" + std::to_string(mesh.nodeCount()) + "  3  " + (attributesAndMarkers ? "2  1" : "0  0") + "\n";
  for (size_t i = 0; i < mesh.nodeCount(); ++i) {
    text += "  " + std::to_string(i + size_t(base)) + "   " + xyz(mesh.nodes[i]);
    if (attributesAndMarkers) text += "  0.5 -7  " + std::to_string(i % 2);
    text += "\n";
  }
  return text + "# Generated by hand\n";
}

std::string tetgenEle(int base, bool labels, int corners = 4) {
  const TetMesh mesh = cube();
  std::string text =
      std::to_string(mesh.tetCount()) + " " + std::to_string(corners) + " " + (labels ? "2" : "0") + "  # tetrahedra\n";
  for (size_t t = 0; t < mesh.tetCount(); ++t) {
    text += std::to_string(t + size_t(base));
    for (const int32_t n : mesh.tets[t]) text += " " + std::to_string(n + base);
    for (int extra = 4; extra < corners; ++extra) text += " " + std::to_string(extra % 8 + base);  // mid-edge nodes
    if (labels) text += "  " + std::to_string(mesh.labels[t]) + ".0 -1";
    text += "\r\n";  // CRLF line ends work too
  }
  return text;
}

std::string medit() {
  const TetMesh mesh = cube();
  std::string text = "# a cube\nMeshVersionFormatted 2\n\nDimension\n3\n\nVertices\n8\n";
  for (size_t i = 0; i < mesh.nodeCount(); ++i) text += xyz(mesh.nodes[i]) + " " + std::to_string(i) + "\n";
  text += "Corners 2\n1 8\nTriangles\n2\n1 2 3 0\n2 3 4 0\nEdges 1\n1 2 7\n";
  text += "Tetrahedra\n5 # count\n";
  for (size_t t = 0; t < mesh.tetCount(); ++t) {
    for (const int32_t n : mesh.tets[t]) text += std::to_string(n + 1) + " ";
    text += std::to_string(mesh.labels[t]) + (t == 2 ? " " : "\n");  // records may share lines
  }
  return text + "\nRidges\n0\nEdges\n0\n End";
}

// Sparse, unordered Gmsh node ids: node i is written with id kGmshIds[i].
const int64_t kGmshIds[8] = {101, 7, 3000000000, 55, 56, 9, 1000, 2};

std::string gmshNodes(bool legacy) {
  const TetMesh mesh = cube();
  std::string text = std::string(legacy ? "$NOD" : "$Nodes") + "\n8\n";
  for (size_t i = 0; i < 8; ++i) text += std::to_string(kGmshIds[i]) + " " + xyz(mesh.nodes[i]) + "\n";
  return text + (legacy ? "$ENDNOD\n" : "$EndNodes\n");
}

std::string gmshTet(size_t t) {
  const TetMesh mesh = cube();
  std::string text;
  for (const int32_t n : mesh.tets[t]) text += " " + std::to_string(kGmshIds[n]);
  return text;
}

std::string gmshLegacy() {
  const TetMesh mesh = cube();
  std::string text = gmshNodes(true) + "$ELM\n9\n";
  text += "1 15 9 9 1 101\n";              // a point
  text += "2 1 8 8 2 101 7\n";             // a line
  text += "3 2 7 7 3 101 7 3000000000\n";  // a triangle
  for (size_t t = 0; t < mesh.tetCount(); ++t)
    text += std::to_string(10 + 3 * t) + " 4 " + std::to_string(mesh.labels[t]) + " 1 4" + gmshTet(t) + "\n";
  text += "40 2 7 7 3 55 56 9\n";
  return text + "$ENDELM\n";
}

std::string gmshVersion2() {
  const TetMesh mesh = cube();
  std::string text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  text += "$PhysicalNames\n2\n3 5 \"grey\"\n3 6 \"white\"\n$EndPhysicalNames\n";
  text += "$Comments\nanything $Nodes here\n$EndComments\n";
  text += gmshNodes(false) + "$Elements\n9\n";
  text += "1 15 2 0 1 101\n2 1 2 0 1 101 7\n3 2 3 1 1 0 101 7 3000000000\n";
  for (size_t t = 0; t < mesh.tetCount(); ++t)
    text += std::to_string(20 + t) + " 4 3 " + std::to_string(mesh.labels[t]) + " 1 0" + gmshTet(t) + "\n";
  text += "99 2 2 0 1 55 56 9\n$EndElements\n";
  return text + "$NodeData\n1\n\"u\"\n1\n0.0\n3\n0\n1\n8\n101 1\n$EndNodeData\n";
}

// VTK cells: the tetrahedra of the cube with a vertex and a triangle among them.
struct VtkCell {
  int type;
  std::vector<int64_t> points;
  int32_t label;
};

std::vector<VtkCell> vtkCells() {
  const TetMesh mesh = cube();
  std::vector<VtkCell> cells = {{1, {0}, 90}, {5, {0, 1, 2}, 91}};
  for (size_t t = 0; t < mesh.tetCount(); ++t)
    cells.push_back({10, {mesh.tets[t].begin(), mesh.tets[t].end()}, mesh.labels[t]});
  cells.insert(cells.begin() + 4, VtkCell{5, {4, 5, 6}, 92});
  return cells;
}

std::string vtkLegacyAscii(bool labels) {
  const TetMesh mesh = cube();
  const std::vector<VtkCell> cells = vtkCells();
  std::string text = "# vtk DataFile Version 3.0\ncube by hand\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  text += "FIELD FieldData 1\nTIME 1 1 double\n0.5\n";
  text += "POINTS 8 double\n";
  for (const Vec3& p : mesh.nodes) text += xyz(p) + "\n";
  size_t size = 0;
  for (const VtkCell& c : cells) size += 1 + c.points.size();
  text += "\nCELLS " + std::to_string(cells.size()) + " " + std::to_string(size) + "\n";
  for (const VtkCell& c : cells) {
    text += std::to_string(c.points.size());
    for (const int64_t p : c.points) text += " " + std::to_string(p);
    text += "\n";
  }
  text += "CELL_TYPES " + std::to_string(cells.size()) + "\n";
  for (const VtkCell& c : cells) text += std::to_string(c.type) + "\n";
  text += "POINT_DATA 8\nSCALARS temperature float 1\nLOOKUP_TABLE default\n1 2 3 4 5 6 7 8\n";
  text += "VECTORS velocity float\n";
  for (int i = 0; i < 24; ++i) text += "0.5 ";
  text += "\nCELL_DATA " + std::to_string(cells.size()) + "\nSCALARS quality double\nLOOKUP_TABLE default\n";
  for (size_t i = 0; i < cells.size(); ++i) text += "0.25\n";
  if (labels) {
    text += "SCALARS tissue int 1\nLOOKUP_TABLE default\n";
    for (const VtkCell& c : cells) text += std::to_string(c.label) + " ";
    text += "\n";
  }
  return text;
}

// Version 5.1: OFFSETS and CONNECTIVITY arrays, labels in a FIELD array.
std::string vtkLegacy51() {
  const TetMesh mesh = cube();
  const std::vector<VtkCell> cells = vtkCells();
  std::string text = "# vtk DataFile Version 5.1\nvtk output\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 float\n";
  for (const Vec3& p : mesh.nodes) text += xyz(p) + " ";
  std::string offsets = "0";
  std::string connectivity;
  size_t size = 0;
  for (const VtkCell& c : cells) {
    size += c.points.size();
    offsets += " " + std::to_string(size);
    for (const int64_t p : c.points) connectivity += std::to_string(p) + " ";
  }
  text += "\nMETADATA\nINFORMATION 0\n\n";
  text += "CELLS " + std::to_string(cells.size() + 1) + " " + std::to_string(size) + "\nOFFSETS vtktypeint64\n" +
          offsets + "\nCONNECTIVITY vtktypeint64\n" + connectivity + "\nCELL_TYPES " + std::to_string(cells.size()) +
          "\n";
  for (const VtkCell& c : cells) text += std::to_string(c.type) + " ";
  text += "\nCELL_DATA " + std::to_string(cells.size()) + "\nFIELD FieldData 2\nquality 1 " +
          std::to_string(cells.size()) + " float\n";
  for (size_t i = 0; i < cells.size(); ++i) text += "1.5 ";
  text += "\ngmsh:physical 1 " + std::to_string(cells.size()) + " vtktypeint64\n";
  for (const VtkCell& c : cells) text += std::to_string(c.label) + " ";
  return text + "\nMETADATA\nINFORMATION 0\n\n";
}

std::string vtkLegacyBinary() {
  const TetMesh mesh = cube();
  const std::vector<VtkCell> cells = vtkCells();
  std::vector<double> xyzValues;
  for (const Vec3& p : mesh.nodes) xyzValues.insert(xyzValues.end(), {p.x(), p.y(), p.z()});
  std::vector<double> cellValues;
  std::vector<double> types;
  std::vector<double> labels;
  for (const VtkCell& c : cells) {
    cellValues.push_back(double(c.points.size()));
    for (const int64_t p : c.points) cellValues.push_back(double(p));
    types.push_back(c.type);
    labels.push_back(c.label);
  }
  std::string text = "# vtk DataFile Version 3.0\nbinary cube\nBINARY\nDATASET UNSTRUCTURED_GRID\n";
  text += "POINTS 8 float\n" + packed<float>(xyzValues, true) + "\n";
  text += "CELLS " + std::to_string(cells.size()) + " " + std::to_string(cellValues.size()) + "\n" +
          packed<int32_t>(cellValues, true) + "\n";
  text += "CELL_TYPES " + std::to_string(cells.size()) + "\n" + packed<int32_t>(types, true) + "\n";
  text += "CELL_DATA " + std::to_string(cells.size()) + "\nSCALARS label int\nLOOKUP_TABLE default\n" +
          packed<int32_t>(labels, true) + "\n";
  return text;
}

// VTK XML arrays.
enum class VtuData { kAscii, kBinary, kBinaryZlib };

// Where binary arrays go: inline as base64, or in <AppendedData> (raw or base64).
enum class VtuPlace { kInline, kAppendedRaw, kAppendedBase64 };

struct VtuOptions {
  VtuData data = VtuData::kAscii;
  bool header64 = false;
  bool bigEndian = false;
  bool separateHeader = true;  // base64 of the header, then of the data (else one stream)
  size_t blockSize = 32768;    // zlib block size
  VtuPlace place = VtuPlace::kInline;
  std::string* appended = nullptr;  // kAppended*: collects the <AppendedData> content
};

std::string header(uint64_t value, const VtuOptions& options) {
  Bytes out;
  if (options.header64)
    put<uint64_t>(out, value, options.bigEndian);
  else
    put<uint32_t>(out, uint32_t(value), options.bigEndian);
  return out;
}

// What VTK writes for a binary array: the byte-count header and the data, or
// the block header and the blocks, each compressed on its own.
std::pair<Bytes, Bytes> binaryArray(const Bytes& data, const VtuOptions& options) {
  if (options.data == VtuData::kBinary) return {header(data.size(), options), data};
  Bytes blocks;
  std::vector<uint64_t> sizes;
  for (size_t start = 0; start < data.size(); start += options.blockSize) {
    const Bytes block = zlibbed(data.substr(start, options.blockSize));
    sizes.push_back(block.size());
    blocks += block;
  }
  Bytes head = header(sizes.size(), options) + header(options.blockSize, options) +
               header(data.size() % options.blockSize, options);
  for (const uint64_t size : sizes) head += header(size, options);
  return {head, blocks};
}

std::string encodedArray(const Bytes& data, const VtuOptions& options) {
  const auto [head, body] = binaryArray(data, options);
  if (options.place == VtuPlace::kAppendedRaw) return head + body;
  // VTK encodes an uncompressed array as one stream; compressed ones always in two.
  return options.data == VtuData::kBinary && !options.separateHeader ? base64(head + body)
                                                                     : base64(head) + base64(body);
}

template <typename T>
std::string vtuArray(const std::string& attributes, const std::vector<double>& values, const VtuOptions& options) {
  if (options.place != VtuPlace::kInline && options.data != VtuData::kAscii) {
    const std::string offset = std::to_string(options.appended->size());
    *options.appended += encodedArray(packed<T>(values, options.bigEndian), options);
    return "        <DataArray " + attributes + " format=\"appended\" offset=\"" + offset + "\"/>\n";
  }
  std::string text = "        <DataArray " + attributes + " format=\"" +
                     (options.data == VtuData::kAscii ? "ascii" : "binary") + "\">\n          ";
  if (options.data == VtuData::kAscii) {
    for (const double v : values) text += number(v) + " ";
  } else {
    text += encodedArray(packed<T>(values, options.bigEndian), options);
  }
  return text + "\n        </DataArray>\n";
}

std::string vtuPiece(const TetMesh& mesh, const std::vector<VtkCell>& cells, const VtuOptions& options, bool labels) {
  std::vector<double> xyzValues;
  for (const Vec3& p : mesh.nodes) xyzValues.insert(xyzValues.end(), {p.x(), p.y(), p.z()});
  std::vector<double> connectivity;
  std::vector<double> offsets;
  std::vector<double> types;
  std::vector<double> labelValues;
  for (const VtkCell& c : cells) {
    for (const int64_t p : c.points) connectivity.push_back(double(p));
    offsets.push_back(double(connectivity.size()));
    types.push_back(c.type);
    labelValues.push_back(c.label);
  }
  std::string text = "    <Piece NumberOfPoints=\"" + std::to_string(mesh.nodeCount()) + "\" NumberOfCells=\"" +
                     std::to_string(cells.size()) + "\">\n";
  text += "      <Points>\n" + vtuArray<float>("type=\"Float32\" NumberOfComponents=\"3\"", xyzValues, options) +
          "      </Points>\n";
  text += "      <Cells>\n";
  text += vtuArray<int64_t>("type=\"Int64\" Name=\"connectivity\"", connectivity, options);
  text += vtuArray<int32_t>("type=\"Int32\" Name=\"offsets\"", offsets, options);
  text += vtuArray<uint8_t>("type=\"UInt8\" Name=\"types\"", types, options);
  text += "      </Cells>\n";
  if (labels) {
    text += "      <CellData Scalars=\"tissue\">\n";
    text += vtuArray<double>("type=\"Float64\" Name=\"label\"", labelValues, options);  // not integer: ignored
    text += vtuArray<int32_t>("type=\"Int32\" Name=\"tissue\"", labelValues, options);
    text += "      </CellData>\n";
  }
  return text + "    </Piece>\n";
}

std::string vtuFile(const std::string& pieces, const VtuOptions& options) {
  std::string text =
      "<?xml version=\"1.0\"?>\n<!-- written by hand -->\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\"";
  text += std::string(" byte_order=\"") + (options.bigEndian ? "BigEndian" : "LittleEndian") + "\"";
  if (options.header64) text += " header_type=\"UInt64\"";
  if (options.data == VtuData::kBinaryZlib) text += " compressor=\"vtkZLibDataCompressor\"";
  text += ">\n  <UnstructuredGrid>\n" + pieces + "  </UnstructuredGrid>\n";
  if (options.appended) {
    text += std::string("  <AppendedData encoding=\"") + (options.place == VtuPlace::kAppendedRaw ? "raw" : "base64") +
            "\">\n   _" + *options.appended + "\n  </AppendedData>\n";
  }
  return text + "</VTKFile>\n";
}

std::string vtu(VtuOptions options, bool labels = true) {
  std::string appended;
  if (options.place != VtuPlace::kInline) options.appended = &appended;
  const std::string pieces = vtuPiece(cube(), vtkCells(), options, labels);
  return vtuFile(pieces, options);
}

// ---------------------------------------------------------------------------
// TetGen

TEST(TetGenReader, OneBasedWithAttributesMarkersAndComments) {
  TempDir dir;
  const auto node = dir.write("cube.node", tetgenNode(1, true));
  dir.write("cube.ele", tetgenEle(1, true));
  expectCube(formats::readTetMesh(node), true);
}

TEST(TetGenReader, ZeroBasedFromEitherFileOrTheBaseName) {
  TempDir dir;
  const auto node = dir.write("cube.1.node", tetgenNode(0, false));
  const auto ele = dir.write("cube.1.ele", tetgenEle(0, false));
  expectCube(formats::readTetMesh(node), false);
  expectCube(formats::readTetMesh(ele), false);
  expectCube(formats::readTetMesh(dir / "cube.1"), false);
}

TEST(TetGenReader, EitherFileMayBeGzipped) {
  TempDir dir;
  writeBytes(dir / "a.node", tetgenNode(1, false));
  writeBytes(dir / "a.ele.gz", gzipped(tetgenEle(1, true)));
  expectCube(formats::readTetMesh(dir / "a.node"), true);
  expectCube(formats::readTetMesh(dir / "a.ele.gz"), true);
  expectCube(formats::readTetMesh(dir / "a"), true);
  writeBytes(dir / "b.node.gz", gzipped(tetgenNode(0, true)));
  writeBytes(dir / "b.ele", tetgenEle(0, false));
  expectCube(formats::readTetMesh(dir / "b.ele"), false);
  expectCube(formats::readTetMesh(dir / "b"), false);
}

TEST(TetGenReader, NodesListedOutOfOrderAreMapped) {
  TempDir dir;
  const TetMesh mesh = cube();
  std::string text = "8 3\n";
  for (const size_t i : {5, 0, 7, 2, 1, 4, 6, 3}) text += std::to_string(i + 1) + " " + xyz(mesh.nodes[i]) + "\n";
  dir.write("c.node", text);
  dir.write("c.ele", tetgenEle(1, false));
  const TetMesh read = formats::readTetMesh(dir / "c.node");
  expectCube(read, false);
  EXPECT_EQ(read.nodes[0], mesh.nodes[0]);  // placed by index, not by line
}

TEST(TetGenReader, QuadraticTetrahedraKeepTheirCorners) {
  TempDir dir;
  dir.write("q.node", tetgenNode(0, false));
  dir.write("q.ele", tetgenEle(0, true, 10));
  expectCube(formats::readTetMesh(dir / "q.ele"), true);
}

TEST(TetGenReader, ErrorsNameTheFileAndPlace) {
  TempDir dir;
  // The partner is missing.
  dir.write("lonely.node", tetgenNode(1, false));
  expectError(dir / "lonely.node", 0, {"element file is missing", "lonely.ele", "lonely.ele.gz"});
  // An element refers to a node outside 1..8 (line 4: header, then tetrahedra 1 and 2).
  std::string ele = tetgenEle(1, false);
  ele.replace(ele.find("2 2 4 3 8"), 9, "2 2 4 3 9");
  dir.write("range.node", tetgenNode(1, false));
  const auto rangeEle = dir.write("range.ele", ele);
  expectError(rangeEle, 3, {"tetrahedron 2 refers to node 9", "range.node numbers its 8 nodes 1..8"});
  // Index 0 in a 1-based mesh.
  ele = tetgenEle(1, false);
  ele.replace(ele.find("1 1 2 3 5"), 9, "1 0 2 3 5");
  dir.write("zero.node", tetgenNode(1, false));
  expectError(dir.write("zero.ele", ele), 2, {"tetrahedron 1 refers to node 0", "1..8"});
  // A NaN coordinate (node 4 is on line 6: comment, header, nodes 1..).
  std::string node = tetgenNode(1, false);
  node.replace(node.find("12.25 100"), 5, "nan");
  dir.write("nan.ele", tetgenEle(1, false));
  expectError(dir.write("nan.node", node), 5, {"node 3 has a non-finite y coordinate 'nan'"});
  // Truncated element file.
  ele = tetgenEle(1, true);
  dir.write("short.node", tetgenNode(1, false));
  expectError(dir.write("short.ele", ele.substr(0, ele.find("4 3 7 5 8"))), 4,
              {"ends after 3 of 5 tetrahedra", "truncated"});
  // A numbering that starts at 2.
  node = "2 3 0 0\n2 0 0 0\n3 1 0 0\n";
  dir.write("base.ele", "1 4 0\n1 2 3 2 3\n");
  expectError(dir.write("base.node", node), 0, {"smallest node index is 2", "expected 0 or 1"});
  // A label that is not a whole number.
  ele = tetgenEle(1, true);
  ele.replace(ele.find("5.0"), 3, "5.5");
  dir.write("label.node", tetgenNode(1, false));
  expectError(dir.write("label.ele", ele), 2, {"tetrahedron 1 has attribute '5.5'", "whole-number tissue label"});
  // A 2D node file, a wrong corner count.
  dir.write("flat.ele", tetgenEle(1, false));
  expectError(dir.write("flat.node", "# 2D\n3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n"), 2, {"dimension is 2, expected 3"});
  dir.write("six.node", tetgenNode(1, false));
  expectError(dir.write("six.ele", "1 6 0\n1 1 2 3 4 5 6\n"), 1,
              {"second number is '6', expected 3 (a .node file) or 4 or 10 (an .ele file)"});
  // A boundary face file is not a mesh.
  expectError(dir.write("cube.face", "2 1\n1 1 2 3 -1\n2 2 3 4 -1\n"), 1, {"second number is '1'", ".face"});
  // A node line that lacks z.
  dir.write("xy.ele", tetgenEle(1, false));
  expectError(dir.write("xy.node", "2 3 0 0\n1 0 0 0\n2 1.0 1.0\n"), 3, {"node 2 has 2 values after its index"});
}

TEST(TetGenReader, AbsurdCountsAreRefusedBeforeAllocating) {
  TempDir dir;
  dir.write("huge.ele", tetgenEle(1, false));
  // 100 million nodes cannot fit in the 30 bytes that follow.
  expectError(dir.write("huge.node", "100000000 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"), 1,
              {"declares 100000000 nodes", "truncated file or corrupt count"});
  expectError(dir.write("huge.node", "9000000000 3 0 0\n"), 1, {"more than the 268435456 supported"});
  dir.write("huge2.node", tetgenNode(1, false));
  expectError(dir.write("huge2.ele", "1000000 4 0\n1 1 2 3 4\n"), 1, {"declares 1000000 tetrahedra"});
}

// ---------------------------------------------------------------------------
// Medit

TEST(MeditReader, SkipsOtherSectionsAndKeepsReferencesAsLabels) {
  TempDir dir;
  expectCube(formats::readTetMesh(dir.write("cube.mesh", medit())), true);
}

TEST(MeditReader, Gzipped) {
  TempDir dir;
  expectCube(formats::readTetMesh(writeBytes(dir / "cube.mesh.gz", gzipped(medit()))), true);
}

TEST(MeditReader, ErrorsNameTheFileAndPlace) {
  TempDir dir;
  std::string text = medit();
  expectError(dir.write("short.mesh", text.substr(0, text.find("2 3 5 8 5") + 8)), 30,
              {"ends inside Tetrahedra at record 5 of 5 (truncated)"});
  text = medit();
  text.replace(text.find("3 7 5 8 6"), 9, "3 7 5 9 6");
  expectError(dir.write("range.mesh", text), 29, {"tetrahedron 4 refers to vertex 9", "vertices 1..8"});
  text = medit();
  text.replace(text.find("2.25 110.125"), 4, "inf");
  expectError(dir.write("inf.mesh", text), 13, {"vertex 5 has a non-finite y coordinate 'inf'"});
  expectError(dir.write("flat.mesh", "MeshVersionFormatted 1\nDimension 2\nVertices\n0\n"), 2,
              {"Dimension 2, expected 3"});
  expectError(dir.write("surface.mesh",
                        "MeshVersionFormatted 1\nDimension 3\nVertices 3\n0 0 0 0\n1 0 0 0\n0 1 0 "
                        "0\nTriangles 1\n1 2 3 0\nEnd\n"),
              0, {"no Tetrahedra section"});
  expectError(dir.write("huge.mesh", "MeshVersionFormatted 1\nDimension 3\nVertices 50000000\n0 0 0 0\n"), 3,
              {"declares 50000000 vertices"});
}

// ---------------------------------------------------------------------------
// Gmsh

TEST(GmshReader, LegacyWithMixedElementsAndSparseIds) {
  TempDir dir;
  expectCube(formats::readTetMesh(dir.write("cube.msh", gmshLegacy())), true);
}

TEST(GmshReader, Version2WithPhysicalNamesTagsAndSparseIds) {
  TempDir dir;
  expectCube(formats::readTetMesh(dir.write("cube.msh", gmshVersion2())), true);
  expectCube(formats::readTetMesh(writeBytes(dir / "cube.msh.gz", gzipped(gmshVersion2()))), true);
}

TEST(GmshReader, Version2WithoutTagsHasNoLabels) {
  TempDir dir;
  std::string text = "$MeshFormat\n2.0 0 8\n$EndMeshFormat\n" + gmshNodes(false) + "$Elements\n5\n";
  for (size_t t = 0; t < 5; ++t) text += std::to_string(t + 1) + " 4 0" + gmshTet(t) + "\n";
  expectCube(formats::readTetMesh(dir.write("plain.msh", text + "$EndElements\n")), false);
}

TEST(GmshReader, BinaryAndOtherVersionsAreRefused) {
  TempDir dir;
  expectError(dir.write("binary.msh", "$MeshFormat\n4.1 1 8\n\x01\0\0\0\n$EndMeshFormat\n"), 2,
              {"binary Gmsh files are not supported", "Version 4 ASCII"});
  expectError(dir.write("v3.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n$Entities\n"), 2,
              {"Gmsh format 3.0 is not supported", "expected 4.1, 4.0, 2.x or the legacy format"});
  expectError(dir.write("v42.msh", "$MeshFormat\n4.2 0 8\n$EndMeshFormat\n"), 2, {"Gmsh format 4.2 is not supported"});
}

// Format 4: the cube's nodes in two entity blocks (a point, and the volume's
// nodes with parametric u v w), its tetrahedra in blocks of volume entities 1
// (physical tag 5) and 2 (physical tag 6), among blocks of other elements.
std::string gmshVersion4(bool v41) {
  const TetMesh mesh = cube();
  std::string text = std::string("$MeshFormat\n") + (v41 ? "4.1" : "4") + " 0 8\n$EndMeshFormat\n";
  text += "$PhysicalNames\n2\n3 5 \"grey\"\n3 6 \"white\"\n$EndPhysicalNames\n";
  text += "$Entities\n1 0 1 3\n";
  text += v41 ? "1 -1.5 2.25 100 0\n" : "1 -1.5 2.25 100 -1.5 2.25 100 0\n";
  text += "4 0 0 0 1 1 1 1 3 1 -2\n";                       // a surface in physical group 3
  text += "1 -1.5 2.25 100 8.5 12.25 110.125 1 5 2 1 4\n";  // volume 1: physical 5
  text += "2 -1.5 2.25 100 8.5 12.25 110.125 2 6 7 0\n";    // volume 2: physical 6 (then 7)
  text += "3 0 0 0 1 1 1 0 0\n";                            // volume 3: no physical group
  text += "$EndEntities\n";
  // 4.1 writes the entity's dimension first, 4.0 its tag.
  auto blockHead = [&](int dim, int tag, int third, size_t n) {
    const std::string entity =
        v41 ? std::to_string(dim) + " " + std::to_string(tag) : std::to_string(tag) + " " + std::to_string(dim);
    return entity + " " + std::to_string(third) + " " + std::to_string(n);
  };
  text += v41 ? "$Nodes\n2 8 2 3000000000\n" : "$Nodes\n2 8\n";
  text += blockHead(0, 1, 0, 1) + "\n";
  text += v41 ? std::to_string(kGmshIds[0]) + "\n" + xyz(mesh.nodes[0]) + "\n"
              : std::to_string(kGmshIds[0]) + " " + xyz(mesh.nodes[0]) + "\n";
  text += blockHead(3, 1, 1, 7) + "\n";
  if (v41) {
    for (size_t i = 1; i < 8; ++i) text += std::to_string(kGmshIds[i]) + "\n";
    for (size_t i = 1; i < 8; ++i) text += xyz(mesh.nodes[i]) + " 0.5 0.25 0\n";
  } else {
    for (size_t i = 1; i < 8; ++i) text += std::to_string(kGmshIds[i]) + " " + xyz(mesh.nodes[i]) + " 0.5 0.25 0\n";
  }
  text += "$EndNodes\n";
  text += v41 ? "$Elements\n5 6 1 90\n" : "$Elements\n5 6\n";
  text += blockHead(2, 4, 2, 1) + "\n1 101 7 3000000000\n";
  text += blockHead(3, 1, 4, 2) + "\n20" + gmshTet(0) + "\n21" + gmshTet(1) + "\n";
  text += blockHead(3, 2, 4, 2) + "\n22" + gmshTet(2) + "\n23" + gmshTet(3) + "\n";
  text += blockHead(3, 1, 4, 1) + "\n24" + gmshTet(4) + "\n";
  text += blockHead(0, 1, 15, 0) + "\n";
  return text + "$EndElements\n";
}

TEST(GmshReader, Version41And40WithEntityBlocksAndPhysicalTags) {
  TempDir dir;
  expectCube(formats::readTetMesh(dir.write("cube41.msh", gmshVersion4(true))), true);
  expectCube(formats::readTetMesh(dir.write("cube40.msh", gmshVersion4(false))), true);
  expectCube(formats::readTetMesh(writeBytes(dir / "cube41.msh.gz", gzipped(gmshVersion4(true)))), true);
}

TEST(GmshReader, Version4WithoutPhysicalGroupsHasNoLabels) {
  TempDir dir;
  std::string text = gmshVersion4(true);
  const size_t entities = text.find("$Entities");
  text.erase(entities, text.find("$Nodes") - entities);
  expectCube(formats::readTetMesh(dir.write("plain.msh", text)), false);
  EXPECT_TRUE(formats::readTetMesh(dir / "plain.msh").labels.empty());
}

TEST(GmshReader, TheVersionsGmshWritesReadAlike) {
  // tests/plugins/tetra_brain/data/two_volumes.geo meshed by Gmsh 4.8 into
  // formats 4.1, 4.0 and 2.2: the same nodes, tetrahedra and physical tags.
  const std::filesystem::path data = test::sourceDir() / "tests/plugins/tetra_brain/data";
  const TetMesh v41 = formats::readTetMesh(data / "two_volumes_v41.msh");
  const TetMesh v40 = formats::readTetMesh(data / "two_volumes_v40.msh");
  const TetMesh v22 = formats::readTetMesh(data / "two_volumes_v22.msh");
  ASSERT_GT(v41.tetCount(), 20u);
  for (const TetMesh* other : {&v40, &v22}) {
    ASSERT_EQ(other->tetCount(), v41.tetCount());
    EXPECT_EQ(other->labels, v41.labels);
    for (size_t t = 0; t < v41.tetCount(); ++t)
      for (size_t k = 0; k < 4; ++k)
        ASSERT_EQ(other->nodes[size_t(other->tets[t][k])], v41.nodes[size_t(v41.tets[t][k])]) << t;
  }
  // Both physical volumes are there, and they fill the 4 x 2 x 2 mm box.
  EXPECT_EQ(std::count(v41.labels.begin(), v41.labels.end(), 5) + std::count(v41.labels.begin(), v41.labels.end(), 6),
            std::ptrdiff_t(v41.tetCount()));
  EXPECT_GT(std::count(v41.labels.begin(), v41.labels.end(), 5), 0);
  EXPECT_GT(std::count(v41.labels.begin(), v41.labels.end(), 6), 0);
  double volume = 0;
  for (const TetIndices& tet : v41.tets)
    volume += std::abs(signedVolume(v41.nodes[size_t(tet[0])], v41.nodes[size_t(tet[1])], v41.nodes[size_t(tet[2])],
                                    v41.nodes[size_t(tet[3])]));
  EXPECT_NEAR(volume, 16.0, 1e-9);
}

TEST(TetMeshReader, SecondOrderTetrahedraKeepTheirCorners) {
  // The same mesh of second order (10-node tetrahedra: Gmsh type 11, VTK 24)
  // as Gmsh 4.1 and 2.2 wrote it and as VTK's writers wrote that (XML and
  // legacy): the corner tetrahedra of the linear mesh, with the same tags;
  // the edge midpoints stay as nodes no tetrahedron uses.
  const std::filesystem::path data = test::sourceDir() / "tests/plugins/tetra_brain/data";
  const TetMesh linear = formats::readTetMesh(data / "two_volumes_v41.msh");
  for (const char* name :
       {"two_volumes_o2_v41.msh", "two_volumes_o2_v22.msh", "two_volumes_o2.vtu", "two_volumes_o2_legacy51.vtk"}) {
    SCOPED_TRACE(name);
    const TetMesh quadratic = formats::readTetMesh(data / name);
    ASSERT_EQ(quadratic.tetCount(), linear.tetCount());
    EXPECT_GT(quadratic.nodeCount(), linear.nodeCount());
    EXPECT_EQ(quadratic.labels, linear.labels);
    for (size_t t = 0; t < linear.tetCount(); ++t)
      for (size_t k = 0; k < 4; ++k)
        ASSERT_EQ(quadratic.nodes[size_t(quadratic.tets[t][k])], linear.nodes[size_t(linear.tets[t][k])]) << t;
  }
  // A 10-node element with a node missing says which type and how many.
  TempDir dir;
  std::string text = gmshVersion2();
  text.replace(text.find("20 4 3 5 1 0"), 12, "20 11 3 5 1 0");
  expectError(dir.write("short10.msh", text), 28,
              {"element 20 has 4 nodes, expected a tetrahedron (type 11, 10 nodes)"});
}

TEST(GmshReader, Version4ErrorsNameTheBlockAndLine) {
  TempDir dir;
  const std::string good = gmshVersion4(true);
  auto broken = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  // Lines: $Entities 9, volume entity 1 on 13, $Nodes 17, the volume's node block 22, its tags 23-29
  // and coordinates 30-36, $Elements 38, the blocks of volume 2 on 45 and of volume 1 again on 48.
  expectError(dir.write("count.msh", broken("$Nodes\n2 8 2", "$Nodes\n2 9 2")), 36,
              {"the blocks hold 8 nodes, but $Nodes declares 9"});
  expectError(dir.write("block.msh", broken("3 1 1 7\n", "3 1 1 8\n")), 22,
              {"the block holds 8 nodes, expected 0 to the 7 left of the 8 $Nodes declares"});
  expectError(dir.write("tags.msh", broken("\n7\n3000000000\n", "\n7 8\n3000000000\n")), 23,
              {"expected one node tag on the line, found 2 values"});
  expectError(dir.write("uvw.msh", broken("8.5 2.25 100 0.5 0.25 0\n", "8.5 2.25 100 0.5\n")), 30,
              {"has 4 values, expected x y z and its 3 parametric coordinates"});
  expectError(dir.write("physical.msh", broken("1 5 2 1 4\n", "9 5 2 1 4\n")), 13,
              {"volume entity 1: 9 physical tags do not fit the line"});
  expectError(dir.write("elements.msh", broken("3 1 4 1\n24", "3 1 4 2\n24")), 48,
              {"expected 0 to the 1 left of the 6 $Elements declares"});
  expectError(dir.write("node.msh", broken("22 7 56", "22 7 57")), 46,
              {"element 22 refers to node 57", "not in the node section"});
  expectError(dir.write("dimension.msh", broken("3 1 1 7\n", "4 1 1 7\n")), 22,
              {"entity dimension 4, expected 0 to 3"});
  expectError(dir.write("header.msh", broken("$Nodes\n2 8 2 3000000000", "$Nodes\n2 8 2")), 18,
              {"expected \"numEntityBlocks numNodes minNodeTag maxNodeTag\" after $Nodes (format 4.1)"});
  expectError(dir.write("header40.msh", broken("4.1 0 8", "4.0 0 8")), 18,
              {"expected \"numEntityBlocks numNodes\" after $Nodes (format 4.0)"});
  expectError(dir.write("blockline.msh", broken("3 2 4 2\n", "3 2 4\n")), 45,
              {"expected a block line \"entityDim entityTag elementType numElementsInBlock\""});
}

TEST(GmshReader, ErrorsNameTheElementAndLine) {
  TempDir dir;
  // Element 17, a "tetrahedron" with 3 nodes, on line 14 (after 11 lines of nodes and 2 of $ELM).
  std::string text = gmshLegacy();
  text.replace(text.find("10 4 5 1 4"), 10, "17 4 5 1 3");
  expectError(dir.write("liver.msh", text), 17, {"element 17 has 3 nodes, expected a tetrahedron (type 4, 4 nodes)"});
  text = gmshVersion2();
  text.replace(text.find("20 4 3 5 1 0 101 7 3000000000 56"), 32, "20 4 3 5 1 0 101 7 3000000000 1001");
  expectError(dir.write("unknown.msh", text), 28, {"element 20 refers to node 1001", "not in the node section"});
  text = gmshVersion2();
  text = text.substr(0, text.find("23 4 3"));
  expectError(dir.write("short.msh", text), 30, {"ends after 6 of 9 elements (truncated)"});
  text = gmshVersion2();
  text.replace(text.find("\n7 8.5"), 6, "\n9 8.5");
  expectError(dir.write("twice.msh", text), 22, {"node id 9 appears twice in $Nodes"});
  text = gmshLegacy();
  text.replace(text.find("1000 -1.5 12.25"), 15, "1000 -1.5 -nan");
  expectError(dir.write("nan.msh", text), 9, {"node 1000 has a non-finite y coordinate '-nan'"});
  expectError(dir.write("flat.msh", "$NOD\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$ENDNOD\n$ELM\n1\n1 2 1 1 3 1 2 3\n$ENDELM\n"),
              0, {"no tetrahedra (element type 4 or 11)", "1 of type 2"});
  expectError(dir.write("early.msh", "$NOD\n3\n1 0 0 0\n$ENDNOD\n$ELM\n0\n$ENDELM\n"), 4,
              {"$NOD ends with '$ENDNOD' after 1 of the 3 nodes"});
  expectError(dir.write("open.msh", "$Comments\nno end\n"), 1, {"'$Comments' has no $EndComments"});
}

// ---------------------------------------------------------------------------
// VTK legacy

TEST(VtkLegacyReader, AsciiClassicCellsWithOtherCellTypesAndLabels) {
  TempDir dir;
  expectCube(formats::readTetMesh(dir.write("cube.vtk", vtkLegacyAscii(true))), true);
  expectCube(formats::readTetMesh(dir.write("plain.vtk", vtkLegacyAscii(false))), false);
}

TEST(VtkLegacyReader, Version51OffsetsConnectivityAndFieldLabels) {
  TempDir dir;
  expectCube(formats::readTetMesh(dir.write("cube51.vtk", vtkLegacy51())), true);
}

TEST(VtkLegacyReader, BinaryBigEndian) {
  TempDir dir;
  expectCube(formats::readTetMesh(writeBytes(dir / "binary.vtk", vtkLegacyBinary())), true);
  expectCube(formats::readTetMesh(writeBytes(dir / "binary.vtk.gz", gzipped(vtkLegacyBinary()))), true);
}

TEST(VtkLegacyReader, ErrorsNameTheCellAndLine) {
  TempDir dir;
  expectError(dir.write("poly.vtk", "# vtk DataFile Version 3.0\nsurface\nASCII\nDATASET POLYDATA\nPOINTS 0 float\n"),
              4, {"DATASET 'POLYDATA' is not supported, expected UNSTRUCTURED_GRID"});
  std::string text = vtkLegacyAscii(true);
  text.replace(text.find("4 1 3 2 7"), 9, "4 1 3 2 8");
  expectError(dir.write("range.vtk", text), 18, {"cell 3 refers to point 8", "points 0..7"});
  text = vtkLegacyAscii(true);
  text.replace(text.find("4 1 3 2 7"), 9, "3 1 3 2 7");  // the cell list no longer adds up
  expectError(dir.write("three.vtk", text), 18, {"CELLS: cell 6 has 7 points, more than the remaining data holds"});
  text = vtkLegacyAscii(true);
  text.replace(text.find("CELL_DATA 8"), 11, "CELL_DATA 7");
  expectError(dir.write("celldata.vtk", text), 42, {"CELL_DATA 7, expected 8 (the number of CELLS)"});
  text = vtkLegacyAscii(true);
  text.replace(text.find("8.5 12.25 100"), 3, "NaN");
  expectError(dir.write("nan.vtk", text), 8, {"point 3 has a non-finite coordinate (nan, 12.25"});
  text = vtkLegacyAscii(true);
  expectError(dir.write("short.vtk", text.substr(0, text.find("CELL_TYPES") + 16)), 27,
              {"declares 8 values of CELL_TYPES but only 4 bytes follow (truncated file or corrupt count)"});
  const size_t quality = text.find("SCALARS quality double\nLOOKUP_TABLE default\n") + 44;
  expectError(dir.write("short2.vtk", text.substr(0, quality + 3 * 5)), 48,
              {"ends after 3 of the 8 values of quality (truncated)"});
  const std::string binary = vtkLegacyBinary();
  expectError(writeBytes(dir / "short_binary.vtk", binary.substr(0, binary.find("POINTS 8 float\n") + 40)), 5,
              {"declares 24 values of POINTS but only 25 bytes follow"});
}

TEST(VtkLegacyReader, TetraWithThreePointsIsAnError) {
  TempDir dir;
  // The triangle (cell 1) marked as a tetrahedron.
  std::string text = vtkLegacyAscii(false);
  text.replace(text.find("CELL_TYPES 8\n1\n5\n"), 17, "CELL_TYPES 8\n1\n10\n");
  expectError(dir.write("bad_tetra.vtk", text), 18, {"cell 1 has type 10 (VTK_TETRA) but 3 points, expected 4"});
}

// ---------------------------------------------------------------------------
// VTK XML

TEST(VtuReader, AsciiWithCellLabelsAndMixedCells) {
  TempDir dir;
  expectCube(formats::readTetMesh(dir.write("cube.vtu", vtu({}))), true);
  expectCube(formats::readTetMesh(dir.write("plain.vtu", vtu({}, false))), false);
}

TEST(VtuReader, Base64WithEveryHeaderLayoutAndByteOrder) {
  TempDir dir;
  for (const bool header64 : {false, true}) {
    for (const bool bigEndian : {false, true}) {
      for (const bool separateHeader : {false, true}) {
        SCOPED_TRACE(testing::Message() << "header64 " << header64 << " bigEndian " << bigEndian << " separate "
                                        << separateHeader);
        VtuOptions options{VtuData::kBinary, header64, bigEndian, separateHeader};
        expectCube(formats::readTetMesh(dir.write("binary.vtu", vtu(options))), true);
      }
    }
  }
}

TEST(VtuReader, ZlibCompressedInOneOrManyBlocks) {
  TempDir dir;
  for (const size_t blockSize : {size_t(32768), size_t(16), size_t(8)}) {  // 8: sizes are multiples, last block full
    for (const bool header64 : {false, true}) {
      SCOPED_TRACE(testing::Message() << "block " << blockSize << " header64 " << header64);
      VtuOptions options{VtuData::kBinaryZlib, header64, blockSize == 16, true, blockSize};
      expectCube(formats::readTetMesh(dir.write("zlib.vtu", vtu(options))), true);
    }
  }
}

TEST(VtuReader, AppendedDataRawAndBase64CompressedOrNot) {
  // ParaView's and VTK's writers put the arrays in <AppendedData> by default.
  TempDir dir;
  for (const VtuPlace place : {VtuPlace::kAppendedRaw, VtuPlace::kAppendedBase64}) {
    for (const VtuData data : {VtuData::kBinary, VtuData::kBinaryZlib}) {
      for (const bool header64 : {false, true}) {
        for (const size_t blockSize : {size_t(32768), size_t(16)}) {
          SCOPED_TRACE(testing::Message()
                       << "raw " << (place == VtuPlace::kAppendedRaw) << " zlib " << (data == VtuData::kBinaryZlib)
                       << " header64 " << header64 << " block " << blockSize);
          VtuOptions options{data, header64, blockSize == 16, blockSize == 16, blockSize};
          options.place = place;
          expectCube(formats::readTetMesh(dir.write("appended.vtu", vtu(options))), true);
        }
      }
    }
  }
  // A comment naming <AppendedData> before the real one, or in a file without one.
  for (const VtuPlace place : {VtuPlace::kInline, VtuPlace::kAppendedRaw}) {
    VtuOptions options{VtuData::kBinaryZlib};
    options.place = place;
    std::string text = vtu(options);
    text.insert(text.find("<VTKFile"), "<!-- data in <AppendedData encoding=\"raw\"> or inline -->\n");
    expectCube(formats::readTetMesh(dir.write("commented.vtu", text)), true);
  }
  // Raw data may hold anything, "<" and "</AppendedData>" included.
  VtuOptions options{VtuData::kBinary};
  options.place = VtuPlace::kAppendedRaw;
  std::string text = vtu(options);
  text.insert(text.find("</AppendedData>"), "</AppendedData> <\x01");
  expectCube(formats::readTetMesh(dir.write("tricky.vtu", text)), true);
}

TEST(TetMeshReader, EveryLayoutVtkWritesReadsAsTheGmshFile) {
  // tests/plugins/tetra_brain/data/write_vtk.py: two_volumes_v22.msh written
  // by VTK 9.1's own writers: XML appended (raw, base64) or inline,
  // compressed or not; legacy 5.1 binary and 4.2 ASCII.
  const std::filesystem::path data = test::sourceDir() / "tests/plugins/tetra_brain/data";
  const TetMesh gmsh = formats::readTetMesh(data / "two_volumes_v22.msh");
  for (const char* name :
       {"default.vtu", "raw.vtu", "raw_plain.vtu", "b64_plain64.vtu", "inline.vtu", "legacy51.vtk", "legacy42.vtk"}) {
    SCOPED_TRACE(name);
    const TetMesh vtu = formats::readTetMesh(data / (std::string("two_volumes_") + name));
    // VTK's legacy ASCII writer keeps 6 significant digits; binary layouts are exact.
    const double tolerance = std::string_view(name) == "legacy42.vtk" ? 1e-5 : 0.0;
    ASSERT_EQ(vtu.nodeCount(), gmsh.nodeCount());
    for (size_t i = 0; i < gmsh.nodeCount(); ++i)
      ASSERT_LE((vtu.nodes[i] - gmsh.nodes[i]).lpNorm<Eigen::Infinity>(), tolerance) << "node " << i;
    EXPECT_EQ(vtu.tets, gmsh.tets);
    EXPECT_EQ(vtu.labels, gmsh.labels);
  }
}

TEST(VtuReader, PiecesAreJoined) {
  TempDir dir;
  // The cube's five tetrahedra in two pieces, each with its own copy of the points.
  std::vector<VtkCell> first = vtkCells();
  std::vector<VtkCell> second(first.begin() + 5, first.end());
  first.resize(5);
  const std::string pieces = vtuPiece(cube(), first, {}, true) + vtuPiece(cube(), second, {}, true);
  const TetMesh mesh = formats::readTetMesh(dir.write("pieces.vtu", vtuFile(pieces, {})));
  ASSERT_EQ(mesh.nodeCount(), 16u);
  ASSERT_EQ(mesh.tetCount(), 5u);
  EXPECT_EQ(mesh.tets[2], (TetIndices{8 + 1, 8 + 4, 8 + 5, 8 + 7}));
  EXPECT_EQ(mesh.labels, cube().labels);
}

TEST(VtuReader, ErrorsNameTheArrayAndLine) {
  TempDir dir;
  std::string text = vtu({});
  text.replace(text.find("format=\"ascii\""), 14, "format=\"appended\" offset=\"0\"");
  expectError(dir.write("appended.vtu", text), 7,
              {"DataArray \"Points\": format=\"appended\" but the file has no <AppendedData>"});
  VtuOptions raw{VtuData::kBinaryZlib};
  raw.place = VtuPlace::kAppendedRaw;
  text = vtu(raw);
  text.replace(text.find("offset=\"0\""), 10, "offset=\"99999\"");
  expectError(dir.write("offset.vtu", text), 7, {"DataArray \"Points\": offset 99999 is beyond the"});
  text = vtu(raw);
  text.replace(text.find("offset=\"0\""), 10, "offset=\"-1\"");
  expectError(dir.write("negative.vtu", text), 7, {"offset '-1', expected the position of its data"});
  text = vtu(raw);
  text.erase(text.find("   _") + 3, 1);
  expectError(dir.write("marker.vtu", text), 20, {"<AppendedData> has no '_' before its data"});
  text = vtu(raw);
  expectError(dir.write("unclosed.vtu", text.substr(0, text.find("</AppendedData>"))), 20,
              {"no closing </AppendedData> (truncated?)"});
  text = vtu(raw);
  text.replace(text.find("encoding=\"raw\""), 14, "encoding=\"hex\"");
  expectError(dir.write("hex.vtu", text), 20, {"<AppendedData> encoding 'hex', expected \"raw\" or \"base64\""});
  VtuOptions encoded{VtuData::kBinary};
  encoded.place = VtuPlace::kAppendedBase64;
  text = vtu(encoded);
  expectError(dir.write("short.vtu", text.substr(0, text.find("   _") + 24) + "</AppendedData></VTKFile>"), 7,
              {"DataArray \"Points\": the base64 data from offset 0 has 12 characters left, expected at least 128"});
  expectError(dir.write("poly.vtu", "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"><PolyData/></VTKFile>"), 2,
              {"VTKFile type 'PolyData', expected \"UnstructuredGrid\""});
  text = vtu({VtuData::kBinaryZlib});
  text.replace(text.find("vtkZLibDataCompressor"), 21, "vtkLZ4DataCompressor");
  expectError(dir.write("lz4.vtu", text), 3, {"compressor 'vtkLZ4DataCompressor' is not supported"});
  text = vtu({VtuData::kBinary});
  const size_t data = text.find('\n', text.find("Name=\"offsets\"")) + 11;
  text.replace(data + 4, 1, "*");
  expectError(dir.write("base64.vtu", text), 15, {"DataArray \"offsets\"", "invalid character", "'*'"});
  text = vtu({});
  expectError(dir.write("cut.vtu", text.substr(0, text.size() / 2)), 13, {"not well-formed XML"});
  text = vtu({});
  text.replace(text.find("1 3 2 7"), 7, "1 3 2 9");
  expectError(dir.write("range.vtu", text), 12, {"cell 3 refers to point 9, but the piece has points 0..7"});
  text = vtu({});
  text.replace(text.find("8.5 12.25 110.125"), 3, "-inf");
  expectError(dir.write("inf.vtu", text), 7, {"point 7 has a non-finite coordinate (-inf"});
  text = vtu({});
  text.replace(text.find("NumberOfCells=\"8\""), 17, "NumberOfCells=\"9\"");
  expectError(dir.write("count.vtu", text), 15, {"DataArray \"offsets\": holds 8 values, expected 9"});
  text = vtu({VtuData::kBinaryZlib});
  const size_t points = text.find('\n', text.find("NumberOfComponents=\"3\"")) + 11;
  text.replace(points + 30, 4, "AAAA");
  expectError(dir.write("zlib.vtu", text), 7, {"DataArray \"Points\": compressed block 0", "corrupt zlib data"});
  text = vtu({});
  text.replace(text.find("NumberOfPoints=\"8\""), 18, "NumberOfPoints=\"90000000\"");
  expectError(dir.write("huge.vtu", text), 7, {"too short for the 270000000 values expected"});
}

// ---------------------------------------------------------------------------
// Format detection and general errors

TEST(TetMeshReader, TheContentDecidesNotTheExtension) {
  TempDir dir;
  expectCube(formats::readTetMesh(dir.write("really_vtu.vtk", vtu({VtuData::kBinary}))), true);
  expectCube(formats::readTetMesh(dir.write("really_medit.msh", medit())), true);
  expectCube(formats::readTetMesh(dir.write("really_gmsh.txt", gmshLegacy())), true);
  expectCube(formats::readTetMesh(dir.write("really_legacy.vtu", vtkLegacyAscii(true))), true);
  expectCube(formats::readTetMesh(writeBytes(dir / "gzipped_without_saying.mesh", gzipped(gmshVersion2()))), true);
  dir.write("tetgen.ele", tetgenEle(0, false));
  expectCube(formats::readTetMesh(dir.write("tetgen.dat", tetgenNode(0, false))), false);
  // A UTF-8 byte order mark and leading blank lines are no obstacle.
  expectCube(formats::readTetMesh(dir.write("bom.vtu", "\xEF\xBB\xBF\n\n" + vtu({}))), true);
}

TEST(TetMeshReader, GeneralErrorsNameTheFile) {
  TempDir dir;
  expectError(dir / "missing.mesh", 0, {"cannot open"});
  std::filesystem::create_directory(dir / "folder.mesh");
  expectError(dir / "folder.mesh", 0, {"not a regular file"});
  expectError(dir.write("empty.mesh", ""), 0, {"the file is empty"});
  expectError(dir.write("text.mesh", "solid cube\nfacet normal 0 0 1\n"), 0,
              {"not a recognised tetrahedral mesh", "'solid cube\\x0afacet normal", "TetGen", "Medit", "Gmsh", "VTK"});
  expectError(writeBytes(dir / "binary.meshb", Bytes("\x01\0\0\0\x02\0\0\0", 8)), 0,
              {"binary Medit (.meshb) files are not supported"});
  const Bytes compressed = gzipped(medit());
  expectError(writeBytes(dir / "cut.mesh.gz", compressed.substr(0, compressed.size() / 2)), 0,
              {"gzip data ends before the end of the compressed stream (truncated file)"});
  Bytes corrupt = compressed;
  corrupt[12] = char(0xff);
  corrupt[13] = char(0xff);
  expectError(writeBytes(dir / "corrupt.mesh.gz", corrupt), 0, {"corrupt gzip data"});
  expectError(writeBytes(dir / "empty.gz", gzipped("")), 0, {"the gzip file holds no data"});
  expectError(dir.write("nothing.vtu", vtuFile(vtuPiece(cube(), {{5, {0, 1, 2}, 0}}, {}, false), {})), 0,
              {"the mesh has no tetrahedra"});
}

// ---------------------------------------------------------------------------
// Real meshes (../shared/data, absent from a fresh clone)

std::filesystem::path realData(const std::string& relative) {
  return std::filesystem::path(TREPHINE_SOURCE_DIR) / "../shared/data" / relative;
}

#define SKIP_WITHOUT_REAL_DATA()                                                                     \
  if (!std::filesystem::exists(realData(""))) {                                                      \
    GTEST_SKIP() << "real mesh data not found at " << realData("") << " (../shared/data); skipping"; \
  }

Box3 bounds(const TetMesh& mesh) {
  Box3 box;
  for (const Vec3& p : mesh.nodes) box.extend(p);
  return box;
}

double volume(const TetMesh& mesh) {
  double sum = 0;
  for (const TetIndices& t : mesh.tets)
    sum += signedVolume(mesh.nodes[size_t(t[0])], mesh.nodes[size_t(t[1])], mesh.nodes[size_t(t[2])],
                        mesh.nodes[size_t(t[3])]);
  return sum;
}

void expectBounds(const TetMesh& mesh, const Vec3& low, const Vec3& high, double tolerance) {
  const Box3 box = bounds(mesh);
  EXPECT_LE((box.min() - low).cwiseAbs().maxCoeff(), tolerance) << box.min().transpose();
  EXPECT_LE((box.max() - high).cwiseAbs().maxCoeff(), tolerance) << box.max().transpose();
}

TEST(RealData, BrainTetGenAndMeditGiveTheSameLabelledMesh) {
  SKIP_WITHOUT_REAL_DATA();
  const auto start = std::chrono::steady_clock::now();
  const TetMesh tetgen = formats::readTetMesh(realData("brain_tetmesh_mmc_head_atlas/brain_gm_wm.node"));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("brain_gm_wm.node + .ele.gz: %zu nodes, %zu tetrahedra read in %.1f ms\n", tetgen.nodeCount(),
              tetgen.tetCount(), 1000 * seconds);
  RecordProperty("brain_read_ms", std::to_string(1000 * seconds));
  EXPECT_EQ(tetgen.nodeCount(), 30871u);
  EXPECT_EQ(tetgen.tetCount(), 145391u);
  std::map<int32_t, size_t> perLabel;
  for (const int32_t label : tetgen.labels) ++perLabel[label];
  EXPECT_EQ(perLabel, (std::map<int32_t, size_t>{{5, 96818}, {6, 48573}}));
  expectBounds(tetgen, {25.8, 20.1, 146.3}, {146.0, 171.5, 201.9}, 0.051);
  EXPECT_NEAR(volume(tetgen), 319212, 1);

  const TetMesh medit = formats::readTetMesh(realData("brain_tetmesh_mmc_head_atlas/brain_gm_wm.mesh.gz"));
  EXPECT_EQ(medit.nodeCount(), 30871u);
  EXPECT_EQ(medit.tets, tetgen.tets);
  EXPECT_EQ(medit.labels, tetgen.labels);
  ASSERT_EQ(medit.nodes.size(), tetgen.nodes.size());
  for (size_t i = 0; i < medit.nodes.size(); ++i) ASSERT_LT((medit.nodes[i] - tetgen.nodes[i]).norm(), 1e-3) << i;
  // The base name and the .ele file find the same pair.
  EXPECT_EQ(formats::readTetMesh(realData("brain_tetmesh_mmc_head_atlas/brain_gm_wm")).tets, tetgen.tets);
  EXPECT_EQ(formats::readTetMesh(realData("brain_tetmesh_mmc_head_atlas/brain_gm_wm.ele.gz")).tetCount(), 145391u);
}

TEST(RealData, SofaMeshesVtuVtkNamedVtuAndGmshLegacy) {
  SKIP_WITHOUT_REAL_DATA();
  const TetMesh armadillo = formats::readTetMesh(realData("tet_sofa_share_mesh/Armadillo_Tetra_4406.vtu"));
  EXPECT_EQ(armadillo.nodeCount(), 1446u);
  EXPECT_EQ(armadillo.tetCount(), 4406u);
  EXPECT_TRUE(armadillo.labels.empty());
  expectBounds(armadillo, {-6.34, -5.40, -5.76}, {6.33, 9.69, 5.76}, 0.006);
  const TetMesh bunny = formats::readTetMesh(realData("tet_sofa_share_mesh/Bunny.vtk"));  // VTK XML inside
  EXPECT_EQ(bunny.nodeCount(), 1911u);
  EXPECT_EQ(bunny.tetCount(), 5897u);
  const TetMesh liver = formats::readTetMesh(realData("tet_sofa_share_mesh/liver.msh"));
  EXPECT_EQ(liver.nodeCount(), 181u);
  EXPECT_EQ(liver.tetCount(), 596u);
  EXPECT_EQ(liver.labels, std::vector<int32_t>(596, 1));  // physical tag 1 throughout
  for (const TetMesh* mesh : {&armadillo, &bunny, &liver}) EXPECT_GT(volume(*mesh), 0);
}

TEST(RealData, LibiglBunnyMedit) {
  SKIP_WITHOUT_REAL_DATA();
  const TetMesh hull = formats::readTetMesh(realData("tet_bunny_libigl/bunny.mesh"));
  EXPECT_EQ(hull.nodeCount(), 5433u);
  EXPECT_EQ(hull.tetCount(), 34055u);
  EXPECT_EQ(hull.labels, std::vector<int32_t>(34055, 0));
  EXPECT_NEAR(volume(hull), 0.0012494, 1e-7);
  const TetMesh inside = formats::readTetMesh(realData("tet_bunny_libigl/bunny_inside_derived.mesh"));
  EXPECT_EQ(inside.nodeCount(), 5433u);
  EXPECT_EQ(inside.tetCount(), 22874u);
  EXPECT_NEAR(volume(inside), 0.00075393, 1e-8);
}

TEST(RealData, ZeroBasedTetGenBunniesAndArmadillo) {
  SKIP_WITHOUT_REAL_DATA();
  struct Case {
    const char* base;
    size_t nodes;
    size_t tets;
    double volume;
  };
  for (const Case& c :
       {Case{"bunny_libigl_p", 4089, 13675, 7.5393e-4}, Case{"bunny_libigl_pq2", 17106, 62288, 7.5393e-4},
        Case{"armadillo_cgal_p", 29594, 100635, 237850}}) {
    SCOPED_TRACE(c.base);
    const TetMesh mesh = formats::readTetMesh(realData(std::string("tet_bunny_armadillo_tetgen_derived/") + c.base + ".ele"));
    EXPECT_EQ(mesh.nodeCount(), c.nodes);
    EXPECT_EQ(mesh.tetCount(), c.tets);
    EXPECT_TRUE(mesh.labels.empty());
    EXPECT_NEAR(volume(mesh), c.volume, c.volume * 1e-4);
    if (std::string(c.base) == "armadillo_cgal_p") expectBounds(mesh, {-63.5, -54.2, -57.7}, {63.5, 97.1, 57.7}, 0.051);
  }
}

TEST(RealData, CowTetGenAndMeditGiveTheSameMesh) {
  SKIP_WITHOUT_REAL_DATA();
  const TetMesh tetgen = formats::readTetMesh(realData("tet_cow_cgal_derived/cow_mesh3.node"));
  const TetMesh medit = formats::readTetMesh(realData("tet_cow_cgal_derived/cow_mesh3.mesh"));
  EXPECT_EQ(tetgen.nodeCount(), 8960u);
  EXPECT_EQ(tetgen.tetCount(), 30850u);
  EXPECT_EQ(medit.tets, tetgen.tets);  // 0-based TetGen and 1-based Medit agree
  ASSERT_EQ(medit.nodes.size(), tetgen.nodes.size());
  for (size_t i = 0; i < medit.nodes.size(); ++i) ASSERT_LT((medit.nodes[i] - tetgen.nodes[i]).norm(), 1e-6) << i;
  EXPECT_NEAR(volume(tetgen), 53.40, 0.01);
  expectBounds(tetgen, {-4.42, -3.62, -1.68}, {5.98, 2.74, 1.68}, 0.006);
}

}  // namespace
}  // namespace trephine::formats
