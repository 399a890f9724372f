#pragma once
// Simplification of a triangle surface by vertex clustering (Rossignac and
// Borrel, 1993): space is cut into cubes of `cell` mm, every vertex moves to
// the mean of the vertices in its cube, and triangles whose corners fall in
// fewer than three cubes vanish. The cubes are global, so surfaces added
// apart (a skull's blocks) join without cracks. A wall thinner than a cube
// (a skull's tables, at coarse cells) folds onto itself: drawn flat-shaded,
// with both sides kept, it still reads as a surface. Used by the browser
// viewer's data (trephine view) and its live stream (VtkExporter). For a viewer that must draw
// a skull of millions of triangles in a software renderer: the triangle
// count falls about as 1 / cell^2.
#include <array>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "framework/data/TriangleMesh.h"

namespace trephine {

class VertexClustering {
 public:
  explicit VertexClustering(double cell) : m_cell(cell) {}

  // Returns the surface's piece: the range of its kept triangles, for piece().
  std::pair<size_t, size_t> add(const TriangleMesh& surface);
  // The clustered surface; each triangle once.
  TriangleMesh result() const;
  // The triangles of one added surface on the clusters of all of them (its
  // own copy of the points it uses): a piece can be replaced alone, and
  // pieces join without cracks.
  TriangleMesh piece(std::pair<size_t, size_t> range) const;

 private:
  int32_t clusterOf(const Vec3& p);

  double m_cell;  // mm
  std::unordered_map<uint64_t, int32_t> m_index;  // cube key -> cluster
  std::vector<Vec3> m_sums;
  std::vector<int32_t> m_counts;
  std::vector<std::array<int32_t, 3>> m_triangles;  // clusters
};

// The surfaces joined, clustered with the smallest cell (from `smallest` mm up,
// each try 1.25 times the last) that gives at most `triangles` triangles;
// with `smallest` 0 and the surfaces within the budget, unchanged.
TriangleMesh simplifyToBudget(const std::vector<const TriangleMesh*>& surfaces, size_t triangles,
                                      double smallest, double* cellUsed = nullptr);

}  // namespace trephine
