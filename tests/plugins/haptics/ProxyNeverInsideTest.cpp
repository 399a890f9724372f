// The proxy never inside the target, as a property: paths drawn at random
// (an approach from any direction of the upper half-space onto a random
// point, a press up to and past the force limit, a slide in a random
// direction along the surface, or a random walk pressed into it), on the
// skull phantom, on a tetrahedral cube (flat faces, edges and corners), on
// the brain phantom (folds and a fissure) and, when ../shared/data has them,
// on the real CT head (its bone at the scanner's resolution) and the real
// atlas brain (145,000 tetrahedra, its sulci), for every collision back-end
// built and every sweep. Each run's proxy must
// never visibly overlap the target and no frame may be NaN; the failures
// name the path so that it can be run again (`trephine run` with the same
// fields). Numerics: left out of the sanitizer presets.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "framework/geometry/SurfaceTarget.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

struct Case {
  std::string target;  // "skull", "cube", "brain", "ct_head" or "atlas"
  std::string backend;
  std::string sweep;
};

// The real data's files (absent from a fresh clone: those cases skip).
const std::filesystem::path kCtHead = "ct_head_vtk_headsq/quarter.nhdr";
const std::filesystem::path kAtlas = "brain_tetmesh_mmc_head_atlas/brain_gm_wm.node";
std::filesystem::path sharedData(const std::filesystem::path& file) {
  return test::sourceDir() / "../shared/data" / file;
}
bool real(const Case& c) { return c.target == "ct_head" || c.target == "atlas"; }

// Every collision back-end built.
std::vector<std::string> builtBackends() {
  std::vector<std::string> backends{"native"};
#ifdef TREPHINE_TEST_EMBREE
  backends.push_back("embree");
#endif
#ifdef TREPHINE_TEST_BULLET
  backends.push_back("bullet");
#endif
  return backends;
}

std::vector<Case> cases() {
  const std::vector<std::string> backends = builtBackends();
  std::vector<Case> all;
  for (const char* target : {"skull", "cube"})
    for (const std::string& backend : backends)
      for (const char* sweep : {"line", "cylinder", "spheres"}) all.push_back({target, backend, sweep});
  // The brain phantom's folds and fissure (22,000 tetrahedra, meshed at load),
  // the line and cylinder sweeps (on a brain the spheres sweep is the
  // cylinder's: the native back-end probes the same rings, and Embree and
  // Bullet cast the whole sphere for every sweep).
  for (const std::string& backend : backends)
    for (const char* sweep : {"line", "cylinder"}) all.push_back({"brain", backend, sweep});
  // Real data: the CT head with every sweep, the atlas brain with the line
  // and cylinder (a brain's spheres sweep is its cylinder's, as above).
  for (const std::string& backend : backends) {
    for (const char* sweep : {"line", "cylinder", "spheres"}) all.push_back({"ct_head", backend, sweep});
    for (const char* sweep : {"line", "cylinder"}) all.push_back({"atlas", backend, sweep});
  }
  return all;
}

std::string vec(const Vec3& v) {
  std::ostringstream text;
  text.precision(4);
  text << v.x() << " " << v.y() << " " << v.z();
  return text.str();
}

// A random path's device fields: `seed` picks the kind and its figures.
std::string randomPath(uint64_t seed, const Vec3& middle, double spread) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(-1, 1), depth(0.3, 3.0), angle(0, 2 * M_PI);
  // Into the target from above: a direction within 60 degrees of straight down.
  Vec3 direction;
  do direction = Vec3(unit(random), unit(random), -std::abs(unit(random)));
  while (direction.norm() > 1 || direction.normalized().z() > -0.5);
  direction.normalize();
  const Vec3 centre = middle + Vec3(spread * unit(random), spread * unit(random), 0);
  const double a = angle(random);
  std::ostringstream fields;
  fields << "direction=\"" << vec(direction) << "\" center=\"" << vec(centre) << "\" depth=\"" << depth(random)
         << "\" ";
  if (seed % 2 == 0)
    fields << R"(path="approach-press-slide" standoff="5" speed="30" slideDistance="12" slideDirection=")"
           << vec(Vec3(std::cos(a), std::sin(a), 0)) << "\"";
  else
    fields << R"(path="random-walk" radius="4" walkDuration="1.5" seed=")" << seed << "\"";
  return fields.str();
}

// The target alone, as a scene's element.
std::string targetElement(const Case& c) {
  const std::string backend = " backend=\"" + c.backend + "\"/>";
  if (c.target == "skull") return R"(<VoxelSkull name="target" file="phantom:skull?voxel=1.0")" + backend;
  if (c.target == "cube") return R"(<TetraBrain name="target" file="phantom:cube?cells=10&amp;size=30")" + backend;
  if (c.target == "brain") return R"(<TetraBrain name="target" file="phantom:brain?tets=22000")" + backend;
  // The CT as the shipped CT scenes read it: bone above 1150, resampled to 1 mm.
  if (c.target == "ct_head")
    return R"(<VoxelSkull name="target" file=")" + sharedData(kCtHead).string() +
           R"(" voxelSize="1.0" isovalue="1150")" + backend;
  return R"(<TetraBrain name="target" file=")" + sharedData(kAtlas).string() + "\"" + backend;
}

std::string scene(const Case& c, const std::string& path) {
  const std::string plugin = c.backend == "native" ? "" : "<RequiredPlugin name=\"" + c.backend + "\"/>";
  const std::string target = targetElement(c);
  if (path.empty())
    return R"(<Node name="root"><RequiredPlugin name="voxel_skull"/><RequiredPlugin name="tetra_brain"/>)" + plugin +
           target + "</Node>";
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  )" + plugin + "\n  " +
         target + R"(
  <ScriptedDevice name="device" target="@target" tipOffset="2.5" record="false" rate="1000" )" +
         path + R"(/>
  <PointshellTool name="burr" radius="2.5" angleStep="15" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@target" sweep=")" +
         c.sweep + R"(" rate="1000"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" damping="0.002" maxForce="3.3" rate="1000"/>
</Node>)";
}

class ProxyNeverInsideTest : public testing::TestWithParam<Case> {};

TEST_P(ProxyNeverInsideTest, OnRandomPathsTheProxyStaysOutAndNoFrameIsNaN) {
  const Case& c = GetParam();
  // Aim points around the middle of the skull's top, and over the cube's top
  // face (30 mm, centred on the origin) up to 2 mm from its edges; on real
  // data, within a fifth of the target's width of its middle (the vertex of
  // the head, the top of the brain's hemispheres and their fissure).
  Vec3 middle = Vec3::Zero();
  double spread = c.target == "cube" ? 13 : c.target == "brain" ? 25 : 20;
  constexpr int paths = 4;
  if (real(c)) {
    const std::filesystem::path file = sharedData(c.target == "ct_head" ? kCtHead : kAtlas);
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is absent (../shared/data): no real " << c.target;
    Diagnostics d;
    auto alone = test::loadScene(scene(c, ""), d);
    ASSERT_TRUE(alone) << test::messages(d);
    const auto* target = dynamic_cast<const SurfaceTarget*>(alone->scene().findComponent("/target"));
    ASSERT_NE(target, nullptr);
    const Box3 box = target->bounds();
    middle = box.center();
    spread = 0.2 * std::min(box.sizes().x(), box.sizes().y());
  }
  size_t contactFrames = 0;
  for (uint64_t seed = 1; seed <= uint64_t(paths); ++seed) {
    const std::string path = randomPath(seed + 100 * uint64_t(c.backend.size()), middle, spread);
    Diagnostics d;
    auto simulation = test::loadScene(scene(c, path), d);
    ASSERT_TRUE(simulation) << test::messages(d) << "\n" << path;
    simulation->run();
    const HapticStats stats = simulation->hapticLog().stats();
    EXPECT_EQ(stats.proxyInsideFrames, 0u) << c.target << " " << c.backend << " " << c.sweep << ": " << path;
    EXPECT_EQ(stats.nanFrames, 0u) << path;
    contactFrames += stats.contactFrames;
  }
  EXPECT_GT(contactFrames, 250u * paths) << "the paths must touch the target for the property to mean something";
}

// A path the property found on the brain phantom, a random walk pressed
// 2.8 mm into a fold at the force limit: with the line sweep the proxy slid
// 0.55 mm into the fold in one frame (the sweep probes only the leading
// point's path), and then chattered between the fold's walls, its spring
// swinging 30 to 40 degrees a frame while the device moved 0.003 mm: force
// steps beyond the device's motion of p99 1.06 N, max 1.65 N. On a rigid
// target the spring now changes by no more than the device's own move plus
// 0.02 mm a frame (as on a drilled one): never inside, and the steps within
// the brief's hard-case bounds (p99 0.05 N, max 0.3 N), on every sweep.
TEST(ProxyNeverInsideTest, AFoldTheLineSweepMissesNeitherTakesTheProxyInNorChatters) {
  for (const char* sweep : {"line", "cylinder"}) {
    const Case c{"brain", "native", sweep};
    Diagnostics d;
    auto simulation = test::loadScene(
        scene(c, R"(direction="0.3066 0.6031 -0.7364" center="22.12 11.99 0" depth="2.790" path="random-walk" )"
                 R"(radius="4" walkDuration="1.5" seed="5")"),
        d);
    ASSERT_TRUE(simulation) << test::messages(d);
    simulation->run();
    const HapticStats stats = simulation->hapticLog().stats();
    EXPECT_GT(stats.contactFrames, 2000u) << sweep;
    EXPECT_EQ(stats.proxyInsideFrames, 0u) << sweep;
    ASSERT_TRUE(stats.hasUnexplainedSteps);
    EXPECT_LE(stats.unexplainedStepP99, 0.05) << sweep;
    EXPECT_LE(stats.unexplainedStepMax, 0.3) << sweep;
    EXPECT_EQ(stats.forceReversals, 0u) << sweep;
  }
}

// The same fold in closed loop: a simulated hand (HandDevice, its defaults)
// whose intent is that random walk pressed 25 mm deep, so that its grip
// presses the probe at up to the force limit, the proxy and the force at
// their defaults. Before the spring's change was held on rigid targets, the
// native back-end's force stepped 2.35 N beyond the hand's motion here.
TEST(ProxyNeverInsideTest, AHandPressingIntoTheFoldAtTheLimitFeelsNoStep) {
  for (const std::string& backend : builtBackends()) {
    const std::string plugin = backend == "native" ? "" : "<RequiredPlugin name=\"" + backend + "\"/>";
    Diagnostics d;
    auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  )" + plugin + R"(
  <TetraBrain name="target" file="phantom:brain?tets=22000" backend=")" + backend + R"("/>
  <ScriptedDevice name="intent" target="@target" tipOffset="2.5" record="false" rate="1000"
                  direction="0.3066 0.6031 -0.7364" center="22.12 11.99 0" depth="25" path="random-walk"
                  radius="4" walkDuration="1.5" seed="5"/>
  <HandDevice name="hand" intent="@intent" rate="1000"/>
  <PointshellTool name="burr" radius="2.5" angleStep="15" device="@hand"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@target" rate="1000"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" damping="0.002" maxForce="3.3" rate="1000"/>
</Node>)",
                                      d);
    ASSERT_TRUE(simulation) << test::messages(d);
    simulation->run();
    const HapticStats stats = simulation->hapticLog().stats();
    EXPECT_GT(stats.contactFrames, 1000u) << backend;
    EXPECT_EQ(stats.proxyInsideFrames, 0u) << backend;
    EXPECT_EQ(stats.nanFrames, 0u) << backend;
    EXPECT_EQ(stats.forceReversals, 0u) << backend;
    ASSERT_TRUE(stats.hasUnexplainedSteps);
    EXPECT_LE(stats.unexplainedStepP99, 0.05) << backend;
    EXPECT_LE(stats.unexplainedStepMax, 0.3) << backend;
  }
}

// The brain phantom's hard places, on every back-end: a probe pressed 1 mm
// into the side of a hemisphere and slid 12 mm up its steep wall (the native
// back-end's proxy once jumped 1 mm into the brain there and stayed for 226
// frames), and pressed 1 mm over the midline fissure and slid 12 mm along it
// and across it (Bullet's proxy was inside for 1 to 3 frames): never inside,
// no NaN, and force steps beyond the device's motion within the brief's
// hard-case bounds (p99 0.05 N, max 0.3 N).
TEST(ProxyNeverInsideTest, UpASteepWallAndAlongAndAcrossTheFissureTheProxyStaysOut) {
  const std::vector<std::string> backends = builtBackends();
  Diagnostics loaded;
  auto alone = test::loadScene(scene({"brain", "native", "line"}, ""), loaded);
  ASSERT_TRUE(alone) << test::messages(loaded);
  const Box3 box = dynamic_cast<const SurfaceTarget*>(alone->scene().findComponent("/target"))->bounds();
  const Vec3 middle = box.center();
  struct Slide {
    const char* name;
    Vec3 direction, centre, along;
  };
  const std::vector<Slide> slides = {
      {"up the lateral wall", Vec3(-1, 0, 0), Vec3(middle.x(), middle.y(), middle.z() - 10), Vec3(0, 0, 1)},
      {"along the fissure", Vec3(0, 0, -1), Vec3(0, middle.y() - 6, middle.z()), Vec3(0, 1, 0)},
      {"across the fissure", Vec3(0, 0, -1), Vec3(-6, middle.y(), middle.z()), Vec3(1, 0, 0)}};
  for (const std::string& backend : backends)
    for (const Slide& slide : slides) {
      const std::string path = "direction=\"" + vec(slide.direction) + "\" center=\"" + vec(slide.centre) +
                               R"(" depth="1" path="approach-press-slide" standoff="5" speed="30" )"
                               R"(slideDistance="12" slideDirection=")" +
                               vec(slide.along) + "\"";
      Diagnostics d;
      auto simulation = test::loadScene(scene({"brain", backend, "line"}, path), d);
      ASSERT_TRUE(simulation) << test::messages(d);
      simulation->run();
      const HapticStats stats = simulation->hapticLog().stats();
      const std::string what = backend + ", " + slide.name + ": " + path;
      EXPECT_GT(stats.contactFrames, 300u) << what;
      EXPECT_EQ(stats.proxyInsideFrames, 0u) << what;
      EXPECT_EQ(stats.nanFrames, 0u) << what;
      ASSERT_TRUE(stats.hasUnexplainedSteps) << what;
      EXPECT_LE(stats.unexplainedStepP99, 0.05) << what;
      EXPECT_LE(stats.unexplainedStepMax, 0.3) << what;
    }
}

INSTANTIATE_TEST_SUITE_P(EveryTargetBackEndAndSweep, ProxyNeverInsideTest, testing::ValuesIn(cases()),
                         [](const testing::TestParamInfo<Case>& info) {
                           return info.param.target + "_" + info.param.backend + "_" + info.param.sweep;
                         });

}  // namespace
}  // namespace trephine
