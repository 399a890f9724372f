#include "framework/formats/mesh/MeditReader.h"

#include <cmath>
#include <optional>
#include <string>

#include "framework/formats/mesh/ReadChecks.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/formats/mesh/TextCursor.h"

namespace trephine::formats {

namespace {

// Shortest records ("0 0 0 0\n", "1 1 1 1 0\n"): bound a declared count by the bytes left.
constexpr uint64_t kMinVertexBytes = 8;
constexpr uint64_t kMinTetBytes = 10;

bool isKeyword(std::string_view token) {
  return !token.empty() && ((token[0] >= 'A' && token[0] <= 'Z') || (token[0] >= 'a' && token[0] <= 'z'));
}

class MeditParser {
 public:
  MeditParser(const std::filesystem::path& file, std::string_view content) : m_text(content, file, '#') {}

  TetMesh read() {
    while (true) {
      const std::string_view keyword = m_text.next();
      if (keyword.empty() || equalsIgnoreCase(keyword, "End")) break;
      if (equalsIgnoreCase(keyword, "MeshVersionFormatted")) {
        const int64_t version = integer("the MeshVersionFormatted version");
        if (version < 1 || version > 4)
          m_text.fail("MeshVersionFormatted " + std::to_string(version) + ", expected 1 to 4");
      } else if (equalsIgnoreCase(keyword, "Dimension")) {
        const int64_t dimension = integer("the Dimension");
        if (dimension != 3) m_text.fail("Dimension " + std::to_string(dimension) + ", expected 3 (a 3D mesh)");
      } else if (equalsIgnoreCase(keyword, "Vertices")) {
        readVertices();
      } else if (equalsIgnoreCase(keyword, "Tetrahedra")) {
        readTetrahedra();
      } else if (isKeyword(keyword)) {
        skipSection();
      } else {
        m_text.fail("unexpected " + quoteForMessage(keyword) + ", expected a keyword (Vertices, Tetrahedra, End, ...)");
      }
    }
    if (!m_haveVertices) throw TetMeshReadError(m_text.file(), "the file has no Vertices section (expected the nodes)");
    if (!m_haveTets)
      throw TetMeshReadError(m_text.file(), "the file has no Tetrahedra section (a surface mesh? expected tetrahedra)");
    if (m_tetsBeforeVertices) checkIndicesLate();
    return std::move(m_mesh);
  }

 private:
  int64_t integer(const std::string& what) { return m_text.nextInteger(what); }

  // The next token of record `ordinal` of a section; fails on a truncated file.
  std::string_view field(const char* section, int64_t ordinal, int64_t count) {
    const std::string_view token = m_text.next();
    if (token.empty())
      m_text.fail("the file ends inside " + std::string(section) + " at record " + std::to_string(ordinal) + " of " +
                  std::to_string(count) + " (truncated)");
    return token;
  }

  void readVertices() {
    if (m_haveVertices) m_text.fail("a second Vertices section (expected one)");
    m_haveVertices = true;
    const int64_t count = integer("the number of Vertices");
    m_text.checkCount(count, kMaxNodes, kMinVertexBytes, "vertices");
    m_mesh.nodes.reserve(size_t(count));
    for (int64_t i = 1; i <= count; ++i) {
      Vec3 position;
      for (int axis = 0; axis < 3; ++axis)
        position[axis] = m_text.coordinate(field("Vertices", i, count), axis, "vertex " + std::to_string(i));
      const std::string_view reference = field("Vertices", i, count);  // unused, but must be there
      if (!parseInteger(reference))
        m_text.fail("vertex " + std::to_string(i) + ": reference " + quoteForMessage(reference) +
                    " is not a whole number (expected x y z reference)");
      m_mesh.nodes.push_back(position);
    }
  }

  void readTetrahedra() {
    if (m_haveTets) m_text.fail("a second Tetrahedra section (expected one)");
    m_haveTets = true;
    m_tetsBeforeVertices = !m_haveVertices;
    const int64_t count = integer("the number of Tetrahedra");
    m_text.checkCount(count, kMaxTets, kMinTetBytes, "tetrahedra");
    const auto nodeCount = int64_t(m_mesh.nodes.size());
    m_mesh.tets.reserve(size_t(count));
    m_mesh.labels.reserve(size_t(count));
    for (int64_t i = 1; i <= count; ++i) {
      TetIndices tet;
      for (size_t k = 0; k < 4; ++k) {
        const std::string_view token = field("Tetrahedra", i, count);
        const std::optional<int64_t> index = parseInteger(token);
        if (!index)
          m_text.fail("tetrahedron " + std::to_string(i) + ": vertex index " + quoteForMessage(token) +
                      " is not a whole number");
        // Indices are checked here when the vertices are known, else after the file is read.
        if (*index < 1 || *index > (m_tetsBeforeVertices ? kMaxNodes : nodeCount))
          m_text.fail("tetrahedron " + std::to_string(i) + " refers to vertex " + std::to_string(*index) +
                      ", but the file has vertices " + indexRange(1, m_tetsBeforeVertices ? kMaxNodes : nodeCount));
        tet[k] = static_cast<int32_t>(*index - 1);
      }
      const std::string_view reference = field("Tetrahedra", i, count);
      const std::optional<int64_t> value = parseInteger(reference);
      const std::optional<int32_t> label = value ? labelFromInteger(*value) : std::nullopt;
      if (!label)
        m_text.fail("tetrahedron " + std::to_string(i) + " has reference " + quoteForMessage(reference) +
                    ", expected a whole-number label");
      m_mesh.tets.push_back(tet);
      m_mesh.labels.push_back(*label);
    }
  }

  void checkIndicesLate() const {
    const auto nodeCount = int64_t(m_mesh.nodes.size());
    for (size_t i = 0; i < m_mesh.tets.size(); ++i) {
      for (const int32_t index : m_mesh.tets[i]) {
        if (index >= nodeCount)
          throw TetMeshReadError(m_text.file(), "tetrahedron " + std::to_string(i + 1) + " refers to vertex " +
                                                    std::to_string(index + 1) + ", but the file has vertices " +
                                                    indexRange(1, nodeCount));
      }
    }
  }

  // A section this reader does not need: its numbers run up to the next keyword.
  void skipSection() {
    while (!m_text.atEnd() && !isKeyword(m_text.peek())) m_text.next();
  }

  TextCursor m_text;
  TetMesh m_mesh;
  bool m_haveVertices = false;
  bool m_haveTets = false;
  bool m_tetsBeforeVertices = false;
};

}  // namespace

bool looksLikeMedit(std::string_view content) {
  TextCursor text(content, {}, '#');
  return equalsIgnoreCase(text.next(), "MeshVersionFormatted");
}

TetMesh readMedit(const std::filesystem::path& file, std::string_view content) {
  return MeditParser(file, content).read();
}

}  // namespace trephine::formats
