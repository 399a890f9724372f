// Tissues of a brain, by label, and the Resection that reads them: what a
// scene declares is checked against the mesh's own labels at load, each
// mistake located at the attribute that made it. The mesh: two tetrahedra
// sharing a face, Medit references 1 and 2 (brain and tumour), so the volume
// of each tissue is known exactly: 1/6 and 1/6 of a unit cube's corner,
// scaled to 10 mm (166.67 mm^3 each).
#include <gtest/gtest.h>

#include "framework/core/Diagnostics.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

constexpr const char* kTwoTissues = R"(MeshVersionFormatted 2
Dimension 3
Vertices
5
0 0 0 0
10 0 0 0
0 10 0 0
0 0 10 0
0 0 -10 0
Tetrahedra
2
1 2 3 4 1
1 3 2 5 2
End
)";

std::string scene(const std::filesystem::path& mesh, const std::string& tissues) {
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <Node name="patient">
    <TetraBrain name="brain" file=")" +
         mesh.string() + R"("/>
    )" + tissues +
         R"(
  </Node>
</Node>)";
}

struct Loaded {
  std::unique_ptr<Simulation> simulation;
  std::string messages;
};

Loaded load(const std::string& xml) {
  Diagnostics d;
  SimulationOptions options;
  options.duration = 0.01;
  Loaded loaded;
  loaded.simulation = test::loadScene(xml, d, options);
  loaded.messages = test::messages(d);
  return loaded;
}

class TissueTest : public testing::Test {
 protected:
  test::TempDir dir{"trephine-tissue"};
  std::filesystem::path mesh = dir.write("two.mesh", kTwoTissues);
};

TEST_F(TissueTest, EachTissueIsMeasuredFromItsOwnTetrahedra) {
  const Loaded loaded = load(scene(mesh, R"(<Tissue name="brain_matter" mesh="@brain" label="1" vascularity="0.03"/>
    <Tissue name="tumour" mesh="@brain" label="2" vascularity="0.12" removalEnergy="0.08"/>
    <Resection name="resection" mesh="@brain"/>)"));
  ASSERT_TRUE(loaded.simulation) << loaded.messages;
  EXPECT_EQ(loaded.messages.find("warning"), std::string::npos) << loaded.messages;
  const double corner = 1000.0 / 6;  // mm^3
  EXPECT_NEAR(test::componentCounter(*loaded.simulation, "Resection", "volume_mm3.brain_matter"), corner, 1e-9);
  EXPECT_NEAR(test::componentCounter(*loaded.simulation, "Resection", "volume_mm3.tumour"), corner, 1e-9);
}

TEST_F(TissueTest, ALabelTheMeshDoesNotHoldIsAnErrorThatListsItsLabels) {
  const Loaded loaded = load(scene(mesh, R"(<Tissue name="vessel" mesh="@brain" label="7" critical="true"/>)"));
  EXPECT_FALSE(loaded.simulation);
  EXPECT_NE(loaded.messages.find("label of Tissue 'vessel'"), std::string::npos) << loaded.messages;
  EXPECT_NE(loaded.messages.find("no tetrahedron of the mesh has label 7; its labels are 1 (1 tetrahedron), 2 (1 "
                                 "tetrahedron)"),
            std::string::npos)
      << loaded.messages;
}

TEST_F(TissueTest, TwoTissuesOfOneLabelAreRefused) {
  const Loaded loaded = load(scene(mesh, R"(<Tissue name="tumour" mesh="@brain" label="2"/>
    <Tissue name="necrosis" mesh="@brain" label="2"/>)"));
  EXPECT_FALSE(loaded.simulation);
  EXPECT_NE(loaded.messages.find("label 2 is already the tissue 'tumour'"), std::string::npos) << loaded.messages;
}

TEST_F(TissueTest, LabelsNoTissueDeclaresAreWarnedOfByNumber) {
  const Loaded loaded = load(scene(mesh, R"(<Tissue name="tumour" mesh="@brain" label="2"/>
    <Resection name="resection" mesh="@brain"/>)"));
  ASSERT_TRUE(loaded.simulation) << loaded.messages;
  EXPECT_NE(loaded.messages.find("warning: mesh of Resection 'resection'"), std::string::npos) << loaded.messages;
  EXPECT_NE(loaded.messages.find("the mesh's labels 1 (1) (tetrahedra) are no declared tissue"), std::string::npos)
      << loaded.messages;
}

TEST_F(TissueTest, AResectionWithNoTissueBeforeItIsAnError) {
  // The tissue placed after the Resection is not seen there: said so.
  const Loaded loaded = load(scene(mesh, R"(<Resection name="resection" mesh="@brain"/>
    <Tissue name="tumour" mesh="@brain" label="2"/>)"));
  EXPECT_FALSE(loaded.simulation);
  EXPECT_NE(loaded.messages.find("no tissue of /patient/brain is declared before this component"), std::string::npos)
      << loaded.messages;
}

TEST_F(TissueTest, UnitSlipsAreCaughtAtTheirAttribute) {
  // A vascularity given as a percentage; a removal energy in J/cm^3 read as J/mm^3.
  const Loaded percent = load(scene(mesh, R"(<Tissue name="tumour" mesh="@brain" label="2" vascularity="12"/>)"));
  EXPECT_FALSE(percent.simulation);
  EXPECT_NE(percent.messages.find("vascularity of Tissue 'tumour'"), std::string::npos) << percent.messages;
  EXPECT_NE(percent.messages.find("not a percentage: 12 is 1200%; 0.12 if a percentage was meant"), std::string::npos)
      << percent.messages;
  const Loaded hard = load(scene(mesh, R"(<Tissue name="tumour" mesh="@brain" label="2" removalEnergy="50"/>)"));
  ASSERT_TRUE(hard.simulation) << hard.messages;
  EXPECT_NE(hard.messages.find("warning: removalEnergy of Tissue 'tumour'"), std::string::npos) << hard.messages;
  EXPECT_NE(hard.messages.find("harder to remove than cortical bone is to cut"), std::string::npos) << hard.messages;
}

TEST_F(TissueTest, AMeshWithoutLabelsSaysWhereLabelsComeFrom) {
  const Loaded loaded = load(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <TetraBrain name="brain" file="phantom:cube?cells=2"/>
  <Tissue name="tumour" mesh="@brain" label="2"/>
</Node>)");
  EXPECT_FALSE(loaded.simulation);
  EXPECT_NE(loaded.messages.find("the mesh holds no tissue labels (its file gives none): a tissue is the tetrahedra "
                                 "of one label (TetGen region attributes, Medit references"),
            std::string::npos)
      << loaded.messages;
}

// A tissue tool's node on the two-tissue mesh: its proxy aims at /patient/brain.
std::string tissueTool(const std::string& tool, const std::string& proxyFields = "") {
  return R"(<Node name="hand">
    <ScriptedDevice name="device" path="drill-in" target="@/patient/brain" direction="0 0 -1" center="2 2 0"
                    tipOffset="1" standoff="3" depth="1" rate="1000"/>
    )" + tool + R"(
    <GodObjectProxy name="proxy" tool="@tool" target="@/patient/brain" )" +
         proxyFields + R"( rate="1000"/>
  </Node>)";
}

std::string sceneWithTools(const std::filesystem::path& mesh, const std::string& patient, const std::string& tools,
                           const std::string& brainFields = "") {
  return std::string(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  )") + (brainFields.find("bullet") != std::string::npos ? R"(<RequiredPlugin name="bullet"/>)" : "") + R"(
  <Node name="patient">
    <TetraBrain name="brain" file=")" +
         mesh.string() + "\" " + brainFields + R"(/>
    )" + patient + R"(
  </Node>
  )" + tools + R"(
</Node>)";
}

constexpr const char* kTissues = R"(<Tissue name="brain_matter" mesh="@brain" label="1"/>
    <Tissue name="tumour" mesh="@brain" label="2"/>)";

TEST_F(TissueTest, ATissueToolAimedAtABrainNoResectionResectsIsRefused) {
  for (const char* tool : {R"(<AspiratorTool name="tool" device="@device"/>)", R"(<BipolarForceps name="tool" device="@device"/>)"}) {
    const Loaded loaded = load(sceneWithTools(mesh, kTissues, tissueTool(tool)));
    EXPECT_FALSE(loaded.simulation) << tool;
    EXPECT_NE(loaded.messages.find("tool of GodObjectProxy 'proxy'"), std::string::npos) << loaded.messages;
    EXPECT_NE(loaded.messages.find("this tool removes or coagulates tissue, but its target cannot be resected: aim it "
                                   "at a TetraBrain with a <Resection mesh=\"@BRAIN\"/> placed before this component"),
              std::string::npos)
        << loaded.messages;
  }
  // With the Resection before the tools, the same scene loads.
  const Loaded resected = load(sceneWithTools(mesh, std::string(kTissues) + R"(<Resection name="resection" mesh="@brain"/>)",
                                              tissueTool(R"(<AspiratorTool name="tool" device="@device"/>)")));
  EXPECT_TRUE(resected.simulation) << resected.messages;
}

TEST_F(TissueTest, ResectionOnAMeshBackEndIsRefusedAtTheBrain) {
#ifndef TREPHINE_HAS_BULLET_BACKEND
  GTEST_SKIP() << "the bullet plugin is not built (Debian: libbullet-dev)";
#endif
  const Loaded loaded = load(sceneWithTools(mesh, std::string(kTissues) + R"(<Resection name="resection" mesh="@brain"/>)",
                                            "", R"(backend="bullet")"));
  EXPECT_FALSE(loaded.simulation);
  EXPECT_NE(loaded.messages.find("mesh of Resection 'resection'"), std::string::npos) << loaded.messages;
  EXPECT_NE(loaded.messages.find("backend=\"bullet\" cannot follow removed tetrahedra: resection needs "
                                 "backend=\"native\""),
            std::string::npos)
      << loaded.messages;
}

TEST_F(TissueTest, ATissueToolHasOnePedal) {
  const Loaded loaded =
      load(sceneWithTools(mesh, std::string(kTissues) + R"(<Resection name="resection" mesh="@brain"/>)",
                          tissueTool(R"(<AspiratorTool name="tool" device="@device" pedal="1"/>)", R"(drillButton="2")")));
  EXPECT_FALSE(loaded.simulation);
  EXPECT_NE(loaded.messages.find("drillButton of GodObjectProxy 'proxy'"), std::string::npos) << loaded.messages;
  EXPECT_NE(loaded.messages.find("the tool has a pedal of its own (button 1): set one of the two"), std::string::npos)
      << loaded.messages;
}

TEST_F(TissueTest, AnAspiratorsUnitSlipsAreWarnedOf) {
  const std::string patient = std::string(kTissues) + R"(<Resection name="resection" mesh="@brain"/>)";
  const Loaded khz = load(sceneWithTools(mesh, patient, tissueTool(R"(<AspiratorTool name="tool" device="@device" frequency="23"/>)")));
  ASSERT_TRUE(khz.simulation) << khz.messages;
  EXPECT_NE(khz.messages.find("warning: frequency of AspiratorTool 'tool'"), std::string::npos) << khz.messages;
  EXPECT_NE(khz.messages.find("kHz typed as Hz?"), std::string::npos) << khz.messages;
  const Loaded milli = load(sceneWithTools(mesh, patient, tissueTool(R"(<BipolarForceps name="tool" device="@device" power="5000"/>)")));
  ASSERT_TRUE(milli.simulation) << milli.messages;
  EXPECT_NE(milli.messages.find("warning: power of BipolarForceps 'tool'"), std::string::npos) << milli.messages;
  // An amplitude in micrometres is out of the field's range (at most 1 mm).
  const Loaded micro = load(sceneWithTools(mesh, patient, tissueTool(R"(<AspiratorTool name="tool" device="@device" amplitude="150"/>)")));
  EXPECT_FALSE(micro.simulation);
  EXPECT_NE(micro.messages.find("amplitude of AspiratorTool 'tool'"), std::string::npos) << micro.messages;
}

TEST_F(TissueTest, ATumourPlacedInAMeshTakesTheTetrahedraOfItsBall) {
  // The second tetrahedron's centre is (2.5, 2.5, -2.5): a ball of 3 mm there takes it alone.
  const Loaded loaded = load(scene(mesh, R"(<PlacedTumour name="lesion" mesh="@brain" center="2.5 2.5 -2.5" radius="3" label="9"/>
    <Tissue name="tumour" mesh="@brain" label="9"/>
    <Resection name="resection" mesh="@brain"/>)"));
  ASSERT_TRUE(loaded.simulation) << loaded.messages;
  EXPECT_EQ(test::componentCounter(*loaded.simulation, "PlacedTumour", "tetrahedra"), 1.0);
  EXPECT_NEAR(test::componentCounter(*loaded.simulation, "PlacedTumour", "volume_mm3"), 1000.0 / 6, 1e-9);
  EXPECT_NEAR(test::componentCounter(*loaded.simulation, "Resection", "volume_mm3.tumour"), 1000.0 / 6, 1e-9);
  // The other tetrahedron keeps its label (1): undeclared, warned of.
  EXPECT_NE(loaded.messages.find("the mesh's labels 1 (1)"), std::string::npos) << loaded.messages;
}

TEST_F(TissueTest, ATumourPlacedOutsideInAUsedLabelOrTooLateIsRefused) {
  const Loaded outside = load(scene(mesh, R"(<PlacedTumour name="lesion" mesh="@brain" center="100 0 0" radius="3" label="9"/>)"));
  EXPECT_FALSE(outside.simulation);
  EXPECT_NE(outside.messages.find("center of PlacedTumour 'lesion'"), std::string::npos) << outside.messages;
  EXPECT_NE(outside.messages.find("the tumour lies outside the brain"), std::string::npos) << outside.messages;
  const Loaded used = load(scene(mesh, R"(<PlacedTumour name="lesion" mesh="@brain" center="2.5 2.5 2.5" radius="3" label="2"/>)"));
  EXPECT_FALSE(used.simulation);
  EXPECT_NE(used.messages.find("label of PlacedTumour 'lesion'"), std::string::npos) << used.messages;
  EXPECT_NE(used.messages.find("label 2 is in use"), std::string::npos) << used.messages;
  const Loaded late = load(scene(mesh, R"(<Tissue name="tumour" mesh="@brain" label="2"/>
    <PlacedTumour name="lesion" mesh="@brain" center="2.5 2.5 2.5" radius="3" label="9"/>)"));
  EXPECT_FALSE(late.simulation);
  EXPECT_NE(late.messages.find("place this before the brain's Tissue, Resection and deformation components"),
            std::string::npos)
      << late.messages;
}

}  // namespace
}  // namespace trephine
