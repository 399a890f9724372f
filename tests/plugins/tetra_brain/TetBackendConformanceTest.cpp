// Every collision back-end of TetraBrain answers the same queries on the same
// mesh against closed forms, with its own stated tolerance: a 200 mm cube of
// tetrahedra (its top face the plane z = 100) and a spherical burr of radius
// r = 2.5 mm. Penetration from grazing to a centre below the face, with the
// normal +z; a burr at an edge of the cube (mesh back-ends: the exact
// distance to the edge); a head-on sweep stops where the burr touches; a ray
// meets the face; a burr sunk a millimetre overlaps visibly, one grazing does
// not; the reaction on the nodes sums to the contact force. On a deforming
// mesh, every back-end gives exactly what it gives for the same shape built
// rigid, with the nodes moved within and far beyond its margin (the native
// grids' displacement margin; the mesh back-ends' refit margin, beyond which
// their trees are rebuilt). The tolerances are the methods' own errors:
//  - native: the deepest of 266 shell points; the lowest sits at
//    z = -r (1 - 1/266), 0.0094 mm above the sphere's bottom;
//  - embree and bullet: the closest point to the exact sphere, exact to
//    round-off (embree's BVH is in single precision: 1e-4 mm).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "framework/core/ChannelHub.h"
#include "framework/core/Diagnostics.h"
#include "framework/runtime/Simulation.h"
#include "plugins/tetra_brain/MeshTetBackend.h"
#include "tests/plugins/tetra_brain/TetTestShapes.h"
#include "tests/support/BrainProbe.h"
#include "tests/support/TestSupport.h"
#ifdef TREPHINE_HAS_EMBREE_BACKEND
#include "plugins/embree/EmbreeEngine.h"
#endif
#ifdef TREPHINE_HAS_BULLET_BACKEND
#include "plugins/bullet/BulletEngine.h"
#endif

namespace trephine::tetra {
namespace {

constexpr double kBurr = 2.5;  // mm
constexpr int kCells = 10;     // 20 mm cells

struct Backend {
  std::string name;
  std::function<std::unique_ptr<TetBackend>()> create;
  double penetration;  // mm, allowed error of the penetration
  double distance;     // mm, allowed error of a sweep's stop and a ray's hit
  bool exactSphere;    // treats the burr as the exact sphere (the edge's closed form applies)
};

void PrintTo(const Backend& backend, std::ostream* os) { *os << backend.name; }

std::vector<Backend> backends() {
  std::vector<Backend> list = {{"native", [] { return std::make_unique<NativeTetBackend>(); }, 0.01, 1e-6, false}};
#ifdef TREPHINE_HAS_EMBREE_BACKEND
  list.push_back({"embree", [] { return std::make_unique<MeshTetBackend>(std::make_unique<embree::EmbreeEngine>()); },
                  1e-4, 1e-3, true});
#endif
#ifdef TREPHINE_HAS_BULLET_BACKEND
  list.push_back({"bullet", [] { return std::make_unique<MeshTetBackend>(std::make_unique<bullet::BulletEngine>()); },
                  1e-6, 1e-3, true});
#endif
  return list;
}

// Vertical spherical wave from (0, 0, 100): amplitude A (mm), wavelength 120 mm.
std::vector<Vec3> waved(const std::vector<Vec3>& rest, double A, double phase) {
  std::vector<Vec3> moved = rest;
  for (Vec3& p : moved) p.z() += A * std::sin(2 * std::numbers::pi * (p - Vec3(0, 0, 100)).norm() / 120.0 - phase);
  return moved;
}

class TetBackendConformanceTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override {
    shell = shapes::sphereShell(kBurr, 266);
    brain.setBackend(GetParam().create());
    shapes::cubeBrain(brain, kCells);
    memory_brain_shell = brain.reserveShell(shell);
  }
  ShellContact touch(const Vec3& centre) {
    return brain.collide(Pose{centre, Quat::Identity()}, shell, false, memory_brain_shell);
  }

  std::vector<ShellPoint> shell;
  TetraBrain brain;
  ContactMemory memory_brain_shell;
};

TEST_P(TetBackendConformanceTest, ContactWithTheTopFaceFollowsTheClosedFormFromGrazingToBelowIt) {
  const Backend& b = GetParam();
  // Penetrations from grazing to a centre 0.5 mm below the face (3 mm).
  for (const double p : {0.02, 0.3, 1.0, 2.2, 3.0}) {
    for (const Vec3& xy : {Vec3(0, 0, 0), Vec3(31.7, -12.2, 0), Vec3(20, 20, 0)}) {  // (20, 20): a mesh vertex
      const ShellContact c = touch(xy + Vec3(0, 0, 100 + kBurr - p));
      SCOPED_TRACE(b.name + " p " + std::to_string(p) + " at " + std::to_string(xy.x()) + "," + std::to_string(xy.y()));
      ASSERT_GT(c.points, 0);
      EXPECT_NEAR(c.penetration, p, b.penetration);
      EXPECT_GT(c.normal.z(), 1 - 1e-9) << c.normal.transpose();
    }
  }
  EXPECT_EQ(touch(Vec3(5, 5, 100 + kBurr + 0.01)).points, 0);
}

TEST_P(TetBackendConformanceTest, AtAnEdgeOfTheCubeTheExactSphereMeasuresToTheEdge) {
  const Backend& b = GetParam();
  if (!b.exactSphere) GTEST_SKIP() << "the pointshell measures each point to its nearest face, not the edge";
  // The centre outside both faces of the edge x = 100, z = 100, 1.7 mm from it.
  const Vec3 centre(100 + 1.2, 7.0, 100 + std::sqrt(1.7 * 1.7 - 1.2 * 1.2));
  const ShellContact c = touch(centre);
  ASSERT_GT(c.points, 0);
  EXPECT_NEAR(c.penetration, kBurr - 1.7, b.penetration);
  // Between the two faces' normals (their weighted mean).
  EXPECT_GT(c.normal.x(), 0.1);
  EXPECT_GT(c.normal.z(), 0.1);
  EXPECT_NEAR(c.normal.y(), 0.0, 1e-9);
}

TEST_P(TetBackendConformanceTest, AHeadOnSweepStopsWhereTheBurrTouchesAndARayMeetsTheFace) {
  const Backend& b = GetParam();
  SweepQuery q;
  q.from = Vec3(3, -4, 100 + kBurr + 5);
  q.to = Vec3(3, -4, 100 + kBurr - 2);
  q.leadingRadius = kBurr;
  q.shell = shell;
  const SweepResult s = brain.sweep(q);
  ASSERT_TRUE(s.blocked);
  EXPECT_NEAR(s.freeFraction * 7.0, 5.0, b.distance);
  EXPECT_FALSE(s.startsInside);
  const auto hit = brain.raycast(Vec3(10, 20, 150), Vec3(0, 0, -1), 100);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->distance, 50.0, b.distance);
  EXPECT_GT(hit->normal.z(), 1 - 1e-9);
  EXPECT_FALSE(brain.raycast(Vec3(10, 20, 150), Vec3(0, 0, 1), 100));
}

TEST_P(TetBackendConformanceTest, ABurrSunkAMillimetreOverlapsVisiblyOneGrazingDoesNot) {
  const Pose sunk{Vec3(1, 2, 100 + kBurr - 1.0), Quat::Identity()};
  const Pose grazing{Vec3(1, 2, 100 + kBurr - 0.2), Quat::Identity()};
  EXPECT_TRUE(brain.overlaps(sunk, shell));
  EXPECT_FALSE(brain.overlaps(grazing, shell));
  EXPECT_TRUE(brain.overlaps({Vec3(0, 0, 50), Quat::Identity()}, shell));  // deep inside
}

TEST_P(TetBackendConformanceTest, TheReactionOnTheNodesSumsToTheContactForce) {
  ChannelHub hub;
  brain.connectChannels(hub);
  auto forces = hub.subscribe<NodeForces>(brain, kNodeForcesChannel);
  brain.prepare(RunPlan{});
  const Vec3 force(0.3, -0.2, -1.5);
  const ShellContact contact = touch(Vec3(13, -7, 100 + kBurr - 0.8));
  ASSERT_GT(contact.points, 0);
  shapes::respondAlone(brain, shapes::pressing(0.25, force, contact.sites));
  ASSERT_TRUE(forces.fetch());
  Vec3 sum = Vec3::Zero();
  // On the nodes of the touched triangle (mesh back-ends), or of the
  // tetrahedra holding the colliding points (native: within a cell of the face).
  const double reach = GetParam().exactSphere ? 1e-9 : 200.0 / kCells + 1e-9;
  for (const NodeForce& f : forces.read().forces) {
    EXPECT_GE(brain.node(f.node).z(), 100.0 - reach);
    sum += f.force;
  }
  EXPECT_NEAR((sum - force).norm(), 0.0, 1e-12);
}

// Every back-end takes a burr on a shaft (Embree point by point, Bullet
// through its solid), and the reaction of its contact reaches the nodes of
// the face it presses, whole.
TEST_P(TetBackendConformanceTest, ABurrOnAShaftPressesOnTheNodesOfTheFaceItTouches) {
  constexpr double r = 1.0, L = 20.0;
  std::vector<ShellPoint> capsule = shapes::sphereShell(kBurr, 266);
  for (int k = 0; k <= 40; ++k)
    for (int i = 0; i < 12; ++i) {
      const Vec3 radial(std::cos(2 * std::numbers::pi * i / 12), std::sin(2 * std::numbers::pi * i / 12), 0);
      capsule.push_back({r * radial + (2.3 + (L - 2.3) * k / 40.0) * Vec3::UnitZ(), -radial});
    }
  ContactMemory memory = brain.reserveShell(capsule);
  brain.describeTool(capsule, ToolSolid{kBurr, r, L, Vec3::UnitZ()});
  ChannelHub hub;
  brain.connectChannels(hub);
  auto forces = hub.subscribe<NodeForces>(brain, kNodeForcesChannel);
  brain.prepare(RunPlan{});
  const ShellContact contact =
      brain.collide(Pose{Vec3(13, -7, 100 + kBurr - 0.8), Quat::Identity()}, capsule, false, memory);
  ASSERT_GT(contact.points, 0);
  EXPECT_NEAR(contact.penetration, 0.8, 0.05);
  const Vec3 force(0.3, -0.2, -1.5);
  shapes::respondAlone(brain, shapes::pressing(0.25, force, contact.sites));
  ASSERT_TRUE(forces.fetch());
  ASSERT_FALSE(forces.read().forces.empty()) << "the reaction reached no node";
  Vec3 sum = Vec3::Zero();
  for (const NodeForce& f : forces.read().forces) {
    EXPECT_GE(brain.node(f.node).z(), 100.0 - 200.0 / kCells - 1e-9);
    sum += f.force;
  }
  EXPECT_NEAR((sum - force).norm(), 0.0, 1e-12);
}

TEST_P(TetBackendConformanceTest, ADeformingMeshAnswersAsTheSameShapeBuiltRigidWithinAndBeyondItsMargin) {
  const Backend& b = GetParam();
  Component producer;
  ChannelHub hub;
  auto& channel = hub.publish<NodePositions>(producer, kNodePositionsChannel);
  ASSERT_FALSE(brain.followDeformation(producer, hub).has_value());
  ContactMemory memory_brain_shell = brain.reserveShell(shell);
  const std::vector<Vec3> rest = brain.mesh().nodes;
  uint64_t step = 0;
  // Half the 20 mm edges' quarter (the native margin, 5 mm) and half edge
  // (the refit margin, 10 mm), and far beyond both.
  for (const double amplitude : {1.0, 4.0, 12.0}) {
    for (const double phase : {0.0, 1.3}) {
      NodePositions frame;
      frame.step = ++step;
      frame.positions = waved(rest, amplitude, phase);
      frame.displacementBound = amplitude;
      channel.publish(frame);
      brain.beginFrame(1e-3 * double(step));
      TetraBrain rigid;
      rigid.setBackend(b.create());
      TetMesh shape = brain.mesh();
      shape.nodes = frame.positions;
      rigid.setMesh(shape);
      ContactMemory memory_rigid_shell = rigid.reserveShell(shell);
      for (const Vec3& xy : {Vec3(0, 0, 0), Vec3(31.4, -12.9, 0), Vec3(-70, 55, 0)}) {
        const double top = 100 + amplitude * std::sin(2 * std::numbers::pi * xy.norm() / 120.0 - phase);
        for (const double press : {0.4, 1.3}) {
          const Pose pose{xy + Vec3(0, 0, top + kBurr - press), Quat::Identity()};
          SCOPED_TRACE(b.name + " amplitude " + std::to_string(amplitude) + " press " + std::to_string(press));
          const ShellContact moving = brain.collide(pose, shell, false, memory_brain_shell),
                             built = rigid.collide(pose, shell, false, memory_rigid_shell);
          EXPECT_EQ(moving.points, built.points);
          EXPECT_NEAR(moving.penetration, built.penetration, 1e-9);
          EXPECT_NEAR((moving.normal - built.normal).norm(), 0.0, 1e-9);
          EXPECT_EQ(brain.overlaps(pose, shell), rigid.overlaps(pose, shell));
          SweepQuery q;
          q.from = pose.position + Vec3(0.3, -0.2, 6.0);
          q.to = pose.position;
          q.leadingRadius = kBurr;
          q.shell = shell;
          const SweepResult a = brain.sweep(q), c = rigid.sweep(q);
          EXPECT_EQ(a.blocked, c.blocked);
          EXPECT_NEAR(a.freeFraction, c.freeFraction, 1e-6);
        }
      }
    }
    // Bullet's allocations are counted: its refits (every frame within the
    // margin) allocate nothing.
    if (b.name == "bullet" && amplitude < 10.0) {
      EXPECT_EQ(test::counter(brain, "follow_allocations"), 0.0);
    }
  }
  // Beyond the margin the native queries widened and the trees were rebuilt.
  if (b.name == "native") {
    EXPECT_GT(test::counter(brain, "frames_beyond_margin"), 0.0);
  } else {
    EXPECT_GT(test::counter(brain, "rebuilt_blocks"), 0.0);
    EXPECT_GT(test::counter(brain, "refits"), 0.0);
  }
  if (b.name == "bullet") {
    EXPECT_GT(test::counter(brain, "follow_allocations"), 0.0) << "a rebuild makes a new tree";
  }
}

// A scene poking a brain that pulsates (every node moves every frame), on `backend`.
std::string pulsatingScene(const std::string& backend, const std::string& brainFields = "") {
  const bool fromPlugin = backend == "embree" || backend == "bullet";
  const std::string plugin = fromPlugin ? "<RequiredPlugin name=\"" + backend + "\"/>" : "";
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  )" + plugin +
         R"(
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:cube?cells=13" backend=")" +
         backend + "\" " + brainFields + R"(/>
    <ScriptedDeformation name="wave" mesh="@brain" amplitude="1" center="5 5 100" rate="1000"/>
  </Node>
  )" + test::brainProbeNode(R"(path="pokes" center="5 5 0" standoff="5" depth="2")") +
         R"(
</Node>)";
}

TEST_P(TetBackendConformanceTest, PokingAPulsatingBrainStaysStable) {
  Diagnostics d;
  SimulationOptions options;
  options.duration = 3.0;
  auto simulation = test::loadScene(pulsatingScene(GetParam().name), d, options);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  const HapticStats s = simulation->hapticLog().stats();
  EXPECT_EQ(s.nanFrames, 0u);
  EXPECT_EQ(s.proxyInsideFrames, 0u);
  EXPECT_GT(s.contactFrames, 800u);
  EXPECT_LE(s.forceStepMax, 0.8) << "N per frame, the thesis's largest peak";
  EXPECT_EQ(test::componentCounter(*simulation, "TetraBrain", "deformation_frames"), 3000.0);
}

INSTANTIATE_TEST_SUITE_P(Backends, TetBackendConformanceTest, ::testing::ValuesIn(backends()),
                         [](const auto& info) { return info.param.name; });

// A burr on a shaft, the shaft tilted 15 degrees below the horizontal and
// dipped into the top face while the burr stays clear of it, on every
// back-end that takes it (docs/architecture.md: the native one point by
// point, Bullet as a sphere and a cylinder). The shaft's lowest point is the
// rim of its end, r cos(15 deg) below the end's centre: pressed 0.6 mm (the
// wall touches with its lowest generator), 1.5 mm (deeper than the shaft's
// radius) and 3 mm (its end all in the brain), the penetration is the press
// and the normal the face's. The wall is sampled in rings 0.4425 mm apart,
// the last at the end: the lowest generator is missed by at most
// r (1 - cos 15 deg), 0.034 mm, on the native back-end, which takes the points.
TEST(TetBackendFieldTest, ABurrOnAShaftMeasuresTheClosedFormAtAnyDepth) {
  constexpr double r = 1.0, L = 20.0, theta = 15.0 * std::numbers::pi / 180.0;
  const Vec3 axis(std::cos(theta), 0, -std::sin(theta));
  std::vector<ShellPoint> shell = shapes::sphereShell(kBurr, 266);
  const Quat toAxis = rotationBetween(Vec3::UnitZ(), axis);
  for (int k = 0; k <= 40; ++k)
    for (int i = 0; i < 12; ++i) {
      const double phi = 2 * std::numbers::pi * i / 12;
      const Vec3 radial(std::cos(phi), std::sin(phi), 0);
      shell.push_back({toAxis * (r * radial + (2.3 + (L - 2.3) * k / 40.0) * Vec3::UnitZ()), toAxis * -radial});
    }
  struct Case {
    std::string name;
    std::function<std::unique_ptr<TetBackend>()> create;
    double tolerance;  // mm
  };
  std::vector<Case> cases = {{"native", [] { return std::make_unique<NativeTetBackend>(); }, 0.04}};
#ifdef TREPHINE_HAS_BULLET_BACKEND
  cases.push_back(
      {"bullet", [] { return std::make_unique<MeshTetBackend>(std::make_unique<bullet::BulletEngine>()); }, 1e-3});
#endif
#ifdef TREPHINE_HAS_EMBREE_BACKEND
  // Point by point, as the native back-end: its shell's spacing bounds the error.
  cases.push_back(
      {"embree", [] { return std::make_unique<MeshTetBackend>(std::make_unique<embree::EmbreeEngine>()); }, 0.04});
#endif
  for (const Case& backend : cases) {
    double worst = 0;
    TetraBrain brain;
    brain.setBackend(backend.create());
    shapes::cubeBrain(brain, kCells);
    ContactMemory memory_brain_shell = brain.reserveShell(shell);
    if (backend.name == "bullet") {  // without a shaft the shell is neither a sphere nor a burr on a shaft
      EXPECT_THROW(brain.describeTool(shell, ToolSolid{kBurr, 0, 0, Vec3::UnitZ()}), std::runtime_error);
    }
    brain.describeTool(shell, ToolSolid{kBurr, r, L, axis});
    for (const double press : {0.6, 1.5, 3.0}) {
      const double height = 100 - press + L * std::sin(theta) + r * std::cos(theta);
      ASSERT_GT(height - kBurr, 100.5) << "the burr is clear of the face";
      const ShellContact c = brain.collide({Vec3(3, -2, height), Quat::Identity()}, shell, false, memory_brain_shell);
      ASSERT_GT(c.points, 0) << backend.name << ", " << press << " mm";
      EXPECT_NEAR(c.penetration, press, backend.tolerance) << backend.name << ", " << press << " mm";
      worst = std::max(worst, std::abs(c.penetration - press));
      EXPECT_GT(c.normal.z(), 1 - 1e-3) << backend.name << ", " << press << " mm: " << c.normal.transpose();
      // Lifted 0.1 mm clear: no contact.
      EXPECT_EQ(
          brain.collide({Vec3(3, -2, height + press + 0.1), Quat::Identity()}, shell, false, memory_brain_shell).points,
          0)
          << backend.name;
    }
    RecordProperty(backend.name + "_worst_penetration_error_mm", std::to_string(worst));
  }
}

// A tool a plugin defines (an ellipsoid of semi-axes 4, 2 and 2 mm, 600
// points, as the out-of-tree EllipsoidTool), turned three ways and pressed
// 0.3 to 1.5 mm into the cube's top face: the native and Embree back-ends
// take it point by point and measure the closed form (the ellipsoid's
// support along the face's normal less the centre's height) with the face's
// normal; Bullet takes spheres and shafts only (through the tool's solid) and
// refuses it when it is described, naming the back-end.
TEST(TetBackendFieldTest, APluginsOwnToolShapeMeasuresTheClosedFormOrIsRefused) {
  const Vec3 axes(4, 2, 2);
  std::vector<ShellPoint> ellipsoid;
  const int count = 600;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1 - 2 * (i + 0.5) / count, r = std::sqrt(1 - z * z);
    const Vec3 p = Vec3(r * std::cos(golden * i), r * std::sin(golden * i), z).cwiseProduct(axes);
    ellipsoid.push_back({p, -p.cwiseQuotient(axes.cwiseProduct(axes)).normalized()});
  }
  const ToolSolid none{0, 0, 0, Vec3::UnitZ()};
  for (const Backend& backend : backends()) {
    TetraBrain brain;
    brain.setBackend(backend.create());
    shapes::cubeBrain(brain, kCells);
    if (backend.name == "bullet") {
      try {
        ContactMemory memory_brain_ellipsoid = brain.reserveShell(ellipsoid);
        brain.describeTool(ellipsoid, none);
        ADD_FAILURE() << backend.name << " took a tool it cannot measure";
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("backend=\"" + backend.name + "\""), std::string::npos) << e.what();
      }
      continue;
    }
    ContactMemory memory_brain_ellipsoid = brain.reserveShell(ellipsoid);
    brain.describeTool(ellipsoid, none);
    double worst = 0;
    for (const Quat& turn : {Quat::Identity(), Quat(Eigen::AngleAxisd(0.6, Vec3(1, 2, 0.5).normalized())),
                             Quat(Eigen::AngleAxisd(1.3, Vec3(-0.4, 0.3, 1).normalized()))})
      for (const double press : {0.3, 0.8, 1.5}) {
        const double support = axes.cwiseProduct(turn.conjugate() * Vec3::UnitZ()).norm();
        const Vec3 centre(3, -2, 100 + support - press);
        const ShellContact c = brain.collide({centre, turn}, ellipsoid, false, memory_brain_ellipsoid);
        ASSERT_GT(c.points, 0) << press;
        EXPECT_NEAR(c.penetration, press, 0.02) << press;
        EXPECT_GT(c.normal.z(), std::cos(0.06)) << press << ": " << c.normal.transpose();
        worst = std::max(worst, std::abs(c.penetration - press));
      }
    RecordProperty("ellipsoid_worst_penetration_error_mm", std::to_string(worst));
  }
}

TEST(TetBackendFieldTest, AnUnknownBackEndOrANativeOptionElsewhereIsALoadErrorAtItsAttribute) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(pulsatingScene("nonesuch"), d));
  std::string m = test::messages(d);
  EXPECT_NE(m.find("inline.xml:6:"), std::string::npos) << m;
  EXPECT_NE(m.find("no collision back-end \"nonesuch\" for TetraBrain"), std::string::npos) << m;
  EXPECT_NE(m.find("no plugin of that name is installed either (installed: "), std::string::npos) << m;
  EXPECT_NE(m.find("tetra_brain"), std::string::npos) << m;
  // The error stops there: nothing that links to the brain adds its own
  // (before, the device's approach "missed" the brain that had no back-end).
  EXPECT_EQ(d.errorCount(), 1) << m;
  // A slip of one letter names the closest back-end, or installed plugin and
  // the <RequiredPlugin/> that loads it.
  Diagnostics typo;
  EXPECT_FALSE(test::loadScene(pulsatingScene("Native"), typo));
  EXPECT_NE(test::messages(typo).find("did you mean \"native\"?"), std::string::npos) << test::messages(typo);
  EXPECT_EQ(typo.errorCount(), 1) << test::messages(typo);
#ifdef TREPHINE_HAS_EMBREE_BACKEND
  Diagnostics plugin;
  EXPECT_FALSE(test::loadScene(pulsatingScene("embre"), plugin));
  EXPECT_NE(test::messages(plugin).find("did you mean \"embree\"? (a plugin of that name is installed: add "
                                        "<RequiredPlugin name=\"embree\"/>)"),
            std::string::npos)
      << test::messages(plugin);
#endif
#ifdef TREPHINE_HAS_EMBREE_BACKEND
  Diagnostics d2;
  EXPECT_FALSE(test::loadScene(pulsatingScene("embree", R"(search="previous-contact" cellSize="3")"), d2));
  m = test::messages(d2);
  EXPECT_NE(m.find("invalid search of TetraBrain 'brain': applies to backend=\"native\" only"), std::string::npos) << m;
  EXPECT_NE(m.find("invalid cellSize"), std::string::npos) << m;
#endif
}

}  // namespace
}  // namespace trephine::tetra
