#pragma once
// Tetrahedral meshing of a solid given by an implicit function (negative
// inside), at a requested tetrahedron count, with CGAL Mesh_3: Delaunay
// refinement with a cell size guessed from the count and re-run with the size
// rescaled from the achieved count (at most four runs); the run closest to
// the target then has its slivers removed (perturbation and exudation:
// smallest dihedral angle 10 deg). From 1500 tets up the count is within 2%
// of the target on the brain phantom (checked up to 200000). Deterministic:
// the same solid and target give identical nodes and tetrahedra on every call
// of the same build. Every tetrahedron has positive signedVolume(), every
// node belongs to a tetrahedron, and all labels are 1. All CGAL code of the
// project is in CgalMesher.cpp (plugin `meshing`, see Meshing.h for a build
// without it).
#include <functional>
#include <numbers>

#include "framework/data/TetMesh.h"

namespace trephine::tetra {

struct ImplicitSolid {
  std::function<double(const Vec3&)> distance;  // negative inside, zero on the surface, about unit gradient there (mm)
  Vec3 centre = Vec3::Zero();                   // of a sphere holding the solid
  double boundingRadius = 1;                    // mm
  // The refined count of Mesh_3 at cell size s is about volumeTerm / s^3 +
  // surfaceTerm / s^2: the first guess of the size (about 4.2 times the
  // volume and 4.3 times the area for a smooth solid).
  double volumeTerm = 1, surfaceTerm = 0;
  double leastFacetDistance = 0;  // mm: surface facets lie within max(this, size / 10) of the surface
};

// A ball of `radius` (mm) at the origin. The count's first guess: about 4.2
// times the volume and 4.3 times the area over the cell size's cube and
// square, as measured on the brain phantom.
inline ImplicitSolid ballSolid(double radius) {
  return {[radius](const Vec3& p) { return p.norm() - radius; },
          Vec3::Zero(),
          1.2 * radius,
          4.2 * 4.0 / 3.0 * std::numbers::pi * radius * radius * radius,
          4.3 * 4.0 * std::numbers::pi * radius * radius,
          0.0};
}

// Throws std::invalid_argument when targetTets is outside [100, 2000000].
TetMesh meshImplicitSolid(const ImplicitSolid& solid, int targetTets);
// One refinement with cells and surface facets of circumradius at most
// `size` (mm), then the slivers' removal. Throws std::invalid_argument for a
// size that is not positive.
TetMesh meshImplicitSolidAtSize(const ImplicitSolid& solid, double size);

}  // namespace trephine::tetra
