#include "plugins/voxel_skull/FootprintCut.h"

#include <algorithm>
#include <cmath>

namespace trephine::voxel {

namespace {

// What every voxel of a cut shares.
struct CutSetup {
  Vec3 center;
  Vec3 direction;
  double inner = 0, outer = 0;  // mm, the radial falloff: weight 1 inside inner, 0 from outer
  double advance = 0;           // mm
  int32_t floorCode = 0;        // codes never fall below this
  int64_t i0 = 0, i1 = -1, j0 = 0, j1 = -1, k0 = 0, k1 = -1;  // the footprint's box of voxels
  int64_t slices = 1, slice = 0;                              // rows cut: (j + k) mod slices == slice
};

CutSetup setupOf(const SolidGrid& grid, const FootprintCut& cut) {
  CutSetup s;
  const double h = grid.smallestSide();
  s.center = cut.center;
  s.direction = cut.direction;
  s.inner = cut.radius + 0.5 * h;
  s.outer = cut.radius + h;
  s.advance = cut.advance;
  s.floorCode = static_cast<int32_t>(std::ceil(grid.emptyCode));
  s.slices = std::max(1, cut.slices);
  s.slice = ((cut.slice % s.slices) + s.slices) % s.slices;
  // Index bounds, clamped as doubles first: a burr far outside the grid must
  // not overflow the conversion to integers.
  const Vec3 lo = (cut.center - Vec3::Constant(s.outer) - grid.corner).cwiseProduct(grid.inverseSpacing);
  const Vec3 hi = (cut.center + Vec3::Constant(s.outer) - grid.corner).cwiseProduct(grid.inverseSpacing);
  const auto first = [](double u, int32_t n) { return int64_t(std::clamp(std::floor(u), 0.0, double(n))); };
  const auto last = [](double u, int32_t n) { return int64_t(std::clamp(std::floor(u), -1.0, double(n - 1))); };
  s.i0 = first(lo.x(), grid.nx), s.i1 = last(hi.x(), grid.nx);
  s.j0 = first(lo.y(), grid.ny), s.j1 = last(hi.y(), grid.ny);
  s.k0 = first(lo.z(), grid.nz), s.k1 = last(hi.z(), grid.nz);
  return s;
}

// The weight of the voxel whose centre is `ox` along x from the burr's centre,
// its row `oy`, `oz` away (alongYZ = oy dy + oz dz, acrossYZ = oy^2 + oz^2):
// 0 behind the burr and beyond the falloff.
inline double weightOf(const CutSetup& s, double ox, double alongYZ, double acrossYZ) {
  const double along = ox * s.direction.x() + alongYZ;
  if (!(along > -kSideCut * s.outer)) return 0;  // behind the burr
  const double distance2 = ox * ox + acrossYZ;
  if (!(distance2 < s.outer * s.outer)) return 0;  // beyond the falloff (before the square root)
  const double distance = std::sqrt(distance2);
  if (!(distance < s.outer)) return 0;
  const double cosine = along / (distance > 0 ? distance : 1.0);  // 0 at the centre itself
  const double facing = std::min(1.0, cosine + kSideCut);         // plus the flutes' side cut
  if (!(facing > 0)) return 0;
  const double u = std::min(1.0, std::max(0.0, (s.outer - distance) / (s.outer - s.inner)));
  return facing * (u * u * (3.0 - 2.0 * u));  // x smoothstep
}

// |gradient| in codes per mm from a voxel's code and its six neighbours, per
// axis the larger one-sided difference: a last layer of bone with air on both
// sides has no central difference at all. Neighbours below the floor count
// as the floor: the cut moves the surface by the contrast between bone and
// what drilling leaves, however deep the air around it (-1000 HU).
inline double slopeOf(const SolidGrid& g, const CutSetup& s, double c, double xm, double xp, double ym, double yp,
                      double zm, double zp) {
  const double floor = s.floorCode;
  xm = std::max(xm, floor), xp = std::max(xp, floor), ym = std::max(ym, floor);
  yp = std::max(yp, floor), zm = std::max(zm, floor), zp = std::max(zp, floor);
  const double gx = std::max(std::abs(c - xm), std::abs(c - xp)) * g.inverseSpacing.x();
  const double gy = std::max(std::abs(c - ym), std::abs(c - yp)) * g.inverseSpacing.y();
  const double gz = std::max(std::abs(c - zm), std::abs(c - zp)) * g.inverseSpacing.z();
  return std::sqrt(gx * gx + gy * gy + gz * gz);
}

// Lowers one voxel by `exact` codes, rounded at random in proportion.
inline void lower(SolidGrid& grid, const CutSetup& s, int64_t voxel, double exact, uint64_t frame,
                  FootprintCutResult& result) {
  if (!(exact > 0)) return;
  exact = std::min(exact, 65536.0);  // codes are 16-bit: a larger fall empties the voxel all the same
  const double whole = double(int64_t(exact));  // floor: exact > 0
  const int32_t step = int32_t(whole) + (unitHash(uint64_t(voxel), frame) < exact - whole ? 1 : 0);
  if (step <= 0) return;
  VoxelCode& code = grid.codes[voxel];
  const int32_t current = code;
  const int32_t lowered = std::max(s.floorCode, current - step);
  if (lowered >= current) return;
  if (current >= grid.threshold && lowered < grid.threshold) ++result.emptied;
  ++result.lowered;
  result.codesRemoved += double(current - lowered);
  code = static_cast<VoxelCode>(lowered);
  grid.noteLowered(voxel, code, VoxelCode(current));  // keeps the point test's occupancy cells exact
}

// One voxel by the plain rule (grid borders included).
inline double exactOf(const SolidGrid& g, const CutSetup& s, int64_t i, int64_t j, int64_t k, double alongYZ,
                      double acrossYZ) {
  const double c = g.codeAtCell(i, j, k);
  if (!(c > s.floorCode)) return 0;
  const double x = g.corner.x() + (double(i) + 0.5) * g.spacing.x();
  const double weight = weightOf(s, x - s.center.x(), alongYZ, acrossYZ);
  if (!(weight > 0)) return 0;
  const double slope = slopeOf(g, s, c, g.codeAtCell(i - 1, j, k), g.codeAtCell(i + 1, j, k), g.codeAtCell(i, j - 1, k),
                               g.codeAtCell(i, j + 1, k), g.codeAtCell(i, j, k - 1), g.codeAtCell(i, j, k + 1));
  return weight * s.advance * slope;
}

// The longest stretch of a row computed at once (rows longer than this, a
// burr of more than 64 voxels across, go in pieces).
constexpr int kRowChunk = 64;

// exact[m] for voxels i0 + m of row (j, k), m < n; those voxels and their six
// neighbours are inside the grid, so they are read by stride without bounds
// checks. Air and voxels outside the footprint are passed over before the
// gradient is taken. (A copy computing 4 voxels at a time with AVX2 measured
// no faster: a row is about 11 voxels, and most of them are passed over.)
inline void rowExactsInterior(const SolidGrid& g, const CutSetup& s, int64_t i0, int n, int64_t j, int64_t k,
                              double alongYZ, double acrossYZ, double* exact) {
  const VoxelCode* row = g.codes + g.linear(i0, j, k);
  const int64_t sy = g.nx, sz = int64_t(g.nx) * g.ny;
  for (int m = 0; m < n; ++m) {
    exact[m] = 0;
    const double c = row[m];
    if (!(c > s.floorCode)) continue;
    const double ox = (g.corner.x() + ((double(i0) + double(m)) + 0.5) * g.spacing.x()) - s.center.x();
    const double weight = weightOf(s, ox, alongYZ, acrossYZ);
    if (!(weight > 0)) continue;
    const double slope = slopeOf(g, s, c, row[m - 1], row[m + 1], row[m - sy], row[m + sy], row[m - sz], row[m + sz]);
    exact[m] = weight * s.advance * slope;
  }
}

// The first j >= j0 of row (j, k) in the cut's slice.
inline int64_t firstRowOfSlice(const CutSetup& s, int64_t k) {
  const int64_t offset = ((s.slice - s.j0 - k) % s.slices + s.slices) % s.slices;
  return s.j0 + offset;
}

// A cut that can remove nothing: not finite, no burr, no advance.
inline bool idle(const FootprintCut& cut) {
  return !cut.center.allFinite() || !cut.direction.allFinite() || !(cut.radius > 0) || !(cut.advance > 0) ||
         !std::isfinite(cut.radius) || !std::isfinite(cut.advance);
}

}  // namespace

FootprintCutResult cutFootprint(SolidGrid& grid, const FootprintCut& cut) {
  FootprintCutResult result;
  if (idle(cut)) return result;
  const CutSetup s = setupOf(grid, cut);
  double exact[kRowChunk];
  for (int64_t k = s.k0; k <= s.k1; ++k) {
    const double oz = grid.corner.z() + (double(k) + 0.5) * grid.spacing.z() - s.center.z();
    for (int64_t j = firstRowOfSlice(s, k); j <= s.j1; j += s.slices) {
      const double oy = grid.corner.y() + (double(j) + 0.5) * grid.spacing.y() - s.center.y();
      // Only the voxels of this row within the footprint's sphere.
      const double acrossYZ = oy * oy + oz * oz;
      const double across2 = s.outer * s.outer - acrossYZ;
      if (!(across2 > 0)) continue;
      const double across = std::sqrt(across2);
      const double alongYZ = oy * s.direction.y() + oz * s.direction.z();
      // (clamped as doubles to the box first: no overflow, and the exact floor of SolidGrid.)
      const int64_t rowFirst = SolidGrid::floorOf(
          std::clamp((s.center.x() - across - grid.corner.x()) * grid.inverseSpacing.x() - 0.5, double(s.i0),
                     double(s.i1) + 1.0));
      const int64_t rowLast = SolidGrid::floorOf(
          std::clamp((s.center.x() + across - grid.corner.x()) * grid.inverseSpacing.x() + 0.5, double(s.i0) - 1.0,
                     double(s.i1)));
      if (rowFirst > rowLast) continue;
      // A row wholly behind the burr has nothing to cut: along is linear in x,
      // so its largest value is at one end of the row.
      const double ox0 = grid.corner.x() + (double(rowFirst) + 0.5) * grid.spacing.x() - s.center.x();
      const double ox1 = grid.corner.x() + (double(rowLast) + 0.5) * grid.spacing.x() - s.center.x();
      if (!(std::max(ox0 * s.direction.x(), ox1 * s.direction.x()) + alongYZ > -kSideCut * s.outer)) continue;
      // A row all air has nothing to cut.
      const VoxelCode* row = grid.codes + grid.linear(0, j, k);
      bool bone = false;
      for (int64_t i = rowFirst; i <= rowLast; ++i) bone |= row[i] > s.floorCode;
      if (!bone) continue;
      const bool interior = rowFirst > 0 && rowLast + 1 < grid.nx && j > 0 && j + 1 < grid.ny && k > 0 &&
                            k + 1 < grid.nz;
      for (int64_t start = rowFirst; start <= rowLast; start += kRowChunk) {
        const int n = int(std::min<int64_t>(kRowChunk, rowLast - start + 1));
        if (interior) {
          rowExactsInterior(grid, s, start, n, j, k, alongYZ, acrossYZ, exact);
        } else {
          for (int m = 0; m < n; ++m) exact[m] = exactOf(grid, s, start + m, j, k, alongYZ, acrossYZ);
        }
        for (int m = 0; m < n; ++m)
          if (exact[m] > 0) lower(grid, s, grid.linear(start + m, j, k), exact[m], cut.frame, result);
      }
    }
  }
  return result;
}

FootprintCutResult cutFootprintReference(SolidGrid& grid, const FootprintCut& cut) {
  FootprintCutResult result;
  if (idle(cut)) return result;
  const CutSetup s = setupOf(grid, cut);
  for (int64_t k = s.k0; k <= s.k1; ++k) {
    const double oz = grid.corner.z() + (double(k) + 0.5) * grid.spacing.z() - s.center.z();
    for (int64_t j = s.j0; j <= s.j1; ++j) {
      if ((j + k) % s.slices != s.slice) continue;
      const double oy = grid.corner.y() + (double(j) + 0.5) * grid.spacing.y() - s.center.y();
      const double acrossYZ = oy * oy + oz * oz;
      const double alongYZ = oy * s.direction.y() + oz * s.direction.z();
      // The row's falls from its codes before any of them falls, then the falls.
      for (int64_t start = s.i0; start <= s.i1; start += kRowChunk) {
        const int n = int(std::min<int64_t>(kRowChunk, s.i1 - start + 1));
        double exact[kRowChunk];
        for (int m = 0; m < n; ++m) exact[m] = exactOf(grid, s, start + m, j, k, alongYZ, acrossYZ);
        for (int m = 0; m < n; ++m) lower(grid, s, grid.linear(start + m, j, k), exact[m], cut.frame, result);
      }
    }
  }
  return result;
}

}  // namespace trephine::voxel
