#pragma once
// One frame of force-driven drilling on the codes of a density volume: every
// voxel of the burr's footprint falls by w v dt |grad rho|, so that the
// interpolated isosurface recedes by about v dt under the burr
// (VoxelSkullDrilling.cpp says why each part of the rule is there):
//  - |grad rho| is each voxel's own density gradient, per axis the larger
//    one-sided difference (codes per mm);
//  - w = min(1, cos(angle from the load) + kSideCut) x a radial smoothstep, 1
//    up to half a voxel beyond the burr, 0 from one voxel beyond (the smallest
//    voxel side), and 0 behind the burr;
//  - each fall is rounded up or down at random in proportion to its fraction,
//    seeded by voxel and frame, so runs are reproducible.
// Codes never fall below the volume's lowest (the grid's outsideCode), and
// each lowered code is reported to the grid's occupancy cells. Rows of x are
// cut in order of z, then y; each row's falls are computed from its codes
// before any of them falls (rows already cut this frame count as cut).
//
// Row by row: rows of air are passed over, each row is clipped to the
// footprint's sphere, and away from the grid's faces neighbours are read by
// stride.
#include <cstdint>

#include "plugins/voxel_skull/SolidGrid.h"

namespace trephine::voxel {

// The flutes also cut sideways what the burr's side touches, at this share of
// the speed ahead: the hole comes out a little wider than the burr (at most the
// falloff's voxel), so the burr never wedges in a bore exactly its own size.
inline constexpr double kSideCut = 0.25;

struct FootprintCut {
  Vec3 center = Vec3::Zero();     // mm, the burr's centre
  Vec3 direction = Vec3::UnitZ(); // unit, the load's direction, into the bone
  double radius = 0;              // mm, the burr's radius
  double advance = 0;             // mm the surface recedes this frame at full weight (v dt)
  uint64_t frame = 0;             // seeds the stochastic rounding
  // Interleaving: only the rows (j, k) with (j + k) mod slices == slice are cut
  // (the caller scales `advance` by `slices`), so a frame walks 1/slices of the
  // footprint and every voxel is cut once every `slices` frames.
  int slices = 1;
  int slice = 0;
};

struct FootprintCutResult {
  int emptied = 0;          // voxels that were bone (code >= threshold) and are not any more
  int lowered = 0;          // voxels whose code fell
  double codesRemoved = 0;  // sum of the falls, in codes
};

// Applies one frame's cut to grid.codes; O(voxels in the footprint), no allocation.
FootprintCutResult cutFootprint(SolidGrid& grid, const FootprintCut& cut);

// The same cut by the plain rule, voxel by voxel over the footprint's whole
// box with bounds-checked neighbours: the reference cutFootprint is tested
// against (identical codes).
FootprintCutResult cutFootprintReference(SolidGrid& grid, const FootprintCut& cut);

// A uniform number in [0, 1) from a voxel and a frame (splitmix64): the same
// on every run and machine, independent between neighbouring voxels and frames.
inline double unitHash(uint64_t voxel, uint64_t frame) {
  uint64_t x = voxel * 0x9E3779B97F4A7C15ull ^ (frame + 0x632BE59BD9B4E019ull);
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return double(x >> 11) * 0x1.0p-53;
}

}  // namespace trephine::voxel
