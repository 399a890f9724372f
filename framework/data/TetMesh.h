#pragma once
// A tetrahedral mesh as read from a file or made by a phantom generator:
// node positions (mm) and tetrahedra as four node indices (0-based), with an
// optional integer label per tetrahedron (tissue). Topology, validation and
// collision structures are built on top of it (TetTopology, TetraBrain).
#include <array>
#include <cstdint>
#include <vector>

#include "framework/math/Math.h"

namespace trephine {

using TetIndices = std::array<int32_t, 4>;

struct TetMesh {
  std::vector<Vec3> nodes;       // mm
  std::vector<TetIndices> tets;  // 0-based node indices
  std::vector<int32_t> labels;   // one per tet, or empty

  size_t nodeCount() const { return nodes.size(); }
  size_t tetCount() const { return tets.size(); }
};

// Signed volume of tetrahedron (a, b, c, d) (mm^3): positive when d lies on the
// side of the plane (a, b, c) that the right-hand normal of a -> b -> c points to.
inline double signedVolume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).cross(c - a).dot(d - a) / 6.0;
}

}  // namespace trephine
