#include "plugins/voxel_skull/VoxelTraversal.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trephine::voxel {

namespace {

// Visits the voxels of a -> b inside the grid in order; `visit(voxel, solid, tEnter, enteredAxis)`
// returns true to stop there. Returns whether it stopped.
template <class Visit>
bool traverse(const SolidGrid& grid, const Vec3& a, const Vec3& b, Visit&& visit) {
  // Grid coordinates: voxel (i, j, k) spans [i, i+1) x [j, j+1) x [k, k+1).
  const Vec3 ga = (a - grid.corner).cwiseProduct(grid.inverseSpacing);
  const Vec3 gd = (b - a).cwiseProduct(grid.inverseSpacing);
  if (!ga.allFinite() || !gd.allFinite()) return false;
  const double n[3] = {double(grid.nx), double(grid.ny), double(grid.nz)};
  // Clip the segment to the grid box.
  double t0 = 0, t1 = 1;
  for (int axis = 0; axis < 3; ++axis) {
    if (gd[axis] == 0) {
      if (ga[axis] < 0 || ga[axis] >= n[axis]) return false;
      continue;
    }
    double ta = (0 - ga[axis]) / gd[axis], tb = (n[axis] - ga[axis]) / gd[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return false;

  const Vec3 start = ga + t0 * gd;
  int64_t cell[3];
  int step[3];
  double tNext[3], tDelta[3];
  for (int axis = 0; axis < 3; ++axis) {
    cell[axis] = std::clamp<int64_t>(static_cast<int64_t>(std::floor(start[axis])), 0, int64_t(n[axis]) - 1);
    if (gd[axis] > 0) {
      step[axis] = 1;
      tDelta[axis] = 1.0 / gd[axis];
      tNext[axis] = t0 + (double(cell[axis] + 1) - start[axis]) / gd[axis];
    } else if (gd[axis] < 0) {
      step[axis] = -1;
      tDelta[axis] = -1.0 / gd[axis];
      tNext[axis] = t0 + (double(cell[axis]) - start[axis]) / gd[axis];
    } else {
      step[axis] = 0;
      tDelta[axis] = std::numeric_limits<double>::infinity();
      tNext[axis] = std::numeric_limits<double>::infinity();
    }
  }
  double tEnter = t0;
  int enteredAxis = t0 > 0 ? -2 : -1;  // -2: entered the grid from outside
  const int64_t maxSteps = int64_t(grid.nx) + grid.ny + grid.nz + 3;
  for (int64_t s = 0; s < maxSteps; ++s) {
    const int64_t v = grid.linear(cell[0], cell[1], cell[2]);
    if (visit(v, grid.codes[v] >= grid.threshold, tEnter, enteredAxis)) return true;
    const int axis = tNext[0] < tNext[1] ? (tNext[0] < tNext[2] ? 0 : 2) : (tNext[1] < tNext[2] ? 1 : 2);
    if (tNext[axis] > t1) break;
    tEnter = tNext[axis];
    cell[axis] += step[axis];
    if (cell[axis] < 0 || cell[axis] >= int64_t(n[axis])) break;
    tNext[axis] += tDelta[axis];
    enteredAxis = axis;
  }
  return false;
}

// Where a -> b crosses the smooth surface inside the bracket [lo, hi] of
// fractions, with inside(lo) false and inside(hi) true; returns a fraction
// where inside() is true, at most `tolerance` (a fraction) past the crossing.
// `value` is the signed distance-like code (code - isovalue, growing into the
// inside) whose linear interpolation guesses the crossing: within one sample
// interval (half a voxel) the trilinear density is nearly linear along the
// segment, so a guess and a probe either side of it usually close the
// bracket in 3 to 4 evaluations where bisection takes 20. After 8 guesses
// it falls back to halving, so it always ends.
template <class Inside, class Value>
double refineCrossing(double lo, double hi, double tolerance, Inside&& inside, Value&& value) {
  double valueLo = value(lo), valueHi = value(hi);
  for (int iteration = 0; iteration < 64 && hi - lo > tolerance; ++iteration) {
    const double width = hi - lo;
    double t = 0.5 * (lo + hi);
    if (iteration < 8 && valueHi > valueLo && std::isfinite(valueHi - valueLo)) {
      t = lo + width * std::clamp(-valueLo / (valueHi - valueLo), 0.0, 1.0);
      t = std::clamp(t, lo + 0.25 * tolerance, hi - 0.25 * tolerance);
    }
    // The guess, then a probe half the tolerance beyond it on the other side.
    if (inside(t)) {
      hi = t;
      valueHi = value(t);
      const double probe = t - 0.5 * tolerance;
      if (probe > lo) {
        if (!inside(probe)) return hi;  // bracket [probe, t] within the tolerance
        hi = probe;
        valueHi = value(probe);
      }
    } else {
      lo = t;
      valueLo = value(t);
      const double probe = t + 0.5 * tolerance;
      if (probe < hi) {
        if (inside(probe)) return probe;
        lo = probe;
        valueLo = value(probe);
      }
    }
  }
  return hi;
}

// The fractions [t0, t1] of a -> b within two voxels of the grid, where the
// trilinear interpolation can differ from the space around it; false when
// the segment stays away from the grid.
bool clipToInterpolatedBox(const SolidGrid& grid, const Vec3& a, const Vec3& b, double& t0, double& t1) {
  const Vec3 ga = (a - grid.corner).cwiseProduct(grid.inverseSpacing);
  const Vec3 gd = (b - a).cwiseProduct(grid.inverseSpacing);
  if (!ga.allFinite() || !gd.allFinite()) return true;  // left to the samples, which see NaN as outside
  const double n[3] = {double(grid.nx), double(grid.ny), double(grid.nz)};
  constexpr double kPad = 2.0;  // voxels
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = -kPad, hi = n[axis] + kPad;
    if (gd[axis] == 0) {
      if (ga[axis] < lo || ga[axis] > hi) return false;
      continue;
    }
    double ta = (lo - ga[axis]) / gd[axis], tb = (hi - ga[axis]) / gd[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

// Smooth surface: samples at half the smallest voxel side (a one-voxel wall is
// at least one voxel wide at the isovalue, so no wall fits between two
// samples), then the crossing between the last sample outside and the first
// inside, to 1e-5 mm. Returns the fraction where `inside(t)` first becomes
// true after `skipInitial` samples that already were, or a value > 1.
constexpr double kCrossingTolerance = 1e-5;  // mm

template <class Inside, class Value>
double marchSegment(const SolidGrid& grid, const Vec3& a, const Vec3& b, bool skipInitial, Inside&& inside,
                    Value&& value) {
  const double length = (b - a).norm();
  if (!std::isfinite(length)) return 2.0;
  // Beyond the interpolation's reach around the grid every point is outside
  // (the space around a volume is its lowest density): only the part of the
  // segment near the grid is sampled, so the samples are bounded by the
  // grid's size in voxels, whatever the segment's length in voxels (a ray
  // from 50 mm away onto a volume of 1e-6 mm voxels).
  double t0 = 0, t1 = 1;
  if (grid.outsideCode <= grid.isoCode && !clipToInterpolatedBox(grid, a, b, t0, t1)) return 2.0;
  const int steps = std::max(1, static_cast<int>(std::ceil((t1 - t0) * length / (0.5 * grid.smallestSide()))));
  bool skipping = skipInitial && t0 == 0;
  double previous = t0;
  for (int k = 0; k <= steps; ++k) {
    const double t = t0 + (t1 - t0) * double(k) / steps;
    if (inside(a + t * (b - a))) {
      if (skipping) continue;
      if (k == 0) return t0;
      const auto at = [&](double f) { return a + f * (b - a); };
      return refineCrossing(
          previous, t, length > 0 ? kCrossingTolerance / length : 1.0, [&](double f) { return inside(at(f)); },
          [&](double f) { return value(at(f)); });
    }
    skipping = false;
    previous = t;
  }
  return 2.0;
}
}  // namespace

SegmentHit firstSolidOnSegment(const SolidGrid& grid, const Vec3& a, const Vec3& b, bool skipInitialSolid) {
  SegmentHit result;
  result.startsSolid = grid.solidAt(a);
  if (grid.smooth) {
    const double t = marchSegment(
        grid, a, b, skipInitialSolid, [&](const Vec3& p) { return grid.solidAt(p); },
        [&](const Vec3& p) { return grid.codeAt(p) - grid.isoCode; });
    if (t <= 1.0) {
      result.hit = true;
      result.t = t;
      result.voxel = grid.voxelOf(a + t * (b - a));
    }
    return result;
  }
  bool skipping = skipInitialSolid;
  traverse(grid, a, b, [&](int64_t voxel, bool solid, double tEnter, int enteredAxis) {
    if (solid && !skipping) {
      result = {true, tEnter, result.startsSolid, voxel, enteredAxis};
      return true;
    }
    if (!solid) skipping = false;
    return false;
  });
  return result;
}

double crossingOnSegment(const SolidGrid& grid, const Vec3& a, const Vec3& b, double lo, double hi) {
  const double length = (b - a).norm();
  const auto at = [&](double f) { return a + f * (b - a); };
  return refineCrossing(
      lo, hi, length > 0 ? kCrossingTolerance / length : 1.0, [&](double f) { return grid.solidAt(at(f)); },
      [&](double f) { return grid.codeAt(at(f)) - grid.isoCode; });
}

double firstFreeOnSegment(const SolidGrid& grid, const Vec3& a, const Vec3& b) {
  if (grid.smooth) {
    return std::min(1.0, marchSegment(
                             grid, a, b, false, [&](const Vec3& p) { return !grid.solidAt(p); },
                             [&](const Vec3& p) { return grid.isoCode - grid.codeAt(p); }));
  }
  double found = 1.0;
  const bool stopped = traverse(grid, a, b, [&](int64_t, bool solid, double tEnter, int) {
    if (!solid) found = tEnter;
    return !solid;
  });
  if (stopped) return found;
  // The segment left the grid (outside is free) or stayed in bone to its end.
  const Vec3 ga = (b - grid.corner).cwiseProduct(grid.inverseSpacing);
  const bool endsInGrid =
      ga.x() >= 0 && ga.y() >= 0 && ga.z() >= 0 && ga.x() < grid.nx && ga.y() < grid.ny && ga.z() < grid.nz;
  if (endsInGrid) return 1.0;
  // Where the segment leaves the grid box.
  const Vec3 g0 = (a - grid.corner).cwiseProduct(grid.inverseSpacing);
  const Vec3 gd = ga - g0;
  double t1 = 1.0;
  const double n[3] = {double(grid.nx), double(grid.ny), double(grid.nz)};
  for (int axis = 0; axis < 3; ++axis) {
    if (gd[axis] > 0) t1 = std::min(t1, (n[axis] - g0[axis]) / gd[axis]);
    if (gd[axis] < 0) t1 = std::min(t1, (0 - g0[axis]) / gd[axis]);
  }
  return std::clamp(t1, 0.0, 1.0);
}

}  // namespace trephine::voxel
