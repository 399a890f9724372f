#pragma once
// Marks the items (tetrahedra, boundary faces) a query has already tested, so
// that an item listed in several grid cells is tested once per query. Items
// sit in every cell their grown box overlaps, so a query over a block of
// cells meets most of them many times. Starting a query costs nothing: each
// takes a new stamp value. The stamps are 64-bit so that they never wrap (at
// millions of queries a second, 32 bits would wrap within the hour and force
// an O(items) clearing inside a haptic frame).
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
  void begin() { ++m_current; }
  // True the first time `item` is met in this query (and marks it).
  bool firstVisit(int32_t item) {
    uint64_t& stamp = m_stamps[size_t(item)];
    if (stamp == m_current) return false;
    stamp = m_current;
    return true;
  }

 private:
  std::vector<uint64_t> m_stamps;
  uint64_t m_current = 0;
};

}  // namespace trephine::tetra
