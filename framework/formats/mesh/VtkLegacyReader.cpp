#include "framework/formats/mesh/VtkLegacyReader.h"

#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "framework/formats/encoding/NumberType.h"
#include "framework/formats/mesh/ReadChecks.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/formats/mesh/TextCursor.h"
#include "framework/formats/mesh/VtkCellTypes.h"

namespace trephine::formats {

namespace {

constexpr std::string_view kMagic = "# vtk DataFile Version";

// Cells as offsets into one connectivity array (the 5.1 layout; the classic one is converted).
struct Cells {
  std::vector<int64_t> offsets{0};  // cell i uses connectivity[offsets[i] .. offsets[i + 1])
  std::vector<int64_t> connectivity;
  size_t line = 0;  // of the CELLS keyword
  int64_t count() const { return int64_t(offsets.size()) - 1; }
};

class VtkLegacyParser {
 public:
  VtkLegacyParser(const std::filesystem::path& file, std::string_view content) : m_text(content, file) {}

  TetMesh read() {
    readHeader();
    while (true) {
      const std::string_view keyword = m_text.next();
      if (keyword.empty()) break;
      if (equalsIgnoreCase(keyword, "POINTS")) {
        readPoints();
      } else if (equalsIgnoreCase(keyword, "CELLS")) {
        readCells();
      } else if (equalsIgnoreCase(keyword, "CELL_TYPES")) {
        readCellTypes();
      } else if (equalsIgnoreCase(keyword, "CELL_DATA") || equalsIgnoreCase(keyword, "POINT_DATA")) {
        if (!readAttributes(equalsIgnoreCase(keyword, "CELL_DATA"))) break;
      } else if (equalsIgnoreCase(keyword, "FIELD")) {
        readField(-1);
      } else if (equalsIgnoreCase(keyword, "METADATA")) {
        skipMetadata();
      } else if (complete()) {
        break;  // data this reader does not know, after everything it needs
      } else {
        m_text.fail("unexpected " + quoteForMessage(keyword) + ", expected POINTS, CELLS or CELL_TYPES");
      }
    }
    if (!m_havePoints) throw TetMeshReadError(m_text.file(), "the file has no POINTS");
    if (!m_haveCells) throw TetMeshReadError(m_text.file(), "the file has no CELLS");
    if (!m_haveTypes) throw TetMeshReadError(m_text.file(), "the file has no CELL_TYPES");
    return assemble();
  }

 private:
  bool complete() const { return m_havePoints && m_haveCells && m_haveTypes; }

  void readHeader() {
    std::string_view magic = m_text.restOfLine();
    while (magic.find_first_not_of(" \t\r") == std::string_view::npos && m_text.bytesLeft() > 0)
      magic = m_text.restOfLine();
    const size_t start = magic.find_first_not_of(" \t\r");
    if (start == std::string_view::npos || !startsWithIgnoreCase(magic.substr(start), kMagic))
      m_text.fail("the first line is not \"# vtk DataFile Version x.y\"");
    m_text.restOfLine();  // the title
    const std::string_view format = m_text.next();
    if (equalsIgnoreCase(format, "BINARY"))
      m_binary = true;
    else if (!equalsIgnoreCase(format, "ASCII"))
      m_text.fail("the third line is " + quoteForMessage(format) + ", expected ASCII or BINARY");
    const std::string_view dataset = m_text.next();
    if (!equalsIgnoreCase(dataset, "DATASET"))
      m_text.fail("expected DATASET UNSTRUCTURED_GRID, found " + quoteForMessage(dataset));
    const std::string_view kind = m_text.next();
    if (!equalsIgnoreCase(kind, "UNSTRUCTURED_GRID"))
      m_text.fail("DATASET " + std::string(quoteForMessage(kind)) + " is not supported, expected UNSTRUCTURED_GRID");
  }

  int64_t integer(const std::string& what) { return m_text.nextInteger(what); }

  NumberType numberType(std::string_view token, bool integerOnly, const std::string& what) {
    const std::optional<NumberType> type = legacyNumberType(token);
    if (!type)
      m_text.fail(what + ": data type " + quoteForMessage(token) +
                  " is not supported, expected float, double, int, ...");
    if (integerOnly && !isInteger(*type))
      m_text.fail(what + ": data type " + quoteForMessage(token) + ", expected an integer type");
    return *type;
  }

  // The end of a keyword line: binary data starts right after its newline.
  void endKeywordLine() {
    if (m_binary) m_text.restOfLine();
  }

  // `count` values of `type`, ASCII tokens or packed big-endian binary.
  template <typename Out>
  std::vector<Out> values(int64_t count, NumberType type, const std::string& what) {
    std::vector<Out> out;
    if (m_binary) {
      m_text.checkCount(count, kMaxArrayValues, byteSize(type), "values of " + what);
      if (uint64_t(count) * byteSize(type) > m_text.bytesLeft())
        m_text.fail(what + ": " + std::to_string(count) + " values need " + std::to_string(count * byteSize(type)) +
                    " bytes of binary data, only " + std::to_string(m_text.bytesLeft()) + " remain (truncated)");
      decodeNumbers(m_text.take(size_t(count) * byteSize(type)), type, true, out);
      return out;
    }
    m_text.checkCount(count, kMaxArrayValues, 2, "values of " + what);
    out.reserve(size_t(count));
    for (int64_t i = 0; i < count; ++i) {
      const std::string_view token = m_text.next();
      if (token.empty())
        m_text.fail("the file ends after " + std::to_string(i) + " of the " + std::to_string(count) + " values of " +
                    what + " (truncated)");
      std::optional<Out> value;
      if constexpr (std::is_same_v<Out, double>)
        value = parseReal(token);
      else
        value = isInteger(type) ? parseInteger(token) : std::nullopt;
      if (!value)
        m_text.fail(what + ": value " + std::to_string(i) + " is " + quoteForMessage(token) + ", expected a number");
      out.push_back(*value);
    }
    return out;
  }

  void readPoints() {
    if (m_havePoints) m_text.fail("a second POINTS section (expected one)");
    m_havePoints = true;
    const int64_t count = integer("the number of POINTS");
    if (count < 0 || count > kMaxNodes)
      m_text.fail("POINTS " + std::to_string(count) + ", expected 0 to " + std::to_string(kMaxNodes));
    const size_t line = m_text.line();
    const NumberType type = numberType(m_text.next(), false, "POINTS");
    endKeywordLine();
    const std::vector<double> xyz = values<double>(3 * count, type, "POINTS");
    m_mesh.nodes.reserve(size_t(count));
    for (int64_t i = 0; i < count; ++i) {
      const Vec3 position(xyz[size_t(3 * i)], xyz[size_t(3 * i + 1)], xyz[size_t(3 * i + 2)]);
      if (!position.allFinite())
        throw TetMeshReadError(m_text.file(), line,
                               "point " + std::to_string(i) + " has a non-finite coordinate (" +
                                   std::to_string(position.x()) + ", " + std::to_string(position.y()) + ", " +
                                   std::to_string(position.z()) + "), expected finite numbers of mm");
      m_mesh.nodes.push_back(position);
    }
  }

  void readCells() {
    if (m_haveCells) m_text.fail("a second CELLS section (expected one)");
    m_haveCells = true;
    m_cells.line = m_text.line();
    const int64_t first = integer("the number of CELLS");
    const int64_t second = integer("the size of CELLS");
    endKeywordLine();
    if (equalsIgnoreCase(m_text.peek(), "OFFSETS")) {
      // Version 5.1: CELLS <offsets> <connectivity>, then OFFSETS <type> and CONNECTIVITY <type> arrays.
      m_text.next();
      const NumberType offsetType = numberType(m_text.next(), true, "OFFSETS");
      endKeywordLine();
      m_cells.offsets = values<int64_t>(first, offsetType, "OFFSETS");
      if (!equalsIgnoreCase(m_text.next(), "CONNECTIVITY")) m_text.fail("expected CONNECTIVITY after the OFFSETS");
      const NumberType connectivityType = numberType(m_text.next(), true, "CONNECTIVITY");
      endKeywordLine();
      m_cells.connectivity = values<int64_t>(second, connectivityType, "CONNECTIVITY");
      if (m_cells.offsets.empty()) m_cells.offsets.push_back(0);
      checkOffsets();
      return;
    }
    // Classic layout: for each cell its point count, then the points.
    if (first < 0 || first > kMaxRecords || second < first)
      m_text.fail("CELLS " + std::to_string(first) + " " + std::to_string(second) +
                  ", expected a cell count and a size of at least that count");
    const std::vector<int64_t> data = values<int64_t>(second, NumberType::kInt32, "CELLS");
    m_cells.offsets.reserve(size_t(first) + 1);
    m_cells.connectivity.reserve(size_t(second - first));
    size_t position = 0;
    for (int64_t cell = 0; cell < first; ++cell) {
      if (position >= data.size())
        throw TetMeshReadError(m_text.file(), m_cells.line,
                               "CELLS: the data ends at cell " + std::to_string(cell) + " of " + std::to_string(first) +
                                   " (the size " + std::to_string(second) + " is too small)");
      const int64_t points = data[position++];
      if (points < 0 || uint64_t(points) > data.size() - position)
        throw TetMeshReadError(m_text.file(), m_cells.line,
                               "CELLS: cell " + std::to_string(cell) + " has " + std::to_string(points) +
                                   " points, more than the remaining data holds");
      m_cells.connectivity.insert(m_cells.connectivity.end(), data.begin() + ptrdiff_t(position),
                                  data.begin() + ptrdiff_t(position) + ptrdiff_t(points));
      position += size_t(points);
      m_cells.offsets.push_back(int64_t(m_cells.connectivity.size()));
    }
    if (position != data.size())
      throw TetMeshReadError(m_text.file(), m_cells.line,
                             "CELLS: the size " + std::to_string(second) + " does not match the " +
                                 std::to_string(position) + " values the cells use");
  }

  void checkOffsets() const {
    const auto size = int64_t(m_cells.connectivity.size());
    for (size_t i = 0; i < m_cells.offsets.size(); ++i) {
      const int64_t offset = m_cells.offsets[i];
      const int64_t previous = i == 0 ? 0 : m_cells.offsets[i - 1];
      if (offset < previous || offset > size || (i == 0 && offset != 0))
        throw TetMeshReadError(m_text.file(), m_cells.line,
                               "OFFSETS: offset " + std::to_string(i) + " is " + std::to_string(offset) +
                                   ", expected " + std::to_string(previous) + " to " + std::to_string(size) +
                                   " (offsets start at 0 and do not decrease)");
    }
    if (m_cells.offsets.back() != size)
      throw TetMeshReadError(m_text.file(), m_cells.line,
                             "OFFSETS: the last offset is " + std::to_string(m_cells.offsets.back()) + ", expected " +
                                 std::to_string(size) + " (the connectivity size)");
  }

  void readCellTypes() {
    if (m_haveTypes) m_text.fail("a second CELL_TYPES section (expected one)");
    if (!m_haveCells) m_text.fail("CELL_TYPES before CELLS (expected CELLS first)");
    m_haveTypes = true;
    const int64_t count = integer("the number of CELL_TYPES");
    if (count != m_cells.count())
      m_text.fail("CELL_TYPES " + std::to_string(count) + ", expected " + std::to_string(m_cells.count()) +
                  " (the number of CELLS)");
    endKeywordLine();
    m_types = values<int64_t>(count, NumberType::kInt32, "CELL_TYPES");
  }

  // The arrays of CELL_DATA or POINT_DATA. Returns false at data it does not
  // know how to skip (everything needed has been read by then).
  bool readAttributes(bool cellData) {
    const int64_t count = integer(cellData ? "the CELL_DATA count" : "the POINT_DATA count");
    if (cellData && m_haveCells && count != m_cells.count())
      m_text.fail("CELL_DATA " + std::to_string(count) + ", expected " + std::to_string(m_cells.count()) +
                  " (the number of CELLS)");
    if (count < 0 || count > kMaxRecords)
      m_text.fail("the attribute count " + std::to_string(count) + " is out of range");
    endKeywordLine();
    while (true) {
      const std::string_view keyword = m_text.peek();
      if (keyword.empty() || equalsIgnoreCase(keyword, "CELL_DATA") || equalsIgnoreCase(keyword, "POINT_DATA"))
        return true;
      m_text.next();
      if (equalsIgnoreCase(keyword, "SCALARS")) {
        readScalars(count, cellData);
      } else if (equalsIgnoreCase(keyword, "FIELD")) {
        readField(cellData ? count : -1);
      } else if (equalsIgnoreCase(keyword, "METADATA")) {
        skipMetadata();
      } else if (!skipAttribute(keyword, count)) {
        return false;
      }
    }
  }

  // SCALARS name type [components], then LOOKUP_TABLE table (required, as VTK's own reader requires it).
  void readScalars(int64_t count, bool cellData) {
    const std::string name(m_text.next());
    const NumberType type = numberType(m_text.next(), false, "SCALARS " + name);
    int64_t components = 1;
    std::string_view token = m_text.next();
    if (!equalsIgnoreCase(token, "LOOKUP_TABLE")) {
      components = parseInteger(token).value_or(0);
      if (components < 1 || components > 4)
        m_text.fail("SCALARS " + name + ": the number of components is " + quoteForMessage(token) +
                    ", expected 1 to 4");
      token = m_text.next();
    }
    if (!equalsIgnoreCase(token, "LOOKUP_TABLE"))
      m_text.fail("SCALARS " + name + ": expected LOOKUP_TABLE, found " + quoteForMessage(token));
    m_text.next();  // the table's name
    endKeywordLine();
    takeArray(name, type, count * components, cellData && components == 1);
  }

  // FIELD name n, then n arrays "name components tuples type" and their values.
  void readField(int64_t cellCount) {
    m_text.next();  // the field's name
    const int64_t arrays = integer("the number of FIELD arrays");
    if (arrays < 0 || arrays > 100000)
      m_text.fail("FIELD with " + std::to_string(arrays) + " arrays, expected 0 to 100000");
    endKeywordLine();
    for (int64_t a = 0; a < arrays; ++a) {
      if (equalsIgnoreCase(m_text.peek(), "METADATA")) {
        m_text.next();
        skipMetadata();
      }
      const std::string name(m_text.next());
      if (name.empty()) m_text.fail("the file ends inside FIELD (truncated)");
      const int64_t components = integer("FIELD array " + name + ": the number of components");
      const int64_t tuples = integer("FIELD array " + name + ": the number of tuples");
      const NumberType type = numberType(m_text.next(), false, "FIELD array " + name);
      if (components < 1 || tuples < 0 || components > 1024 || tuples > kMaxRecords)
        m_text.fail("FIELD array " + name + ": " + std::to_string(components) + " components of " +
                    std::to_string(tuples) + " tuples is out of range");
      endKeywordLine();
      takeArray(name, type, components * tuples, components == 1 && tuples == cellCount);
    }
  }

  // The values of an attribute array, kept as labels when `mayBeLabels` and its name and type say so.
  void takeArray(const std::string& name, NumberType type, int64_t count, bool mayBeLabels) {
    if (mayBeLabels && isInteger(type) && isLabelArrayName(name) && m_labels.empty()) {
      m_labelsLine = m_text.line();
      m_labels = values<int64_t>(count, type, name);
      return;
    }
    values<double>(count, type, name);
  }

  // Known attribute kinds, skipped by their size; false for unknown ones.
  bool skipAttribute(std::string_view keyword, int64_t count) {
    int64_t perTuple = 0;
    if (equalsIgnoreCase(keyword, "VECTORS") || equalsIgnoreCase(keyword, "NORMALS")) perTuple = 3;
    if (equalsIgnoreCase(keyword, "TENSORS")) perTuple = 9;
    if (equalsIgnoreCase(keyword, "TENSORS6")) perTuple = 6;
    if (equalsIgnoreCase(keyword, "GLOBAL_IDS") || equalsIgnoreCase(keyword, "PEDIGREE_IDS")) perTuple = 1;
    if (perTuple > 0) {
      const std::string name(m_text.next());
      const NumberType type = numberType(m_text.next(), false, std::string(keyword) + " " + name);
      endKeywordLine();
      values<double>(perTuple * count, type, name);
      return true;
    }
    if (equalsIgnoreCase(keyword, "TEXTURE_COORDINATES")) {
      const std::string name(m_text.next());
      const int64_t dimension = integer("TEXTURE_COORDINATES dimension");
      if (dimension < 1 || dimension > 3)
        m_text.fail("TEXTURE_COORDINATES dimension " + std::to_string(dimension) + ", expected 1 to 3");
      const NumberType type = numberType(m_text.next(), false, "TEXTURE_COORDINATES " + name);
      endKeywordLine();
      values<double>(dimension * count, type, name);
      return true;
    }
    if (equalsIgnoreCase(keyword, "COLOR_SCALARS") || equalsIgnoreCase(keyword, "LOOKUP_TABLE")) {
      const bool colors = equalsIgnoreCase(keyword, "COLOR_SCALARS");
      const std::string name(m_text.next());
      const int64_t size = integer(std::string(keyword) + " size");
      if (size < 1 || size > (colors ? 4 : kMaxRecords))
        m_text.fail(std::string(keyword) + " size " + std::to_string(size) + " is out of range");
      endKeywordLine();
      // ASCII: reals in [0, 1]; binary: unsigned bytes.
      values<double>((colors ? count : 4) * size, m_binary ? NumberType::kUInt8 : NumberType::kFloat32, name);
      return true;
    }
    return false;
  }

  // METADATA blocks (version 5) run up to an empty line.
  void skipMetadata() {
    m_text.restOfLine();
    while (m_text.bytesLeft() > 0) {
      const std::string_view line = m_text.restOfLine();
      if (line.find_first_not_of(" \t\r") == std::string_view::npos) return;
    }
  }

  TetMesh assemble() {
    const auto pointCount = int64_t(m_mesh.nodes.size());
    const bool labelled = !m_labels.empty();
    for (int64_t cell = 0; cell < m_cells.count(); ++cell) {
      const int64_t type = m_types[size_t(cell)];
      const int64_t points = vtkTetraPointCount(type);
      if (points == 0) continue;
      const int64_t start = m_cells.offsets[size_t(cell)];
      const int64_t end = m_cells.offsets[size_t(cell) + 1];
      if (end - start != points)
        throw TetMeshReadError(m_text.file(), m_cells.line,
                               "cell " + std::to_string(cell) + " has " + vtkTetraTypeName(type) + " but " +
                                   std::to_string(end - start) + " points, expected " + std::to_string(points));
      if (int64_t(m_mesh.tets.size()) >= kMaxTets)
        throw TetMeshReadError(m_text.file(), m_cells.line, "more than " + std::to_string(kMaxTets) + " tetrahedra");
      TetIndices tet;
      for (size_t k = 0; k < 4; ++k) {
        const int64_t point = m_cells.connectivity[size_t(start) + k];
        if (point < 0 || point >= pointCount)
          throw TetMeshReadError(m_text.file(), m_cells.line,
                                 "cell " + std::to_string(cell) + " refers to point " + std::to_string(point) +
                                     ", but the file has points " + indexRange(0, pointCount));
        tet[k] = static_cast<int32_t>(point);
      }
      m_mesh.tets.push_back(tet);
      if (labelled) {
        const std::optional<int32_t> label = labelFromInteger(m_labels[size_t(cell)]);
        if (!label)
          throw TetMeshReadError(m_text.file(), m_labelsLine,
                                 "cell " + std::to_string(cell) + " has label " +
                                     std::to_string(m_labels[size_t(cell)]) + ", expected a 32-bit integer");
        m_mesh.labels.push_back(*label);
      }
    }
    return std::move(m_mesh);
  }

  TextCursor m_text;
  bool m_binary = false;
  bool m_havePoints = false;
  bool m_haveCells = false;
  bool m_haveTypes = false;
  TetMesh m_mesh;
  Cells m_cells;
  std::vector<int64_t> m_types;
  std::vector<int64_t> m_labels;  // per cell, when a label array was found
  size_t m_labelsLine = 0;
};

}  // namespace

bool looksLikeVtkLegacy(std::string_view content) {
  const size_t start = content.find_first_not_of(" \t\r\n");
  return start != std::string_view::npos && startsWithIgnoreCase(content.substr(start), kMagic);
}

TetMesh readVtkLegacy(const std::filesystem::path& file, std::string_view content) {
  return VtkLegacyParser(file, content).read();
}

}  // namespace trephine::formats
