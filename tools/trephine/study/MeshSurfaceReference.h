#pragma once
// A study's reference for a tetrahedral mesh read from a file: its boundary
// triangles (the faces of one tetrahedron only) at the mesh's node
// positions, and the exact contact of a sphere with the solid they bound:
// the nearest point over every triangle (exact point-to-triangle distance),
// inside or outside by the generalised winding number. Written here, apart
// from every collision back-end, so that none of them is measured against
// itself. Offline only: every triangle at every query.
#include <array>
#include <vector>

#include "framework/data/TetMesh.h"
#include "tools/trephine/study/ExactSphereContact.h"

namespace trephine::study {

struct BoundarySurface {
  std::vector<Vec3> nodes;                        // mm
  std::vector<std::array<int32_t, 3>> triangles;  // each turned so that its right-hand normal points out
};

// The faces that belong to one tetrahedron only.
BoundarySurface boundarySurface(const TetMesh& mesh);

// Inside when the winding number of the surface about `p` is above 1/2 in magnitude.
bool insideSurface(const BoundarySurface& surface, const Vec3& p);

// As exactSphereContact, but exact to rounding: radius less the distance to
// the nearest surface point outside, radius plus it inside; the normal from
// that point to the centre (outside) or from the centre to it (inside).
ExactSphereContact meshSphereContact(const BoundarySurface& surface, const Vec3& center, double radius);

}  // namespace trephine::study
