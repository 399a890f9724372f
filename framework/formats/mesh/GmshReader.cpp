#include "framework/formats/mesh/GmshReader.h"

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "framework/formats/mesh/GmshParser.h"
#include "framework/formats/mesh/ReadChecks.h"
#include "framework/formats/mesh/TetMeshReader.h"

namespace trephine::formats {

namespace {
// Shortest record lines ("1 0 0 0\n", "1 15 0 1\n"): bound a declared count by the bytes left.
constexpr uint64_t kMinNodeLineBytes = 8;
constexpr uint64_t kMinElementLineBytes = 8;
}  // namespace

TetMesh GmshParser::read() {
  while (m_text.nextLine(m_tokens)) {
    const std::string_view head = m_tokens[0];
    const bool blocks = m_version == Version::k40 || m_version == Version::k41;
    if (head == "$MeshFormat") {
      readMeshFormat();
    } else if (head == "$NOD" || head == "$Nodes") {
      if (blocks && head == "$Nodes") {
        readNodeBlocks();
      } else {
        readNodes(head == "$NOD");
      }
    } else if (head == "$ELM" || head == "$Elements") {
      if (blocks && head == "$Elements") {
        readElementBlocks();
      } else {
        readElements(head == "$ELM");
      }
    } else if (head == "$Entities" && blocks) {
      readEntities();
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
    throw TetMeshReadError(m_text.file(), "the file has no tetrahedra (element type 4 or 11); its elements are " +
                                              (types.empty() ? std::string("none") : types));
  }
  if (!m_anyTagged) m_mesh.labels.clear();
  return std::move(m_mesh);
}

void GmshParser::readMeshFormat() {
  if (m_haveFormat) m_text.fail("a second $MeshFormat section (expected one)");
  if (m_haveNodes || m_haveElements) m_text.fail("$MeshFormat comes after the nodes or elements (expected it first)");
  m_haveFormat = true;
  if (!m_text.nextLine(m_tokens)) m_text.fail("the file ends inside $MeshFormat (truncated)");
  const std::string_view versionText = m_tokens[0];
  const std::optional<double> version = parseReal(versionText);
  if (!version || !std::isfinite(*version))
    m_text.fail("the format version is " + quoteForMessage(versionText) + ", expected a number such as 4.1 or 2.2");
  if (versionText == "4.1") {
    m_version = Version::k41;
  } else if (versionText == "4" || versionText == "4.0") {
    m_version = Version::k40;
  } else if (*version >= 2 && *version < 3) {
    m_version = Version::k2;
  } else {
    m_text.fail("Gmsh format " + std::string(versionText) +
                " is not supported, expected 4.1, 4.0, 2.x or the legacy format (in Gmsh, export as "
                "\"Version 4 ASCII\" or \"Version 2 ASCII\")");
  }
  if (m_tokens.size() < 2 || m_tokens[1] != "0")
    m_text.fail(m_tokens.size() < 2 ? std::string("the file type is missing, expected 0 (ASCII)")
                                    : "the file type is " + quoteForMessage(m_tokens[1]) +
                                          ": binary Gmsh files are not supported, expected 0 (ASCII; in Gmsh, "
                                          "export as \"Version 4 ASCII\" or \"Version 2 ASCII\")");
  if (!m_text.nextLine(m_tokens) || m_tokens[0] != "$EndMeshFormat")
    m_text.fail("expected $EndMeshFormat after the format line");
}

int64_t GmshParser::sectionCount(const char* section, int64_t maxCount, uint64_t minBytesEach, const char* what) {
  if (!m_text.nextLine(m_tokens)) m_text.fail(std::string("the file ends after ") + section + " (truncated)");
  const std::optional<int64_t> count = parseInteger(m_tokens[0]);
  if (!count || m_tokens.size() != 1)
    m_text.fail(std::string("the number of ") + what + " is " + quoteForMessage(m_tokens[0]) +
                ", expected one whole number after " + section);
  m_text.checkCount(*count, maxCount, minBytesEach, what);
  return *count;
}

void GmshParser::recordLine(const char* section, int64_t i, int64_t count, const char* what) {
  if (!m_text.nextLine(m_tokens))
    m_text.fail("the file ends after " + std::to_string(i) + " of " + std::to_string(count) + " " + what +
                " (truncated)");
  if (m_tokens[0].starts_with("$"))
    m_text.fail(std::string(section) + " ends with " + quoteForMessage(m_tokens[0]) + " after " + std::to_string(i) +
                " of the " + std::to_string(count) + " " + what + " it declares");
}

void GmshParser::expectEnd(const char* end, int64_t count, const char* what) {
  if (!m_text.nextLine(m_tokens)) m_text.fail(std::string("the file ends before ") + end + " (truncated)");
  if (m_tokens[0] != end)
    m_text.fail("expected " + std::string(end) + " after " + std::to_string(count) + " " + what + ", found " +
                quoteForMessage(m_tokens[0]) + " (more records than declared?)");
}

int64_t GmshParser::integerToken(size_t index, const std::string& what) {
  if (index >= m_tokens.size()) m_text.fail(what + " is missing (the line is cut short)");
  const std::optional<int64_t> value = parseInteger(m_tokens[index]);
  if (!value) m_text.fail(what + " " + quoteForMessage(m_tokens[index]) + " is not a whole number");
  return *value;
}

Vec3 GmshParser::readCoordinates(size_t firstToken, int64_t nodeId, int64_t extraValues) {
  const size_t expected = firstToken + 3 + size_t(extraValues);
  if (m_tokens.size() != expected)
    m_text.fail(
        "node " + std::to_string(nodeId) + " has " + std::to_string(m_tokens.size() - firstToken) +
        " values, expected x y z" +
        (extraValues > 0 ? " and its " + std::to_string(extraValues) + " parametric coordinates" : std::string()));
  Vec3 position;
  const std::string owner = "node " + std::to_string(nodeId);
  for (int axis = 0; axis < 3; ++axis)
    position[axis] = m_text.coordinate(m_tokens[firstToken + size_t(axis)], axis, owner);
  return position;
}

void GmshParser::finishNodes(std::vector<int64_t>& ids, const char* section) {
  int64_t duplicate = 0;
  std::optional<NodeIdMap> map = NodeIdMap::build(ids, duplicate);
  if (!map) m_text.fail("node id " + std::to_string(duplicate) + " appears twice in " + section);
  m_ids = std::move(map);
}

void GmshParser::readNodes(bool legacy) {
  const char* section = legacy ? "$NOD" : "$Nodes";
  if (m_haveNodes) m_text.fail("a second node section (expected one)");
  m_haveNodes = true;
  const int64_t count = sectionCount(section, kMaxNodes, kMinNodeLineBytes, "nodes");
  std::vector<int64_t> ids;
  ids.reserve(size_t(count));
  m_mesh.nodes.reserve(size_t(count));
  for (int64_t i = 0; i < count; ++i) {
    recordLine(section, i, count, "nodes");
    const int64_t id = integerToken(0, "node id");
    m_mesh.nodes.push_back(readCoordinates(1, id, 0));
    ids.push_back(id);
  }
  expectEnd(legacy ? "$ENDNOD" : "$EndNodes", count, "nodes");
  finishNodes(ids, section);
}

void GmshParser::readElements(bool legacy) {
  const char* section = legacy ? "$ELM" : "$Elements";
  if (m_haveElements) m_text.fail(std::string("a second element section ") + section + " (expected one)");
  if (!m_haveNodes) m_text.fail(std::string(section) + " comes before the nodes (expected the node section first)");
  m_haveElements = true;
  const int64_t count = sectionCount(section, kMaxRecords, kMinElementLineBytes, "elements");
  for (int64_t i = 0; i < count; ++i) {
    recordLine(section, i, count, "elements");
    readElement(legacy);
  }
  expectEnd(legacy ? "$ENDELM" : "$EndElements", count, "elements");
}

// Legacy: "id type physical elementary n nodes..."; format 2: "id type ntags tags... nodes...".
void GmshParser::readElement(bool legacy) {
  const int64_t id = integerToken(0, "element id");
  const std::string name = "element " + std::to_string(id);
  if (m_tokens.size() < 3) m_text.fail(name + " has no type and tags, expected \"id type ...\"");
  const int64_t type = integerToken(1, name + ": type");
  const int64_t nodes = gmshTetrahedronNodes(type);
  if (nodes == 0) {
    ++m_skippedTypes[type];
    return;
  }
  size_t firstNode = 0;
  std::optional<int64_t> label;
  if (legacy) {
    if (m_tokens.size() < 5) m_text.fail(name + " is cut short, expected \"id type physical elementary n nodes...\"");
    const std::optional<int64_t> nodeCount = parseInteger(m_tokens[4]);
    if (!nodeCount || *nodeCount != nodes)
      m_text.fail(name + " has " + (nodeCount ? std::to_string(*nodeCount) : quoteForMessage(m_tokens[4])) +
                  " nodes, expected a tetrahedron (type " + std::to_string(type) + ", " + std::to_string(nodes) +
                  " nodes)");
    if (m_tokens.size() != 5 + size_t(nodes))
      m_text.fail(name + " lists " + std::to_string(m_tokens.size() - 5) + " node ids after its node count " +
                  std::to_string(nodes) + ", expected " + std::to_string(nodes));
    label = integerToken(2, name + ": physical tag");
    firstNode = 5;
  } else {
    const std::optional<int64_t> tagCount = parseInteger(m_tokens[2]);
    if (!tagCount || *tagCount < 0 || uint64_t(*tagCount) > m_tokens.size() - 3)
      m_text.fail(name + ": tag count " + quoteForMessage(m_tokens[2]) + " does not fit the line, expected 0 to " +
                  std::to_string(m_tokens.size() - 3));
    firstNode = 3 + size_t(*tagCount);
    if (*tagCount > 0) label = integerToken(3, name + ": physical tag");
  }
  addTet(name, type, firstNode, label);
}

void GmshParser::addTet(const std::string& name, int64_t type, size_t firstNode, std::optional<int64_t> label) {
  const int64_t nodes = gmshTetrahedronNodes(type);
  if (m_tokens.size() - firstNode != size_t(nodes))
    m_text.fail(name + " has " + std::to_string(m_tokens.size() - firstNode) + " nodes, expected a tetrahedron (type " +
                std::to_string(type) + ", " + std::to_string(nodes) + " nodes)");
  if (m_mesh.tets.size() >= size_t(kMaxTets))
    m_text.fail("more than " + std::to_string(kMaxTets) + " tetrahedra, more than supported");
  TetIndices tet;
  for (size_t k = 0; k < 4; ++k) {
    const int64_t nodeId = integerToken(firstNode + k, name + ": node id");
    tet[k] = m_ids->find(nodeId);
    if (tet[k] < 0)
      m_text.fail(name + " refers to node " + std::to_string(nodeId) + ", which is not in the node section");
  }
  const std::optional<int32_t> checkedLabel = label ? labelFromInteger(*label) : std::optional<int32_t>(0);
  if (!checkedLabel) m_text.fail(name + ": physical tag " + std::to_string(*label) + " does not fit 32 bits");
  m_anyTagged = m_anyTagged || label.has_value();
  m_mesh.tets.push_back(tet);
  m_mesh.labels.push_back(*checkedLabel);
}

// $PhysicalNames, $Periodic, $NodeData, ...: skipped up to their end line.
void GmshParser::skipSection(std::string_view head) {
  const std::string name(head.substr(1));
  const size_t start = m_text.line();
  while (m_text.nextLine(m_tokens)) {
    if (equalsIgnoreCase(m_tokens[0], "$End" + name)) return;
  }
  throw TetMeshReadError(m_text.file(), start,
                         "the section " + quoteForMessage(head) + " has no $End" + name + " line (truncated file?)");
}

TetMesh readGmsh(const std::filesystem::path& file, std::string_view content) {
  return GmshParser(file, content).read();
}

}  // namespace trephine::formats
