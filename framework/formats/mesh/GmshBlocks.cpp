// Gmsh format 4 (4.1, the default since Gmsh 4.1, and 4.0): nodes and
// elements come in blocks, one per geometric entity, and an element's
// physical tag is that of its entity, listed in $Entities.
//
//   4.1 $Nodes:     numBlocks numNodes minTag maxTag
//                   per block "entityDim entityTag parametric n", then n tag
//                   lines, then n lines "x y z [u [v [w]]]"
//   4.0 $Nodes:     numBlocks numNodes
//                   per block "entityTag entityDim parametric n", then n lines "tag x y z [u [v [w]]]"
//   $Elements:      the same headers (4.0 with entityTag before entityDim);
//                   per block "... elementType n", then n lines "tag node..."
//   $Entities:      numPoints numCurves numSurfaces numVolumes, one line each;
//                   a volume's is "tag minX minY minZ maxX maxY maxZ
//                   numPhysicalTags physicalTag... numSurfaces surfaceTag..."
#include <string>
#include <vector>

#include "framework/formats/mesh/GmshParser.h"
#include "framework/formats/mesh/ReadChecks.h"

namespace trephine::formats {

namespace {
// Shortest lines: an entity or block line ("1 0 0 0\n"), a node's two lines
// in 4.1 ("1\n0 0 0\n"), an element of one node ("1 1\n").
constexpr uint64_t kMinEntityLineBytes = 8;
constexpr uint64_t kMinNodeBytes = 8;
constexpr uint64_t kMinElementBytes = 4;
// Values on a volume entity line before its physical tags: tag and box.
constexpr size_t kVolumeBoxTokens = 7;
}  // namespace

void GmshParser::readEntities() {
  if (!m_text.nextLine(m_tokens)) m_text.fail("the file ends after $Entities (truncated)");
  if (m_tokens.size() != 4)
    m_text.fail("expected the numbers of points, curves, surfaces and volumes after $Entities, found " +
                std::to_string(m_tokens.size()) + " values");
  int64_t counts[4];
  static const char* const kKinds[4] = {"points", "curves", "surfaces", "volumes"};
  for (size_t k = 0; k < 4; ++k) {
    counts[k] = integerToken(k, std::string("the number of ") + kKinds[k]);
    m_text.checkCount(counts[k], kMaxRecords, kMinEntityLineBytes, std::string("entity ") + kKinds[k]);
  }
  const int64_t total = counts[0] + counts[1] + counts[2] + counts[3];
  int64_t i = 0;
  for (; i < counts[0] + counts[1] + counts[2]; ++i) recordLine("$Entities", i, total, "entities");
  for (; i < total; ++i) {
    recordLine("$Entities", i, total, "entities");
    const int64_t tag = integerToken(0, "volume entity tag");
    const std::string name = "volume entity " + std::to_string(tag);
    const int64_t physicalCount = integerToken(kVolumeBoxTokens, name + ": the number of physical tags");
    if (physicalCount < 0 || uint64_t(physicalCount) > m_tokens.size() - kVolumeBoxTokens - 1)
      m_text.fail(name + ": " + std::to_string(physicalCount) + " physical tags do not fit the line");
    if (m_volumePhysical.contains(tag)) m_text.fail(name + " is listed twice in $Entities");
    if (physicalCount > 0) m_volumePhysical[tag] = integerToken(kVolumeBoxTokens + 1, name + ": physical tag");
  }
  expectEnd("$EndEntities", total, "entities");
}

std::pair<int64_t, int64_t> GmshParser::blockSectionHeader(const char* section, const char* countFields41,
                                                           const char* what, int64_t maxCount, uint64_t minBytesEach) {
  const bool v41 = m_version == Version::k41;
  if (!m_text.nextLine(m_tokens)) m_text.fail(std::string("the file ends after ") + section + " (truncated)");
  if (m_tokens.size() != (v41 ? 4u : 2u)) {
    const std::string fields41(countFields41);
    m_text.fail("expected \"numEntityBlocks " + (v41 ? fields41 : fields41.substr(0, fields41.find(' '))) +
                "\" after " + section + (v41 ? " (format 4.1)" : " (format 4.0)"));
  }
  const int64_t blocks = integerToken(0, "the number of entity blocks");
  m_text.checkCount(blocks, kMaxRecords, kMinEntityLineBytes, std::string(what) + " entity blocks");
  const int64_t count = integerToken(1, std::string("the number of ") + what);
  m_text.checkCount(count, maxCount, minBytesEach, what);
  return {blocks, count};
}

void GmshParser::blockLine(const char* section, int64_t block, int64_t blocks, const char* lastFields) {
  recordLine(section, block, blocks, "entity blocks");
  if (m_tokens.size() != 4)
    m_text.fail(std::string("expected a block line \"") +
                (m_version == Version::k41 ? "entityDim entityTag " : "entityTag entityDim ") + lastFields + "\"");
}

void GmshParser::readNodeBlocks() {
  const bool v41 = m_version == Version::k41;
  if (m_haveNodes) m_text.fail("a second node section (expected one)");
  m_haveNodes = true;
  const auto [blocks, count] =
      blockSectionHeader("$Nodes", "numNodes minNodeTag maxNodeTag", "nodes", kMaxNodes, kMinNodeBytes);
  std::vector<int64_t> ids;
  ids.reserve(size_t(count));
  m_mesh.nodes.reserve(size_t(count));
  for (int64_t b = 0; b < blocks; ++b) {
    blockLine("$Nodes", b, blocks, "parametric numNodesInBlock");
    const int64_t dimension = integerToken(v41 ? 0 : 1, "entity dimension");
    if (dimension < 0 || dimension > 3)
      m_text.fail("entity dimension " + std::to_string(dimension) + ", expected 0 to 3");
    const int64_t parametric = integerToken(2, "parametric flag");
    if (parametric != 0 && parametric != 1)
      m_text.fail("parametric flag " + std::to_string(parametric) + ", expected 0 or 1");
    const int64_t inBlock = integerToken(3, "number of nodes in the block");
    const int64_t left = count - int64_t(ids.size());
    if (inBlock < 0 || inBlock > left)
      m_text.fail("the block holds " + std::to_string(inBlock) + " nodes, expected 0 to the " + std::to_string(left) +
                  " left of the " + std::to_string(count) + " $Nodes declares");
    const int64_t extra = parametric ? dimension : 0;  // u, v, w on curves, surfaces, volumes
    const size_t first = ids.size();
    for (int64_t i = 0; i < inBlock; ++i) {
      recordLine("$Nodes", int64_t(ids.size()), count, "nodes");
      if (v41) {
        if (m_tokens.size() != 1)
          m_text.fail("expected one node tag on the line, found " + std::to_string(m_tokens.size()) +
                      " values (format 4.1 lists a block's tags, then its coordinates)");
        ids.push_back(integerToken(0, "node tag"));
      } else {
        ids.push_back(integerToken(0, "node tag"));
        m_mesh.nodes.push_back(readCoordinates(1, ids.back(), extra));
      }
    }
    if (v41) {
      for (int64_t i = 0; i < inBlock; ++i) {
        recordLine("$Nodes", int64_t(first) + i, count, "node coordinates");
        m_mesh.nodes.push_back(readCoordinates(0, ids[first + size_t(i)], extra));
      }
    }
  }
  if (int64_t(ids.size()) != count)
    m_text.fail("the blocks hold " + std::to_string(ids.size()) + " nodes, but $Nodes declares " +
                std::to_string(count));
  expectEnd("$EndNodes", count, "nodes");
  finishNodes(ids, "$Nodes");
}

void GmshParser::readElementBlocks() {
  const bool v41 = m_version == Version::k41;
  if (m_haveElements) m_text.fail("a second element section $Elements (expected one)");
  if (!m_haveNodes) m_text.fail("$Elements comes before the nodes (expected the node section first)");
  m_haveElements = true;
  const auto [blocks, count] = blockSectionHeader("$Elements", "numElements minElementTag maxElementTag", "elements",
                                                  kMaxRecords, kMinElementBytes);
  int64_t read = 0;
  for (int64_t b = 0; b < blocks; ++b) {
    blockLine("$Elements", b, blocks, "elementType numElementsInBlock");
    const int64_t dimension = integerToken(v41 ? 0 : 1, "entity dimension");
    const int64_t entity = integerToken(v41 ? 1 : 0, "entity tag");
    const int64_t type = integerToken(2, "element type");
    const int64_t inBlock = integerToken(3, "number of elements in the block");
    if (inBlock < 0 || inBlock > count - read)
      m_text.fail("the block holds " + std::to_string(inBlock) + " elements, expected 0 to the " +
                  std::to_string(count - read) + " left of the " + std::to_string(count) + " $Elements declares");
    std::optional<int64_t> label;
    if (const auto found = m_volumePhysical.find(entity); dimension == 3 && found != m_volumePhysical.end())
      label = found->second;
    const bool tetrahedra = gmshTetrahedronNodes(type) > 0;
    if (!tetrahedra) m_skippedTypes[type] += inBlock;
    for (int64_t i = 0; i < inBlock; ++i, ++read) {
      recordLine("$Elements", read, count, "elements");
      if (!tetrahedra) continue;
      const int64_t id = integerToken(0, "element tag");
      addTet("element " + std::to_string(id), type, 1, label);
    }
  }
  if (read != count)
    m_text.fail("the blocks hold " + std::to_string(read) + " elements, but $Elements declares " +
                std::to_string(count));
  expectEnd("$EndElements", count, "elements");
}

}  // namespace trephine::formats
