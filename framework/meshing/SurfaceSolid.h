#pragma once
// The inside of a closed triangle surface as an implicit solid for the
// mesher (meshImplicitSolid): the winding number of the surface around a
// point, counted along the vertical ray above it (each triangle the ray
// crosses adds the sign of its normal's z). It is 1 inside a closed surface
// whose normals point out (-1 when they point in), 0 outside, and stays
// right where the surface passes through itself (2 where two parts of a
// self-intersecting surface overlap), where counting crossings by parity
// would carve the overlap out. Shared edges and corners are counted once
// (the rasteriser's top-left rule on each triangle's projection).
#include <array>
#include <cstdint>
#include <vector>

#include "framework/data/TriangleMesh.h"
#include "framework/meshing/TetMeshing.h"

namespace trephine {

class SurfaceSolid {
 public:
  // Throws std::invalid_argument for a surface with no area.
  explicit SurfaceSolid(TriangleMesh surface);

  int windingNumber(const Vec3& p) const;
  // The solid for the mesher: its distance is -1 inside (a non-zero winding
  // number) and 1 outside (the mesher finds the surface by bisection on the
  // sign); the bounding sphere and the count's first guess from the box, the
  // enclosed volume and the area.
  ImplicitSolid solid() const;

  double area() const { return m_area; }      // mm^2
  double volume() const { return m_volume; }  // mm^3, signed: negative for inward normals
  const Box3& bounds() const { return m_bounds; }
  size_t triangleCount() const { return m_surface.triangles.size(); }

 private:
  TriangleMesh m_surface;
  Box3 m_bounds;
  double m_area = 0, m_volume = 0;
  // Columns over the xy extent, each listing the triangles whose projection's box overlaps it.
  Vec3 m_origin = Vec3::Zero();
  double m_side = 1;
  int32_t m_columns[2] = {1, 1};
  std::vector<uint32_t> m_start;
  std::vector<int32_t> m_items;
};

}  // namespace trephine
