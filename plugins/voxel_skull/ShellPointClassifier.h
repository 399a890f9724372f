#pragma once
// The per-point voxel test of the collision step, the innermost loop of the
// haptic frame: transform each shell point to the world, find its voxel and
// compare the voxel's code with the solid threshold. Written as flat loops over
// arrays so the compiler vectorises them; compiled twice, for the x86-64
// baseline (SSE2) and for AVX2, and the AVX2 version is chosen at start-up
// when the processor has it (correctness never depends on it). The smooth
// test decides most points from the grid's occupancy cells (OccupancyCells.h)
// and interpolates only in the cells the isosurface may cross; its AVX2 copy
// is written with intrinsics (4 points a lane group, gathers of the cell
// states and of the codes).
#include <cstdint>
#include <span>
#include <vector>

#include "framework/geometry/ShellTool.h"
#include "plugins/voxel_skull/SolidGrid.h"

namespace trephine::voxel {

// A shell in structure-of-arrays form (tool frame, mm), for vector loads.
struct ShellArrays {
  std::vector<double> x, y, z;
  void assign(std::span<const ShellPoint> shell);
  size_t size() const { return x.size(); }
};

// Output per point: the linear voxel index (-1 outside the grid) and whether it is solid.
struct PointTestOutput {
  int64_t* voxel;
  uint8_t* solid;
};

using ShellPointTestFunction = void (*)(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT,
                                        PointTestOutput out);

void testShellPointsBaseline(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT, PointTestOutput out);
// The same against the smooth (trilinear) surface: solid where
// grid.codeAt(p) > grid.isoCode, voxel grid.voxelOf(p), bit for bit, with p
// = R p_T + t as Eigen computes it. The transform and cell lookup run as flat
// loops; with grid.occupancy, points in cells the surface cannot cross are
// decided from the cell's state alone; the rest interpolate (AVX2: 4 points at
// a time with gathers); points near the grid's faces go through
// SolidGrid::codeAt itself.
void testShellPointsSmoothBaseline(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT,
                                   PointTestOutput out);
// The plain one-point-at-a-time smooth test (grid.codeAt and grid.voxelOf per
// point): the reference the fast versions are tested against.
void testShellPointsSmoothScalar(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT,
                                 PointTestOutput out);
#if defined(__x86_64__) && defined(__GNUC__)
#define TREPHINE_HAS_AVX2_PATH 1
void testShellPointsAvx2(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT, PointTestOutput out);
void testShellPointsSmoothAvx2(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT, PointTestOutput out);
#endif
// The fastest version this processor runs, and its instruction set ("avx2" or "sse2").
ShellPointTestFunction bestShellPointTest(bool smooth = false);
const char* bestShellPointTestName();

}  // namespace trephine::voxel
