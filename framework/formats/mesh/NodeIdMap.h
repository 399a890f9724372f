#pragma once
// From the node ids a file uses (Gmsh numbers nodes with arbitrary, possibly
// non-contiguous positive ids) to 0-based positions in TetMesh::nodes. Dense
// id ranges use a lookup table, sparse ones a hash map, so that a file with
// ids 1 and 10^12 costs no more memory than its node count.
#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

namespace trephine::formats {

class NodeIdMap {
 public:
  // Maps ids[i] to i. Returns nothing and sets `duplicate` when an id repeats.
  static std::optional<NodeIdMap> build(std::span<const int64_t> ids, int64_t& duplicate);

  // The position of node `id`, or -1 when the file has no such node.
  int32_t find(int64_t id) const {
    if (m_dense) {
      if (id < m_first || uint64_t(id) - uint64_t(m_first) >= m_table.size()) return -1;
      return m_table[size_t(uint64_t(id) - uint64_t(m_first))];
    }
    const auto found = m_sparse.find(id);
    return found == m_sparse.end() ? -1 : found->second;
  }

 private:
  NodeIdMap() = default;

  bool m_dense = true;
  int64_t m_first = 0;
  std::vector<int32_t> m_table;  // dense: position of id m_first + k, or -1
  std::unordered_map<int64_t, int32_t> m_sparse;
};

}  // namespace trephine::formats
