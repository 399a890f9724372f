// The study's exact reference for a burr on a shaft against closed forms: a
// half-space below z = 0 and a tool of burr radius r, shaft radius rho and
// length L, its burr's centre at height h, its shaft tilted theta from
// pointing straight down. The deepest point of the tool is the burr's
// (r - h), or the rim of the shaft's flat end, L cos theta + rho sin theta - h
// below the plane; lying flat (theta = 90 deg) the shaft reaches rho - h.
// And on a ball: a shaft lying along the ball's surface reaches its radius
// below the shaft's axis at the axis's nearest point to the ball's centre.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tools/trephine/study/ExactToolContact.h"

namespace trephine::study {
namespace {

constexpr double kBurr = 2.5, kShaft = 1.0, kLength = 20.0;  // mm
constexpr double kTolerance = 2e-4;                           // mm: the sphere search's and the axis search's

SphereReference spheresOn(const LevelSet& solid) {
  return [solid](const Vec3& c, double r) { return exactSphereContact(solid, c, r); };
}

// The shaft's axis in the tool frame, tilted theta from -z towards +x.
ToolSolid toolTilted(double theta) {
  return {kBurr, kShaft, kLength, Vec3(std::sin(theta), 0, -std::cos(theta))};
}

TEST(ExactToolContactTest, OnAPlaneTheDeepestPointIsTheBurrsOrTheRimOfTheShaftsEnd) {
  const SphereReference plane = spheresOn([](const Vec3& p) { return p.z(); });
  // The tool placed so that the shaft's deepest point is `depth` below the
  // plane (negative: above it), within the sphere search's reach.
  for (const double degrees : {0.0, 20.0, 45.0, 70.0, 89.0, 90.0})
    for (const double depth : {-0.5, 0.05, 0.8, 3.0}) {
      const double theta = degrees * std::numbers::pi / 180;
      const double h = kLength * std::cos(theta) + kShaft * std::sin(theta) - depth;
      const ExactSphereContact c =
          exactToolContact(plane, Pose{Vec3(3, -2, h), Quat::Identity()}, toolTilted(theta));
      const double expected = std::max(kBurr - h, depth);
      if (expected <= 0) {
        EXPECT_LE(c.penetration, kTolerance) << degrees << " deg, depth " << depth;
        continue;
      }
      EXPECT_NEAR(c.penetration, expected, kTolerance) << degrees << " deg, depth " << depth;
      EXPECT_NEAR(c.normal.z(), 1.0, 1e-3) << degrees << " deg, depth " << depth;
    }
}

TEST(ExactToolContactTest, RotatingTheToolTurnsItsShaft) {
  // The same tool pointing down, posed rotated 90 deg about y: the shaft
  // now lies along x, flat on the plane, and reaches rho - h.
  const SphereReference plane = spheresOn([](const Vec3& p) { return p.z(); });
  const Quat quarter(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitY()));
  const ExactSphereContact c = exactToolContact(plane, Pose{Vec3(0, 0, 0.4), quarter}, toolTilted(0));
  EXPECT_NEAR(c.penetration, kBurr - 0.4, kTolerance) << "the burr is the deeper";
  const ToolSolid thinBurr{0.2, kShaft, kLength, -Vec3::UnitZ()};
  EXPECT_NEAR(exactToolContact(plane, Pose{Vec3(0, 0, 0.4), quarter}, thinBurr).penetration, kShaft - 0.4,
              kTolerance);
}

TEST(ExactToolContactTest, AShaftAlongABallReachesItsRadiusBelowTheAxisAtItsNearestPoint) {
  const double ball = 9.3;
  const SphereReference balls = spheresOn([&](const Vec3& p) { return p.norm() - ball; });
  // A small burr far off the ball; the shaft along x at height z over the
  // ball's centre, passing over it at x = 0.
  const ToolSolid tool{0.2, kShaft, kLength, Vec3::UnitX()};
  for (const double z : {9.5, 10.0, 10.2}) {
    const ExactSphereContact c = exactToolContact(balls, Pose{Vec3(-8, 0, z), Quat::Identity()}, tool);
    EXPECT_NEAR(c.penetration, kShaft - (z - ball), kTolerance) << z;
    EXPECT_NEAR(c.normal.z(), 1.0, 1e-3) << z;
  }
}

}  // namespace
}  // namespace trephine::study
