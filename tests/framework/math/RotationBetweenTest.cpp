// rotationBetween: the shortest turn from one direction to another, and a
// half turn that takes one onto the other where they are opposite.
#include <gtest/gtest.h>

#include <random>

#include "framework/math/Math.h"

namespace trephine {
namespace {

Vec3 randomDirection(std::mt19937& random) {
  std::normal_distribution<double> normal;
  return Vec3(normal(random), normal(random), normal(random)) * std::exp(normal(random));  // any length
}

TEST(RotationBetweenTest, IsTheTurnAboutTheNormalOfBothByTheAngleBetweenThem) {
  // Against an independent construction (an angle and an axis; Eigen's FromTwoVectors would
  // instantiate the SVD this function exists to avoid).
  std::mt19937 random(7);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 from = i % 3 == 0 ? Vec3::UnitZ() : randomDirection(random), to = randomDirection(random);
    const Vec3 a = from.normalized(), b = to.normalized();
    const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
    const Quat expected(Eigen::AngleAxisd(angle, a.cross(b).normalized()));
    const Quat q = rotationBetween(from, to);
    ASSERT_LT(q.angularDistance(expected), 1e-15 * (10 + 1 / a.cross(b).norm())) << from.transpose() << " to " << to.transpose();
    ASSERT_NEAR(q.norm(), 1.0, 1e-15);
    // Near opposite directions the axis is a short cross product: its rounding over its length.
    ASSERT_LT((q * a - b).norm(), 1e-15 * (10 + 1 / a.cross(b).norm()));
  }
}

TEST(RotationBetweenTest, TakesADirectionOntoItsOppositeByAHalfTurn) {
  std::mt19937 random(11);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 from = i == 0 ? Vec3::UnitZ() : randomDirection(random);
    const Vec3 to = -2.5 * from + (i % 2 ? Vec3::Zero() : Vec3(1e-14, 0, 0));  // opposite, or all but
    const Quat q = rotationBetween(from, to);
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    EXPECT_LT((q * from.normalized() - to.normalized()).norm(), 1e-12) << from.transpose();
    EXPECT_NEAR(std::abs(q.w()), 0.0, 1e-6) << "a half turn";
  }
}

TEST(RotationBetweenTest, IsNoTurnForOneDirectionAndTheShortestTurnBetweenTwo) {
  std::mt19937 random(13);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 from = randomDirection(random), to = randomDirection(random);
    EXPECT_LT(rotationBetween(from, 3 * from).angularDistance(Quat::Identity()), 1e-15);
    // Shortest: its axis is normal to both, its angle the one between them.
    const Quat q = rotationBetween(from, to);
    const Eigen::AngleAxisd turn(q);
    const double between = std::acos(std::clamp(from.normalized().dot(to.normalized()), -1.0, 1.0));
    EXPECT_NEAR(turn.angle(), between, 1e-9);
    EXPECT_NEAR(turn.axis().dot(from.normalized()), 0, 1e-9);
    EXPECT_NEAR(turn.axis().dot(to.normalized()), 0, 1e-9);
  }
}

}  // namespace
}  // namespace trephine
