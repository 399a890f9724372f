#pragma once
// A deterministic brain-shaped tetrahedral phantom at a requested tetrahedron
// count, meshed with CGAL Mesh_3 from an implicit surface. The thesis's brain
// models (Table 4.2) have about 3.5k, 12.5k, 22k, 40.5k and 50k tetrahedra.
//
// Shape (mm, centred at the origin, x left-right, y posterior-anterior, z up):
// an adult brain of about 140 (x) x 170 (y) x 115 (z) made of two overlapping
// ellipsoidal hemispheres, a flat base at z = kBrainBaseZ, a longitudinal
// fissure along the mid-sagittal plane x = 0 (kBrainFissureWidth wide, open at
// the top down to kBrainFissureBottomZ, so the hemispheres stay joined below
// it), and gyri/sulci as a smooth sinusoidal modulation of the surface of up
// to kBrainGyriAmplitude.
#include "framework/data/TetMesh.h"

namespace trephine::tetra {

inline constexpr double kBrainBaseZ = -57.5;          // mm, the flat base
inline constexpr double kBrainFissureWidth = 5.0;     // mm, between the fissure's walls
inline constexpr double kBrainFissureBottomZ = 27.5;  // mm, deepest point of the fissure (rounded)
inline constexpr double kBrainGyriAmplitude = 3.0;    // mm, largest outward or inward displacement

// Signed-distance-like function of the phantom's surface (mm): negative inside,
// zero on the surface, positive outside, with a gradient of magnitude about 1
// near the surface. The mesh's boundary nodes lie on its zero set.
double brainPhantomDistance(const Vec3& p);

// Meshes the phantom with about `targetTets` tetrahedra: Mesh_3's Delaunay
// refinement runs with a cell size guessed from the count and is re-run with
// the size rescaled from the achieved count (at most four runs); the run
// closest to the target then has its slivers removed (perturbation and
// exudation: smallest dihedral angle 10 deg). From 1500 tets up the count is
// within 2% of the target (checked up to 200000); coarser meshes are dominated
// by the surface, whose count jumps with the size, and may miss by up to 20%.
// Takes about 0.5 s for 3500 tets, 4 s for 50000 and 20 s for 200000 (Release).
// Deterministic: the same target gives identical nodes and tetrahedra on every
// call of the same build. Every tetrahedron has positive signedVolume(), every
// node belongs to a tetrahedron, and all labels are 1.
// Throws std::invalid_argument when targetTets is outside [100, 2000000].
TetMesh makeBrainPhantom(int targetTets);

// Regions the phantom can hold, for resection (labels): the brain 1, a
// tumour 2 (a ball), a vessel 3 (a tube along y, the whole brain's length);
// a radius of 0 leaves one out. The defaults put a tumour of the given
// radius in the right hemisphere, its centre 25 mm below the top of the
// cortex, and the vessel beside it, 3 mm from its side.
struct BrainPhantomRegions {
  double tumourRadius = 0;               // mm
  Vec3 tumourCentre = Vec3(25, 10, 30);  // mm
  double vesselRadius = 0;               // mm
  double vesselX = 0, vesselZ = 30;      // mm, the tube's axis (0 for x: beside the tumour)
  double detail = 3;                     // the regions' cells are this many times smaller than the brain's
  bool any() const { return tumourRadius > 0 || vesselRadius > 0; }
  // mm: the vessel's axis's x (vesselX, or beside the tumour when 0).
  double vesselAxisX() const { return vesselX != 0 ? vesselX : tumourCentre.x() + tumourRadius + 3.0 + vesselRadius; }
};
inline constexpr int32_t kBrainLabel = 1, kTumourLabel = 2, kVesselLabel = 3;

// The label of a point inside the phantom: the vessel's over the tumour's over the brain's.
int32_t brainPhantomRegion(const Vec3& p, const BrainPhantomRegions& regions);

// The phantom with its regions, their surfaces conforming (the tumour's and
// the vessel's faces lie on the ball and the tube).
TetMesh makeBrainPhantom(int targetTets, const BrainPhantomRegions& regions);

}  // namespace trephine::tetra
