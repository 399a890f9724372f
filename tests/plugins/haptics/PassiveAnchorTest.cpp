// The passive move of a proxy's spring anchor (PassiveAnchor.h): an anchor
// that comes nearer the device is taken as it is; one that would stretch the
// spring beyond last frame's anchor stops where the stretch equals it.
#include <gtest/gtest.h>

#include "plugins/haptics/PassiveAnchor.h"

namespace trephine::haptics {
namespace {

const Vec3 kDevice(0, 0, 0);  // mm
const Vec3 kLast(0, 0, 1);    // mm, last frame's anchor 1 mm above the device

TEST(PassiveAnchorTest, AnAnchorNoFartherThanTheLastIsTakenAsItIs) {
  for (const Vec3& wanted : {Vec3(0, 0, 0.5), Vec3(0.6, 0, 0.8), Vec3(0, 0, 1), Vec3(0, 0, 0)})
    EXPECT_EQ(passiveAnchor(kLast, wanted, kDevice), wanted);
}

TEST(PassiveAnchorTest, ALiftStraightOutKeepsTheLastAnchor) {
  // Out along the spring: any step of it stretches the spring.
  EXPECT_EQ(passiveAnchor(kLast, Vec3(0, 0, 1.2), kDevice), kLast);
}

TEST(PassiveAnchorTest, ASlideWithALiftGoesAsFarAsTheLastStretch) {
  // From (0, 0, 1) towards (1, 0, 1.5): u = (1, 0, 0.5), held = (0, 0, 1);
  // |held + l u| = 1 again at l = -2 held.u / |u|^2 = -2 (0.5) / 1.25 = -0.8 < 0:
  // the lift outweighs the slide, nothing of it is taken.
  EXPECT_EQ(passiveAnchor(kLast, Vec3(1, 0, 1.5), kDevice), kLast);
  // Towards (1, 0, 0.9), which is farther (|.| = 1.345) but comes down:
  // u = (1, 0, -0.1), l = 0.2 / 1.01; the anchor stays on the unit sphere.
  const Vec3 wanted(1, 0, 0.9);
  const Vec3 anchor = passiveAnchor(kLast, wanted, kDevice);
  const double l = 0.2 / 1.01;
  EXPECT_NEAR((anchor - (kLast + l * (wanted - kLast))).norm(), 0.0, 1e-15);
  EXPECT_LE((anchor - kDevice).squaredNorm(), (kLast - kDevice).squaredNorm());
  EXPECT_NEAR((anchor - kDevice).norm(), 1.0, 1e-15);
}

TEST(PassiveAnchorTest, TheBoundIsWhereTheDeviceNowIs) {
  // The device moved 0.3 mm in under a held anchor: the spring may be 1.3 mm.
  const Vec3 device(0, 0, -0.3);
  const Vec3 wanted(0, 0, 1.1);  // a lift of 0.1 mm on top
  EXPECT_EQ(passiveAnchor(kLast, wanted, device), kLast);
  EXPECT_EQ(passiveAnchor(kLast, Vec3(0, 0, 0.9), device), Vec3(0, 0, 0.9));
}

}  // namespace
}  // namespace trephine::haptics
