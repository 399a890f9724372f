#pragma once
// A closed surface as triangles, in blocks: what the mesh collision back-ends
// (embree, bullet) query, whichever target made it. The skull's isosurface
// is cut into blocks of cells (a drilled block is re-extracted alone); the
// brain's boundary is one block whose vertices follow the deformation.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "framework/data/TriangleMesh.h"
#include "framework/math/Math.h"

namespace trephine {

class TriangleBlocks {
 public:
  virtual ~TriangleBlocks() = default;
  virtual size_t blockCount() const = 0;
  virtual const TriangleMesh& block(size_t index) const = 0;
  size_t triangleCount() const {
    size_t n = 0;
    for (size_t b = 0; b < blockCount(); ++b) n += block(b).triangles.size();
    return n;
  }
};

// Which triangle: its block and its index there.
struct TriangleRef {
  int block = -1, triangle = -1;
  bool valid() const { return block >= 0 && triangle >= 0; }
};

// Unit outward normal of a triangle (zero for one of no area).
inline Vec3 faceNormal(const TriangleBlocks& blocks, TriangleRef ref) {
  const TriangleMesh& mesh = blocks.block(size_t(ref.block));
  const auto& t = mesh.triangles[size_t(ref.triangle)];
  const Vec3& a = mesh.vertices[size_t(t[0])];
  const Vec3 n = (mesh.vertices[size_t(t[1])] - a).cross(mesh.vertices[size_t(t[2])] - a);
  const double length = n.norm();
  return length > 0 ? Vec3(n / length) : Vec3::Zero();
}

}  // namespace trephine
