#include "plugins/tetra_brain/TetGridSet.h"

#include <algorithm>
#include <cmath>

namespace trephine::tetra {

void buildTetGrids(const TetMesh& mesh, std::span<const BoundaryFace> faces, std::span<const Vec3> positions,
                   double margin, double cellSize, double faceCellSize, TetGridSet& out) {
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
  boxes.clear();
  boxes.reserve(faces.size());
  for (const BoundaryFace& f : faces) {
    Box3 box;
    for (int32_t i : faceNodes(mesh.tets[f.tet], f.face)) box.extend(positions[i]);
    boxes.push_back(grown(box));
  }
  out.faceGrid.build(grown(out.bounds), faceCellSize, boxes);
}

double driftFromReference(const TetGridSet& set, std::span<const Vec3> positions) {
  return driftFromReference(set, positions, 0);
}

double driftFromReference(const TetGridSet& set, std::span<const Vec3> positions, size_t first) {
  // Four running maxima: one would chain every node through the latency of a max.
  double largest[4] = {0, 0, 0, 0};
  const size_t n = first < set.reference.size() ? std::min(set.reference.size() - first, positions.size()) : 0;
  const Vec3* reference = set.reference.data() + first;
  size_t i = 0;
  for (; i + 4 <= n; i += 4)
    for (size_t k = 0; k < 4; ++k)
      largest[k] = std::max(largest[k], (positions[i + k] - reference[i + k]).squaredNorm());
  for (; i < n; ++i) largest[0] = std::max(largest[0], (positions[i] - reference[i]).squaredNorm());
  return std::sqrt(std::max(std::max(largest[0], largest[1]), std::max(largest[2], largest[3])));
}

}  // namespace trephine::tetra
