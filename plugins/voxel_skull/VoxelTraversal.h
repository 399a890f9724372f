#pragma once
// Exact traversal of the voxels a segment crosses (Amanatides and Woo, 1987):
// every voxel the segment passes through is visited once, in order, so no
// voxel is skipped whatever the step, unlike sampling at fixed steps.
#include "plugins/voxel_skull/SolidGrid.h"

namespace trephine::voxel {

struct SegmentHit {
  bool hit = false;
  double t = 0;              // fraction of the segment [0, 1] where it enters the first solid voxel
  bool startsSolid = false;  // the start point itself is in a solid voxel
  int64_t voxel = -1;        // linear index of that voxel
  int enteredAxis = -1;      // axis of the face it entered through (-1: it started there)
};

// First solid voxel along a -> b. With skipInitialSolid, solid voxels at the
// start are passed over until the segment reaches a free voxel (a point
// already in contact does not block; entering new material does).
SegmentHit firstSolidOnSegment(const SolidGrid& grid, const Vec3& a, const Vec3& b, bool skipInitialSolid);

// Smooth surface: where a -> b enters the bone between fractions lo (outside)
// and hi (inside), to 1e-5 mm; the fraction returned is inside. For a march
// that sampled the segment itself (the batched sweep of NativeVoxelSweep.cpp).
double crossingOnSegment(const SolidGrid& grid, const Vec3& a, const Vec3& b, double lo, double hi);

// Where a -> b first enters a free voxel (or leaves the grid), as a fraction of
// the segment; 1 when it stays in solid voxels all the way.
double firstFreeOnSegment(const SolidGrid& grid, const Vec3& a, const Vec3& b);

}  // namespace trephine::voxel
