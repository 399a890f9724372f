#include "plugins/voxel_skull/OccupancyCells.h"

#include <algorithm>
#include <cmath>

#include "plugins/voxel_skull/SolidGrid.h"

namespace trephine::voxel {

std::shared_ptr<OccupancyCells> OccupancyCells::build(const SolidGrid& grid) {
  auto cells = std::make_shared<OccupancyCells>();
  OccupancyCells& o = *cells;
  o.m_nx = grid.nx;
  o.m_ny = grid.ny;
  o.m_nz = grid.nz;
  o.m_voxels = int64_t(grid.nx) * grid.ny * grid.nz;
  o.m_inverseRow = grid.nx > 0 ? 1.0 / grid.nx : 0.0;
  o.m_inversePlane = grid.nx > 0 && grid.ny > 0 ? 1.0 / (double(grid.nx) * grid.ny) : 0.0;
  o.m_strideY = grid.nx + 3;
  o.m_strideZ = (grid.nx + 3) * (grid.ny + 3);
  const int64_t cellCount = int64_t(o.m_strideZ) * (grid.nz + 3);
  // 8 spare bytes: the point test may read a 32-bit word at any cell's byte.
  o.m_states.assign(size_t((cellCount + 3) / 4 + 8), 0);

  // Clearly outside: at most iso - margin; clearly inside: at least iso + margin.
  // The trilinear interpolation of values of magnitude M rounds by less than
  // 16 M 2^-53 (three levels of a + t (b - a)), 1e-15 M; the margin is 1e-6 M.
  const double iso = grid.isoCode, outside = grid.outsideCode;
  const bool finite = std::isfinite(iso) && std::isfinite(outside);
  const double magnitude = std::max({32768.0, finite ? std::abs(iso) : 0.0, finite ? std::abs(outside) : 0.0});
  const double margin = 1e-6 * (1 + magnitude);
  // Codes are int16: thresholds beyond +-40000 mean "no code qualifies".
  o.m_outsideCode = finite ? int32_t(std::clamp(std::floor(iso - margin), -40000.0, 40000.0)) : -40000;
  o.m_insideCode = finite ? int32_t(std::clamp(std::ceil(iso + margin), -40000.0, 40000.0)) : 40000;
  // Per corner: bit 0 clearly outside, bit 1 clearly inside; a cell keeps the AND of its 8 corners.
  const uint8_t outsideClass =
      finite ? uint8_t((outside <= iso - margin ? 1 : 0) | (outside >= iso + margin ? 2 : 0)) : uint8_t(0);
  const int32_t lowCode = o.m_outsideCode, highCode = o.m_insideCode;
  o.m_aroundIsOutside = (outsideClass & 1) != 0;

  const int64_t nx = grid.nx, ny = grid.ny, nz = grid.nz;
  const int64_t cx = nx + 4, cy = ny + 4;  // corners -2..n+1 per axis
  const int64_t lx = nx + 3, ly = ny + 3;  // cells -2..n
  std::vector<uint8_t> corners(size_t(cx * cy)), rows(size_t(lx * cy));
  std::vector<uint8_t> layer(size_t(lx * ly)), previous(size_t(lx * ly));
  for (int64_t kc = 0; kc < nz + 4; ++kc) {  // padded corner layer kc: k = kc - 2
    const int64_t k = kc - 2;
    std::fill(corners.begin(), corners.end(), outsideClass);
    if (k >= 0 && k < nz) {
      for (int64_t j = 0; j < ny; ++j) {
        const VoxelCode* row = grid.codes + nx * (j + ny * k);
        uint8_t* out = corners.data() + cx * (j + 2) + 2;
        for (int64_t i = 0; i < nx; ++i)
          out[i] = uint8_t((row[i] <= lowCode ? 1 : 0) | (row[i] >= highCode ? 2 : 0));
      }
    }
    // Along x, then y: the 4 corners of each cell in this layer.
    for (int64_t j = 0; j < cy; ++j)
      for (int64_t i = 0; i < lx; ++i) rows[j * lx + i] = corners[j * cx + i] & corners[j * cx + i + 1];
    for (int64_t j = 0; j < ly; ++j)
      for (int64_t i = 0; i < lx; ++i) layer[j * lx + i] = rows[j * lx + i] & rows[(j + 1) * lx + i];
    // Cells of padded layer kc - 1 span corner layers kc - 1 and kc.
    if (kc > 0) {
      const int64_t first = (kc - 1) * lx * ly;
      for (int64_t c = 0; c < lx * ly; ++c) {
        const uint8_t both = previous[c] & layer[c];
        const uint8_t state = (both & 2) ? kInside : (both & 1) ? kOutside : kSurface;
        const int64_t cell = first + c;
        o.m_states[size_t(cell >> 2)] |= uint8_t(state << (int(cell & 3) * 2));
      }
    }
    std::swap(previous, layer);
  }
  return cells;
}

void OccupancyCells::emptied(int64_t voxel, const VoxelCode* codes) {
  if (voxel < 0 || voxel >= m_voxels || codes[voxel] > m_outsideCode) return;
  int64_t i, j, k;
  split(voxel, i, j, k);
  const auto cornerOutside = [&](int64_t a, int64_t b, int64_t c) {
    if (a < 0 || b < 0 || c < 0 || a >= m_nx || b >= m_ny || c >= m_nz) return m_aroundIsOutside;
    return codes[a + int64_t(m_nx) * (b + int64_t(m_ny) * c)] <= m_outsideCode;
  };
  for (int cell = 0; cell < 8; ++cell) {
    // Cells with base corners i - 1 and i per axis: this voxel is one of their corners.
    const int64_t a = i - 1 + (cell & 1), b = j - 1 + ((cell >> 1) & 1), c = k - 1 + (cell >> 2);
    const int64_t index = cellIndex(a, b, c);
    if (state(index) == kOutside) continue;
    bool outside = true;
    for (int corner = 0; corner < 8 && outside; ++corner)
      outside = cornerOutside(a + (corner & 1), b + ((corner >> 1) & 1), c + (corner >> 2));
    if (!outside) continue;
    uint8_t& byte = m_states[size_t(index >> 2)];
    const int shift = int(index & 3) * 2;
    byte = uint8_t((byte & ~(3 << shift)) | (kOutside << shift));
  }
}

}  // namespace trephine::voxel
