// What an attacker plants in an output folder before the program runs there
// (as root, say): links to folders and files elsewhere, devices and pipes.
// `run`, `view`, `study` and `cellsize` write, replace and remove nothing
// outside the folder and read nothing from outside it, and never hang or
// fill the disk on a special file; each refusal says what is in the way.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

namespace fs = std::filesystem;
using test::runProgram;

const std::string kPlaneTouch = (test::sourceDir() / "scenes/examples/plane_touch.xml").string();
const std::string kExport = (test::sourceDir() / "scenes/examples/fem_press_export.xml").string();

// A folder outside the run's, with a file whose contents must survive and
// must never be shown.
struct Outside {
  test::TempDir dir{"trephine-outside"};
  fs::path file = dir.write("secret.txt", "SECRET-NOT-FOR-THE-VIEWER\n");
  fs::path index = dir.write("index.html", "the other folder's own page\n");
  Outside() { fs::create_directories(dir / "data"), dir.write("data/keep.js", "keep"); }
  bool untouched() const {
    return test::readFile(file) == "SECRET-NOT-FOR-THE-VIEWER\n" &&
           test::readFile(index) == "the other folder's own page\n" && fs::exists(dir / "data/keep.js") &&
           std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()) == 3;
  }
};

// Everything under `folder` (links not followed), as one string, to look for the secret.
std::string allBytesUnder(const fs::path& folder) {
  std::string bytes;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (fs::is_regular_file(fs::symlink_status(entry.path()))) bytes += test::readFile(entry.path());
  return bytes;
}

// A run of the exporting scene (a few frames of vtk/ files and a trace) in
// dir/run: a copy of one run made once for the whole program, since its brain
// of 22,000 tetrahedra takes seconds to mesh and press under a sanitizer and
// each test plants its links in a run of its own.
fs::path exportedRun(const test::TempDir& dir) {
  static const test::TempDir original("trephine-exported-run");
  static const bool ran = [] {
    std::string out;
    const int status =
        runProgram({"run", kExport, "--duration", "0.3", "--out", (original / "run").string(), "--quiet"}, &out);
    EXPECT_EQ(status, 0) << out;
    return status == 0;
  }();
  EXPECT_TRUE(ran) << "the exporting scene did not run";
  const fs::path run = dir / "run";
  fs::copy(original / "run", run, fs::copy_options::recursive);
  return run;
}

// A skull phantom at 2 mm voxels and an exporter of it, for the runs that
// need only the skull's files (the whole procedure takes seconds more under a sanitizer).
constexpr const char* kSkullExportScene = R"(<?xml version="1.0"?>
<Node name="root" units="mm">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="viewer"/>
  <Node name="patient"><VoxelSkull name="skull" file="phantom:skull?voxel=2.0" isovalue="400"/></Node>
  <Node name="out"><VtkExporter name="vtk" skull="@/patient/skull" rate="30"/></Node>
</Node>
)";

TEST(PlantedLinksTest, AViewFolderThatIsALinkIsRefusedAndTheOtherFolderKeepsItsData) {
  test::TempDir dir;
  Outside outside;
  const fs::path run = exportedRun(dir);
  fs::create_directory_symlink(outside.dir.path(), run / "view");
  test::FakeViewerAssets assets;
  std::string out;
  EXPECT_NE(runProgram({"view", run.string()}, &out, assets.environment()), 0) << out;
  EXPECT_NE(out.find("view: is a link"), std::string::npos) << out;
  EXPECT_TRUE(outside.untouched());
}

TEST(PlantedLinksTest, LinksAtTheViewersFilesAreReplacedNotWrittenThrough) {
  test::TempDir dir;
  Outside outside;
  const fs::path run = exportedRun(dir);
  fs::create_directories(run / "view");
  fs::create_symlink(outside.index, run / "view/index.html");
  fs::create_symlink(outside.file, run / "view/viewer.js");
  fs::create_directory_symlink(outside.dir / "data", run / "view/data");
  test::FakeViewerAssets assets;
  std::string out;
  ASSERT_EQ(runProgram({"view", run.string()}, &out, assets.environment()), 0) << out;
  EXPECT_TRUE(outside.untouched());
  for (const char* name : {"view/index.html", "view/viewer.js"})
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(run / name))) << name;
  EXPECT_TRUE(fs::is_directory(fs::symlink_status(run / "view/data")));
}

TEST(PlantedLinksTest, TheViewerCopiesNothingFromOutsideTheRunThroughALink) {
  Outside outside;
  test::FakeViewerAssets assets;
  // A link in each place the viewer reads: the trace, the summary, a frame, the exporter's folder.
  for (const std::string planted : {"trace.csv", "summary.json", "vtk/tool_00001.vtp", "vtk"}) {
    test::TempDir dir;
    const fs::path run = exportedRun(dir);
    fs::remove_all(run / planted);
    if (planted == "vtk") {
      fs::create_directory_symlink(outside.dir.path(), run / planted);
    } else {
      fs::create_symlink(outside.file, run / planted);
    }
    std::string out;
    const int status = runProgram({"view", run.string(), "--out", (dir / "page").string()}, &out, assets.environment());
    EXPECT_NE(status, 0) << planted << ": " << out;
    EXPECT_NE(out.find("is a link"), std::string::npos) << planted << ": " << out;
    if (fs::exists(dir / "page")) {
      EXPECT_EQ(allBytesUnder(dir / "page").find("SECRET"), std::string::npos) << planted;
    }
    EXPECT_TRUE(outside.untouched()) << planted;
  }
}

// The skull's volume header rewritten to name another data file (a link to
// a secret), in ways a lexical look would miss: a comment holding the key,
// the key in capitals. The viewer takes the header as its reader does and
// refuses a data file that is not the exporter's own.
TEST(PlantedLinksTest, ASkullHeaderNamingAnotherDataFileIsRefused) {
  test::TempDir dir;
  Outside outside;
  const fs::path run = dir / "run";
  std::string out;
  ASSERT_EQ(runProgram({"run", dir.write("skull_export.xml", kSkullExportScene).string(), "--duration", "0.1", "--out",
                        run.string(), "--quiet"},
                       &out),
            0)
      << out;
  const std::string header = test::readFile(run / "vtk/skull_density.mhd");
  fs::create_symlink(outside.file, run / "vtk/x.raw");
  test::FakeViewerAssets assets;
  for (const std::string& crafted :
       {header.substr(0, header.find("ElementDataFile")) + "Comment = ElementDataFile = LOCAL\nELEMENTDATAFILE = x.raw\n",
        header.substr(0, header.find("ElementDataFile")) + "elementdatafile = x.raw\n"}) {
    std::ofstream(run / "vtk/skull_density.mhd", std::ios::trunc) << crafted;
    EXPECT_NE(runProgram({"view", run.string(), "--out", (dir / "page").string()}, &out, assets.environment()), 0)
        << out;
    EXPECT_NE(out.find("is not the exporter's"), std::string::npos) << out;
    if (fs::exists(dir / "page")) {
      EXPECT_EQ(allBytesUnder(dir / "page").find("SECRET"), std::string::npos);
    }
  }
  EXPECT_TRUE(outside.untouched());
}

TEST(PlantedLinksTest, ARunWritesItsExportersFilesIntoAFolderOfItsOwnNotThroughALink) {
  test::TempDir dir;
  Outside outside;
  const fs::path run = dir / "run";
  fs::create_directories(run);
  fs::create_directory_symlink(outside.dir.path(), run / "vtk");
  fs::create_symlink(outside.file, run / "trace.csv");
  fs::create_symlink(outside.index, run / "summary.json");
  std::string out;
  ASSERT_EQ(runProgram({"run", kExport, "--duration", "0.3", "--out", run.string(), "--quiet"}, &out), 0) << out;
  EXPECT_TRUE(outside.untouched());
  EXPECT_TRUE(fs::is_directory(fs::symlink_status(run / "vtk")));
  EXPECT_TRUE(fs::exists(run / "vtk/brain_00000.vtu"));
  for (const char* name : {"trace.csv", "summary.json"})
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(run / name))) << name;
}

TEST(PlantedLinksTest, AStudysSettingFolderThatIsALinkStopsTheStudyBeforeAnythingRuns) {
  test::TempDir dir;
  Outside outside;
  fs::create_directories(dir / "study/settings");
  fs::create_directory_symlink(outside.dir.path(), dir / "study/settings/002");
  std::string out;
  const int status = runProgram({"study", kPlaneTouch, "--vary", "/tool/force.stiffness=1,1.5", "--duration", "0.3",
                                 "--out", (dir / "study").string()},
                                &out);
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("settings/002: is a link"), std::string::npos) << out;
  EXPECT_TRUE(outside.untouched());
}

TEST(PlantedLinksTest, CellSizeExperimentReplacesLinksAtItsOutputs) {
  test::TempDir dir;
  Outside outside;
  fs::create_directories(dir / "cs");
  fs::create_symlink(outside.file, dir / "cs/cellsize.csv");
  fs::create_symlink(outside.index, dir / "cs/cellsize.json");
  std::string out;
  ASSERT_EQ(runProgram({"cellsize", "phantom:cube?cells=4", "--experiment", "--out", (dir / "cs").string()}, &out), 0)
      << out;
  EXPECT_TRUE(outside.untouched());
  for (const char* name : {"cs/cellsize.csv", "cs/cellsize.json"})
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(dir / name))) << name;
}

// Runs `arguments` and fails the test unless it ends within `seconds`.
int runWithin(double seconds, const std::vector<std::string>& arguments, std::string& out,
              const std::string& environment = "") {
  const auto start = std::chrono::steady_clock::now();
  const int status = runProgram(arguments, &out, (environment.empty() ? "" : environment + " ") + "timeout 20");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), seconds)
      << "hung on a special file: " << out;
  return status;
}

TEST(PlantedLinksTest, SpecialFilesInARunFolderAreRefusedAtOnceNeverReadWithoutEnd) {
  test::FakeViewerAssets assets;
  for (const std::string kind : {"device link", "fifo"}) {
    test::TempDir dir;
    const fs::path run = exportedRun(dir);
    fs::remove(run / ".trephine-run");
    if (kind == "fifo")
      ASSERT_EQ(::mkfifo((run / ".trephine-run").c_str(), 0600), 0);
    else
      fs::create_symlink("/dev/zero", run / ".trephine-run");
    std::string out;
    EXPECT_EQ(runWithin(10, {"view", run.string()}, out, assets.environment()), 1) << kind << ": " << out;
    EXPECT_NE(out.find(".trephine-run: is a"), std::string::npos) << kind << ": " << out;
    EXPECT_EQ(runWithin(10, {"run", kPlaneTouch, "--duration", "0.1", "--out", run.string(), "--quiet"}, out), 1)
        << kind << ": " << out;
    EXPECT_NE(out.find(".trephine-run: is a"), std::string::npos) << kind << ": " << out;
  }
  // A trace that is a pipe: the viewer says so instead of waiting for a writer.
  test::TempDir dir;
  const fs::path run = exportedRun(dir);
  fs::remove(run / "trace.csv");
  ASSERT_EQ(::mkfifo((run / "trace.csv").c_str(), 0600), 0);
  std::string out;
  EXPECT_EQ(runWithin(10, {"view", run.string()}, out, assets.environment()), 1) << out;
  EXPECT_NE(out.find("trace.csv: is a pipe"), std::string::npos) << out;
}

}  // namespace
}  // namespace trephine
