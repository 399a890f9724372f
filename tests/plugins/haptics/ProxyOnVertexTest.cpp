// A proxy the target holds back renders the spring to the device. Pressed
// straight down onto a vertex or an edge (a tetrahedron's apex, the rim of a
// crack made by duplicate nodes, the corners and edges of a meshed cube, the
// voxel skull), the colliding points' nearest face may be a side face whose
// normal is horizontal: the force must still be k (proxy - device), never
// zero while the device is millimetres beyond the proxy.
#include <gtest/gtest.h>

#include <random>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

constexpr double kStiffness = 0.3;  // N/mm
constexpr double kMaxForce = 10.0;  // N, above every force here

// One tetrahedron whose apex (0, 0, 10) sits on two vertical faces (x = 0 and
// y = 0): a device coming down the z axis runs along their common edge.
const std::string kCornerTet = R"(MeshVersionFormatted 2
Dimension 3
Vertices 4
0 0 0 0
10 0 0 0
0 10 0 0
0 0 10 0
Tetrahedra 1
1 2 3 4 0
End
)";

// The same tetrahedron and its mirror in x = 0 with their own copies of the
// three nodes on that plane: the shared face is two boundary faces, a crack.
const std::string kCrack = R"(MeshVersionFormatted 2
Dimension 3
Vertices 8
0 0 0 0
10 0 0 0
0 10 0 0
0 0 10 0
0 0 0 0
-10 0 0 0
0 10 0 0
0 0 10 0
Tetrahedra 2
1 2 3 4 0
5 7 6 8 0
End
)";

std::string sceneXml(const std::string& target, const Vec3& above, double depth) {
  const Vec3 top = above, bottom = above - Vec3(0, 0, depth);
  auto point = [](double t, const Vec3& p) {
    return std::to_string(t) + " " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " +
           std::to_string(p.z()) + "  ";
  };
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  )" + target +
         R"(
  <ScriptedDevice name="device" record="false" path="waypoints" waypoints=")" +
         point(0, top) + point(0.6, bottom) + point(1.0, bottom) + R"("/>
  <PointshellTool name="probe" radius="2.5" angleStep="15" device="@device"/>
  <GodObjectProxy name="proxy" tool="@probe" target="@target"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness=")" +
         std::to_string(kStiffness) + R"(" damping="0" maxForce=")" + std::to_string(kMaxForce) + R"("/>
</Node>)";
}

struct Held {
  size_t frames = 0;          // frames the proxy is more than 1 mm from the device
  size_t withoutForce = 0;    // of those, frames with no force
  double worstShortfall = 0;  // N, largest k |P - D| - |F| over them
};

Held heldFrames(const Simulation& simulation) {
  Held held;
  const HapticFrameLog& log = simulation.hapticLog();
  for (size_t i = 0; i < log.size(); ++i) {
    const double gap = (log[i].proxy - log[i].device).norm();
    if (gap < 1.0) continue;
    ++held.frames;
    if (log[i].force.norm() < 1e-9) ++held.withoutForce;
    held.worstShortfall = std::max(held.worstShortfall, kStiffness * gap - log[i].force.norm());
  }
  return held;
}

// Pressed 5 mm below where the probe's bottom meets the target, its centre
// starts 10 mm above that.
void expectSpringWhileHeld(const std::string& target, const Vec3& surfacePoint, const std::string& what) {
  const Vec3 above = surfacePoint + Vec3(0, 0, 2.5 + 10.0);
  auto simulation = test::runScene(sceneXml(target, above, 15.0));
  ASSERT_TRUE(simulation) << what;
  const Held held = heldFrames(*simulation);
  EXPECT_GT(held.frames, 100u) << what << ": the target holds the proxy above the device";
  EXPECT_EQ(held.withoutForce, 0u) << what;
  // The spring k (P + skin n - D): within k times the skin (at most 0.1 mm
  // on these targets) of k |P - D|.
  EXPECT_LE(held.worstShortfall, kStiffness * 0.1 + 1e-9) << what;
}

TEST(ProxyOnVertexTest, OnTheApexOfOneTetrahedronTheForceIsTheSpring) {
  test::TempDir dir;
  const auto mesh = dir.write("corner.mesh", kCornerTet);
  expectSpringWhileHeld(R"(<TetraBrain name="target" file=")" + mesh.string() + R"("/>)", Vec3(0, 0, 10), "apex");
}

TEST(ProxyOnVertexTest, OnTheRimOfACrackMadeByDuplicateNodesTheForceIsTheSpring) {
  test::TempDir dir;
  const auto mesh = dir.write("crack.mesh", kCrack);
  const std::string target = R"(<TetraBrain name="target" file=")" + mesh.string() + R"("/>)";
  // Along the ridge over the crack, from the apex (0, 0, 10) to (0, 10, 0).
  std::mt19937 random(7);
  std::uniform_real_distribution<double> along(0.0, 6.0);
  for (int k = 0; k < 4; ++k) {
    const double y = k == 0 ? 0.0 : along(random);
    expectSpringWhileHeld(target, Vec3(0, y, 10 - y), "crack rim at y = " + std::to_string(y));
  }
}

TEST(ProxyOnVertexTest, OnRandomVerticesAndEdgesOfAMeshedCubeTheForceIsTheSpring) {
  // The cube of side 20 mm in 2 x 2 x 2 cells: its top nodes lie on a 10 mm
  // grid, every one a vertex of several boundary faces; edges in between.
  const std::string target = R"(<TetraBrain name="target" file="phantom:cube?cells=2&amp;size=20"/>)";
  std::mt19937 random(11);
  std::uniform_int_distribution<int> node(0, 2);
  std::uniform_real_distribution<double> onEdge(-10.0, 10.0);
  for (int k = 0; k < 6; ++k) {
    Vec3 p(-10.0 + 10.0 * node(random), -10.0 + 10.0 * node(random), 10.0);
    if (k % 2 == 1) p.x() = onEdge(random);  // along an edge of the grid
    expectSpringWhileHeld(target, p, "cube top at (" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ")");
  }
}

TEST(ProxyOnVertexTest, OnRandomPointsOfTheVoxelSkullTheForceIsTheSpring) {
  // The skull phantom's top (outer surface at z = 69.25 mm over the origin);
  // the surface point under the device is found by the force's first contact.
  const std::string target =
      R"(<VoxelSkull name="target" file="phantom:skull?voxel=1.0" isovalue="400" drill="false"/>)";
  std::mt19937 random(13);
  std::uniform_real_distribution<double> across(-20.0, 20.0);
  for (int k = 0; k < 3; ++k) {
    const Vec3 p(across(random), across(random), 69.25);
    expectSpringWhileHeld(target, p, "skull at (" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ")");
  }
}

}  // namespace
}  // namespace trephine
