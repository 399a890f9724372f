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
#include "framework/formats/mesh/VtuDataArray.h"

namespace trephine::formats {

namespace {

using tinyxml2::XMLElement;

std::string_view attribute(const XMLElement* element, const char* name) {
  const char* value = element->Attribute(name);
  return value ? std::string_view(value) : std::string_view();
}

// The first `needle` in `text` that is not inside an XML comment.
size_t findOutsideComments(std::string_view text, std::string_view needle) {
  size_t from = 0;
  for (;;) {
    const size_t hit = text.find(needle, from);
    const size_t comment = text.find("<!--", from);
    if (hit == std::string_view::npos || comment == std::string_view::npos || hit < comment) return hit;
    const size_t commentEnd = text.find("-->", comment + 4);
    if (commentEnd == std::string_view::npos) return std::string_view::npos;
    from = commentEnd + 3;
  }
}

class VtuParser {
 public:
  VtuParser(const std::filesystem::path& file, std::string_view content) : m_file(file), m_content(content) {}

  TetMesh read() {
    // <AppendedData> holds raw bytes or base64 text, not XML: it is cut out
    // and the XML before and after it parsed (line numbers stay those of the file).
    std::string cut;
    const std::string_view xml = withoutAppendedData(cut);
    tinyxml2::XMLDocument document;
    if (document.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
      throw TetMeshReadError(m_file, size_t(std::max(document.ErrorLineNum(), 1)),
                             std::string("not well-formed XML (") + document.ErrorName() + ")");
    const XMLElement* root = document.RootElement();
    if (!root || std::string_view(root->Name()) != "VTKFile")
      fail(root, "the XML root is <" + std::string(root ? root->Name() : "") +
                     ">, expected <VTKFile type=\"UnstructuredGrid\">");
    const std::string_view type = attribute(root, "type");
    if (type != "UnstructuredGrid")
      fail(root, "VTKFile type " + quoteForMessage(type) + ", expected \"UnstructuredGrid\" (a .vtu file" +
                     (type == "PUnstructuredGrid" ? "; a .pvtu only lists the .vtu pieces)" : ")"));
    readEncoding(root);
    if (m_encoding.hasAppended) readAppendedEncoding(root);
    const XMLElement* grid = root->FirstChildElement("UnstructuredGrid");
    if (!grid) fail(root, "VTKFile has no <UnstructuredGrid> element");
    const XMLElement* piece = grid->FirstChildElement("Piece");
    if (!piece) fail(grid, "<UnstructuredGrid> has no <Piece>");
    for (; piece; piece = piece->NextSiblingElement("Piece")) readPiece(piece);
    if (!m_anyLabels) m_mesh.labels.clear();
    return std::move(m_mesh);
  }

 private:
  [[noreturn]] void fail(const XMLElement* element, const std::string& problem) const {
    throw TetMeshReadError(m_file, element ? size_t(element->GetLineNum()) : 0, problem);
  }

  void readEncoding(const XMLElement* root) {
    const std::string_view byteOrder = attribute(root, "byte_order");
    if (byteOrder == "BigEndian")
      m_encoding.bigEndian = true;
    else if (!byteOrder.empty() && byteOrder != "LittleEndian")
      fail(root, "byte_order " + quoteForMessage(byteOrder) + ", expected \"LittleEndian\" or \"BigEndian\"");
    const std::string_view headerType = attribute(root, "header_type");
    if (headerType == "UInt64")
      m_encoding.header64 = true;
    else if (!headerType.empty() && headerType != "UInt32")
      fail(root, "header_type " + quoteForMessage(headerType) + ", expected \"UInt32\" or \"UInt64\"");
    const std::string_view compressor = attribute(root, "compressor");
    if (compressor == "vtkZLibDataCompressor")
      m_encoding.zlib = true;
    else if (!compressor.empty())
      fail(root, "compressor " + quoteForMessage(compressor) +
                     " is not supported, expected none or \"vtkZLibDataCompressor\"");
  }

  size_t lineAt(size_t position) const {
    return size_t(std::count(m_content.begin(), m_content.begin() + std::ptrdiff_t(position), '\n')) + 1;
  }

  // The file's XML: the content, or with the data of <AppendedData> removed
  // (kept in m_encoding.appended) into `cut`.
  std::string_view withoutAppendedData(std::string& cut) {
    const size_t tag = findOutsideComments(m_content, "<AppendedData");
    if (tag == std::string_view::npos) return m_content;
    const size_t tagEnd = m_content.find('>', tag);
    if (tagEnd == std::string_view::npos)
      throw TetMeshReadError(m_file, lineAt(tag), "the <AppendedData> tag is not closed (truncated?)");
    size_t marker = tagEnd + 1;
    while (marker < m_content.size() && std::isspace(static_cast<unsigned char>(m_content[marker]))) ++marker;
    if (marker >= m_content.size() || m_content[marker] != '_')
      throw TetMeshReadError(m_file, lineAt(tag),
                             "<AppendedData> has no '_' before its data (expected \"<AppendedData "
                             "encoding=...>\" then \"_\" and the data)");
    const size_t close = m_content.rfind("</AppendedData>");
    if (close == std::string_view::npos || close < marker)
      throw TetMeshReadError(m_file, lineAt(tag), "<AppendedData> has no closing </AppendedData> (truncated?)");
    m_encoding.hasAppended = true;
    m_encoding.appended = m_content.substr(marker + 1, close - marker - 1);
    cut = std::string(m_content.substr(0, marker + 1)) + std::string(m_content.substr(close));
    return cut;
  }

  void readAppendedEncoding(const XMLElement* root) {
    const XMLElement* appended = root->FirstChildElement("AppendedData");
    if (!appended) fail(root, "<AppendedData> is not inside <VTKFile>");
    const std::string_view encoding = attribute(appended, "encoding");
    if (encoding == "base64")
      m_encoding.appendedBase64 = true;
    else if (encoding != "raw")
      fail(appended, "<AppendedData> encoding " + (encoding.data() ? quoteForMessage(encoding) : "missing") +
                         ", expected \"raw\" or \"base64\"");
  }

  int64_t count(const XMLElement* piece, const char* name, int64_t maxCount) const {
    const std::string_view text = attribute(piece, name);
    const std::optional<int64_t> value = parseInteger(text);
    if (!value || *value < 0 || *value > maxCount)
      fail(piece, std::string("<Piece> ") + name + " is " + (text.data() ? quoteForMessage(text) : "missing") +
                      ", expected a whole number from 0 to " + std::to_string(maxCount));
    return *value;
  }

  VtuArray describe(const XMLElement* array) const {
    VtuArray described;
    described.name = attribute(array, "Name");
    // Unnamed arrays (the points) are named by their parent element in messages.
    if (described.name.empty() && array->Parent() && array->Parent()->ToElement())
      described.name = array->Parent()->ToElement()->Name();
    described.type = attribute(array, "type");
    described.format = attribute(array, "format");
    const char* text = array->GetText();
    described.text = text ? std::string_view(text) : std::string_view();
    described.line = size_t(array->GetLineNum());
    if (described.format == "appended") {
      const std::string_view offset = attribute(array, "offset");
      const std::optional<int64_t> value = parseInteger(offset);
      if (!value || *value < 0)
        fail(array, "DataArray \"" + std::string(described.name) + "\": offset " +
                        (offset.data() ? quoteForMessage(offset) : "missing") +
                        ", expected the position of its data in <AppendedData> (a whole number from 0)");
      described.offset = uint64_t(*value);
    }
    return described;
  }

  int64_t components(const XMLElement* array) const {
    const std::string_view text = attribute(array, "NumberOfComponents");
    if (text.empty()) return 1;
    const std::optional<int64_t> value = parseInteger(text);
    if (!value || *value < 1) fail(array, "NumberOfComponents " + quoteForMessage(text) + ", expected 1 or more");
    return *value;
  }

  const XMLElement* namedArray(const XMLElement* parent, std::string_view name) const {
    for (const XMLElement* array = parent->FirstChildElement("DataArray"); array;
         array = array->NextSiblingElement("DataArray"))
      if (attribute(array, "Name") == name) return array;
    fail(parent, "<" + std::string(parent->Name()) + "> has no DataArray named \"" + std::string(name) + "\"");
  }

  // The first integer, single-component cell array whose name says it is a label.
  const XMLElement* labelArray(const XMLElement* piece) const {
    const XMLElement* cellData = piece->FirstChildElement("CellData");
    if (!cellData) return nullptr;
    for (const XMLElement* array = cellData->FirstChildElement("DataArray"); array;
         array = array->NextSiblingElement("DataArray")) {
      const std::string_view type = attribute(array, "type");
      const bool integer = type.starts_with("Int") || type.starts_with("UInt");
      if (isLabelArrayName(attribute(array, "Name")) && integer && components(array) == 1) return array;
    }
    return nullptr;
  }

  void readPiece(const XMLElement* piece) {
    const int64_t pointCount = count(piece, "NumberOfPoints", kMaxNodes);
    const int64_t cellCount = count(piece, "NumberOfCells", kMaxRecords);
    const auto firstNode = int64_t(m_mesh.nodes.size());
    if (firstNode + pointCount > kMaxNodes)
      fail(piece, "the pieces hold more than " + std::to_string(kMaxNodes) + " points, more than supported");
    readPoints(piece, pointCount);

    const XMLElement* cells = piece->FirstChildElement("Cells");
    if (!cells) {
      if (cellCount == 0) return;
      fail(piece, "<Piece> has NumberOfCells=" + std::to_string(cellCount) + " but no <Cells>");
    }
    const XMLElement* offsetsArray = namedArray(cells, "offsets");
    const XMLElement* typesArray = namedArray(cells, "types");
    const XMLElement* connectivityArray = namedArray(cells, "connectivity");
    const std::vector<int64_t> offsets = readVtuIntegers(describe(offsetsArray), cellCount, m_encoding, m_file);
    const std::vector<int64_t> types = readVtuIntegers(describe(typesArray), cellCount, m_encoding, m_file);
    const int64_t connectivitySize = offsets.empty() ? 0 : offsets.back();
    if (connectivitySize < 0 || connectivitySize > kMaxArrayValues)
      fail(offsetsArray, "the last offset is " + std::to_string(connectivitySize) + ", expected 0 to " +
                             std::to_string(kMaxArrayValues));
    const std::vector<int64_t> connectivity =
        readVtuIntegers(describe(connectivityArray), connectivitySize, m_encoding, m_file);
    std::vector<int64_t> labels;
    const XMLElement* labelsArray = labelArray(piece);
    if (labelsArray) {
      labels = readVtuIntegers(describe(labelsArray), cellCount, m_encoding, m_file);
      m_anyLabels = true;
    }

    int64_t start = 0;
    for (int64_t cell = 0; cell < cellCount; ++cell) {
      const int64_t end = offsets[size_t(cell)];
      if (end < start || end > connectivitySize)
        fail(offsetsArray, "cell " + std::to_string(cell) + " ends at offset " + std::to_string(end) + ", expected " +
                               std::to_string(start) + " to " + std::to_string(connectivitySize) +
                               " (offsets must not decrease)");
      if (vtkTetraPointCount(types[size_t(cell)]) > 0)
        addTet(connectivityArray, cell, types[size_t(cell)], connectivity, start, end, pointCount, firstNode, labels,
               labelsArray);
      start = end;
    }
  }

  void readPoints(const XMLElement* piece, int64_t pointCount) {
    const XMLElement* points = piece->FirstChildElement("Points");
    const XMLElement* array = points ? points->FirstChildElement("DataArray") : nullptr;
    if (!array) {
      if (pointCount == 0) return;
      fail(piece, "<Piece> has NumberOfPoints=" + std::to_string(pointCount) + " but no <Points><DataArray>");
    }
    if (components(array) != 3)
      fail(array, "the points have NumberOfComponents=" + std::to_string(components(array)) + ", expected 3");
    const std::vector<double> xyz = readVtuReals(describe(array), 3 * pointCount, m_encoding, m_file);
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

  void addTet(const XMLElement* connectivityArray, int64_t cell, int64_t type, const std::vector<int64_t>& connectivity,
              int64_t start, int64_t end, int64_t pointCount, int64_t firstNode, const std::vector<int64_t>& labels,
              const XMLElement* labelsArray) {
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

  const std::filesystem::path& m_file;
  std::string_view m_content;
  VtuEncoding m_encoding;
  TetMesh m_mesh;
  bool m_anyLabels = false;
};

}  // namespace

TetMesh readVtu(const std::filesystem::path& file, std::string_view content) { return VtuParser(file, content).read(); }

}  // namespace trephine::formats
