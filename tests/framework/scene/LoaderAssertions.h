#pragma once
// Assertions on loader diagnostics: the exact "file:line:col: error: " prefix
// plus a key part of the message; on failure every diagnostic is printed.
#include <gtest/gtest.h>

#include <string>

#include "tests/support/TestSupport.h"

namespace trephine::test {

// Passes when some diagnostic reads "<location>: error: ..." and contains `text`.
inline ::testing::AssertionResult hasError(const Diagnostics& diagnostics, const std::string& location,
                                           const std::string& text) {
  const std::string prefix = location + ": error: ";
  for (const Diagnostic& d : diagnostics.all()) {
    const std::string line = d.str();
    if (line.starts_with(prefix) && line.find(text) != std::string::npos) return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "expected an error starting \"" << prefix << "\" containing \"" << text
                                       << "\"; got:\n"
                                       << messages(diagnostics);
}

// Passes when no diagnostic contains `text`.
inline ::testing::AssertionResult mentionsNowhere(const Diagnostics& diagnostics, const std::string& text) {
  if (messages(diagnostics).find(text) == std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "unexpected \"" << text << "\" in:\n" << messages(diagnostics);
}

// A scene that loads: a 2.5 mm sphere on a scripted device touching a plane
// through a spring of 2 N/mm (its target a relative link).
inline constexpr const char* kPlaneTouchScene = R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <Node name="patient">
    <AnalyticPlane name="plane"/>
  </Node>
  <Node name="tool">
    <ScriptedDevice name="device" target="@/patient/plane" rate="1000"/>
    <SphereTool name="burr" device="@device"/>
    <SpringForce name="force" tool="@burr" target="@../patient/plane" stiffness="2"/>
  </Node>
</Node>)";

// A scene that must not load, and where and what its error is: a row of a
// table of such cases.
struct LocatedErrorCase {
  const char* name;  // what the case shows, as the test's name
  std::string xml;
  const char* location;  // file:line:col the error must start with
  const char* message;   // a part of the error
  const char* fileName = "inline.xml";
};

inline std::string caseName(const ::testing::TestParamInfo<LocatedErrorCase>& info) { return info.param.name; }

// Loads `xml` as "inline.xml" (or `fileName`) and returns what the load reported;
// the load is expected to fail.
inline Diagnostics loadFailure(const std::string& xml, const SimulationOptions& options = {},
                               const std::string& fileName = "inline.xml") {
  Diagnostics diagnostics;
  auto simulation = loadScene(xml, diagnostics, options, fileName);
  EXPECT_EQ(simulation, nullptr) << "the scene loaded although it should not";
  EXPECT_TRUE(diagnostics.hasErrors());
  return diagnostics;
}

}  // namespace trephine::test
