#pragma once
// The Gmsh reader's parser (internal to readGmsh): the sections common to
// every format version are read in GmshReader.cpp, the node and element
// sections of the legacy format and format 2 there too, and those of format 4
// (entity blocks, and $Entities for the physical tags) in GmshBlocks.cpp.
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "framework/data/TetMesh.h"
#include "framework/formats/mesh/NodeIdMap.h"
#include "framework/formats/mesh/TextCursor.h"

namespace trephine::formats {

// Gmsh element types of tetrahedra: 4 nodes, and 10 (the corners first, then
// the edge midpoints; only the corners are kept).
inline constexpr int64_t kGmshTetrahedron = 4;
inline constexpr int64_t kGmshQuadraticTetrahedron = 11;
// Nodes an element of `type` lists when it is a tetrahedron (4 or 10), else 0.
inline int64_t gmshTetrahedronNodes(int64_t type) {
  return type == kGmshTetrahedron ? 4 : type == kGmshQuadraticTetrahedron ? 10 : 0;
}

class GmshParser {
 public:
  GmshParser(const std::filesystem::path& file, std::string_view content) : m_text(content, file) {}
  TetMesh read();

 private:
  enum class Version { kLegacy, k2, k40, k41 };

  void readMeshFormat();
  void readNodes(bool legacy);
  void readElements(bool legacy);
  void readElement(bool legacy);
  void skipSection(std::string_view head);
  void finishNodes(std::vector<int64_t>& ids, const char* section);

  // Format 4 (GmshBlocks.cpp).
  void readEntities();
  void readNodeBlocks();
  void readElementBlocks();
  Vec3 readCoordinates(size_t firstToken, int64_t nodeId, int64_t extraValues);
  // The line after $Nodes or $Elements: the numbers of entity blocks and of
  // `what` (4.1 adds the smallest and largest tag: `countFields41`).
  std::pair<int64_t, int64_t> blockSectionHeader(const char* section, const char* countFields41, const char* what,
                                                 int64_t maxCount, uint64_t minBytesEach);
  // The header line of entity block `block`: four values, the last two `lastFields`.
  void blockLine(const char* section, int64_t block, int64_t blocks, const char* lastFields);

  // Shared record handling.
  int64_t sectionCount(const char* section, int64_t maxCount, uint64_t minBytesEach, const char* what);
  void recordLine(const char* section, int64_t i, int64_t count, const char* what);
  void expectEnd(const char* end, int64_t count, const char* what);
  int64_t integerToken(size_t index, const std::string& what);
  // The tetrahedron of element `name` of `type` whose node ids start at token `firstNode`.
  void addTet(const std::string& name, int64_t type, size_t firstNode, std::optional<int64_t> label);

  TextCursor m_text;
  std::vector<std::string_view> m_tokens;
  TetMesh m_mesh;
  std::optional<NodeIdMap> m_ids;
  std::map<int64_t, int64_t> m_skippedTypes;  // element type -> how many were skipped
  Version m_version = Version::kLegacy;
  bool m_haveFormat = false;
  bool m_haveNodes = false;
  bool m_haveElements = false;
  bool m_anyTagged = false;
  // Format 4: volume entity tag -> its first physical tag ($Entities).
  std::unordered_map<int64_t, int64_t> m_volumePhysical;
};

}  // namespace trephine::formats
