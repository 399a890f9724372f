#pragma once
// A density volume's codes on their grid, as the code that reads them in
// place sees it: where voxel (0, 0, 0)'s outer corner is, the voxels' sides,
// and the isovalue in code units. The voxel skull's hot-loop grid extends it
// (plugins/voxel_skull/SolidGrid.h); the isosurface (IsoSurface.h) and an
// exporter that follows a drilled skull read it. Plain data, inline
// functions, no allocation.
#include <cstdint>

#include "framework/data/DensityVolume.h"
#include "framework/math/Math.h"

namespace trephine {

// A voxel's code after a change (drilling only lowers codes).
struct VoxelEdit {
  int64_t voxel = -1;  // linear index, i + nx (j + ny k)
  VoxelCode code = 0;
};

struct VoxelGrid {
  VoxelCode* codes = nullptr;
  int32_t nx = 0, ny = 0, nz = 0;
  Vec3 corner = Vec3::Zero();          // mm, outer corner of voxel (0, 0, 0)
  Vec3 spacing = Vec3::Ones();         // mm
  Vec3 inverseSpacing = Vec3::Ones();  // 1/mm
  double isoCode = 0;      // the isovalue in code units (the smooth surface's)
  double outsideCode = 0;  // code of the space around the grid (the volume's lowest)
  DensityEncoding encoding;  // a code's density (for exports; the queries work in codes)

  // The codes of `volume` in place, with the isovalue (in the volume's
  // densities) in code units.
  static VoxelGrid of(DensityVolume& volume, double isovalue) {
    VoxelGrid g;
    g.codes = volume.codes();
    g.nx = volume.dims()[0];
    g.ny = volume.dims()[1];
    g.nz = volume.dims()[2];
    g.spacing = volume.spacing();
    g.corner = volume.origin() - 0.5 * g.spacing;
    g.inverseSpacing = g.spacing.cwiseInverse();
    g.isoCode = (isovalue - volume.encoding().offset) / volume.encoding().scale;
    g.encoding = volume.encoding();
    g.outsideCode =
        volume.voxelCount() ? (volume.minDensity() - volume.encoding().offset) / volume.encoding().scale : 0;
    return g;
  }

  size_t voxelCount() const { return size_t(nx) * size_t(ny) * size_t(nz); }
  bool inside(int64_t i, int64_t j, int64_t k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz;
  }
  int64_t linear(int64_t i, int64_t j, int64_t k) const { return i + int64_t(nx) * (j + int64_t(ny) * k); }
  // The code of voxel (i, j, k), the outside code beyond the grid.
  double codeAtCell(int64_t i, int64_t j, int64_t k) const {
    return inside(i, j, k) ? double(codes[linear(i, j, k)]) : outsideCode;
  }
};

}  // namespace trephine
