#include "framework/data/TetTopology.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace trephine {

namespace {

constexpr size_t kListed = 5;  // indices quoted per kind of problem

struct FaceKey {
  std::array<int32_t, 3> nodes;  // sorted
  int32_t tet;
  int8_t face;
  bool operator<(const FaceKey& o) const { return nodes < o.nodes || (nodes == o.nodes && tet < o.tet); }
};

void note(std::vector<int32_t>& list, int32_t index) {
  if (list.size() < kListed) list.push_back(index);
}

std::string listed(const std::vector<int32_t>& list, size_t count) {
  std::ostringstream s;
  for (size_t i = 0; i < list.size(); ++i) s << (i ? ", " : "") << list[i];
  if (count > list.size()) s << ", ...";
  return s.str();
}

}  // namespace

TetTopology::TetTopology(const TetMesh& mesh) {
  const size_t n = mesh.tetCount();
  std::vector<FaceKey> faces;
  faces.reserve(4 * n);
  for (size_t t = 0; t < n; ++t) {
    for (int f = 0; f < 4; ++f) {
      auto nodes = faceNodes(mesh.tets[t], f);
      std::sort(nodes.begin(), nodes.end());
      faces.push_back({nodes, int32_t(t), int8_t(f)});
    }
  }
  std::sort(faces.begin(), faces.end());
  m_neighbours.assign(4 * n, kNoNeighbour);
  m_boundaryMask.assign(n, 0);
  for (size_t i = 0; i < faces.size();) {
    size_t j = i + 1;
    while (j < faces.size() && faces[j].nodes == faces[i].nodes) ++j;
    if (j - i == 2) {
      m_neighbours[size_t(faces[i].tet) * 4 + faces[i].face] = faces[i + 1].tet;
      m_neighbours[size_t(faces[i + 1].tet) * 4 + faces[i + 1].face] = faces[i].tet;
    } else if (j - i == 1) {
      m_boundary.push_back({faces[i].tet, faces[i].face});
      m_boundaryMask[faces[i].tet] |= uint8_t(1u << faces[i].face);
    } else {
      ++m_nonManifold;
      if (m_firstNonManifoldTet < 0) m_firstNonManifoldTet = faces[i].tet;
    }
    i = j;
  }
}

MeshReport inspectMesh(const TetMesh& mesh, const TetTopology& topology, double degenerateFraction) {
  MeshReport r;
  double total = 0;
  std::vector<double> volumes(mesh.tetCount());
  for (size_t t = 0; t < mesh.tetCount(); ++t) {
    const TetIndices& k = mesh.tets[t];
    volumes[t] = signedVolume(mesh.nodes[k[0]], mesh.nodes[k[1]], mesh.nodes[k[2]], mesh.nodes[k[3]]);
    total += std::abs(volumes[t]);
  }
  const double tolerance = mesh.tetCount() ? degenerateFraction * total / double(mesh.tetCount()) : 0;
  for (size_t t = 0; t < volumes.size(); ++t) {
    const double v = volumes[t];
    if (t == 0 || v < r.minVolume) r.minVolume = v;
    if (t == 0 || v > r.maxVolume) r.maxVolume = v;
    if (!(std::abs(v) > tolerance)) {
      ++r.degenerateTets;
      note(r.firstDegenerate, int32_t(t));
    } else if (v < 0) {
      ++r.invertedTets;
      note(r.firstInverted, int32_t(t));
    }
  }
  std::vector<uint8_t> used(mesh.nodeCount(), 0);
  for (const TetIndices& k : mesh.tets)
    for (int32_t i : k) used[i] = 1;
  for (size_t i = 0; i < used.size(); ++i) {
    if (!used[i]) {
      ++r.unusedNodes;
      note(r.firstUnused, int32_t(i));
    }
  }
  r.nonManifoldFaces = topology.nonManifoldFaces();
  if (r.nonManifoldFaces) r.firstNonManifold.push_back(topology.firstNonManifoldTet());
  return r;
}

std::string MeshReport::describe() const {
  std::ostringstream s;
  if (invertedTets)
    s << invertedTets << " tetrahedra with negative volume (first: " << listed(firstInverted, invertedTets) << ")\n";
  if (degenerateTets)
    s << degenerateTets
      << " tetrahedra with zero or near-zero volume (first: " << listed(firstDegenerate, degenerateTets) << ")\n";
  if (unusedNodes)
    s << unusedNodes << " nodes used by no tetrahedron (first: " << listed(firstUnused, unusedNodes) << ")\n";
  if (nonManifoldFaces)
    s << nonManifoldFaces << " faces shared by more than two tetrahedra (first at tetrahedron "
      << listed(firstNonManifold, 1) << ")\n";
  return s.str();
}

size_t reorient(TetMesh& mesh) {
  size_t flipped = 0;
  for (TetIndices& k : mesh.tets) {
    if (signedVolume(mesh.nodes[k[0]], mesh.nodes[k[1]], mesh.nodes[k[2]], mesh.nodes[k[3]]) < 0) {
      std::swap(k[2], k[3]);
      ++flipped;
    }
  }
  return flipped;
}

}  // namespace trephine
