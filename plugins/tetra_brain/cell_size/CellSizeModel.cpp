#include "plugins/tetra_brain/cell_size/CellSizeModel.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>

namespace trephine::tetra {

namespace {

// A key for an edge or a triangle of node indices, sorted.
uint64_t edgeKey(int32_t a, int32_t b) {
  if (a > b) std::swap(a, b);
  return uint64_t(uint32_t(a)) << 32 | uint32_t(b);
}

struct TriangleKey {
  int32_t n[3];
  bool operator==(const TriangleKey& o) const { return n[0] == o.n[0] && n[1] == o.n[1] && n[2] == o.n[2]; }
};
struct TriangleHash {
  size_t operator()(const TriangleKey& k) const {
    return size_t(k.n[0]) * 73856093u ^ size_t(k.n[1]) * 19349663u ^ size_t(k.n[2]) * 83492791u;
  }
};

}  // namespace

CellSizeInputs measureCellSizeInputs(const TetMesh& mesh) {
  if (mesh.tets.empty()) throw std::invalid_argument("the mesh has no tetrahedra");
  CellSizeInputs in;
  std::unordered_set<uint64_t> edges;
  std::unordered_set<TriangleKey, TriangleHash> facets;
  edges.reserve(mesh.tets.size() * 2);
  facets.reserve(mesh.tets.size() * 3);
  double longestSum = 0, edgeSum = 0, areaSum = 0;
  constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (const TetIndices& t : mesh.tets) {
    double longest = 0;
    for (const auto& e : kEdges) {
      const double length = (mesh.nodes[t[e[0]]] - mesh.nodes[t[e[1]]]).norm();
      longest = std::max(longest, length);
      if (edges.insert(edgeKey(t[e[0]], t[e[1]])).second) edgeSum += length;
    }
    longestSum += longest;
    in.largestEdge = std::max(in.largestEdge, longest);
    for (const auto& f : kFaces) {
      TriangleKey key{{t[f[0]], t[f[1]], t[f[2]]}};
      std::sort(key.n, key.n + 3);
      if (!facets.insert(key).second) continue;
      const Vec3 &a = mesh.nodes[key.n[0]], &b = mesh.nodes[key.n[1]], &c = mesh.nodes[key.n[2]];
      areaSum += 0.5 * (b - a).cross(c - a).norm();
    }
  }
  in.tetrahedra = mesh.tets.size();
  in.edges = edges.size();
  in.facets = facets.size();
  in.longestEdge = longestSum / double(in.tetrahedra);
  in.averageEdge = edgeSum / double(in.edges);
  in.facetArea = areaSum / double(in.facets);
  if (!(in.facetArea > 0) || !(in.longestEdge > 0))
    throw std::invalid_argument("the mesh's tetrahedra are degenerate (no facet has an area)");
  return in;
}

namespace {
// q of the cost: (1 - p_nc) r_t 3 sqrt(3) / (2 A_t), 1/mm^2.
double particleWeight(const CellSizeInputs& in, const CostParameters& p) {
  return (1 - p.collisionFreeProbability) * p.testTimeRatio * 3 * std::sqrt(3.0) / (2 * in.facetArea);
}
}  // namespace

double relativeCost(const CellSizeInputs& in, const CostParameters& p, double delta) {
  const double cells = std::pow(in.longestEdge / delta + 2, 3);
  return cells * (p.collisionFreeProbability + particleWeight(in, p) * delta * delta);
}

double optimalCellSize(const CellSizeInputs& in, const CostParameters& p) {
  if (!(p.collisionFreeProbability > 0 && p.collisionFreeProbability < 1) || !(p.testTimeRatio > 0))
    throw std::invalid_argument("p_nc must lie in (0, 1) and r_t be positive");
  // f(delta) = 4 q delta^3 - s q delta^2 - 3 s p_nc: negative at 0, one sign
  // change, so one positive root; f grows past it. Bisection on a bracket.
  const double s = in.longestEdge, q = particleWeight(in, p), pnc = p.collisionFreeProbability;
  const auto f = [&](double d) { return ((4 * q * d - s * q) * d) * d - 3 * s * pnc; };
  double low = 0, high = s;
  while (f(high) < 0) high *= 2;
  for (int i = 0; i < 200 && high - low > 1e-12 * high; ++i) {
    const double mid = 0.5 * (low + high);
    (f(mid) < 0 ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

}  // namespace trephine::tetra
