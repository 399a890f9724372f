// DriftBound: the haptic frame's bound on how far the nodes are from the
// shape the grids were built on. Checked against the drift measured over every
// node, frame by frame, on nodes that wander and on nodes that vibrate (whose
// summed moves grow without bound while their drift does not).
#include <gtest/gtest.h>

#include <random>

#include "plugins/tetra_brain/DriftBound.h"

namespace trephine::tetra {
namespace {

struct Walk {
  TetGridSet grids;
  std::vector<Vec3> nodes;
};

Walk restingNodes(size_t count) {
  Walk walk;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-50, 50);
  for (size_t i = 0; i < count; ++i) walk.nodes.emplace_back(coordinate(random), coordinate(random), coordinate(random));
  walk.grids.reference = walk.nodes;
  return walk;
}

// Moves every node, returns the largest move (mm).
template <typename Motion>
double moveAll(std::vector<Vec3>& nodes, Motion&& motion) {
  double largest = 0;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Vec3 next = motion(i, nodes[i]);
    largest = std::max(largest, (next - nodes[i]).norm());
    nodes[i] = next;
  }
  return largest;
}

TEST(DriftBound, BoundsTheMeasuredDriftAndIsStaleByAtMostOneRoundOfSlices) {
  Walk walk = restingNodes(1001);  // slices of unequal size
  std::mt19937 random(3);
  std::normal_distribution<double> step(0, 0.01);  // mm per frame
  DriftBound bound;
  double largestMove = 0;
  for (int frame = 0; frame < 400; ++frame) {
    const double move = moveAll(walk.nodes, [&](size_t, const Vec3& p) {
      return Vec3(p + Vec3(step(random), step(random), step(random)));
    });
    largestMove = std::max(largestMove, move);
    const double b = bound.update(walk.grids, walk.nodes, move, 1e9);
    const double drift = driftFromReference(walk.grids, walk.nodes);
    ASSERT_GE(b, drift) << "frame " << frame;
    // Each slice is at most kChunks frames old: its drift then plus the moves since.
    ASSERT_LE(b, drift + DriftBound::kChunks * largestMove + 1e-12) << "frame " << frame;
  }
  EXPECT_EQ(bound.fullMeasurements(), 1u);  // the first frame only
}

TEST(DriftBound, VibratingNodesKeepTheBoundNearTheirAmplitude) {
  // 0.3 mm at 50 Hz: moves up to 0.094 mm a millisecond frame (a brain's
  // surface under a probe moves so), 24 mm of summed moves in 400 frames,
  // while no node is ever more than 0.3 mm away. The bound stays below
  // 0.3 + 8 x 0.094 mm without measuring every node again.
  Walk walk = restingNodes(500);
  DriftBound bound;
  for (int frame = 1; frame <= 400; ++frame) {
    const double phase = 2 * 3.141592653589793 * 50 * frame * 1e-3 + 0.5;
    const double move = moveAll(walk.nodes, [&](size_t i, const Vec3&) {
      return Vec3(walk.grids.reference[i] + Vec3(0, 0, 0.3 * std::sin(phase + 1e-3 * double(i))));
    });
    const double b = bound.update(walk.grids, walk.nodes, move, 1.5);
    ASSERT_GE(b, driftFromReference(walk.grids, walk.nodes));
    ASSERT_LE(b, 0.3 + DriftBound::kChunks * 0.3 * 2 * 3.141592653589793 * 50 * 1e-3 + 1e-9);
  }
  EXPECT_EQ(bound.fullMeasurements(), 1u);
}

TEST(DriftBound, MeasuresEveryNodeAfterUnknownMovesNewGridsAndBeyondTheLimit) {
  Walk walk = restingNodes(64);
  DriftBound bound;
  EXPECT_EQ(bound.update(walk.grids, walk.nodes, 0.0, 1.0), 0.0);
  EXPECT_EQ(bound.fullMeasurements(), 1u);
  walk.nodes[5].x() += 0.25;
  EXPECT_GE(bound.update(walk.grids, walk.nodes, 0.25, 1.0), 0.25);
  EXPECT_EQ(bound.fullMeasurements(), 1u);
  // A move the producer could not report: every node again, exact.
  walk.nodes[9].y() += 0.5;
  EXPECT_NEAR(bound.update(walk.grids, walk.nodes, INFINITY, 1.0), 0.5, 1e-12);
  EXPECT_EQ(bound.fullMeasurements(), 2u);
  // New grids on the current shape: exact again, and zero.
  walk.grids.reference = walk.nodes;
  bound.forget();
  EXPECT_EQ(bound.update(walk.grids, walk.nodes, 0.5, 1.0), 0.0);
  EXPECT_EQ(bound.fullMeasurements(), 3u);
  // A reported move that would pass the limit: measured rather than assumed.
  walk.nodes[1].z() += 0.1;
  EXPECT_NEAR(bound.update(walk.grids, walk.nodes, 2.0, 1.0), 0.1, 1e-12);
  EXPECT_EQ(bound.fullMeasurements(), 4u);
}

}  // namespace
}  // namespace trephine::tetra
