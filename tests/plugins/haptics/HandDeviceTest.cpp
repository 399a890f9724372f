// The simulated hand closes the loop: it presses a tool on a target through
// its grip, the rendered force pushes it back, and the passivity check at load
// tells the settings that stay bounded from those that pump energy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

constexpr double kRadius = 2.5;           // mm, burr radius; the surface is z = 0
constexpr double kGripStiffness = 0.135;  // N/mm, HandDevice's default
constexpr double kMaxForce = 3.3;         // N

// The hand means to go from 2.5 mm above the touching height down to `press`
// mm below it in 1 s (after 0.2 s at rest), stay there until `end` s and, if
// `retractAt` > 0, come back up by then.
std::string intentWaypoints(double press, double end, double retractAt = 0) {
  const double above = kRadius + 2.5, below = kRadius - press;
  std::string w =
      "0 0 0 " + std::to_string(above) + "  0.2 0 0 " + std::to_string(above) + "  1.2 0 0 " + std::to_string(below);
  if (retractAt > 0) {
    w += "  " + std::to_string(retractAt) + " 0 0 " + std::to_string(below) + "  " + std::to_string(end) + " 0 0 " +
         std::to_string(above);
  } else {
    w += "  " + std::to_string(end) + " 0 0 " + std::to_string(below);
  }
  return w;
}

// A sphere on an exact plane, with a penalty spring-damper.
std::string springScene(const std::string& waypoints, const std::string& force) {
  return R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <AnalyticPlane name="plane" point="0 0 0" normal="0 0 1"/>
  <ScriptedDevice name="intent" path="waypoints" record="false" waypoints=")" +
         waypoints + R"("/>
  <HandDevice name="hand" intent="@intent" record="false"/>
  <SphereTool name="burr" radius="2.5" device="@hand"/>
  <SpringForce name="force" tool="@burr" target="@plane" )" +
         force + R"(/>
</Node>)";
}

// A pointshell burr on the half-space phantom through the god-object proxy.
std::string proxyScene(const std::string& waypoints, const std::string& force) {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <VoxelSkull name="skull" file="phantom:halfspace?voxel=0.5" isovalue="500"/>
  <ScriptedDevice name="intent" path="waypoints" record="false" waypoints=")" +
         waypoints + R"("/>
  <HandDevice name="hand" intent="@intent" record="false"/>
  <PointshellTool name="burr" radius="2.5" angleStep="10" device="@hand"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@skull"/>
  <ForceFeedback name="force" proxy="@proxy" )" +
         force + R"(/>
</Node>)";
}

struct Run {
  std::unique_ptr<Simulation> simulation;
  Diagnostics diagnostics;
  bool warned() const {
    return std::any_of(diagnostics.all().begin(), diagnostics.all().end(),
                       [](const Diagnostic& d) { return d.severity == Severity::Warning; });
  }
};

std::unique_ptr<Run> run(const std::string& xml) {
  auto r = std::make_unique<Run>();
  r->simulation = test::loadScene(xml, r->diagnostics);
  EXPECT_TRUE(r->simulation) << test::messages(r->diagnostics);
  if (r->simulation) r->simulation->run();
  return r;
}

// Peak-to-peak of the force along z over frames with t in [t0, t1) s.
double forceSwing(const HapticFrameLog& log, double t0, double t1) {
  double lo = INFINITY, hi = -INFINITY;
  for (size_t i = 0; i < log.size(); ++i)
    if (log[i].t >= t0 && log[i].t < t1) lo = std::min(lo, log[i].force.z()), hi = std::max(hi, log[i].force.z());
  return hi - lo;
}

TEST(HandDeviceTest, AtRestTheHandsPullEqualsTheRenderedForce) {
  // The hand means to be 8 mm below the touching height. At rest the grip's
  // pull balances the force, k_h (z_intent - z) + F = 0, and with a spring k
  // the device sinks p = k_h D / (k + k_h) (0.506 mm, F = 1.01 N at k = 2).
  constexpr double press = 8.0, k = 2.0;
  const double depth = kGripStiffness * press / (k + kGripStiffness);
  for (const bool proxy : {false, true}) {
    const std::string force = R"(stiffness="2" damping="0.002" rate="1000")";
    const std::string waypoints = intentWaypoints(press, 4.0);
    auto r = run(proxy ? proxyScene(waypoints, force) : springScene(waypoints, force));
    ASSERT_TRUE(r->simulation);
    const HapticFrameLog& log = r->simulation->hapticLog();
    const HapticFrame& last = log[log.size() - 1];
    const double intentZ = kRadius - press;
    const double pull = kGripStiffness * (intentZ - last.device.z());  // N, negative: the hand pushes down
    EXPECT_NEAR(last.force.z() + pull, 0.0, 1e-6) << (proxy ? "proxy" : "spring");
    EXPECT_NEAR(last.force.z(), k * last.penetration, 1e-6) << "the rendered spring, the device at rest";
    // The plane is exact; the phantom's interpolated half-space is z = 0 to well within 1e-4 mm.
    const double tolerance = proxy ? 1e-4 : 1e-6;
    EXPECT_NEAR(kRadius - last.device.z(), depth, tolerance);
    EXPECT_NEAR(last.force.z(), kGripStiffness * (press - depth), k * tolerance);
    EXPECT_FALSE(r->warned()) << test::messages(r->diagnostics);
  }
}

struct Figures {
  double minEnergy, generated, swingFirst, swingLast, forceMax;
  double storedMax;  // mJ, the most a spring of this stiffness held at forceMax, F^2 / 2k
};

// Presses with about 1 N for 10 s on the phantom through the proxy.
Figures pressLong(double stiffness, const std::string& force, const std::string& hand, bool expectWarning) {
  constexpr double end = 11.2;
  std::string xml = proxyScene(intentWaypoints(8.0, end), "stiffness=\"" + std::to_string(stiffness) + "\" " + force);
  xml.replace(xml.find("record=\"false\"/>"), 17, "record=\"false\" " + hand + "/>");
  auto r = run(xml);
  if (!r->simulation) return {};
  EXPECT_EQ(r->warned(), expectWarning) << force << "\n" << test::messages(r->diagnostics);
  const HapticFrameLog& log = r->simulation->hapticLog();
  const HapticStats s = log.stats();
  EXPECT_EQ(s.nanFrames, 0u);
  // The first second once the hand has arrived, and the last.
  const Figures f{s.minEnergyIn_mJ,
                  s.maxGeneratedPer100ms_mJ,
                  forceSwing(log, 1.2, 2.2),
                  forceSwing(log, end - 1, end),
                  s.forceMax,
                  s.forceMax * s.forceMax / (2.0 * stiffness)};
  std::cout << "[ figures  ] k " << stiffness << " " << force << " " << hand << ": energy in " << s.energyIn_mJ
            << " mJ, min " << f.minEnergy << " mJ, generated max " << f.generated << " mJ/100 ms (stored at most "
            << f.storedMax << "), |F| max " << f.forceMax << " N, swing " << f.swingFirst << " N then " << f.swingLast
            << " N, unexplained step max " << s.unexplainedStepMax << " N\n";
  return f;
}

TEST(HandDeviceTest, SettingsTheCheckCallsPassiveStayBoundedInClosedLoop) {
  for (const double k : {0.5, 1.0, 2.0, 3.0}) {
    const Figures f = pressLong(k, R"(damping="0.002")", "", false);
    // Passive: the observer never goes below zero, and what it gives back
    // within 100 ms is energy the spring had stored (at most F^2 / 2k).
    EXPECT_GT(f.minEnergy, -0.01) << k;
    EXPECT_LT(f.generated, f.storedMax) << k;
    // The contact settles: whatever rang on arrival has died out by the end.
    EXPECT_LT(f.swingLast, 0.01) << k;
    EXPECT_LE(f.swingLast, f.swingFirst) << k;
    EXPECT_LT(f.forceMax, 2.0) << k << ": about 1 N was pressed, nothing near the clamp";
  }
}

TEST(HandDeviceTest, ASettingTheCheckCallsNonPassivePumpsEnergyInClosedLoop) {
  // k = 20 N/mm without virtual damping needs b > k T / 2 = 0.01 N s/mm; the
  // hand brings 0.00645. The loop gains energy every cycle and the force
  // swings between nothing and the clamp: the burr bounces on the bone.
  const Figures pumping = pressLong(20.0, R"(damping="0")", "", true);
  EXPECT_LT(pumping.minEnergy, -1.0) << "the rendering generated energy";
  EXPECT_GT(pumping.generated, pumping.storedMax) << "more than any spring of this stiffness could give back";
  EXPECT_GT(pumping.swingLast, 1.0) << "still oscillating by newtons at the end";
  EXPECT_GE(pumping.swingLast, 0.5 * pumping.swingFirst) << "not dying out";
  EXPECT_GE(pumping.forceMax, kMaxForce - 1e-9) << "at the clamp";

  // The passive setting next to it, k = 3 N/mm with 0.002 N s/mm, generates none.
  const Figures passive = pressLong(3.0, R"(damping="0.002")", "", false);
  EXPECT_GT(pumping.generated, 3.0 * passive.generated);
  EXPECT_LT(pumping.minEnergy, passive.minEnergy - 1.0);

  // The same wall held by a firmer grip (0.02 N s/mm > 0.01): passive again,
  // and it settles. The observer, which sees the wall and not the hand, still
  // notes the trace the hold generates, which the grip's damping absorbs.
  const Figures firm = pressLong(20.0, R"(damping="0")", R"(gripDamping="0.02")", false);
  EXPECT_GT(firm.minEnergy, -0.1);
  EXPECT_LT(firm.swingLast, 0.01);
  EXPECT_LT(firm.forceMax, 2.0);
}

}  // namespace
}  // namespace trephine
