#include "plugins/tetra_brain/io/GmshReader.h"

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "plugins/tetra_brain/io/NodeIdMap.h"
#include "plugins/tetra_brain/io/ReadChecks.h"
#include "plugins/tetra_brain/io/TetMeshReader.h"
#include "plugins/tetra_brain/io/TextCursor.h"

namespace trephine::tetra {

namespace {

constexpr int64_t kTetrahedron = 4;  // Gmsh element type of the 4-node tetrahedron
// Shortest record lines ("1 0 0 0\n", "1 15 0 1\n"): bound a declared count by the bytes left.
constexpr uint64_t kMinNodeLineBytes = 8;
constexpr uint64_t kMinElementLineBytes = 8;

class GmshParser {
 public:
  GmshParser(const std::filesystem::path& file, std::string_view content) : m_text(content, file) {}

  TetMesh read() {
    while (m_text.nextLine(m_tokens)) {
      const std::string_view head = m_tokens[0];
      if (head == "$MeshFormat") {
        readMeshFormat();
      } else if (head == "$NOD" || head == "$Nodes") {
        m_legacy = head == "$NOD";
        readNodes(m_legacy ? "$ENDNOD" : "$EndNodes");
      } else if (head == "$ELM" || head == "$Elements") {
        readElements(head == "$ELM", head == "$ELM" ? "$ENDELM" : "$EndElements");
      } else if (head.size() > 1 && head[0] == '$') {
        skipSection(head);
      } else {
        m_text.fail("unexpected " + quoteForMessage(head) +
                    " outside a section, expected a $Section line ($Nodes, $Elements, ...)");
      }
    }
    if (!m_haveNodes) throw TetMeshReadError(m_text.file(), "the file has no $Nodes (or $NOD) section");
    if (!m_haveElements) throw TetMeshReadError(m_text.file(), "the file has no $Elements (or $ELM) section");
    if (m_mesh.tets.empty()) {
      std::string types;
      size_t listed = 0;
      for (const auto& [type, count] : m_skippedTypes) {
        if (++listed > 8) {
          types += ", ...";
          break;
        }
        types += (types.empty() ? "" : ", ") + std::to_string(count) + " of type " + std::to_string(type);
      }
      throw TetMeshReadError(m_text.file(), "the file has no tetrahedra (element type 4); its elements are " +
                                                (types.empty() ? std::string("none") : types));
    }
    if (!m_anyTagged) m_mesh.labels.clear();
    return std::move(m_mesh);
  }

 private:
  void readMeshFormat() {
    if (!m_text.nextLine(m_tokens)) m_text.fail("the file ends inside $MeshFormat (truncated)");
    const std::optional<double> version = parseReal(m_tokens[0]);
    if (!version || !std::isfinite(*version))
      m_text.fail("the format version is " + quoteForMessage(m_tokens[0]) + ", expected a number such as 2.2");
    if (*version >= 3)
      m_text.fail("Gmsh format " + std::string(m_tokens[0]) +
                  " is not supported, expected 2.x ASCII or the legacy format (in Gmsh, export as "
                  "\"Version 2 ASCII\")");
    if (*version < 2) m_text.fail("Gmsh format " + std::string(m_tokens[0]) + " in $MeshFormat, expected 2.x");
    if (m_tokens.size() < 2 || m_tokens[1] != "0")
      m_text.fail(m_tokens.size() < 2 ? std::string("the file type is missing, expected 0 (ASCII)")
                                      : "the file type is " + quoteForMessage(m_tokens[1]) +
                                            ": binary Gmsh files are not supported, expected 0 (ASCII; in Gmsh, "
                                            "export as \"Version 2 ASCII\")");
    if (!m_text.nextLine(m_tokens) || m_tokens[0] != "$EndMeshFormat")
      m_text.fail("expected $EndMeshFormat after the format line");
  }

  // The declared number of records on the line after a section header.
  int64_t sectionCount(const char* section, int64_t maxCount, uint64_t minBytesEach, const char* what) {
    if (!m_text.nextLine(m_tokens)) m_text.fail(std::string("the file ends after ") + section + " (truncated)");
    const std::optional<int64_t> count = parseInteger(m_tokens[0]);
    if (!count || m_tokens.size() != 1)
      m_text.fail(std::string("the number of ") + what + " is " + quoteForMessage(m_tokens[0]) +
                  ", expected one whole number after " + section);
    m_text.checkCount(*count, maxCount, minBytesEach, what);
    return *count;
  }

  // The next record line of a section, which must not be its end yet.
  void recordLine(const char* section, int64_t i, int64_t count, const char* what) {
    if (!m_text.nextLine(m_tokens))
      m_text.fail("the file ends after " + std::to_string(i) + " of " + std::to_string(count) + " " + what +
                  " (truncated)");
    if (m_tokens[0].starts_with("$"))
      m_text.fail(std::string(section) + " ends with " + quoteForMessage(m_tokens[0]) + " after " + std::to_string(i) +
                  " of the " + std::to_string(count) + " " + what + " it declares");
  }

  void expectEnd(const char* end, int64_t count, const char* what) {
    if (!m_text.nextLine(m_tokens)) m_text.fail(std::string("the file ends before ") + end + " (truncated)");
    if (m_tokens[0] != end)
      m_text.fail("expected " + std::string(end) + " after " + std::to_string(count) + " " + what + ", found " +
                  quoteForMessage(m_tokens[0]) + " (more records than declared?)");
  }

  void readNodes(const char* end) {
    if (m_haveNodes) m_text.fail("a second node section (expected one)");
    m_haveNodes = true;
    const char* section = m_legacy ? "$NOD" : "$Nodes";
    const int64_t count = sectionCount(section, kMaxNodes, kMinNodeLineBytes, "nodes");
    std::vector<int64_t> ids;
    ids.reserve(size_t(count));
    m_mesh.nodes.reserve(size_t(count));
    for (int64_t i = 0; i < count; ++i) {
      recordLine(section, i, count, "nodes");
      const std::optional<int64_t> id = parseInteger(m_tokens[0]);
      if (!id) m_text.fail("node id " + quoteForMessage(m_tokens[0]) + " is not a whole number");
      if (m_tokens.size() != 4)
        m_text.fail("node " + std::to_string(*id) + " has " + std::to_string(m_tokens.size() - 1) +
                    " values after its id, expected x y z");
      Vec3 position;
      for (int axis = 0; axis < 3; ++axis) {
        const std::string_view token = m_tokens[size_t(axis) + 1];
        const std::optional<double> value = parseReal(token);
        if (!value)
          m_text.fail("node " + std::to_string(*id) + ": " + "xyz"[axis] + " coordinate " + quoteForMessage(token) +
                      " is not a number");
        if (!std::isfinite(*value))
          m_text.fail("node " + std::to_string(*id) + " has a non-finite " + "xyz"[axis] + " coordinate " +
                      quoteForMessage(token) + " (expected a finite number of mm)");
        position[axis] = *value;
      }
      ids.push_back(*id);
      m_mesh.nodes.push_back(position);
    }
    expectEnd(end, count, "nodes");
    int64_t duplicate = 0;
    std::optional<NodeIdMap> map = NodeIdMap::build(ids, duplicate);
    if (!map) m_text.fail("node id " + std::to_string(duplicate) + " appears twice in " + section);
    m_ids = std::move(map);
  }

  void readElements(bool legacy, const char* end) {
    const char* section = legacy ? "$ELM" : "$Elements";
    if (m_haveElements) m_text.fail(std::string("a second element section ") + section + " (expected one)");
    if (!m_haveNodes) m_text.fail(std::string(section) + " comes before the nodes (expected the node section first)");
    m_haveElements = true;
    const int64_t count = sectionCount(section, kMaxRecords, kMinElementLineBytes, "elements");
    for (int64_t i = 0; i < count; ++i) {
      recordLine(section, i, count, "elements");
      readElement(legacy);
    }
    expectEnd(end, count, "elements");
  }

  // Legacy: "id type physical elementary n nodes..."; format 2: "id type ntags tags... nodes...".
  void readElement(bool legacy) {
    const std::optional<int64_t> id = parseInteger(m_tokens[0]);
    if (!id) m_text.fail("element id " + quoteForMessage(m_tokens[0]) + " is not a whole number");
    const std::string name = "element " + std::to_string(*id);
    if (m_tokens.size() < 3) m_text.fail(name + " has no type and tags, expected \"id type ...\"");
    const std::optional<int64_t> type = parseInteger(m_tokens[1]);
    if (!type) m_text.fail(name + ": type " + quoteForMessage(m_tokens[1]) + " is not a whole number");
    if (*type != kTetrahedron) {
      ++m_skippedTypes[*type];
      return;
    }
    size_t firstNode = 0;
    std::optional<int64_t> label;
    if (legacy) {
      if (m_tokens.size() < 5) m_text.fail(name + " is cut short, expected \"id type physical elementary n nodes...\"");
      const std::optional<int64_t> nodeCount = parseInteger(m_tokens[4]);
      if (!nodeCount || *nodeCount != 4)
        m_text.fail(name + " has " + (nodeCount ? std::to_string(*nodeCount) : quoteForMessage(m_tokens[4])) +
                    " nodes, expected a tetrahedron (type 4, 4 nodes)");
      if (m_tokens.size() != 9)
        m_text.fail(name + " lists " + std::to_string(m_tokens.size() - 5) +
                    " node ids after its node count 4, expected 4");
      label = parseInteger(m_tokens[2]);
      if (!label) m_text.fail(name + ": physical tag " + quoteForMessage(m_tokens[2]) + " is not a whole number");
      firstNode = 5;
    } else {
      const std::optional<int64_t> tagCount = parseInteger(m_tokens[2]);
      if (!tagCount || *tagCount < 0 || uint64_t(*tagCount) > m_tokens.size() - 3)
        m_text.fail(name + ": tag count " + quoteForMessage(m_tokens[2]) + " does not fit the line, expected 0 to " +
                    std::to_string(m_tokens.size() - 3));
      firstNode = 3 + size_t(*tagCount);
      if (m_tokens.size() - firstNode != 4)
        m_text.fail(name + " has " + std::to_string(m_tokens.size() - firstNode) +
                    " nodes, expected a tetrahedron (type 4, 4 nodes)");
      if (*tagCount > 0) {
        label = parseInteger(m_tokens[3]);
        if (!label) m_text.fail(name + ": physical tag " + quoteForMessage(m_tokens[3]) + " is not a whole number");
      }
    }
    if (m_mesh.tets.size() >= size_t(kMaxTets))
      m_text.fail("more than " + std::to_string(kMaxTets) + " tetrahedra, more than supported");
    TetIndices tet;
    for (size_t k = 0; k < 4; ++k) {
      const std::string_view token = m_tokens[firstNode + k];
      const std::optional<int64_t> nodeId = parseInteger(token);
      if (!nodeId) m_text.fail(name + ": node id " + quoteForMessage(token) + " is not a whole number");
      tet[k] = m_ids->find(*nodeId);
      if (tet[k] < 0)
        m_text.fail(name + " refers to node " + std::to_string(*nodeId) + ", which is not in the node section");
    }
    const std::optional<int32_t> checkedLabel = label ? labelFromInteger(*label) : std::optional<int32_t>(0);
    if (!checkedLabel) m_text.fail(name + ": physical tag " + std::to_string(*label) + " does not fit 32 bits");
    m_anyTagged = m_anyTagged || label.has_value();
    m_mesh.tets.push_back(tet);
    m_mesh.labels.push_back(*checkedLabel);
  }

  // $PhysicalNames, $Periodic, $NodeData, ...: skipped up to their end line.
  void skipSection(std::string_view head) {
    const std::string name(head.substr(1));
    const size_t start = m_text.line();
    while (m_text.nextLine(m_tokens)) {
      if (equalsIgnoreCase(m_tokens[0], "$End" + name)) return;
    }
    throw TetMeshReadError(m_text.file(), start,
                           "the section " + quoteForMessage(head) + " has no $End" + name + " line (truncated file?)");
  }

  TextCursor m_text;
  std::vector<std::string_view> m_tokens;
  TetMesh m_mesh;
  std::optional<NodeIdMap> m_ids;
  std::map<int64_t, int64_t> m_skippedTypes;  // element type -> how many were skipped
  bool m_legacy = false;
  bool m_haveNodes = false;
  bool m_haveElements = false;
  bool m_anyTagged = false;
};

}  // namespace

TetMesh readGmsh(const std::filesystem::path& file, std::string_view content) {
  return GmshParser(file, content).read();
}

}  // namespace trephine::tetra
