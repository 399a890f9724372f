// Every kind of scene error, reported once with its exact file:line:col.
// Columns: an element error points at its '<', an unknown attribute at the
// attribute name, a bad value or link at the first character inside the quotes.
#include <gtest/gtest.h>

#include "tests/framework/scene/LoaderAssertions.h"

namespace trephine::test {
namespace {

TEST(SceneLoaderErrorTest, ValidSceneLoadsWithoutDiagnostics) {
  Diagnostics d;
  auto simulation = loadScene(kPlaneTouchScene, d);
  ASSERT_NE(simulation, nullptr) << messages(d);
  EXPECT_TRUE(d.all().empty()) << messages(d);
  EXPECT_NE(simulation->scene().findComponent("/tool/force"), nullptr);
}

TEST(SceneLoaderErrorTest, ExampleSceneLoadsFromItsFile) {
  Diagnostics d;
  auto simulation = Simulation::fromFile(sourceDir() / "scenes/examples/plane_touch.xml", {}, d);
  ASSERT_NE(simulation, nullptr) << messages(d);
  EXPECT_EQ(d.errorCount(), 0);
}

// ---- components -------------------------------------------------------------

TEST(SceneLoaderErrorTest, UnknownComponentIsReportedAtItsTagWithTheClosestTypeSuggested) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recordr name="r"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:3", "unknown component 'Recordr', did you mean 'Recorder'?"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, UnknownComponentFarFromEveryTypeGetsNoSuggestion) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Xyzzy/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:3", "unknown component 'Xyzzy'"));
  EXPECT_TRUE(mentionsNowhere(d, "did you mean"));
}

TEST(SceneLoaderErrorTest, MisspelledPluginComponentSuggestsTheTypeAndItsRequiredPlugin) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <SphereTol name="burr"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:3",
                       "unknown component 'SphereTol', did you mean 'SphereTool'? (in plugin 'haptics': "
                       "add <RequiredPlugin name=\"haptics\"/>)"));
}

TEST(SceneLoaderErrorTest, ComponentOfAPluginTheSceneDoesNotLoadNamesTheLineToAdd) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <SphereTool name="burr"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:3:3",
                       "component 'SphereTool' is provided by plugin 'haptics', which this scene does not load; "
                       "add <RequiredPlugin name=\"haptics\"/>"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, ComponentWithChildElementsIsReportedAtTheChild) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <AnalyticPlane name="plane">
    <Node name="inside"/>
  </AnalyticPlane>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:4:5", "<AnalyticPlane> is a component and has no child elements"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, RootElementOtherThanNodeIsReported) {
  const Diagnostics d = loadFailure(R"(<Recorder name="r"/>)");
  EXPECT_TRUE(hasError(d, "inline.xml:1:1", "the root element of a scene is <Node>, found <Recorder>"));
  EXPECT_EQ(d.errorCount(), 1);
}

// ---- attributes and values --------------------------------------------------

TEST(SceneLoaderErrorTest, UnknownAttributeIsReportedAtItsNameWithSuggestion) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <AnalyticPlane name="plane" extnt="5"/>
</Node>)");
  EXPECT_TRUE(
      hasError(d, "inline.xml:3:31", "unknown attribute 'extnt' of AnalyticPlane 'plane', did you mean 'extent'?"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, UnknownNodeAttributeIsReportedWithSuggestion) {
  const Diagnostics d = loadFailure(R"(<Node name="root" unit="mm">
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:1:19", "unknown attribute 'unit' of <Node>, did you mean 'units'?"));
}

TEST(SceneLoaderErrorTest, NonNumericDoubleIsReportedAtTheValue) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <AnalyticPlane name="plane"/>
  <ScriptedDevice name="device" target="@plane"/>
  <SphereTool name="burr" device="@device"/>
  <SpringForce name="force" tool="@burr" target="@plane"
               stiffness="abc"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:8:27", "invalid stiffness of SpringForce 'force': expected a number, got 'abc'"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, Vec3WithTwoNumbersSaysThreeAreExpected) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <AnalyticPlane name="plane" normal="0 1"/>
</Node>)");
  EXPECT_TRUE(
      hasError(d, "inline.xml:3:39",
               "invalid normal of AnalyticPlane 'plane': expected three numbers 'x y z', got 2 value(s) in '0 1'"));
}

TEST(SceneLoaderErrorTest, BoolAcceptsOnlyTrueFalseOneOrZero) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ReplayDevice name="replay" loop="yes"/>
</Node>)");
  EXPECT_TRUE(
      hasError(d, "inline.xml:3:37", "invalid loop of ReplayDevice 'replay': expected true or false, got 'yes'"));
  EXPECT_TRUE(hasError(d, "inline.xml:3:3", "missing required file of ReplayDevice 'replay'"));
  EXPECT_EQ(d.errorCount(), 2);
}

TEST(SceneLoaderErrorTest, MisspelledEnumValueIsReportedWithTheOptionsAndASuggestion) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ScriptedDevice name="device" path="circel"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:3:39",
                       "invalid path of ScriptedDevice 'device': expected one of: approach-press-slide, drill-in, "
                       "circle, random-walk, pokes, waypoints, got 'circel', did you mean 'circle'?"));
}

TEST(SceneLoaderErrorTest, NegativeRadiusIsOutOfItsExclusiveRange) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ScriptedDevice name="device"/>
  <SphereTool name="burr" device="@device" radius="-1"/>
</Node>)");
  EXPECT_TRUE(
      hasError(d, "inline.xml:4:52", "invalid radius of SphereTool 'burr': value -1 is out of range (0, inf) mm"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, RateZeroIsOutOfRange) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ScriptedDevice name="device" rate="0"/>
</Node>)");
  EXPECT_TRUE(
      hasError(d, "inline.xml:3:39", "invalid rate of ScriptedDevice 'device': value 0 is out of range [0.001, 1e+06] Hz"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, RateBelowOneMillihertzIsAUnitSlip) {
  // A period in seconds given for a rate: one call in 30 years.
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ScriptedDevice name="device" rate="1e-9"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:3:39",
                       "invalid rate of ScriptedDevice 'device': value 1e-09 is out of range [0.001, 1e+06] Hz"));
}

TEST(SceneLoaderErrorTest, InvisibleCharactersInAValueAreShown) {
  // A byte order mark and a non-breaking space, pasted from elsewhere, look like nothing.
  const Diagnostics d = loadFailure("<Node name=\"root\">\n  <RequiredPlugin name=\"haptics\"/>\n"
                                    "  <SphereTool name=\"burr\" radius=\"\xEF\xBB\xBF"
                                    "2.5\"/>\n  <SphereTool name=\"probe\" radius=\"2\xC2\xA0\"/>\n</Node>");
  EXPECT_NE(messages(d).find("expected a number, got '\\u{FEFF}2.5'"), std::string::npos) << messages(d);
  EXPECT_NE(messages(d).find("expected a number, got '2\\u{00A0}'"), std::string::npos) << messages(d);
}

TEST(SceneLoaderErrorTest, InvalidComponentNameIsReportedAtTheValue) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <AnalyticPlane name="a plane"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:3:24", "invalid name 'a plane': use letters, digits, '_' and '-'"));
}

// ---- required fields ----------------------------------------------------------

TEST(SceneLoaderErrorTest, MissingRequiredLinkIsReportedAtTheElementWithItsTypeAndHelp) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <SphereTool name="burr"/>
</Node>)");
  EXPECT_TRUE(
      hasError(d, "inline.xml:3:3",
               "missing required device of SphereTool 'burr' (link<HapticDevice>: Device that moves the tool)"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, RequiredFieldWithARejectedValueIsNotAlsoReportedMissing) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <SphereTool name="burr" device="device"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:3:35",
                       "invalid device of SphereTool 'burr': expected a link '@path' to a HapticDevice, got 'device'"));
  EXPECT_EQ(d.errorCount(), 1);
}

// ---- links ----------------------------------------------------------------

TEST(SceneLoaderErrorTest, DanglingLinkSuggestsTheClosestMember) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ScriptedDevice name="device"/>
  <SphereTool name="burr" device="@devise"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:4:35",
                       "link device=\"@devise\" of SphereTool 'burr': no component 'devise' in node '/', "
                       "did you mean 'device'?"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, DanglingLinkThroughAMissingNodeNamesThatNode) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <Node name="patient">
    <AnalyticPlane name="plane"/>
  </Node>
  <ScriptedDevice name="device" target="@/patent/plane"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:7:41",
                       "link target=\"@/patent/plane\" of ScriptedDevice 'device': no node 'patent' in node '/', "
                       "did you mean 'patient'?"));
}

TEST(SceneLoaderErrorTest, OneLetterDanglingLinkGetsNoUnrelatedSuggestion) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ScriptedDevice name="d"/>
  <SphereTool name="burr" device="@x"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:4:35", "no component 'x' in node '/'"));
  EXPECT_TRUE(mentionsNowhere(d, "did you mean"));
}

TEST(SceneLoaderErrorTest, LinkToAComponentOfTheWrongTypeNamesTheExpectedType) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <ScriptedDevice name="device"/>
  <SphereTool name="burr" device="@device"/>
  <SpringForce name="force" tool="@burr" target="@device"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:6:50",
                       "link target=\"@device\" of SpringForce 'force' points to ScriptedDevice 'device', "
                       "expected an ImplicitSurface"));
  EXPECT_TRUE(d.all().front().message.ends_with("expected an ImplicitSurface")) << d.all().front().message;
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, LinkToItselfIsReported) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name="r" source="@r"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:30", "link source=\"@r\" of Recorder 'r' points to the component itself"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, LinkToANodeSaysItIsNotAComponent) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Node name="sub"/>
  <Recorder name="r" source="@sub"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:3:30", "link source=\"@sub\" of Recorder 'r': 'sub' is a node, not a component"));
}

TEST(SceneLoaderErrorTest, LinkAboveTheRootIsReported) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Recorder name="r" source="@../x"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:30", "'..' goes above the root node"));
}

// ---- names ----------------------------------------------------------------

TEST(SceneLoaderErrorTest, DuplicateComponentNameIsReportedAtTheSecondNameWithTheFirstLocation) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <AnalyticPlane name="plane"/>
  <AnalyticPlane name="plane" point="0 0 1"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:4:24", "duplicate name 'plane' in node '/' (first used at inline.xml:3:3)"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, TwoUnnamedComponentsOfOneTypeInANodeAreDuplicates) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <Node name="patient">
    <AnalyticPlane/>
    <AnalyticPlane normal="1 0 0"/>
  </Node>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:5:5",
                       "duplicate name 'AnalyticPlane' in node '/patient' (first used at inline.xml:4:5); "
                       "give each a distinct name attribute"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, NodeAndComponentShareOneNamespace) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <Node name="plane"/>
  <AnalyticPlane name="plane"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:4:24", "duplicate name 'plane' in node '/' (first used at inline.xml:3:3)"));
}

TEST(SceneLoaderErrorTest, SameNameInDifferentNodesIsFine) {
  Diagnostics d;
  auto simulation = loadScene(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <Node name="a"><AnalyticPlane name="plane"/></Node>
  <Node name="b"><AnalyticPlane name="plane"/></Node>
</Node>)",
                              d);
  EXPECT_NE(simulation, nullptr) << messages(d);
}

TEST(SceneLoaderErrorTest, EachUnnamedChildNodeIsReportedOnceAndNotAsADuplicate) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <Node/>
  <Node/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:3", "<Node> needs a name attribute"));
  EXPECT_TRUE(hasError(d, "inline.xml:3:3", "<Node> needs a name attribute"));
  EXPECT_EQ(d.errorCount(), 2);
}

// ---- plugins ----------------------------------------------------------------

TEST(SceneLoaderErrorTest, UnknownPluginIsReportedAtItsNameWithSuggestion) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="haptic"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:25", "unknown plugin 'haptic', did you mean 'haptics'?"));
  EXPECT_EQ(d.errorCount(), 1);
}

TEST(SceneLoaderErrorTest, RequiredPluginWithoutANameShowsTheExpectedForm) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin nme="haptics"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:2:19", "unknown attribute 'nme' of <RequiredPlugin>, did you mean 'name'?"));
  EXPECT_TRUE(hasError(d, "inline.xml:2:3", "<RequiredPlugin> needs a name: <RequiredPlugin name=\"haptics\"/>"));
}

// ---- several at once --------------------------------------------------------

TEST(SceneLoaderErrorTest, ThreeDifferentErrorsAreAllReported) {
  const Diagnostics d = loadFailure(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <AnalyticPlane name="plane" extnt="5"/>
  <Recordr name="r"/>
  <AnalyticPlane name="floor" point="0 0"/>
</Node>)");
  EXPECT_TRUE(hasError(d, "inline.xml:3:31", "unknown attribute 'extnt'"));
  EXPECT_TRUE(hasError(d, "inline.xml:4:3", "unknown component 'Recordr'"));
  EXPECT_TRUE(hasError(d, "inline.xml:5:38", "invalid point of AnalyticPlane 'floor': expected three numbers"));
  EXPECT_EQ(d.errorCount(), 3);
}

}  // namespace
}  // namespace trephine::test
