#pragma once
// A surface as triangles: what surface files hold, what the skull's
// isosurface and the brain's boundary are cut into for the mesh back-ends,
// and what the viewer draws.
#include <array>
#include <cstdint>
#include <vector>

#include "framework/math/Math.h"

namespace trephine {

struct TriangleMesh {
  std::vector<Vec3> vertices;                     // mm
  std::vector<std::array<int32_t, 3>> triangles;  // 0-based vertex indices, counter-clockwise seen from outside
};

}  // namespace trephine
