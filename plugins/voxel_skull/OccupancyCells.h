#pragma once
// Which interpolation cells the smooth surface may cross: the coarse level of
// the smooth per-point test (ShellPointClassifier.cpp).
//
// A cell is the box between 8 neighbouring voxel centres, (i..i+1, j..j+1,
// k..k+1); the trilinear density of any point in it interpolates those 8
// codes. When all 8 are clearly at or below the isovalue, every point of the
// cell is outside the bone; when all 8 are clearly above it, every point is
// inside; only the other cells (the surface's, a band about one voxel thick)
// need the 8 loads and the interpolation. "Clearly" keeps a margin of 1e-6
// (of the largest code magnitude) to the isovalue, far above the rounding of
// the interpolation (about 1e-15 of it), so a decided cell gives exactly the
// answer the interpolation would: the fast test and SolidGrid::codeAt agree
// point for point.
//
// Cells are kept for base corners -2..n (each axis), so the cells around the
// grid, whose outer corners take the grid's outsideCode, are classified too;
// points farther out never interpolate. 2 bits per cell, 4 cells a byte:
// (nx+3)(ny+3)(nz+3)/4 bytes, 0.25 byte per voxel (Skull5, 48.5 M voxels:
// 12.3 MB beside the 97 MB of codes).
//
// Drilling only lowers codes. A lowered code can turn an "inside" cell into a
// surface cell, never an "outside" one into anything else, so lowered()
// updates the 8 cells around the voxel in O(1); and once a voxel falls
// through the outside threshold, emptied() turns those of its cells whose
// corners are now all clearly outside into "outside" ones, so a drilled hole
// is decided without interpolating again and the cells stay what a build
// would give. Raising a code needs a new build.
#include <cstdint>
#include <memory>
#include <vector>

#include "framework/data/DensityVolume.h"

namespace trephine::voxel {

struct SolidGrid;

class OccupancyCells {
 public:
  // Cell states (2 bits): surface (interpolate), decided outside, decided inside.
  static constexpr uint8_t kSurface = 0, kOutside = 1, kInside = 3;

  // From the grid's codes, isoCode and outsideCode; O(voxels), about 5 ns a voxel.
  static std::shared_ptr<OccupancyCells> build(const SolidGrid& grid);

  // The hook: voxel `voxel` (linear index) now holds `newCode`, lower than (or
  // equal to) the code it held. O(1): when newCode is no longer clearly above
  // the isovalue, the up to 8 cells with this voxel as a corner that were
  // "inside" become surface cells. Indices outside the grid are ignored.
  void lowered(int64_t voxel, VoxelCode newCode) {
    if (newCode >= m_insideCode || voxel < 0 || voxel >= m_voxels) return;
    // voxel = i + nx (j + ny k), without divisions (exact below 2^52 voxels)
    int64_t i, j, k;
    split(voxel, i, j, k);
    // Cells with bases i-1 and i: padded indices i+1 and i+2.
    const int64_t first = cellIndex(i - 1, j - 1, k - 1);
    for (int c = 0; c < 8; ++c) {
      const int64_t cell = first + (c & 1) + m_strideY * ((c >> 1) & 1) + m_strideZ * (c >> 2);
      uint8_t& byte = m_states[size_t(cell >> 2)];
      const int shift = int(cell & 3) * 2;
      if (((byte >> shift) & 3) == kInside) byte = uint8_t(byte & ~(3 << shift));
    }
  }

  // The hook of drilling through the outside threshold: voxel `voxel` now
  // holds a code clearly outside (at most outsideCodeMax) and held one that
  // was not. Each of the up to 8 cells with this voxel as a corner whose 8
  // corner codes (`codes`, the grid's; the space around the grid counts as its
  // outsideCode) are all clearly outside now becomes an "outside" cell, as a
  // build would find it, so points in a drilled hole are decided again without
  // interpolating. At most 64 code reads, once per voxel.
  void emptied(int64_t voxel, const VoxelCode* codes);

  // Index of the cell with base corner (i, j, k), each in -2..n.
  int64_t cellIndex(int64_t i, int64_t j, int64_t k) const { return (i + 2) + m_strideY * (j + 2) + m_strideZ * (k + 2); }
  uint8_t state(int64_t cell) const { return (m_states[size_t(cell >> 2)] >> (int(cell & 3) * 2)) & 3; }
  // For the point test: 4 cells a byte, cell c in bits 2(c & 3) of byte c >> 2.
  const uint8_t* states() const { return m_states.data(); }
  int32_t strideY() const { return m_strideY; }  // nx + 3
  int32_t strideZ() const { return m_strideZ; }  // (nx + 3)(ny + 3)
  size_t bytes() const { return m_states.size(); }
  // Codes at or below outsideCodeMax are clearly outside, at or above insideCode clearly inside.
  int32_t outsideCodeMax() const { return m_outsideCode; }
  int32_t insideCode() const { return m_insideCode; }

 private:
  std::vector<uint8_t> m_states;
  int32_t m_nx = 0, m_ny = 0, m_nz = 0;
  int64_t m_voxels = 0;
  double m_inverseRow = 0, m_inversePlane = 0;  // 1 / nx, 1 / (nx ny)
  int32_t m_strideY = 0, m_strideZ = 0;
  int32_t m_outsideCode = 0, m_insideCode = 0;
  bool m_aroundIsOutside = false;  // the grid's outsideCode is clearly outside
  // (i, j, k) of a linear voxel index, without divisions.
  void split(int64_t voxel, int64_t& i, int64_t& j, int64_t& k) const {
    const int64_t plane = int64_t(m_nx) * m_ny;
    k = int64_t(double(voxel) * m_inversePlane);
    k -= k * plane > voxel;
    k += (k + 1) * plane <= voxel;
    const int64_t inPlane = voxel - k * plane;
    j = int64_t(double(inPlane) * m_inverseRow);
    j -= j * m_nx > inPlane;
    j += (j + 1) * m_nx <= inPlane;
    i = inPlane - j * m_nx;
  }
};

}  // namespace trephine::voxel
