#pragma once
// A study's reference for a scan: the isosurface, at the isovalue, of the
// scan's density interpolated trilinearly between voxel centres, in double
// precision, as a level set for exactSphereContact. Written here, apart from
// every collision back-end, so that none of them is measured against itself.
#include "framework/geometry/ExactShape.h"

namespace trephine::study {

// Negative inside (interpolated density above the isovalue), positive
// outside; outside the scan's cells, outside. Within half a voxel of the
// border the nearest centres' values are held.
LevelSet scanIsosurface(const ScanAsRead& scan);

}  // namespace trephine::study
