#include "framework/formats/vtk/VtkSurfaceReader.h"

#include <tinyxml2.h>

#include <fstream>
#include <sstream>
#include <string>

#include "framework/formats/mesh/ReadChecks.h"
#include "framework/formats/vtk/VtkXmlFile.h"

namespace trephine::formats {

namespace {

using Element = VtkXmlFile::Element;

void readPiece(const VtkXmlFile& vtk, const Element& piece, TriangleMesh& surface) {
  const int64_t pointCount = vtk.count(piece, "NumberOfPoints", kMaxNodes);
  const int64_t polyCount = piece.Attribute("NumberOfPolys") ? vtk.count(piece, "NumberOfPolys", kMaxRecords) : 0;
  const auto first = int64_t(surface.vertices.size());
  if (first + pointCount > kMaxNodes)
    vtk.fail(&piece, "the pieces hold more than " + std::to_string(kMaxNodes) + " points, more than supported");
  if (pointCount > 0) {
    const Element* points = piece.FirstChildElement("Points");
    const Element* array = points ? points->FirstChildElement("DataArray") : nullptr;
    if (!array)
      vtk.fail(&piece, "<Piece> has NumberOfPoints=" + std::to_string(pointCount) + " but no <Points><DataArray>");
    if (vtk.components(*array) != 3)
      vtk.fail(array, "the points have NumberOfComponents=" + std::to_string(vtk.components(*array)) + ", expected 3");
    const std::vector<double> xyz = vtk.reals(*array, 3 * pointCount);
    for (int64_t i = 0; i < pointCount; ++i) {
      const Vec3 p(xyz[size_t(3 * i)], xyz[size_t(3 * i + 1)], xyz[size_t(3 * i + 2)]);
      if (!p.allFinite()) vtk.fail(array, "point " + std::to_string(i) + " has a non-finite coordinate");
      surface.vertices.push_back(p);
    }
  }
  if (polyCount == 0) return;
  const Element* polys = piece.FirstChildElement("Polys");
  if (!polys) vtk.fail(&piece, "<Piece> has NumberOfPolys=" + std::to_string(polyCount) + " but no <Polys>");
  const Element& offsetsArray = vtk.namedArray(*polys, "offsets");
  const Element& connectivityArray = vtk.namedArray(*polys, "connectivity");
  const std::vector<int64_t> offsets = vtk.integers(offsetsArray, polyCount);
  const int64_t connectivitySize = offsets.back();
  if (connectivitySize < 0 || connectivitySize > kMaxArrayValues)
    vtk.fail(&offsetsArray, "the last offset is " + std::to_string(connectivitySize) + ", expected 0 to " +
                                std::to_string(kMaxArrayValues));
  const std::vector<int64_t> connectivity = vtk.integers(connectivityArray, connectivitySize);
  int64_t start = 0;
  for (int64_t poly = 0; poly < polyCount; ++poly) {
    const int64_t end = offsets[size_t(poly)];
    if (end < start || end > connectivitySize)
      vtk.fail(&offsetsArray, "polygon " + std::to_string(poly) + " ends at offset " + std::to_string(end) +
                                  ", expected " + std::to_string(start) + " to " + std::to_string(connectivitySize) +
                                  " (offsets must not decrease)");
    if (end - start == 3) {
      std::array<int32_t, 3> triangle;
      for (int k = 0; k < 3; ++k) {
        const int64_t point = connectivity[size_t(start + k)];
        if (point < 0 || point >= pointCount)
          vtk.fail(&connectivityArray, "polygon " + std::to_string(poly) + " refers to point " +
                                           std::to_string(point) + ", but the piece has points " +
                                           indexRange(0, pointCount));
        triangle[size_t(k)] = int32_t(first + point);
      }
      surface.triangles.push_back(triangle);
    }
    start = end;
  }
}

}  // namespace

TriangleMesh readVtkPolyData(const std::filesystem::path& file, std::string_view content) {
  const VtkXmlFile vtk(file, content, "PolyData");
  TriangleMesh surface;
  for (const Element* piece = vtk.dataSet().FirstChildElement("Piece"); piece;
       piece = piece->NextSiblingElement("Piece"))
    readPiece(vtk, *piece, surface);
  return surface;
}

TriangleMesh readVtkPolyDataSurface(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw FileReadError(file, "cannot be read");
  std::ostringstream all;
  all << in.rdbuf();
  if (!in.good() && !in.eof()) throw FileReadError(file, "read error");
  return readVtkPolyData(file, all.str());
}

}  // namespace trephine::formats
