#pragma once
// The hot-loop view of a density volume: which voxel a point falls in and
// whether it is solid. Two surfaces:
//  - voxels (the thesis): a voxel is bone when its density is above the
//    isovalue; the bone is a union of boxes, its surface a staircase;
//  - smooth: the density is interpolated trilinearly between voxel centres and
//    bone is where it exceeds the isovalue; the surface is the isosurface,
//    continuous across voxels, with the density gradient as its normal.
// Plain data and inline functions, no allocation (but for the optional
// occupancy cells of the smooth surface, built once).
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "framework/channels/ChangeQueue.h"
#include "framework/data/DensityVolume.h"
#include "framework/data/IsoSurface.h"
#include "framework/data/VoxelGrid.h"
#include "plugins/voxel_skull/OccupancyCells.h"

namespace trephine::voxel {

using trephine::VoxelEdit;

// The codes, their grid and isovalue (VoxelGrid), and how this skull reads them.
struct SolidGrid : VoxelGrid {
  int32_t threshold = 0;  // codes >= threshold are solid
  bool smooth = false;
  // Code drilled bone falls to: density 0 (air in a raw scanner scale, water
  // in Hounsfield units, as the irrigation fills a burr hole) or the volume's
  // lowest if that is higher; not the air of a CT in Hounsfield units (-1000),
  // whose contrast with bone would make each cut step (FootprintCut: the
  // surface recedes by the density gradient) 1.7 times as deep.
  double emptyCode = 0;
  // Smooth surface only, optional: which interpolation cells the surface may
  // cross (OccupancyCells.h), so the smooth point test interpolates only there.
  // Shared by copies of the grid, as the codes are. Null: every point interpolates.
  std::shared_ptr<OccupancyCells> occupancy;
  // Optional: every code change, for the readers on other threads that keep
  // a copy of the codes (an exporter of the surface, the rebuild of a mesh
  // back-end's surface), one queue each. Shared by copies of the grid. Empty
  // unless a reader asked (VoxelSkull::recordEdits); set at init only.
  std::vector<std::shared_ptr<ChangeQueue<VoxelEdit>>> edits;

  static SolidGrid of(DensityVolume& volume, double isovalue, bool smoothSurface = false) {
    SolidGrid g;
    static_cast<VoxelGrid&>(g) = VoxelGrid::of(volume, isovalue);
    g.threshold = volume.encoding().thresholdCode(isovalue);
    g.smooth = smoothSurface;
    g.emptyCode = isovalue > 0 ? std::max(g.outsideCode, -volume.encoding().offset / volume.encoding().scale)
                               : g.outsideCode;
    return g;
  }

  // Builds `occupancy` from the codes when the surface is smooth (nothing on
  // voxels): once after the codes are set, O(voxels).
  void buildOccupancy() { occupancy = smooth && codes ? OccupancyCells::build(*this) : nullptr; }
  // For an isosurface's extraction: the cells the occupancy decided (all
  // corners clearly in or out) hold no surface. Empty without occupancy cells;
  // valid while this grid's occupancy lives (a pointer kept, no allocation).
  CellsWithoutSurface cellsWithoutSurface() const {
    if (!occupancy) return {};
    return [cells = occupancy.get()](int64_t i, int64_t j, int64_t k) {
      return cells->state(cells->cellIndex(i, j, k)) != OccupancyCells::kSurface;
    };
  }
  // The hook of every change that lowers a code (drilling): call it after
  // codes[voxel] was lowered to newCode, with newCode the code now stored. O(1)
  // (at most 8 cell states change), nothing without occupancy cells. A code
  // lowered without it can leave a cell marked inside that is not: the smooth
  // point test would then report bone where the interpolation finds none.
  // Raising a code needs buildOccupancy() again.
  void noteLowered(int64_t voxel, VoxelCode newCode) {
    for (const auto& queue : edits) queue->push({voxel, newCode});
    if (occupancy) occupancy->lowered(voxel, newCode);
  }
  // The same, knowing the code before (drilling): a voxel lowered through the
  // outside threshold also turns the cells it empties "outside", so the cells
  // stay exactly what a build would give (OccupancyCells::emptied).
  void noteLowered(int64_t voxel, VoxelCode newCode, VoxelCode oldCode) {
    for (const auto& queue : edits) queue->push({voxel, newCode});
    if (!occupancy) return;
    occupancy->lowered(voxel, newCode);
    if (newCode <= occupancy->outsideCodeMax() && oldCode > occupancy->outsideCodeMax())
      occupancy->emptied(voxel, codes);
  }

  // floor(u), exactly, for the finite u of a grid's range (|u| < 2^62): a
  // truncation corrected for negatives, instead of a call to floor(), which
  // the x86-64 baseline has no instruction for.
  static int64_t floorOf(double u) {
    const int64_t t = int64_t(u);
    return t - (double(t) > u ? 1 : 0);
  }

  bool solidCell(int64_t i, int64_t j, int64_t k) const {
    return inside(i, j, k) && codes[linear(i, j, k)] >= threshold;
  }
  // Voxel of a world point, or -1 outside the grid (also for NaN).
  int64_t voxelOf(const Vec3& p) const {
    const double gx = (p.x() - corner.x()) * inverseSpacing.x();
    const double gy = (p.y() - corner.y()) * inverseSpacing.y();
    const double gz = (p.z() - corner.z()) * inverseSpacing.z();
    if (!(gx >= 0 && gy >= 0 && gz >= 0 && gx < nx && gy < ny && gz < nz)) return -1;
    return linear(int64_t(gx), int64_t(gy), int64_t(gz));
  }
  bool solidAt(const Vec3& p) const {
    if (smooth) {
      // The occupancy cells decide most points with one load, exactly as the
      // interpolation would (OccupancyCells.h); the sweeps' marches and the
      // drilling's look-ahead sample far more points than the surface holds.
      if (occupancy) {
        const double ux = (p.x() - corner.x()) * inverseSpacing.x() - 0.5;
        const double uy = (p.y() - corner.y()) * inverseSpacing.y() - 0.5;
        const double uz = (p.z() - corner.z()) * inverseSpacing.z() - 0.5;
        if (ux > -2 && uy > -2 && uz > -2 && ux < nx + 1 && uy < ny + 1 && uz < nz + 1) {
          const uint8_t state =
              occupancy->state(occupancy->cellIndex(floorOf(ux), floorOf(uy), floorOf(uz)));
          if (state == OccupancyCells::kOutside) return false;
          if (state == OccupancyCells::kInside) return true;
        }
      }
      return codeAt(p) > isoCode;
    }
    const int64_t v = voxelOf(p);
    return v >= 0 && codes[v] >= threshold;
  }
  // Trilinear interpolation of the codes between voxel centres, and optionally
  // its gradient (codes per mm). NaN points give NaN.
  double codeAt(const Vec3& p, Vec3* gradient = nullptr) const {
    // Coordinates relative to voxel centres: centre (i, j, k) is at i + 0.5 from the corner.
    const double ux = (p.x() - corner.x()) * inverseSpacing.x() - 0.5;
    const double uy = (p.y() - corner.y()) * inverseSpacing.y() - 0.5;
    const double uz = (p.z() - corner.z()) * inverseSpacing.z() - 0.5;
    if (!(ux > -2 && uy > -2 && uz > -2 && ux < nx + 1 && uy < ny + 1 && uz < nz + 1)) {
      if (gradient) gradient->setZero();
      return (ux == ux && uy == uy && uz == uz) ? outsideCode : ux + uy + uz;
    }
    const int64_t i = floorOf(ux), j = floorOf(uy), k = floorOf(uz);
    const double fx = double(i), fy = double(j), fz = double(k);
    const double tx = ux - fx, ty = uy - fy, tz = uz - fz;
    double c[2][2][2];
    if (i >= 0 && j >= 0 && k >= 0 && i + 1 < nx && j + 1 < ny && k + 1 < nz) {
      const VoxelCode* base = codes + linear(i, j, k);
      const int64_t sy = nx, sz = int64_t(nx) * ny;
      c[0][0][0] = base[0], c[1][0][0] = base[1], c[0][1][0] = base[sy], c[1][1][0] = base[sy + 1];
      c[0][0][1] = base[sz], c[1][0][1] = base[sz + 1], c[0][1][1] = base[sz + sy], c[1][1][1] = base[sz + sy + 1];
    } else {
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int d = 0; d < 2; ++d) c[a][b][d] = codeAtCell(i + a, j + b, k + d);
    }
    const double c00 = c[0][0][0] + tx * (c[1][0][0] - c[0][0][0]);
    const double c10 = c[0][1][0] + tx * (c[1][1][0] - c[0][1][0]);
    const double c01 = c[0][0][1] + tx * (c[1][0][1] - c[0][0][1]);
    const double c11 = c[0][1][1] + tx * (c[1][1][1] - c[0][1][1]);
    const double c0 = c00 + ty * (c10 - c00), c1 = c01 + ty * (c11 - c01);
    if (gradient) {
      const double dx0 = (c[1][0][0] - c[0][0][0]) + ty * ((c[1][1][0] - c[0][1][0]) - (c[1][0][0] - c[0][0][0]));
      const double dx1 = (c[1][0][1] - c[0][0][1]) + ty * ((c[1][1][1] - c[0][1][1]) - (c[1][0][1] - c[0][0][1]));
      (*gradient)[0] = (dx0 + tz * (dx1 - dx0)) * inverseSpacing.x();
      (*gradient)[1] = ((c10 - c00) + tz * ((c11 - c01) - (c10 - c00))) * inverseSpacing.y();
      (*gradient)[2] = (c1 - c0) * inverseSpacing.z();
    }
    return c0 + tz * (c1 - c0);
  }

  Vec3 centerOf(int64_t linearIndex) const {
    const int64_t i = linearIndex % nx, j = (linearIndex / nx) % ny, k = linearIndex / (int64_t(nx) * ny);
    return corner + Vec3((i + 0.5) * spacing.x(), (j + 0.5) * spacing.y(), (k + 0.5) * spacing.z());
  }
  double smallestSide() const { return spacing.minCoeff(); }
};

}  // namespace trephine::voxel
