#include "framework/formats/mesh/VtuReader.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "framework/formats/mesh/ReadChecks.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/formats/mesh/TextCursor.h"
#include "framework/formats/mesh/VtkCellTypes.h"
#include "framework/formats/vtk/VtkXmlFile.h"

namespace trephine::formats {

namespace {

using Element = VtkXmlFile::Element;

class VtuParser {
 public:
  VtuParser(const std::filesystem::path& file, std::string_view content)
      : m_vtk(file, content, "UnstructuredGrid") {}

  TetMesh read() {
    const Element* piece = m_vtk.dataSet().FirstChildElement("Piece");
    if (!piece) m_vtk.fail(&m_vtk.dataSet(), "<UnstructuredGrid> has no <Piece>");
    for (; piece; piece = piece->NextSiblingElement("Piece")) readPiece(*piece);
    if (!m_anyLabels) m_mesh.labels.clear();
    return std::move(m_mesh);
  }

 private:
  [[noreturn]] void fail(const Element* element, const std::string& problem) const { m_vtk.fail(element, problem); }

  // The first integer, single-component cell array whose name says it is a label.
  const Element* labelArray(const Element& piece) const {
    const Element* cellData = piece.FirstChildElement("CellData");
    if (!cellData) return nullptr;
    for (const Element* array = cellData->FirstChildElement("DataArray"); array;
         array = array->NextSiblingElement("DataArray")) {
      const std::string_view type = vtkXmlAttribute(*array, "type");
      const bool integer = type.starts_with("Int") || type.starts_with("UInt");
      if (isLabelArrayName(vtkXmlAttribute(*array, "Name")) && integer && m_vtk.components(*array) == 1) return array;
    }
    return nullptr;
  }

  void readPiece(const Element& piece) {
    const int64_t pointCount = m_vtk.count(piece, "NumberOfPoints", kMaxNodes);
    const int64_t cellCount = m_vtk.count(piece, "NumberOfCells", kMaxRecords);
    const auto firstNode = int64_t(m_mesh.nodes.size());
    if (firstNode + pointCount > kMaxNodes)
      fail(&piece, "the pieces hold more than " + std::to_string(kMaxNodes) + " points, more than supported");
    readPoints(piece, pointCount);

    const Element* cells = piece.FirstChildElement("Cells");
    if (!cells) {
      if (cellCount == 0) return;
      fail(&piece, "<Piece> has NumberOfCells=" + std::to_string(cellCount) + " but no <Cells>");
    }
    const Element& offsetsArray = m_vtk.namedArray(*cells, "offsets");
    const Element& typesArray = m_vtk.namedArray(*cells, "types");
    const Element& connectivityArray = m_vtk.namedArray(*cells, "connectivity");
    const std::vector<int64_t> offsets = m_vtk.integers(offsetsArray, cellCount);
    const std::vector<int64_t> types = m_vtk.integers(typesArray, cellCount);
    const int64_t connectivitySize = offsets.empty() ? 0 : offsets.back();
    if (connectivitySize < 0 || connectivitySize > kMaxArrayValues)
      fail(&offsetsArray, "the last offset is " + std::to_string(connectivitySize) + ", expected 0 to " +
                              std::to_string(kMaxArrayValues));
    const std::vector<int64_t> connectivity = m_vtk.integers(connectivityArray, connectivitySize);
    std::vector<int64_t> labels;
    const Element* labelsArray = labelArray(piece);
    if (labelsArray) {
      labels = m_vtk.integers(*labelsArray, cellCount);
      m_anyLabels = true;
    }

    int64_t start = 0;
    for (int64_t cell = 0; cell < cellCount; ++cell) {
      const int64_t end = offsets[size_t(cell)];
      if (end < start || end > connectivitySize)
        fail(&offsetsArray, "cell " + std::to_string(cell) + " ends at offset " + std::to_string(end) +
                                ", expected " + std::to_string(start) + " to " + std::to_string(connectivitySize) +
                                " (offsets must not decrease)");
      if (vtkTetraPointCount(types[size_t(cell)]) > 0)
        addTet(&connectivityArray, cell, types[size_t(cell)], connectivity, start, end, pointCount, firstNode, labels,
               labelsArray);
      start = end;
    }
  }

  void readPoints(const Element& piece, int64_t pointCount) {
    const Element* points = piece.FirstChildElement("Points");
    const Element* array = points ? points->FirstChildElement("DataArray") : nullptr;
    if (!array) {
      if (pointCount == 0) return;
      fail(&piece, "<Piece> has NumberOfPoints=" + std::to_string(pointCount) + " but no <Points><DataArray>");
    }
    if (m_vtk.components(*array) != 3)
      fail(array, "the points have NumberOfComponents=" + std::to_string(m_vtk.components(*array)) + ", expected 3");
    const std::vector<double> xyz = m_vtk.reals(*array, 3 * pointCount);
    m_mesh.nodes.reserve(m_mesh.nodes.size() + size_t(pointCount));
    for (int64_t i = 0; i < pointCount; ++i) {
      const Vec3 position(xyz[size_t(3 * i)], xyz[size_t(3 * i + 1)], xyz[size_t(3 * i + 2)]);
      if (!position.allFinite())
        fail(array, "point " + std::to_string(i) + " has a non-finite coordinate (" + std::to_string(position.x()) +
                        ", " + std::to_string(position.y()) + ", " + std::to_string(position.z()) +
                        "), expected finite numbers of mm");
      m_mesh.nodes.push_back(position);
    }
  }

  void addTet(const Element* connectivityArray, int64_t cell, int64_t type, const std::vector<int64_t>& connectivity,
              int64_t start, int64_t end, int64_t pointCount, int64_t firstNode, const std::vector<int64_t>& labels,
              const Element* labelsArray) {
    const int64_t points = vtkTetraPointCount(type);
    if (end - start != points)
      fail(connectivityArray, "cell " + std::to_string(cell) + " has " + vtkTetraTypeName(type) + " but " +
                                  std::to_string(end - start) + " points, expected " + std::to_string(points));
    if (int64_t(m_mesh.tets.size()) >= kMaxTets)
      fail(connectivityArray, "more than " + std::to_string(kMaxTets) + " tetrahedra, more than supported");
    TetIndices tet;
    for (size_t k = 0; k < 4; ++k) {
      const int64_t point = connectivity[size_t(start) + k];
      if (point < 0 || point >= pointCount)
        fail(connectivityArray, "cell " + std::to_string(cell) + " refers to point " + std::to_string(point) +
                                    ", but the piece has points " + indexRange(0, pointCount));
      tet[k] = static_cast<int32_t>(firstNode + point);
    }
    m_mesh.tets.push_back(tet);
    std::optional<int32_t> label = 0;
    if (!labels.empty()) label = labelFromInteger(labels[size_t(cell)]);
    if (!label)
      fail(labelsArray, "cell " + std::to_string(cell) + " has label " + std::to_string(labels[size_t(cell)]) +
                            ", expected a 32-bit integer");
    m_mesh.labels.push_back(*label);
  }

  VtkXmlFile m_vtk;
  TetMesh m_mesh;
  bool m_anyLabels = false;
};

}  // namespace

TetMesh readVtu(const std::filesystem::path& file, std::string_view content) { return VtuParser(file, content).read(); }

}  // namespace trephine::formats
