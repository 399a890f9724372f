// VtkExporter through `trephine run`: the files a run leaves and their index,
// read back by the project's VTU reader and as XML; nothing written when the
// run writes no files; clear errors for scenes that name nothing or order the
// deformation after the exporter; a file that cannot be written reported.
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <cmath>
#include <regex>
#include <set>
#include <sstream>

#include "plugins/tetra_brain/CubePhantom.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/data/IsoSurface.h"
#include "framework/formats/volume/VolumeReader.h"
#include "tests/support/TestSupport.h"
#include "tests/support/VtkAppended.h"

namespace trephine {
namespace {

// A 0.5 mm wave through a cube brain under a probe poking its top (first contact at 0.58 s).
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

// Runs `xml` for `seconds` with trephine run into dir/run; the program's output.
std::string runInto(const test::TempDir& dir, const std::string& xml, const std::string& seconds) {
  dir.write("scene.xml", xml);
  std::string output;
  EXPECT_EQ(test::runProgram({"run", (dir / "scene.xml").string(), "--quiet", "--duration", seconds, "--out",
                              (dir / "run").string()},
                             &output),
            0)
      << output;
  return output;
}

constexpr const char* kExporter = R"(<VtkExporter name="vtk" brain="@/patient/brain" force="@/tool/force" rate="30"/>)";

TEST(VtkExporterTest, ARunLeavesItsFilesAndAnIndexInTime) {
  test::TempDir dir;
  const std::string output = runInto(dir, scene(kExporter), "1.0");
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
  // 1 s at 30 Hz: 30 or 31 frames, a brain and a tool each (the wave moves the brain every frame).
  EXPECT_GE(tools, 30);
  EXPECT_LE(tools, 31);
  EXPECT_EQ(brains, tools);
  EXPECT_NEAR(lastTime, 1.0, 1.0 / 30 + 1e-9);
  // The brain read back: the phantom's mesh, its nodes where the wave put them
  // (within its 0.5 mm amplitude of rest, and not all at rest).
  const TetMesh rest = tetra::makeCubeMesh(6);
  const TetMesh brain = formats::readTetMesh(dir / "run" / lastBrain);
  ASSERT_EQ(brain.nodeCount(), rest.nodeCount());
  ASSERT_EQ(brain.tetCount(), rest.tetCount());
  double largest = 0;
  for (size_t i = 0; i < rest.nodeCount(); ++i) largest = std::max(largest, (brain.nodes[i] - rest.nodes[i]).norm());
  EXPECT_GT(largest, 0.05);
  EXPECT_LE(largest, 0.5 + 1e-4);
  // The probe's forces reach the deforming brain's files: on some frame the
  // nodes carry a force, and it pushes down (the probe presses the top face).
  double strongest = 0, downward = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "vtk")) {
    if (!entry.path().filename().string().starts_with("brain_")) continue;
    const std::string text = test::readFile(entry.path());
    const std::vector<float> force = test::appendedArray<float>(text, test::appendedOffset(text, "force"));
    ASSERT_EQ(force.size(), 3 * rest.nodeCount());
    Vec3 total = Vec3::Zero();
    for (size_t i = 0; i < rest.nodeCount(); ++i) total += Vec3(force[3 * i], force[3 * i + 1], force[3 * i + 2]);
    if (total.norm() > strongest) strongest = total.norm(), downward = -total.z();
  }
  EXPECT_GT(strongest, 0.01) << "N";
  EXPECT_GT(downward, 0.9 * strongest);
  // In contact, the tool's file has a third point, where the displayed probe
  // meets the top face (z = 100 mm, the wave within 0.5 mm of it): 2.5 mm
  // (the probe's radius) below the proxy. Out of contact, two points.
  int inContact = 0, outOfContact = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "vtk")) {
    if (!entry.path().filename().string().starts_with("tool_")) continue;
    const std::string text = test::readFile(entry.path());
    const size_t points = text.find("<Points>");
    ASSERT_NE(points, std::string::npos);
    const std::vector<float> xyz =
        test::appendedArray<float>(text, std::stoull(text.substr(text.find("offset=\"", points) + 8)));
    if (xyz.size() == 6) {
      ++outOfContact;
      continue;
    }
    ASSERT_EQ(xyz.size(), 9u) << entry.path();
    ++inContact;
    const Vec3 proxy(xyz[3], xyz[4], xyz[5]), contact(xyz[6], xyz[7], xyz[8]);
    EXPECT_NEAR((proxy - contact).norm(), 2.5, 1e-4) << entry.path();
    EXPECT_NEAR(contact.z(), 100.0, 0.6) << entry.path();
    EXPECT_LT(proxy.z() - contact.z(), 2.5 + 1e-4);
    EXPECT_GT(proxy.z() - contact.z(), 2.4) << "the normal is the top face's";
  }
  EXPECT_GT(inContact, 3);
  EXPECT_GT(outOfContact, 3);
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

// The number of triangles in a .vtp the exporter wrote (its Piece's NumberOfPolys).
int polysIn(const std::filesystem::path& file) {
  const std::string text = test::readFile(file);
  const size_t at = text.find("NumberOfPolys=\"");
  return at == std::string::npos ? -1 : std::stoi(text.substr(at + 15));
}

// The triangles of a skull frame: those of every block file its .vtm lists.
int polysOfFrame(const std::filesystem::path& vtm) {
  tinyxml2::XMLDocument xml;
  if (xml.LoadFile(vtm.c_str()) != tinyxml2::XML_SUCCESS) return -1;
  int total = 0;
  for (const auto* set = xml.RootElement()->FirstChildElement("vtkMultiBlockDataSet")->FirstChildElement("DataSet");
       set; set = set->NextSiblingElement("DataSet"))
    total += polysIn(vtm.parent_path() / set->Attribute("file"));
  return total;
}

// A burr drilling the skull phantom (1.5 mm voxels) for 0.6 s, the surface
// written at most every 0.1 s and the drilled volume saved at the end.
std::string drillScene(bool drill) {
  return std::string(R"(<Node name="root" units="mm">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="viewer"/>
  <Node name="patient">
    <VoxelSkull name="skull" file="phantom:skull?voxel=1.5" isovalue="600" drill=")") +
         (drill ? "true\" saveDrilled=\"drilled.mha\"" : "false\"") + R"(/>
  </Node>
  <Node name="tool">
    <ScriptedDevice name="device" path="circle" target="@/patient/skull" direction="0 0 -1" tipOffset="2.5"
                    standoff="2" speed="20" depth="1.5" radius="5" period="1" turns="2" rate="1000"/>
    <PointshellTool name="burr" radius="2.5" pointCount="466" device="@device"/>
    <GodObjectProxy name="proxy" tool="@burr" target="@/patient/skull" sweep="line" rate="1000"/>
    <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" maxForce="3.3" rate="1000"/>
  </Node>
  <Node name="out">
    <VtkExporter name="vtk" skull="@/patient/skull" rate="30" skullInterval="0.1"/>
  </Node>
</Node>)";
}

// The copy the exporter keeps from the drill's changes ends as the skull
// itself: its last surface is the one extracted from the drilled volume the
// skull saves, triangle for triangle.
TEST(VtkExporterTest, TheSkullFollowsTheDrillToTheSavedVolume) {
  test::TempDir dir;
  const std::string output = runInto(dir, drillScene(true), "0.6");
  std::vector<std::filesystem::path> skulls;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "vtk"))
    if (std::regex_match(entry.path().filename().string(), std::regex("skull_[0-9]{5}\\.vtm"))) skulls.push_back(entry.path());
  std::sort(skulls.begin(), skulls.end());
  ASSERT_GE(skulls.size(), 2u) << "the start and at least one drilled state";
  EXPECT_LE(skulls.size(), 8u) << "at most every 0.1 s, and the end";
  // After the first frame only the drilled blocks get files: far fewer than the skull has.
  size_t blockFiles = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "vtk" / "skull")) blockFiles += entry.is_regular_file();
  tinyxml2::XMLDocument first;
  ASSERT_EQ(first.LoadFile(skulls.front().c_str()), tinyxml2::XML_SUCCESS);
  size_t firstBlocks = 0;
  for (const auto* set = first.RootElement()->FirstChildElement("vtkMultiBlockDataSet")->FirstChildElement("DataSet");
       set; set = set->NextSiblingElement("DataSet"))
    ++firstBlocks;
  EXPECT_GT(blockFiles, firstBlocks) << "drilled blocks were written again";
  // Every index names its block (skull/bB_frame.vtp), whichever blocks are
  // empty: a block that empties or fills moves no other.
  for (const auto& skull : skulls) {
    tinyxml2::XMLDocument vtm;
    ASSERT_EQ(vtm.LoadFile(skull.c_str()), tinyxml2::XML_SUCCESS);
    for (const auto* set = vtm.RootElement()->FirstChildElement("vtkMultiBlockDataSet")->FirstChildElement("DataSet");
         set; set = set->NextSiblingElement("DataSet")) {
      std::smatch block;
      const std::string file = set->Attribute("file");
      ASSERT_TRUE(std::regex_match(file, block, std::regex("skull/b([0-9]+)_[0-9]{5}\\.vtp"))) << file;
      EXPECT_EQ(set->IntAttribute("index"), std::stoi(block[1])) << skull;
    }
  }
  EXPECT_LT(blockFiles, firstBlocks + firstBlocks / 4) << "only the drilled ones";
  DensityVolume drilled = formats::readVolume(dir / "run" / "drilled.mha");
  BlockedIsoSurface expected;
  expected.build(VoxelGrid::of(drilled, 600.0));
  const TriangleMesh merged = expected.merged();
  EXPECT_EQ(polysOfFrame(skulls.back()), int(merged.triangles.size()));
  EXPECT_NE(polysOfFrame(skulls.front()), polysOfFrame(skulls.back())) << "the drill changed the surface";
  // The volume as the run started and the voxels the drill cut, against the
  // volume the skull saved at the end: a voxel is listed exactly when it was
  // bone (600 and up) at the start and is not at the end, and every voxel
  // not listed is as it started or only lowered while staying bone.
  const DensityVolume start = formats::readVolume(dir / "run" / "vtk" / "skull_density.mhd");
  ASSERT_EQ(start.dims(), drilled.dims());
  EXPECT_EQ(start.origin(), drilled.origin());
  std::set<size_t> listed;
  {
    std::istringstream csv(test::readFile(dir / "run" / "vtk" / "skull_removed.csv"));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "i,j,k,t");
    double lastT = 0;
    while (std::getline(csv, line)) {
      int i, j, k;
      double t;
      ASSERT_EQ(std::sscanf(line.c_str(), "%d,%d,%d,%lf", &i, &j, &k, &t), 4) << line;
      EXPECT_GE(t, lastT) << "in time order";
      EXPECT_LE(t, 0.6 + 1e-6);  // s, float
      lastT = t;
      EXPECT_TRUE(listed.insert(start.index(i, j, k)).second) << "listed once: " << line;
    }
  }
  size_t cut = 0;
  for (size_t v = 0; v < start.voxelCount(); ++v) {
    const double before = start.encoding().density(start.code(v)), after = drilled.encoding().density(drilled.code(v));
    const bool wentBelow = before >= 600 && after < 600;
    cut += wentBelow;
    ASSERT_EQ(listed.count(v) == 1, wentBelow) << "voxel " << v << ": " << before << " then " << after;
    ASSERT_LE(after, before) << "voxel " << v;
  }
  EXPECT_GT(cut, 10u);
  const std::string summary = test::readFile(dir / "run" / "summary.json");
  const size_t at = summary.find("\"skull_edits\": ");
  ASSERT_NE(at, std::string::npos) << summary;
  EXPECT_GT(std::stod(summary.substr(at + 15)), 0.0) << "code changes reached the copy";
}

TEST(VtkExporterTest, ASkullNotDrilledIsWrittenOnce) {
  test::TempDir dir;
  const std::string output = runInto(dir, drillScene(false), "0.3");
  int skulls = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "vtk"))
    skulls += std::regex_match(entry.path().filename().string(), std::regex("skull_[0-9]{5}\\.vtm"));
  EXPECT_EQ(skulls, 1);
  // Its volume, and no voxel cut.
  EXPECT_TRUE(std::filesystem::is_regular_file(dir / "run" / "vtk" / "skull_density.mhd"));
  EXPECT_EQ(test::readFile(dir / "run" / "vtk" / "skull_removed.csv"), "i,j,k,t\n");
}

// A file the exporter cannot write (here a folder stands at its name; a
// process out of descriptors fails the same way) does not stop the run, and
// is not lost in silence: it is counted, the run ends with a run-time
// failure, and summary.json says which file and why.
// Files larger than 8 KB cannot be written (a file size limit; an obstacle
// left in the run's folder beforehand would be cleared by the run's claim on
// it): every brain frame (9 KB) fails, every tool frame (2 KB) is written.
TEST(VtkExporterTest, AFileThatCannotBeWrittenIsCountedAndReported) {
  test::TempDir dir;
  dir.write("scene.xml", scene(kExporter));
  std::string output;
  EXPECT_EQ(test::runProgram({"run", (dir / "scene.xml").string(), "--quiet", "--duration", "0.5", "--out",
                              (dir / "run").string()},
                             &output, "trap '' XFSZ; ulimit -f 16;"),
            3)
      << output;
  EXPECT_NE(output.find("15 files could not be written; the first: "), std::string::npos) << output;
  EXPECT_NE(output.find("brain_00000.vtu: write failed: File too large"), std::string::npos) << output;
  const std::string summary = test::readFile(dir / "run" / "summary.json");
  EXPECT_NE(summary.find("\"failed_files\": 15"), std::string::npos) << summary;
  const size_t errors = summary.find("\"output_errors\"");
  ASSERT_NE(errors, std::string::npos) << summary;
  EXPECT_NE(summary.find("brain_00000.vtu", errors), std::string::npos) << summary;
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "vtk" / "brain_00000.vtu")) << "no frame is left cut short";
  EXPECT_TRUE(std::filesystem::exists(dir / "run" / "vtk" / "tool_00014.vtp")) << "the frames that fit were written";
}

// A burr on a shaft (a 2 mm burr, 40 mm of shaft) is drawn with its burr's
// radius, and its contact point is on the burr: before, the radius written
// was the tool's bounding radius, the shaft's length, and the viewer drew a
// 40 mm ball.
TEST(VtkExporterTest, ACapsulesBurrIsDrawnWithItsOwnRadius) {
  test::TempDir dir;
  std::string xml = scene(kExporter);
  const size_t at = xml.find("<PointshellTool");
  xml.replace(at, xml.find("/>", at) + 2 - at,
              R"(<CapsuleTool name="probe" radius="2" shaftLength="40" device="@device"/>)");
  xml.replace(xml.find(R"(tipOffset="2.5")"), 15, R"(tipOffset="2")");
  runInto(dir, xml, "1.0");
  int files = 0, inContact = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "vtk")) {
    if (!entry.path().filename().string().starts_with("tool_")) continue;
    ++files;
    const std::string text = test::readFile(entry.path());
    for (const float radius : test::appendedArray<float>(text, test::appendedOffset(text, "radius")))
      EXPECT_FLOAT_EQ(radius, 2.0f) << entry.path();
    const size_t points = text.find("<Points>");
    const std::vector<float> xyz =
        test::appendedArray<float>(text, std::stoull(text.substr(text.find("offset=\"", points) + 8)));
    if (xyz.size() != 9) continue;
    ++inContact;
    EXPECT_NEAR((Vec3(xyz[3], xyz[4], xyz[5]) - Vec3(xyz[6], xyz[7], xyz[8])).norm(), 2.0, 1e-4) << entry.path();
  }
  EXPECT_GT(files, 10);
  EXPECT_GT(inContact, 3);
}

// The tool in hand is also drawn in its true shape (toolshape_NNNNN.vtp):
// the burr's sphere at the proxy and the shaft from it along the tool's axis
// (here the device's +z, its orientation the identity), 40 mm long and of
// the shaft's radius, closed at its end. Every point lies on that surface,
// and the surface reaches the shaft's end.
TEST(VtkExporterTest, ACapsuleIsDrawnWithItsShaft) {
  test::TempDir dir;
  std::string xml = scene(kExporter);
  const size_t at = xml.find("<PointshellTool");
  xml.replace(at, xml.find("/>", at) + 2 - at,
              R"(<CapsuleTool name="probe" radius="2" shaftRadius="0.8" shaftLength="40" device="@device"/>)");
  xml.replace(xml.find(R"(tipOffset="2.5")"), 15, R"(tipOffset="2")");
  runInto(dir, xml, "1.0");
  const auto pointsOf = [](const std::string& text) {
    const size_t points = text.find("<Points>");
    return test::appendedArray<float>(text, std::stoull(text.substr(text.find("offset=\"", points) + 8)));
  };
  int shapes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "vtk")) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("toolshape_")) continue;
    ++shapes;
    const std::vector<float> tool = pointsOf(test::readFile(dir / "run" / "vtk" / ("tool_" + name.substr(10))));
    ASSERT_GE(tool.size(), 6u) << name;
    const Vec3 proxy(tool[3], tool[4], tool[5]);
    const std::string text = test::readFile(entry.path());
    EXPECT_NE(text.find("<Polys>"), std::string::npos) << name;
    const std::vector<float> xyz = pointsOf(text);
    ASSERT_GT(xyz.size(), 300u) << name;
    double farthest = 0;
    for (size_t i = 0; i + 2 < xyz.size(); i += 3) {
      const Vec3 p = Vec3(xyz[i], xyz[i + 1], xyz[i + 2]) - proxy;
      const bool onBurr = std::abs(p.norm() - 2.0) < 1e-4;
      const double along = p.z(), across = std::hypot(p.x(), p.y());
      const bool onShaft = along > -1e-4 && along < 40 + 1e-4 && across < 0.8 + 1e-4 &&
                           (std::abs(across - 0.8) < 1e-4 || std::abs(along - 40) < 1e-4);
      EXPECT_TRUE(onBurr || onShaft) << name << ": " << p.transpose();
      farthest = std::max(farthest, p.norm());
    }
    EXPECT_NEAR(farthest, std::hypot(40.0, 0.8), 1e-3) << name << ": the shaft's end is drawn";
  }
  EXPECT_GT(shapes, 10);
  EXPECT_NE(test::readFile(dir / "run" / "vtk.pvd").find("toolshape_00000.vtp"), std::string::npos);
}

// With the TLED FEM deforming the cube under the probe, each brain file
// carries every element's von Mises stress (kPa): zero at the start, and
// under the probe the most stressed element is the one it presses (near the
// top face's middle). The FEM computes stresses only for such a reader.
TEST(VtkExporterTest, TheFemsStressesReachTheBrainFilesOnlyWhenExported) {
  const std::string fem = R"(<TetraBrain name="brain" file="phantom:cube?cells=6"/>
    <TLEDForceField name="fem" mesh="@brain" rate="500")";
  auto withFem = [&](const std::string& exporter) {
    std::string xml = scene(exporter);
    xml.replace(xml.find(R"(<TetraBrain name="brain" file="phantom:cube?cells=6"/>)"),
                std::string(R"(<TetraBrain name="brain" file="phantom:cube?cells=6"/>)").size(), fem + "/>");
    xml.insert(xml.find(R"(<RequiredPlugin name="viewer"/>)"), R"(<RequiredPlugin name="fem"/>
  )");
    xml.erase(xml.find("<ScriptedDeformation"), xml.find("/>", xml.find("<ScriptedDeformation")) + 2 -
                                                   xml.find("<ScriptedDeformation"));
    return xml;
  };
  test::TempDir dir;
  const std::string output = runInto(dir, withFem(kExporter), "1.5");
  const TetMesh rest = tetra::makeCubeMesh(6);
  double peak = 0;
  Vec3 peakAt = Vec3::Zero();
  int files = 0;
  bool firstAtRest = false;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "vtk")) {
    if (!entry.path().filename().string().starts_with("brain_")) continue;
    const std::string text = test::readFile(entry.path());
    const std::vector<float> stress = test::appendedArray<float>(text, test::appendedOffset(text, "von_mises"));
    ASSERT_EQ(stress.size(), rest.tetCount()) << entry.path();
    ++files;
    if (entry.path().filename() == "brain_00000.vtu")
      firstAtRest = *std::max_element(stress.begin(), stress.end()) == 0.0f;
    for (size_t e = 0; e < stress.size(); ++e) {
      ASSERT_TRUE(std::isfinite(stress[e]) && stress[e] >= 0) << entry.path() << " element " << e;
      if (stress[e] > peak) {
        peak = stress[e];
        peakAt = Vec3::Zero();
        for (int32_t node : rest.tets[e]) peakAt += rest.nodes[node] / 4;
      }
    }
  }
  ASSERT_GT(files, 5) << output;
  EXPECT_TRUE(firstAtRest);
  EXPECT_GT(peak, 0.01) << "kPa";
  // The probe presses the top face (z = 100 mm) at x = y = 0; elements are
  // 33 mm across: the most stressed one touches that point's cell.
  EXPECT_LT(std::hypot(peakAt.x(), peakAt.y()), 34.0) << peakAt.transpose();
  EXPECT_GT(peakAt.z(), 100 - 34.0) << peakAt.transpose();
  // Read by the exporter: computed at most every stressInterval (1/30 s) of
  // the 1.5 s. Without it: never.
  test::TempDir none;
  dir.write("plain.xml", withFem(R"(<VtkExporter name="vtk" force="@/tool/force"/>)"));
  auto stressUpdates = [](const std::filesystem::path& run) {
    const std::string summary = test::readFile(run / "summary.json");
    const size_t at = summary.find("\"stress_updates\"");
    return at == std::string::npos ? -1.0 : std::stod(summary.substr(summary.find(':', at) + 1));
  };
  const double exported = stressUpdates(dir / "run");
  EXPECT_GT(exported, 5);
  EXPECT_LE(exported, 1.5 * 30 + 1);
  std::string plainOutput;
  ASSERT_EQ(test::runProgram({"run", (dir / "plain.xml").string(), "--quiet", "--duration", "0.5", "--out",
                              (none / "run").string()}, &plainOutput), 0) << plainOutput;
  EXPECT_EQ(stressUpdates(none / "run"), 0.0);
}

// The tumour resection on a coarser phantom (5,000 tetrahedra), exported:
// the brain's files follow the removal, the last one holding exactly the
// tetrahedra that remain (the brain's counter), fewer than the mesh had.
TEST(VtkExporterTest, AResectedBrainsFilesHoldWhatRemains) {
  test::TempDir dir;
  std::string xml = test::readFile(test::sourceDir() / "scenes" / "resection.xml");
  xml.replace(xml.find("tets=22000"), std::string("tets=22000").size(), "tets=5000");
  xml.insert(xml.rfind("</Node>"), R"(<Node name="out"><VtkExporter name="vtk" brain="@/patient/brain" rate="10"/></Node>
)");
  xml.insert(xml.find("<RequiredPlugin"), R"(<RequiredPlugin name="viewer"/>
  )");
  runInto(dir, xml, "10");
  const std::string summary = test::readFile(dir / "run" / "summary.json");
  const size_t at = summary.find("\"remaining_tetrahedra\":", summary.find("\"resection\": {"));
  ASSERT_NE(at, std::string::npos) << summary.substr(0, 400);
  const size_t remaining = size_t(std::stod(summary.substr(at + 24)));
  std::filesystem::path first, last;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "run" / "vtk")) {
    if (!entry.path().filename().string().starts_with("brain_")) continue;
    if (first.empty() || entry.path() < first) first = entry.path();
    if (last.empty() || entry.path() > last) last = entry.path();
  }
  ASSERT_FALSE(last.empty());
  const TetMesh brain = formats::readTetMesh(last);
  const TetMesh whole = formats::readTetMesh(first);  // written at the start, before any removal
  EXPECT_LT(remaining, whole.tetCount());
  EXPECT_EQ(brain.tetCount(), remaining);
  // Each cell keeps its label: the tumour's are fewer than at first.
  size_t tumourNow = 0, tumourAtFirst = 0;
  for (int32_t label : brain.labels) tumourNow += label == 2;
  for (int32_t label : whole.labels) tumourAtFirst += label == 2;
  EXPECT_LT(tumourNow, tumourAtFirst);
  EXPECT_GT(tumourNow, 0u);
}

}  // namespace
}  // namespace trephine
