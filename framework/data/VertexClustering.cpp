#include "framework/data/VertexClustering.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace trephine {

int32_t VertexClustering::clusterOf(const Vec3& p) {
  // 21 bits a coordinate around the origin: 2^20 cubes each way.
  uint64_t key = 0;
  for (int a = 0; a < 3; ++a) {
    const int64_t i = std::clamp<int64_t>(int64_t(std::floor(p[a] / m_cell)) + (int64_t(1) << 20), 0, (int64_t(1) << 21) - 1);
    key = (key << 21) | uint64_t(i);
  }
  auto [at, added] = m_index.try_emplace(key, int32_t(m_sums.size()));
  if (added) {
    m_sums.push_back(Vec3::Zero());
    m_counts.push_back(0);
  }
  return at->second;
}

std::pair<size_t, size_t> VertexClustering::add(const TriangleMesh& surface) {
  const size_t first = m_triangles.size();
  std::vector<int32_t> cluster(surface.vertices.size());
  for (size_t i = 0; i < surface.vertices.size(); ++i) {
    cluster[i] = clusterOf(surface.vertices[i]);
    m_sums[size_t(cluster[i])] += surface.vertices[i];
    ++m_counts[size_t(cluster[i])];
  }
  for (const auto& t : surface.triangles) {
    const std::array<int32_t, 3> c{cluster[size_t(t[0])], cluster[size_t(t[1])], cluster[size_t(t[2])]};
    if (c[0] != c[1] && c[1] != c[2] && c[0] != c[2]) m_triangles.push_back(c);
  }
  return {first, m_triangles.size()};
}

TriangleMesh VertexClustering::piece(std::pair<size_t, size_t> range) const {
  TriangleMesh out;
  std::set<std::array<int32_t, 3>> seen;
  std::unordered_map<int32_t, int32_t> renumber;
  for (size_t i = range.first; i < range.second && i < m_triangles.size(); ++i) {
    std::array<int32_t, 3> key = m_triangles[i];
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    if (!seen.insert(key).second) continue;
    std::array<int32_t, 3> kept;
    for (int k = 0; k < 3; ++k) {
      const int32_t cluster = m_triangles[i][k];
      auto [at, added] = renumber.try_emplace(cluster, int32_t(out.vertices.size()));
      if (added) out.vertices.push_back(m_sums[size_t(cluster)] / m_counts[size_t(cluster)]);
      kept[k] = at->second;
    }
    out.triangles.push_back(kept);
  }
  return out;
}

TriangleMesh VertexClustering::result() const {
  TriangleMesh out;
  // Each triangle once, whatever its turn (both sides of a thin wall can
  // collapse onto the same three clusters: those are kept, one a side).
  std::set<std::array<int32_t, 3>> seen;
  std::vector<int32_t> renumber(m_sums.size(), -1);
  for (const auto& t : m_triangles) {
    std::array<int32_t, 3> key = t;
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    if (!seen.insert(key).second) continue;
    std::array<int32_t, 3> kept;
    for (int k = 0; k < 3; ++k) {
      int32_t& n = renumber[size_t(t[k])];
      if (n < 0) {
        n = int32_t(out.vertices.size());
        out.vertices.push_back(m_sums[size_t(t[k])] / m_counts[size_t(t[k])]);
      }
      kept[k] = n;
    }
    out.triangles.push_back(kept);
  }
  return out;
}

TriangleMesh simplifyToBudget(const std::vector<const TriangleMesh*>& surfaces, size_t triangles,
                                      double smallest, double* cellUsed) {
  size_t total = 0;
  double edge = 0;  // mean edge, mm: where clustering starts to matter
  size_t edges = 0;
  for (const auto* s : surfaces) {
    total += s->triangles.size();
    for (size_t i = 0; i < s->triangles.size(); i += 97, ++edges)
      edge += (s->vertices[size_t(s->triangles[i][0])] - s->vertices[size_t(s->triangles[i][1])]).norm();
  }
  if (total <= triangles && smallest <= 0) {
    TriangleMesh joined;
    for (const auto* s : surfaces) {
      const int32_t base = int32_t(joined.vertices.size());
      joined.vertices.insert(joined.vertices.end(), s->vertices.begin(), s->vertices.end());
      for (auto t : s->triangles) joined.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    if (cellUsed) *cellUsed = 0;
    return joined;
  }
  edge = edges ? edge / double(edges) : 1.0;
  // Clustering keeps about total * (edge / cell)^2 / 2 triangles: start there.
  double cell = std::max(smallest, edge * std::sqrt(0.5 * double(total) / double(std::max<size_t>(triangles, 1))));
  cell = std::max(cell, edge);
  for (;;) {
    VertexClustering clustering(cell);
    for (const auto* s : surfaces) clustering.add(*s);
    TriangleMesh out = clustering.result();
    if (out.triangles.size() <= triangles || cell > 1e4 * edge) {
      if (cellUsed) *cellUsed = cell;
      return out;
    }
    cell *= 1.25;
  }
}

}  // namespace trephine
