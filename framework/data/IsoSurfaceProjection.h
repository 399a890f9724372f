#pragma once
// Moves the vertices of a surface near a voxel grid's isosurface onto it: each
// vertex goes along its normal (the mean of its triangles', by area; facing
// out of the bone) to the nearest point within `reach` mm where the grid's
// trilinear codes cross the isovalue: inward from air, outward from bone
// (found by half-voxel steps, then bisection). A vertex with no crossing
// within reach takes the mean of its neighbours' new places (ten rounds):
// left where it was, it would stand out as a spike. Vertices at the same position
// move together (a surface in blocks stays without cracks). For a coarse
// isosurface of a max-pooled volume (CoarseVoxelGrid): its vertices, up to a
// coarse voxel off, land on the full surface, the outer table's from
// outside and the inner's from inside, with the coarse surface's topology.
#include "framework/data/TriangleMesh.h"
#include "framework/data/VoxelGrid.h"

namespace trephine {

struct ProjectionCounts {
  size_t moved = 0, stayed = 0;
};

ProjectionCounts projectOntoIsoSurface(TriangleMesh& surface, const VoxelGrid& grid, double reach);

// The grid's codes interpolated trilinearly between voxel centres at p (mm),
// the outside code beyond the grid (the isosurface's field).
double trilinearCode(const VoxelGrid& grid, const Vec3& p);

}  // namespace trephine
