// The trephine program's contract: commands, exit codes, outputs.
#include <gtest/gtest.h>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using test::runProgram;

const std::string kPlaneTouch = (test::sourceDir() / "scenes/examples/plane_touch.xml").string();

TEST(TrephineProgramTest, VersionAndHelpExitZero) {
  std::string out;
  EXPECT_EQ(runProgram({"--version"}, &out), 0);
  EXPECT_TRUE(out.starts_with("trephine ")) << out;
  EXPECT_EQ(runProgram({"--help"}, &out), 0);
  EXPECT_NE(out.find("trephine run SCENE"), std::string::npos);
}

// Every command named in the whole help answers --help (and -h, and
// `trephine help COMMAND`) with its own part of it, exit 0, whatever else is
// on the line; a usage error points there.
TEST(TrephineProgramTest, EveryCommandAnswersHelpWithItsPartOfTheWholeHelp) {
  std::string whole;
  ASSERT_EQ(runProgram({"--help"}, &whole), 0);
  std::vector<std::string> names;
  for (size_t at = whole.find("\n  trephine "); at != std::string::npos; at = whole.find("\n  trephine ", at + 1)) {
    const size_t start = at + 12, end = whole.find_first_of(" \n", start);
    const std::string name = whole.substr(start, end - start);
    if (name.starts_with("-") || name == "COMMAND") continue;
    if (names.empty() || names.back() != name) names.push_back(name);
  }
  ASSERT_GE(names.size(), 8u) << whole;
  for (const std::string& name : names) {
    std::string help, shortHelp, viaHelp;
    EXPECT_EQ(runProgram({name, "--help"}, &help), 0) << name;
    EXPECT_TRUE(help.starts_with("usage:\n  trephine " + name + " ")) << help;
    // Its lines are the whole help's, from its first usage line to the next command's.
    const std::string body = help.substr(7, help.find("\nPlugins are searched") - 7);
    EXPECT_NE(whole.find(body), std::string::npos) << name << ":\n" << body;
    EXPECT_EQ(runProgram({name, "-h"}, &shortHelp), 0) << name;
    EXPECT_EQ(runProgram({"help", name}, &viaHelp), 0) << name;
    EXPECT_EQ(shortHelp, help);
    EXPECT_EQ(viaHelp, help);
    std::string withOthers;
    EXPECT_EQ(runProgram({name, "no-such-file.xml", "--no-such-option", "--help"}, &withOthers), 0) << name;
    EXPECT_EQ(withOthers, help);
    std::string error;
    EXPECT_EQ(runProgram({name, "--no-such-option"}, &error), 2) << name;
    EXPECT_NE(error.find("(trephine " + name + " --help)"), std::string::npos) << error;
  }
  std::string unknown;
  EXPECT_EQ(runProgram({"help", "fly"}, &unknown), 2);
  EXPECT_NE(unknown.find("unknown command 'fly'"), std::string::npos) << unknown;
}

TEST(TrephineProgramTest, UsageErrorsExitTwo) {
  std::string out;
  EXPECT_EQ(runProgram({}, &out), 2);
  EXPECT_EQ(runProgram({"fly"}, &out), 2);
  EXPECT_EQ(runProgram({"run"}, &out), 2);
  EXPECT_EQ(runProgram({"run", kPlaneTouch, "--duratoin", "1"}, &out), 2);
  EXPECT_NE(out.find("unknown option '--duratoin', did you mean '--duration'?"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"run", kPlaneTouch, "--duration", "-1"}, &out), 2);
  EXPECT_EQ(runProgram({"run", kPlaneTouch, "--seed", "x"}, &out), 2);
}

TEST(TrephineProgramTest, ValidateSaysOkOrListsEveryErrorWithExitOne) {
  std::string out;
  EXPECT_EQ(runProgram({"validate", kPlaneTouch}, &out), 0);
  EXPECT_EQ(out, "ok\n");

  test::TempDir dir;
  const auto bad = dir.write("bad.xml", R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <SphereTool name="burr" radius="-1" colour="red"/>
</Node>
)");
  EXPECT_EQ(runProgram({"validate", bad.string()}, &out), 1);
  EXPECT_NE(out.find(bad.string() + ":3:"), std::string::npos) << out;
  EXPECT_NE(out.find("3 errors"), std::string::npos) << out;
}

TEST(TrephineProgramTest, SetOverridesGoThroughValidation) {
  std::string out;
  EXPECT_EQ(runProgram({"validate", kPlaneTouch, "--set", "tool/force.stiffness=1.5"}, &out), 0) << out;
  EXPECT_EQ(runProgram({"validate", kPlaneTouch, "--set", "tool/force.stiffness=soft"}, &out), 1);
  EXPECT_NE(out.find("--set tool/force.stiffness=soft: error: invalid stiffness"), std::string::npos) << out;
}

TEST(TrephineProgramTest, RunWritesTheContractedOutputs) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(runProgram({"run", kPlaneTouch, "--duration", "0.5", "--out", dir.path().string(), "--seed", "3"}, &out), 0)
      << out;
  for (const char* file :
       {"summary.json", "trace.csv", "timings.csv", "device.tool.device.csv", "recording.record.recorder.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir / file)) << file;
  const std::string summary = test::readFile(dir / "summary.json");
  EXPECT_NE(summary.find("\"seed\": 3"), std::string::npos);
  EXPECT_NE(summary.find("\"sim_time_s\": 0.5"), std::string::npos);
  EXPECT_NE(out.find("haptics"), std::string::npos) << "the human summary is printed";
}

TEST(TrephineProgramTest, SceneErrorsExitOneAndRunNothing) {
  test::TempDir dir;
  const auto bad = dir.write("bad.xml", "<Node name=\"root\"><Nothing/></Node>\n");
  std::string out;
  EXPECT_EQ(runProgram({"run", bad.string(), "--out", (dir / "out").string()}, &out), 1);
  EXPECT_NE(out.find("unknown component 'Nothing'"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

TEST(TrephineProgramTest, ComponentsDocumentsEveryFieldOfEveryPlugin) {
  std::string out;
  ASSERT_EQ(runProgram({"components", "--json"}, &out), 0);
  for (const char* text : {"\"ScriptedDevice\"", "\"ReplayDevice\"", "\"AnalyticPlane\"", "\"Recorder\"",
                           "\"unit\": \"N/mm\"", "\"type\": \"link<HapticDevice>\""})
    EXPECT_NE(out.find(text), std::string::npos) << text;
  ASSERT_EQ(runProgram({"components", "SpringForce"}, &out), 0);
  EXPECT_NE(out.find("stiffness : double = 2 N/mm"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"components", "SpringForse"}, &out), 1);
  EXPECT_NE(out.find("did you mean 'SpringForce'?"), std::string::npos) << out;
}

TEST(TrephineProgramTest, GeneratedSchemaAcceptsEveryShippedSceneAndRejectsMistakes) {
  if (std::system("command -v xmllint > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "xmllint (libxml2-utils) is not installed";
  test::TempDir dir;
  std::string schema;
  ASSERT_EQ(runProgram({"components", "--xsd"}, &schema, "env -u TREPHINE_PLUGIN_PATH"), 0);
  const auto xsd = dir.write("trephine.xsd", schema);
  for (const auto& entry : std::filesystem::recursive_directory_iterator(test::sourceDir() / "scenes")) {
    // The patient template leaves its input files to the command line.
    if (entry.path().extension() != ".xml" || entry.path().parent_path().filename() == "patient") continue;
    const std::string command = "xmllint --noout --schema '" + xsd.string() + "' '" + entry.path().string() + "' 2>&1";
    EXPECT_EQ(std::system((command + " > /dev/null").c_str()), 0) << entry.path();
  }
  const auto bad =
      dir.write("bad.xml", R"(<Node name="r"><SphereTool radus="1"/><ScriptedDevice path="zigzag"/></Node>)");
  EXPECT_NE(
      std::system(("xmllint --noout --schema '" + xsd.string() + "' '" + bad.string() + "' > /dev/null 2>&1").c_str()),
      0);
}

TEST(TrephineProgramTest, PhantomWritesAVolumeTheSceneCanLoad) {
  test::TempDir dir;
  std::string out;
  ASSERT_EQ(runProgram({"phantom", "skull?voxel=4", "--out", (dir / "skull.mha").string()}, &out), 0) << out;
  EXPECT_NE(out.find("54 x 51 x 36 voxels of 4 mm"), std::string::npos) << out;
  // The same skull as a file and as a phantom source give the same run.
  const std::string scene = R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <VoxelSkull name="skull" file="SOURCE"/>
  <ScriptedDevice name="device" target="@skull" tipOffset="2.5" record="false"/>
  <PointshellTool name="burr" radius="2.5" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@skull"/>
  <ForceFeedback name="force" proxy="@proxy"/>
</Node>)";
  std::string fileTrace;
  for (const std::string source : {"skull.mha", "phantom:skull?voxel=4"}) {
    std::string xml = scene;
    xml.replace(xml.find("SOURCE"), 6, source);
    dir.write("scene.xml", xml);
    ASSERT_EQ(runProgram({"run", (dir / "scene.xml").string(), "--quiet", "--out", (dir / "run").string()}, &out), 0)
        << out;
    if (source == "skull.mha") {
      fileTrace = test::readFile(dir / "run/trace.csv");
    } else {
      EXPECT_EQ(test::readFile(dir / "run/trace.csv"), fileTrace) << "file and phantom differ";
    }
  }
  EXPECT_EQ(runProgram({"phantom", "sphere", "--out", (dir / "x.mha").string()}, &out), 1);
  EXPECT_NE(out.find("unknown phantom 'sphere'"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"phantom", "skull?voxel=4"}, &out), 2) << "no --out";
  // The plugins write their phantoms: a mesh from tetra_brain, by the suffix.
  ASSERT_EQ(runProgram({"phantom", "cube?cells=3", "--out", (dir / "cube.mesh").string()}, &out), 0) << out;
  EXPECT_NE(out.find("64 nodes, 135 tetrahedra"), std::string::npos) << out;
  EXPECT_EQ(runProgram({"phantom", "cube?cells=3", "--out", (dir / "cube.vtk").string()}, &out), 2);
  EXPECT_NE(out.find("expected .mesh or .mesh.gz (a tetrahedral mesh) or .mha or .mhd (a volume)"), std::string::npos)
      << out;
  EXPECT_EQ(runProgram({"phantom", "cube?cells=3", "--raw", "--out", (dir / "cube.mesh").string()}, &out), 2);
}

TEST(TrephineProgramTest, TheSceneReferenceInTheDocsIsCurrent) {
  std::string generated;
  ASSERT_EQ(runProgram({"components", "--markdown"}, &generated, "env -u TREPHINE_PLUGIN_PATH"), 0);
  const std::string doc = test::readFile(test::sourceDir() / "docs/scene-format.md");
  const std::string begin = "<!-- BEGIN GENERATED COMPONENT REFERENCE -->\n";
  const std::string end = "<!-- END GENERATED COMPONENT REFERENCE -->";
  const size_t from = doc.find(begin), to = doc.find(end);
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  EXPECT_EQ(doc.substr(from + begin.size(), to - from - begin.size()), generated)
      << "docs/scene-format.md is out of date: run tools/update-docs";
}

}  // namespace
}  // namespace trephine
