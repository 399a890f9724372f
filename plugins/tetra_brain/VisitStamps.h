#pragma once
// Marks the items (tetrahedra, boundary faces) a query has already tested, so
// that an item listed in several grid cells is tested once per query. Items
// sit in every cell their grown box overlaps, so a query over a block of
// cells meets most of them many times. Starting a query costs nothing: each
// takes a new stamp value; the marks are cleared only when the 32-bit stamp
// wraps.
#include <algorithm>
#include <cstdint>
#include <vector>

namespace trephine::tetra {

class VisitStamps {
 public:
  void resize(size_t items) {
    m_stamps.assign(items, 0);
    m_current = 0;
  }
  // Starts a query: nothing is marked.
  void begin() {
    if (++m_current == 0) {
      std::fill(m_stamps.begin(), m_stamps.end(), 0u);
      m_current = 1;
    }
  }
  // True the first time `item` is met in this query (and marks it).
  bool firstVisit(int32_t item) {
    uint32_t& stamp = m_stamps[size_t(item)];
    if (stamp == m_current) return false;
    stamp = m_current;
    return true;
  }

 private:
  std::vector<uint32_t> m_stamps;
  uint32_t m_current = 0;
};

}  // namespace trephine::tetra
