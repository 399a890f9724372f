// --set path.field=value: checked like an attribute, reported at "--set <text>".
#include <gtest/gtest.h>

#include "tests/framework/scene/LoaderAssertions.h"

namespace trephine::test {
namespace {

constexpr const char* kScene = kPlaneTouchScene;

SimulationOptions withOverrides(std::vector<std::string> overrides) {
  SimulationOptions options;
  options.overrides = std::move(overrides);
  return options;
}

TEST(OverrideTest, OverrideReplacesTheAttributeValueAndRemembersWhereItCameFrom) {
  Diagnostics d;
  auto simulation = loadScene(kScene, d, withOverrides({"tool/force.stiffness=3.5"}));
  ASSERT_NE(simulation, nullptr) << messages(d);
  const BaseField* stiffness = simulation->scene().findComponent("tool/force")->findField("stiffness");
  EXPECT_EQ(stiffness->valueText(), "3.5");
  EXPECT_EQ(stiffness->location().str(), "--set tool/force.stiffness=3.5");
}

TEST(OverrideTest, PathMayStartAtTheRootSlash) {
  Diagnostics d;
  auto simulation = loadScene(kScene, d, withOverrides({"/tool/burr.radius=1.5"}));
  ASSERT_NE(simulation, nullptr) << messages(d);
  EXPECT_EQ(simulation->scene().findComponent("tool/burr")->findField("radius")->valueText(), "1.5");
}

TEST(OverrideTest, NodeFieldsCanBeSetByNodePath) {
  Diagnostics d;
  auto simulation = loadScene(kScene, d, withOverrides({"tool.units=mm"}));
  EXPECT_NE(simulation, nullptr) << messages(d);
}

TEST(OverrideTest, UnknownComponentInThePathIsReportedWithSuggestion) {
  const Diagnostics d = loadFailure(kScene, withOverrides({"tool/forc.stiffness=3"}));
  EXPECT_TRUE(hasError(d, "--set tool/forc.stiffness=3", "no component 'forc' in node '/tool', did you mean 'force'?"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(OverrideTest, UnknownNodeInThePathIsReportedWithSuggestion) {
  const Diagnostics d = loadFailure(kScene, withOverrides({"tol/force.stiffness=3"}));
  EXPECT_TRUE(hasError(d, "--set tol/force.stiffness=3", "no node 'tol' in node '/', did you mean 'tool'?"));
}

TEST(OverrideTest, UnknownFieldIsReportedWithSuggestion) {
  const Diagnostics d = loadFailure(kScene, withOverrides({"tool/force.stifness=3"}));
  EXPECT_TRUE(hasError(d, "--set tool/force.stifness=3",
                       "unknown field 'stifness' of SpringForce 'force', did you mean 'stiffness'?"));
}

TEST(OverrideTest, BadValueIsReportedLikeABadAttribute) {
  const Diagnostics d = loadFailure(kScene, withOverrides({"tool/force.stiffness=abc"}));
  EXPECT_TRUE(hasError(d, "--set tool/force.stiffness=abc",
                       "invalid stiffness of SpringForce 'force': expected a number, got 'abc'"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(OverrideTest, OutOfRangeValueIsReported) {
  const Diagnostics d = loadFailure(kScene, withOverrides({"tool/force.rate=0"}));
  EXPECT_TRUE(hasError(d, "--set tool/force.rate=0", "value 0 is out of range [0.001, 1e+06] Hz"));
}

TEST(OverrideTest, TextWithoutFieldAndValueShowsTheExpectedForm) {
  const Diagnostics d = loadFailure(kScene, withOverrides({"stiffness"}));
  EXPECT_TRUE(hasError(d, "--set stiffness", "expected path.field=value, e.g. --set tool/force.stiffness=1.5"));
}

TEST(OverrideTest, RenamingIsRefused) {
  const Diagnostics d = loadFailure(kScene, withOverrides({"tool/force.name=other"}));
  EXPECT_TRUE(hasError(d, "--set tool/force.name=other", "--set cannot rename a component"));
}

TEST(OverrideTest, LinkOverrideToTheWrongTypeIsReportedAtTheOverride) {
  const Diagnostics d = loadFailure(kScene, withOverrides({"tool/force.tool=@device"}));
  EXPECT_TRUE(hasError(
      d, "--set tool/force.tool=@device",
      "link tool=\"@device\" of SpringForce 'force' points to ScriptedDevice 'device', expected a SphereTool"));
}

TEST(OverrideTest, EveryBadOverrideIsReported) {
  const Diagnostics d =
      loadFailure(kScene, withOverrides({"tool/force.stiffness=x", "tool/burr.radius=-1", "nowhere.x=1"}));
  EXPECT_TRUE(hasError(d, "--set tool/force.stiffness=x", "expected a number"));
  EXPECT_TRUE(hasError(d, "--set tool/burr.radius=-1", "out of range"));
  EXPECT_TRUE(hasError(d, "--set nowhere.x=1", "no component 'nowhere' in node '/'"));
  EXPECT_EQ(d.errorCount(), 3);
}

}  // namespace
}  // namespace trephine::test
