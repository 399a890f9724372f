#include "framework/formats/mesh/TetGenReader.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "framework/formats/mesh/FileContent.h"
#include "framework/formats/mesh/ReadChecks.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/formats/mesh/TextCursor.h"

namespace trephine::formats {

namespace {

// Shortest possible record lines ("0 0 0 0\n", "0 0 0 0 0\n"): bounds a
// declared count by the bytes that follow it.
constexpr uint64_t kMinNodeLineBytes = 8;
constexpr uint64_t kMinEleLineBytes = 10;

// The optional header field `index` (TetGen fills in defaults for missing ones).
int64_t headerField(TextCursor& text, const std::vector<std::string_view>& header, size_t index, int64_t fallback,
                    const char* what) {
  if (index >= header.size()) return fallback;
  const std::optional<int64_t> value = parseInteger(header[index]);
  if (!value || *value < 0)
    text.fail(std::string("the header's ") + what + " is " + quoteForMessage(header[index]) +
              ", expected a whole number of 0 or more");
  return *value;
}

struct TetGenNodes {
  std::vector<Vec3> positions;
  int64_t firstIndex = 0;  // 0 or 1
};

TetGenNodes readNodes(TextCursor& text) {
  std::vector<std::string_view> tokens;
  if (!text.nextLine(tokens))
    text.fail("the node file has no header line (expected \"<nodes> 3 <attributes> <markers>\")");
  const int64_t count = headerField(text, tokens, 0, 0, "node count");
  const int64_t dimension = headerField(text, tokens, 1, 3, "dimension");
  if (dimension != 3) text.fail("the dimension is " + std::to_string(dimension) + ", expected 3 (a 3D mesh)");
  if (count == 0)
    text.fail(
        "the node file declares 0 nodes (TetGen then takes them from a .poly or .smesh file; expected the "
        "nodes here)");
  text.checkCount(count, kMaxNodes, kMinNodeLineBytes, "nodes");

  std::vector<int64_t> ids;
  std::vector<Vec3> read;
  ids.reserve(size_t(count));
  read.reserve(size_t(count));
  for (int64_t i = 0; i < count; ++i) {
    if (!text.nextLine(tokens))
      text.fail("the file ends after " + std::to_string(i) + " of " + std::to_string(count) + " nodes (truncated)");
    const std::optional<int64_t> id = parseInteger(tokens[0]);
    if (!id) text.fail("node index " + quoteForMessage(tokens[0]) + " is not a whole number");
    if (tokens.size() < 4)
      text.fail("node " + std::to_string(*id) + " has " + std::to_string(tokens.size() - 1) +
                " values after its index, expected x y z");
    Vec3 position;
    for (int axis = 0; axis < 3; ++axis)
      position[axis] = text.coordinate(tokens[size_t(axis) + 1], axis, "node " + std::to_string(*id));
    ids.push_back(*id);
    read.push_back(position);
  }

  // The numbering starts at the smallest index (TetGen's "firstnumber").
  TetGenNodes nodes;
  nodes.firstIndex = *std::min_element(ids.begin(), ids.end());
  if (nodes.firstIndex != 0 && nodes.firstIndex != 1)
    throw TetMeshReadError(text.file(), "the smallest node index is " + std::to_string(nodes.firstIndex) +
                                            ", expected 0 or 1 (TetGen numbers nodes from 0 or from 1)");
  bool inOrder = true;
  for (size_t i = 0; i < ids.size() && inOrder; ++i) inOrder = ids[i] == nodes.firstIndex + int64_t(i);
  if (inOrder) {
    nodes.positions = std::move(read);
    return nodes;
  }
  // Listed out of order: every index of first..first+count-1 exactly once.
  nodes.positions.assign(read.size(), Vec3::Zero());
  std::vector<bool> seen(read.size(), false);
  for (size_t i = 0; i < ids.size(); ++i) {
    const int64_t position = ids[i] - nodes.firstIndex;
    if (position >= count)
      throw TetMeshReadError(text.file(), "node index " + std::to_string(ids[i]) + " is outside " +
                                              indexRange(nodes.firstIndex, count) + " (the file has " +
                                              std::to_string(count) + " nodes)");
    if (seen[size_t(position)])
      throw TetMeshReadError(text.file(), "node " + std::to_string(ids[i]) + " is listed twice");
    seen[size_t(position)] = true;
    nodes.positions[size_t(position)] = read[i];
  }
  return nodes;
}

void readElements(TextCursor& text, const TetGenNodes& nodes, const std::filesystem::path& nodeFile, TetMesh& mesh) {
  std::vector<std::string_view> tokens;
  if (!text.nextLine(tokens))
    text.fail("the element file has no header line (expected \"<tetrahedra> 4 <attributes>\")");
  const int64_t count = headerField(text, tokens, 0, 0, "tetrahedron count");
  const int64_t corners = headerField(text, tokens, 1, 4, "nodes per tetrahedron");
  const int64_t attributes = headerField(text, tokens, 2, 0, "attribute count");
  if (corners != 4 && corners != 10)
    text.fail("the header gives " + std::to_string(corners) + " nodes per tetrahedron, expected 4 or 10");
  text.checkCount(count, kMaxTets, kMinEleLineBytes, "tetrahedra");
  const size_t needed = 1 + size_t(corners) + (attributes > 0 ? 1 : 0);
  const auto nodeCount = int64_t(nodes.positions.size());

  mesh.tets.reserve(size_t(count));
  if (attributes > 0) mesh.labels.reserve(size_t(count));
  for (int64_t i = 0; i < count; ++i) {
    if (!text.nextLine(tokens))
      text.fail("the file ends after " + std::to_string(i) + " of " + std::to_string(count) +
                " tetrahedra (truncated)");
    const std::optional<int64_t> id = parseInteger(tokens[0]);
    if (!id) text.fail("tetrahedron index " + quoteForMessage(tokens[0]) + " is not a whole number");
    if (tokens.size() < needed)
      text.fail("tetrahedron " + std::to_string(*id) + " has " + std::to_string(tokens.size() - 1) +
                " values after its index, expected " + std::to_string(needed - 1) + " (" + std::to_string(corners) +
                " node indices" + (attributes > 0 ? " and an attribute)" : ")"));
    TetIndices tet;
    for (size_t k = 0; k < 4; ++k) {
      const std::optional<int64_t> index = parseInteger(tokens[k + 1]);
      if (!index)
        text.fail("tetrahedron " + std::to_string(*id) + ": node index " + quoteForMessage(tokens[k + 1]) +
                  " is not a whole number");
      if (*index < nodes.firstIndex || *index - nodes.firstIndex >= nodeCount)
        text.fail("tetrahedron " + std::to_string(*id) + " refers to node " + std::to_string(*index) + ", but " +
                  nodeFile.filename().string() + " numbers its " + std::to_string(nodeCount) + " nodes " +
                  indexRange(nodes.firstIndex, nodeCount));
      tet[k] = static_cast<int32_t>(*index - nodes.firstIndex);
    }
    mesh.tets.push_back(tet);
    if (attributes > 0) {
      const std::string_view token = tokens[size_t(corners) + 1];
      const std::optional<double> value = parseReal(token);
      const std::optional<int32_t> label = value ? labelFromReal(*value) : std::nullopt;
      if (!label)
        text.fail("tetrahedron " + std::to_string(*id) + " has attribute " + quoteForMessage(token) +
                  ", expected a whole-number tissue label");
      mesh.labels.push_back(*label);
    }
  }
}

}  // namespace

std::optional<TetGenPart> tetGenPartOf(std::string_view content) {
  TextCursor text(content, {}, '#');
  std::vector<std::string_view> header;
  if (!text.nextLine(header) || header.size() < 2 || !parseInteger(header[0])) return std::nullopt;
  const std::optional<int64_t> second = parseInteger(header[1]);
  // A 2D node file is a node file, refused for its dimension.
  if (second == 3 || second == 2) return TetGenPart::kNode;
  if (second == 4 || second == 10) return TetGenPart::kEle;
  return std::nullopt;
}

TetMesh readTetGen(const std::filesystem::path& file, std::string content) {
  const std::optional<TetGenPart> part = tetGenPartOf(content);
  if (!part) {
    TextCursor text(content, file, '#');
    std::vector<std::string_view> header;
    text.nextLine(header);
    text.fail("the header's second number is " +
              (header.size() < 2 ? std::string("missing") : quoteForMessage(header[1])) +
              ", expected 3 (a .node file) or 4 or 10 (an .ele file); TetGen .face, .edge and .neigh files hold no "
              "tetrahedra");
  }
  const std::filesystem::path partner = findTetGenPartner(file, *part);
  std::string partnerContent = readFileContent(partner);
  const bool givenIsNode = *part == TetGenPart::kNode;
  const std::filesystem::path& nodeFile = givenIsNode ? file : partner;
  const std::filesystem::path& eleFile = givenIsNode ? partner : file;
  const std::string nodeContent = givenIsNode ? std::move(content) : std::move(partnerContent);
  const std::string eleContent = givenIsNode ? std::move(partnerContent) : std::move(content);

  TextCursor nodeText(nodeContent, nodeFile, '#');
  TetGenNodes nodes = readNodes(nodeText);
  TetMesh mesh;
  TextCursor eleText(eleContent, eleFile, '#');
  readElements(eleText, nodes, nodeFile, mesh);
  mesh.nodes = std::move(nodes.positions);
  return mesh;
}

}  // namespace trephine::formats
