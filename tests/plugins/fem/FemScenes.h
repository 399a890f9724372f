#pragma once
// Scenes the FEM's scene tests share: a probe pressing a deforming brain,
// and running a scene for a while into a directory.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "framework/core/Diagnostics.h"
#include "tests/support/BrainProbe.h"
#include "tests/support/TestSupport.h"

namespace trephine::fem::scenes {

inline std::unique_ptr<Simulation> runFor(const std::string& xml, double seconds, const std::filesystem::path& out) {
  Diagnostics d;
  SimulationOptions options;
  options.duration = seconds;
  auto simulation = trephine::test::loadScene(xml, d, options);
  EXPECT_TRUE(simulation) << trephine::test::messages(d);
  if (!simulation) return nullptr;
  simulation->run();
  std::vector<std::string> errors;
  simulation->writeOutputs(out, &errors);
  EXPECT_TRUE(errors.empty()) << errors.front();
  return simulation;
}

// The tool presses into a deforming brain (a coarse phantom of 1,200 tetrahedra, base held) and lifts.
// `femAttributes` on the FEM; the force's smoothing and the contact's
// damping are off unless given (the bare coupling, whose chatter and
// divergence these tests measure; the component's defaults have both).
inline std::string pressScene(std::string femAttributes = "") {
  if (femAttributes.find("forceSmoothing") == std::string::npos) femAttributes += R"( forceSmoothing="0")";
  if (femAttributes.find("contactDamping") == std::string::npos) femAttributes += R"( contactDamping="0")";
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="fem"/>
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:brain?tets=1200" saveDeformed="brain_final.mesh"/>
    <TLEDForceField name="fem" mesh="@brain" dt="0.33e-3" massScaling="true" rate="1000" )" +
         femAttributes + R"(/>
    <FixedConstraint name="base" fem="@fem" box="-100 -100 -100 100 100 -45"/>
  </Node>
  )" +
         test::brainProbeNode(R"(path="drill-in" center="10 10 0" standoff="5" speed="20" depth="4" feedSpeed="16")",
                              R"(sweep="line")") +
         R"(
</Node>)";
}

}  // namespace trephine::fem::scenes
