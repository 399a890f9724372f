#pragma once
// A bound on how far the nodes of a deforming mesh are from the shape its
// grids were built on, kept every haptic frame at a small fixed cost.
//
// Measuring every node each frame costs tens of microseconds on a brain of a
// few thousand nodes once the FEM has pushed the positions out of this
// core's caches. Instead the nodes are split into kChunks slices, one slice
// is measured per frame, and each slice's measurement is grown by the
// producer's largest node move since it was taken:
//   drift <= max over slices (measured_s + moves since slice s was measured).
// Every node is measured at once only after new grids, a frame whose moves are
// unknown (skipped or not reported), or when the bound passes `limit`.
#include <array>
#include <cstdint>
#include <span>

#include "framework/math/Math.h"
#include "plugins/tetra_brain/TetGridSet.h"

namespace trephine::tetra {

class DriftBound {
 public:
  static constexpr size_t kChunks = 8;

  // The next update() measures every node.
  void forget() { m_known = false; }
  // `largestMove`: mm, no node moved farther since the previous update
  // (infinite when unknown). Returns mm, no node of `nodes` is farther than
  // this from `grids.reference`; measures every node when the grown bound
  // would pass `limit`. Allocation-free.
  double update(const TetGridSet& grids, std::span<const Vec3> nodes, double largestMove, double limit);
  uint64_t fullMeasurements() const { return m_fullMeasurements; }

 private:
  void measureAll(const TetGridSet& grids, std::span<const Vec3> nodes);
  double bound() const;

  bool m_known = false;
  double m_moves = 0;                    // mm, sum of the largest moves since the last full measurement
  std::array<double, kChunks> m_drift{};  // mm, per slice, when measured
  std::array<double, kChunks> m_movesAt{};  // m_moves when the slice was measured
  size_t m_next = 0;                      // slice measured next frame
  uint64_t m_fullMeasurements = 0;
};

}  // namespace trephine::tetra
