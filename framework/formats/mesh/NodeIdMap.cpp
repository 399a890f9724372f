#include "framework/formats/mesh/NodeIdMap.h"

#include <algorithm>

namespace trephine::formats {

std::optional<NodeIdMap> NodeIdMap::build(std::span<const int64_t> ids, int64_t& duplicate) {
  NodeIdMap map;
  if (ids.empty()) return map;
  const auto [low, high] = std::minmax_element(ids.begin(), ids.end());
  // The span of ids, computed without overflow (ids may be any int64_t).
  const uint64_t span = uint64_t(*high) - uint64_t(*low);
  // A table up to a few times the node count is cheaper than hashing.
  map.m_dense = span < 4 * uint64_t(ids.size()) + 1024;
  map.m_first = *low;
  if (map.m_dense) {
    map.m_table.assign(size_t(span) + 1, -1);
    for (size_t i = 0; i < ids.size(); ++i) {
      int32_t& slot = map.m_table[size_t(uint64_t(ids[i]) - uint64_t(map.m_first))];
      if (slot >= 0) {
        duplicate = ids[i];
        return std::nullopt;
      }
      slot = static_cast<int32_t>(i);
    }
    return map;
  }
  map.m_sparse.reserve(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    if (!map.m_sparse.emplace(ids[i], static_cast<int32_t>(i)).second) {
      duplicate = ids[i];
      return std::nullopt;
    }
  }
  return map;
}

}  // namespace trephine::formats
