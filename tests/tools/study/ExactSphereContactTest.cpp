// The study's exact reference against closed forms: a sphere touching a ball
// (outside and with its centre inside), a plane, and the edge of a box, where
// the closest point is on the crease.
#include <gtest/gtest.h>

#include <random>

#include "tools/trephine/study/ExactSphereContact.h"

namespace trephine::study {
namespace {

constexpr double kRadius = 2.5;      // mm, the sphere
constexpr double kTolerance = 1e-4;  // mm and rad: the search's refinement reaches far below it

std::vector<Vec3> randomDirections(int count) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  std::vector<Vec3> out;
  for (int i = 0; i < count; ++i) out.push_back(Vec3(normal(rng), normal(rng), normal(rng)).normalized());
  return out;
}

TEST(ExactSphereContactTest, ABallGivesRadiusPlusBallMinusDistanceAlongTheCentreLine) {
  const double ball = 9.3;
  const LevelSet solid = [&](const Vec3& p) { return p.norm() - ball; };
  for (const Vec3& u : randomDirections(20))
    for (const double depth : {0.05, 0.8, 2.4, 3.0 /* centre inside the ball */}) {
      const Vec3 centre = (ball + kRadius - depth) * u;
      const ExactSphereContact c = exactSphereContact(solid, centre, kRadius);
      EXPECT_NEAR(c.penetration, depth, kTolerance) << depth;
      EXPECT_LT((c.normal - u).norm(), kTolerance) << depth;
    }
}

TEST(ExactSphereContactTest, APlaneGivesTheDepthAlongItsNormalAndNothingOutOfReach) {
  const Vec3 n = Vec3(0.3, 0.2, 0.93).normalized();
  const LevelSet solid = [&](const Vec3& p) { return p.dot(n); };
  for (const double depth : {0.001, 0.5, 1.5}) {
    const ExactSphereContact c = exactSphereContact(solid, (kRadius - depth) * n + Vec3(1, -2, 0).cross(n), kRadius);
    EXPECT_NEAR(c.penetration, depth, kTolerance);
    EXPECT_LT((c.normal - n).norm(), kTolerance);
  }
  const ExactSphereContact away = exactSphereContact(solid, (kRadius + 0.3) * n, kRadius);
  EXPECT_NEAR(away.penetration, -0.3, kTolerance) << "within the search's reach the gap is measured";
  EXPECT_EQ(away.normal, Vec3::Zero());
  EXPECT_LE(exactSphereContact(solid, (kRadius + 5) * n, kRadius).penetration, -1.0) << "out of reach";
}

TEST(ExactSphereContactTest, AtTheEdgeOfABoxTheNormalPointsFromTheCrease) {
  // The solid x < 0 and z < 0 (a right-angled edge along y): a centre in the
  // quadrant x, z > 0 is closest to the crease line.
  const LevelSet solid = [](const Vec3& p) { return std::max(p.x(), p.z()); };
  const Vec3 centre(1.0, 3.0, 1.5);
  const ExactSphereContact c = exactSphereContact(solid, centre, kRadius);
  const double distance = std::hypot(1.0, 1.5);
  EXPECT_NEAR(c.penetration, kRadius - distance, kTolerance);
  // Along the crease the distance grows only quadratically with the angle,
  // and across it the search's rings find the narrow valley late: the
  // direction is good to 0.006 rad (the distance to 1e-4 mm all the same).
  EXPECT_LT((c.normal - Vec3(1.0, 0, 1.5) / distance).norm(), 0.01);
  // Over a face, the face's normal.
  const ExactSphereContact face = exactSphereContact(solid, Vec3(-1.0, 0, 2.0), kRadius);
  EXPECT_NEAR(face.penetration, 0.5, kTolerance);
  EXPECT_LT((face.normal - Vec3::UnitZ()).norm(), kTolerance);
}

TEST(ExactSphereContactTest, AWallThinnerThanTheSphereIsFoundFromEitherSide) {
  const LevelSet wall = [](const Vec3& p) { return std::abs(p.z()) - 0.25; };  // 0.5 mm thick
  const ExactSphereContact above = exactSphereContact(wall, Vec3(0, 0, 2.0), kRadius);
  EXPECT_NEAR(above.penetration, 0.75, kTolerance);
  EXPECT_LT((above.normal - Vec3::UnitZ()).norm(), kTolerance);
  const ExactSphereContact below = exactSphereContact(wall, Vec3(0, 0, -2.0), kRadius);
  EXPECT_LT((below.normal + Vec3::UnitZ()).norm(), kTolerance);
}

}  // namespace
}  // namespace trephine::study
