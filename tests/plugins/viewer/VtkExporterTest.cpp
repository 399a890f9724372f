// VtkExporter through `trephine run`: the files a run leaves and their index,
// read back by the project's VTU reader and as XML; nothing written when the
// run writes no files; clear errors for scenes that name nothing or order the
// deformation after the exporter.
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <cmath>
#include <regex>

#include "plugins/tetra_brain/io/TetMeshReader.h"
#include "plugins/tetra_brain/CubePhantom.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

// A 0.5 mm wave through a cube brain under a probe pressing its top, for 0.4 s.
std::string scene(const std::string& exporter, bool exporterFirst = false) {
  const std::string deformation =
      R"(<ScriptedDeformation name="wave" mesh="@brain" shape="wave" amplitude="0.5" period="0.2" center="0 0 100" rate="1000"/>)";
  return R"(<Node name="root" units="mm">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="viewer"/>
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:cube?cells=6"/>
    )" + (exporterFirst ? exporter + "\n    " + deformation : deformation) + R"(
  </Node>
  <Node name="tool">
    <ScriptedDevice name="device" path="pokes" target="@/patient/brain" direction="0 0 -1" center="0 0 0"
                    tipOffset="2.5" rate="1000"/>
    <PointshellTool name="probe" radius="2.5" angleStep="15" device="@device"/>
    <GodObjectProxy name="proxy" tool="@probe" target="@/patient/brain" rate="1000"/>
    <ForceFeedback name="force" proxy="@proxy" stiffness="0.3" maxForce="3.3" rate="1000"/>
  </Node>
  <Node name="out">)" + (exporterFirst ? "" : exporter) + R"(</Node>
</Node>)";
}

constexpr const char* kExporter = R"(<VtkExporter name="vtk" brain="@/patient/brain" force="@/tool/force" rate="30"/>)";

TEST(VtkExporterTest, ARunLeavesItsFilesAndAnIndexInTime) {
  test::TempDir dir;
  dir.write("scene.xml", scene(kExporter));
  std::string output;
  ASSERT_EQ(test::runProgram({"run", (dir / "scene.xml").string(), "--quiet", "--duration", "0.4", "--out",
                              (dir / "run").string()},
                             &output),
            0)
      << output;
  tinyxml2::XMLDocument pvd;
  ASSERT_EQ(pvd.LoadFile((dir / "run" / "vtk.pvd").c_str()), tinyxml2::XML_SUCCESS) << output;
  int brains = 0, tools = 0;
  double lastTime = -1;
  std::string lastBrain;
  for (const auto* set = pvd.RootElement()->FirstChildElement("Collection")->FirstChildElement("DataSet"); set;
       set = set->NextSiblingElement("DataSet")) {
    const std::string file = set->Attribute("file");
    const double t = set->DoubleAttribute("timestep");
    EXPECT_GE(t, lastTime) << file;
    lastTime = t;
    EXPECT_TRUE(std::filesystem::exists(dir / "run" / file)) << file;
    if (std::regex_match(file, std::regex("vtk/brain_[0-9]{5}\\.vtu"))) ++brains, lastBrain = file;
    if (std::regex_match(file, std::regex("vtk/tool_[0-9]{5}\\.vtp"))) ++tools;
  }
  // 0.4 s at 30 Hz: 12 or 13 frames, a brain and a tool each (the wave moves the brain every frame).
  EXPECT_GE(tools, 12);
  EXPECT_LE(tools, 13);
  EXPECT_EQ(brains, tools);
  EXPECT_NEAR(lastTime, 0.4, 1.0 / 30 + 1e-9);
  // The brain read back: the phantom's mesh, its nodes where the wave put them
  // (within its 0.5 mm amplitude of rest, and not all at rest).
  const tetra::TetMesh rest = tetra::makeCubeMesh(6);
  const tetra::TetMesh brain = tetra::readTetMesh(dir / "run" / lastBrain);
  ASSERT_EQ(brain.nodeCount(), rest.nodeCount());
  ASSERT_EQ(brain.tetCount(), rest.tetCount());
  double largest = 0;
  for (size_t i = 0; i < rest.nodeCount(); ++i) largest = std::max(largest, (brain.nodes[i] - rest.nodes[i]).norm());
  EXPECT_GT(largest, 0.05);
  EXPECT_LE(largest, 0.5 + 1e-4);
}

TEST(VtkExporterTest, ARunThatWritesNoFilesWritesNoneOfThese) {
  test::TempDir dir;
  auto simulation = test::runScene(scene(kExporter));
  ASSERT_TRUE(simulation);
  EXPECT_EQ(test::componentCounter(*simulation, "VtkExporter", "files"), 0.0);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

TEST(VtkExporterTest, ScenesThatNameNothingOrDeformLateAreRefused) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(scene(R"(<VtkExporter name="vtk"/>)"), d));
  EXPECT_NE(test::messages(d).find("names nothing to write"), std::string::npos) << test::messages(d);
  EXPECT_NE(test::messages(d).find("inline.xml:"), std::string::npos) << test::messages(d);
  Diagnostics late;
  SimulationOptions options;
  options.outputDirectory = "unused";
  EXPECT_FALSE(test::loadScene(scene(R"(<VtkExporter name="vtk" brain="@brain"/>)", true), late, options));
  EXPECT_NE(test::messages(late).find("place the VtkExporter after it"), std::string::npos) << test::messages(late);
}

}  // namespace
}  // namespace trephine
