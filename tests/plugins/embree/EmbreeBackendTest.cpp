// The Embree back-end of VoxelSkull against closed forms: a ball of bone
// (density falling linearly with the distance from its centre, so the
// isovalue is a sphere of radius R) and a spherical burr of radius r at
// centre distance D: penetration R + r - D and normal along the centre's
// direction, also with the burr's centre inside the ball; no contact beyond
// touching; a sweep towards the ball stops where the spheres touch; a ray
// meets the sphere; a burr sunk more than a voxel overlaps visibly.
// Tolerance: the triangles lie within 0.041 mm of the sphere (IsoSurfaceTest).
#include <gtest/gtest.h>

#include <random>

#include "plugins/embree/EmbreeVoxelBackend.h"
#include "plugins/haptics/ShellSampling.h"
#include "tests/support/TestSupport.h"

namespace trephine::embree {
namespace {

constexpr double kBall = 9.3;    // mm, R
constexpr double kBurr = 2.5;    // mm, r
constexpr double kMesh = 0.06;   // mm, the surface's distance from the sphere, with margin
constexpr int kSide = 40;        // voxels of 1 mm

struct Ball {
  Ball() : volume({kSide, kSide, kSide}, Vec3::Ones(), Vec3::Constant(-0.5 * (kSide - 1))) {
    for (int32_t k = 0; k < kSide; ++k)
      for (int32_t j = 0; j < kSide; ++j)
        for (int32_t i = 0; i < kSide; ++i) {
          const Vec3 p = volume.origin() + Vec3(i, j, k);
          volume.setDensity(i, j, k, std::max(0.0, 1000.0 + 100.0 * (kBall - p.norm())));
        }
    grid = voxel::SolidGrid::of(volume, 1000.0, true);
    grid.buildOccupancy();
    backend.bind({&volume, &grid, false});
    for (const Vec3& d : haptics::evenDirections(466)) shell.push_back({kBurr * d, -d});
    backend.reserveShell(shell);
  }
  voxel::DensityVolume volume;
  voxel::SolidGrid grid;
  EmbreeVoxelBackend backend;
  std::vector<ShellPoint> shell;
};

std::vector<Vec3> directions(int count) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  std::vector<Vec3> out;
  for (int n = 0; n < count; ++n) out.push_back(Vec3(normal(rng), normal(rng), normal(rng)).normalized());
  return out;
}

TEST(EmbreeBackendTest, PenetrationAndNormalOfASphereAgainstABallFollowTheClosedForm) {
  Ball ball;
  int contacts = 0;
  for (const Vec3& u : directions(60)) {
    // Shallow, deep, and with the burr's centre 1 mm inside the ball.
    for (const double D : {kBall + kBurr - 0.3, kBall + kBurr - 1.7, kBall - 1.0}) {
      const voxel::VoxelContact c = ball.backend.collide({D * u, Quat::Identity()}, ball.shell, false);
      ASSERT_GT(c.contact.points, 0) << "D " << D;
      EXPECT_NEAR(c.contact.penetration, kBall + kBurr - D, kMesh) << "D " << D;
      // The normal: the closest point of a triangle within 0.06 mm of the
      // sphere, seen from at least 1 mm away, is within about 0.06 rad.
      EXPECT_GT(c.contact.normal.dot(u), std::cos(0.08)) << "D " << D;
      EXPECT_TRUE(c.touched.empty());
      ++contacts;
    }
    // Apart by more than the mesh's error: no contact.
    EXPECT_EQ(ball.backend.collide({(kBall + kBurr + 0.1) * u, Quat::Identity()}, ball.shell, false).contact.points, 0);
  }
  EXPECT_EQ(contacts, 180);
}

TEST(EmbreeBackendTest, ASweepStopsWhereTheSpheresTouchAndARayMeetsTheSphere) {
  Ball ball;
  for (const Vec3& u : directions(30)) {
    SweepQuery q;
    q.from = (kBall + kBurr + 3.0) * u;
    q.to = (kBall + kBurr - 2.0) * u;
    q.probe = SweepProbe::Spheres;
    q.leadingRadius = kBurr;
    q.shell = ball.shell;
    const SweepResult r = ball.backend.sweep(q);
    ASSERT_TRUE(r.blocked);
    EXPECT_FALSE(r.startsInside);
    const double stop = (q.from + r.freeFraction * (q.to - q.from)).norm();
    EXPECT_NEAR(stop, kBall + kBurr, kMesh);
    EXPECT_NEAR(r.contactPoint.norm(), kBall, kMesh);
    // Away from the ball: free.
    q.to = q.from + 2.0 * u;
    EXPECT_FALSE(ball.backend.sweep(q).blocked);

    const auto hit = ball.backend.raycast(20.0 * u, -u, 30.0);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->distance, 20.0 - kBall, kMesh);
    EXPECT_GT(hit->normal.dot(u), std::cos(0.15));  // a triangle's own normal, near the sphere's
  }
}

TEST(EmbreeBackendTest, ABurrSunkMoreThanAVoxelOverlapsVisibly) {
  Ball ball;
  for (const Vec3& u : directions(20)) {
    EXPECT_FALSE(ball.backend.overlaps({(kBall + kBurr - 0.5) * u, Quat::Identity()}, ball.shell));
    EXPECT_TRUE(ball.backend.overlaps({(kBall + kBurr - 1.5) * u, Quat::Identity()}, ball.shell));
    EXPECT_TRUE(ball.backend.overlaps({(kBall - 3.0) * u, Quat::Identity()}, ball.shell));
  }
}

std::string skullScene(const std::string& skullAttributes) {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="embree"/>
  <VoxelSkull name="skull" file="phantom:skull?voxel=3" backend="embree" )" +
         skullAttributes + R"(/>
  <ScriptedDevice name="device" target="@skull" tipOffset="2.5" record="false" path="approach-press-slide"
                  direction="0 0 -1" depth="1" slideDistance="5"/>
  <PointshellTool name="burr" radius="2.5" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@skull" sweep="spheres"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" maxForce="3.3"/>
</Node>)";
}

TEST(EmbreeBackendTest, AScenePicksItByTheBackendFieldAndTheThesisLawIsRefused) {
  // Pressed 1 mm into the skull phantom and slid: the spring of the press,
  // never inside, and the summary names the back-end.
  test::TempDir dir;
  dir.write("scene.xml", skullScene(""));
  std::string output;
  ASSERT_EQ(test::runProgram({"run", (dir / "scene.xml").string(), "--quiet", "--out", (dir / "run").string()}, &output),
            0)
      << output;
  const std::string summary = test::readFile(dir / "run/summary.json");
  EXPECT_NE(summary.find("\"backend\": \"embree\""), std::string::npos);
  EXPECT_NE(summary.find("\"proxy_inside_frames\": 0"), std::string::npos) << summary;

  Diagnostics d;
  EXPECT_FALSE(test::loadScene(skullScene(R"(drill="true" removal="thesis")"), d));
  EXPECT_NE(test::messages(d).find("removal=\"thesis\" cuts the voxels the native back-end's contacts touch"),
            std::string::npos)
      << test::messages(d);
}

}  // namespace
}  // namespace trephine::embree
