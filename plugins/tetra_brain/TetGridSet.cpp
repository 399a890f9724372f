#include "plugins/tetra_brain/TetGridSet.h"

#include <algorithm>
#include <cmath>

namespace trephine::tetra {

void buildTetGrids(const TetMesh& mesh, const TetTopology& topology, std::span<const Vec3> positions, double margin,
                   double cellSize, TetGridSet& out) {
  const size_t n = mesh.tetCount();
  out.reference.assign(positions.begin(), positions.end());
  out.margin = margin;
  out.boxes.resize(n);
  out.bounds.setEmpty();
  for (size_t t = 0; t < n; ++t) {
    Box3 box;
    for (int32_t i : mesh.tets[t]) box.extend(positions[i]);
    out.boxes[t] = box;
    out.bounds.extend(box);
  }
  const Vec3 grow = Vec3::Constant(margin);
  auto grown = [&](const Box3& box) { return Box3(box.min() - grow, box.max() + grow); };
  std::vector<Box3> boxes(n);
  for (size_t t = 0; t < n; ++t) boxes[t] = grown(out.boxes[t]);
  out.tetGrid.build(grown(out.bounds), cellSize, boxes);
  const auto& faces = topology.boundaryFaces();
  boxes.clear();
  boxes.reserve(faces.size());
  for (const BoundaryFace& f : faces) {
    Box3 box;
    for (int32_t i : faceNodes(mesh.tets[f.tet], f.face)) box.extend(positions[i]);
    boxes.push_back(grown(box));
  }
  out.faceGrid.build(grown(out.bounds), out.tetGrid.cellSide(), boxes);
}

double driftFromReference(const TetGridSet& set, std::span<const Vec3> positions) {
  double largest = 0;
  const size_t n = std::min(set.reference.size(), positions.size());
  for (size_t i = 0; i < n; ++i) largest = std::max(largest, (positions[i] - set.reference[i]).squaredNorm());
  return std::sqrt(largest);
}

}  // namespace trephine::tetra
