// Writing into a folder where links and special files were planted beforehand:
// nothing outside the folder is written, replaced, removed or read.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "framework/core/AtomicFile.h"
#include "framework/core/FolderInput.h"
#include "framework/core/OutputFolder.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

namespace fs = std::filesystem;

// A folder outside the output folder, holding a file whose contents must survive.
struct Outside {
  test::TempDir dir{"trephine-outside"};
  fs::path file = dir.write("precious.txt", "precious\n");
  bool untouched() const {
    return fs::is_regular_file(file) && test::readFile(file) == "precious\n" &&
           std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator()) == 1;
  }
};

TEST(OutputFolderTest, ASubfolderThatIsALinkIsRefusedNamingIt) {
  test::TempDir out;
  Outside outside;
  fs::create_directory_symlink(outside.dir.path(), out / "vtk");
  const OutputFolder folder = OutputFolder::open(out.path());
  try {
    folder.subfolder("vtk");
    FAIL() << "a link was taken for a folder";
  } catch (const FileWriteError& e) {
    EXPECT_NE(std::string(e.what()).find("vtk: is a link"), std::string::npos) << e.what();
  }
  // A link deeper down, and a file where a folder goes.
  fs::create_directories(out / "settings");
  fs::create_directory_symlink(outside.dir.path(), out / "settings/002");
  EXPECT_THROW(folder.subfolder("settings/002"), FileWriteError);
  std::ofstream(out / "data") << "a file";
  EXPECT_THROW(folder.subfolder("data/run_0"), FileWriteError);
  EXPECT_THROW(folder.subfolder("../escape"), FileWriteError);
  EXPECT_THROW(AtomicFile(folder, "vtk/brain_00000.vtu"), FileWriteError);
  EXPECT_TRUE(outside.untouched());
  // Folders of its own are made on the way.
  EXPECT_TRUE(fs::is_directory(folder.subfolder("a/b/c").path()));
}

TEST(OutputFolderTest, RemovingAFolderRemovesLinksInsideItNeverWhatTheyPointAt) {
  test::TempDir out;
  Outside outside;
  fs::create_directories(out / "view/data/inner");
  fs::create_directory_symlink(outside.dir.path(), out / "view/data/inner/to_folder");
  fs::create_symlink(outside.file, out / "view/data/to_file");
  std::ofstream(out / "view/data/own.js") << "x";
  const OutputFolder folder = OutputFolder::open(out.path());
  folder.subfolder("view").remove("data");
  EXPECT_FALSE(fs::exists(fs::symlink_status(out / "view/data")));
  EXPECT_TRUE(outside.untouched());
  // A link where a folder was: the link goes, its target stays.
  fs::create_directory_symlink(outside.dir.path(), out / "view/data");
  folder.subfolder("view").remove("data");
  EXPECT_FALSE(fs::exists(fs::symlink_status(out / "view/data")));
  EXPECT_TRUE(outside.untouched());
  folder.remove("missing");  // nothing there: nothing to do
  EXPECT_THROW(folder.remove(".."), FileWriteError);
  EXPECT_THROW(folder.remove("view/data"), FileWriteError) << "one name at a time";
}

TEST(OutputFolderTest, AFileIsRenamedOverALinkAtItsNameNeverWrittenThroughIt) {
  test::TempDir out;
  Outside outside;
  fs::create_symlink(outside.file, out / "index.html");
  writeFileAtomically(out / "index.html", [](std::ostream& s) { s << "<html>"; });
  EXPECT_TRUE(outside.untouched());
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(out / "index.html")));
  EXPECT_EQ(test::readFile(out / "index.html"), "<html>");
}

TEST(OutputFolderTest, ATemporaryNamePlantedAsALinkIsNeverTheOneOpened) {
  test::TempDir out;
  Outside outside;
  // The names earlier versions used (NAME.partial-PID), and more.
  fs::create_symlink(outside.file, out / ("trace.csv.partial-" + std::to_string(::getpid())));
  for (int pid = 1; pid < 300; ++pid)
    fs::create_symlink(outside.file, out / ("trace.csv.partial-" + std::to_string(::getpid() + pid)));
  std::set<std::string> names;
  for (int k = 0; k < 20; ++k) {
    AtomicFile file(out / "trace.csv");
    file.write(std::string("t\n"));
    for (const auto& entry : fs::directory_iterator(out.path()))
      if (fs::is_regular_file(fs::symlink_status(entry.path()))) names.insert(entry.path().filename().string());
    file.commit();
    fs::remove(out / "trace.csv");
  }
  EXPECT_EQ(names.size(), 20u) << "each temporary name is new";
  EXPECT_TRUE(outside.untouched());
}

TEST(OutputFolderTest, AFileOfTheFolderIsReadOnlyWhenItIsARegularFileOfItsOwn) {
  test::TempDir run;
  Outside outside;
  std::ofstream(run / "summary.json") << "{}";
  fs::create_symlink(outside.file, run / "trace.csv");
  fs::create_directory_symlink(outside.dir.path(), run / "vtk");
  ASSERT_EQ(::mkfifo((run / "timings.csv").c_str(), 0600), 0);
  EXPECT_EQ(regularFileInside(run.path(), "summary.json"), run / "summary.json");
  for (const char* name : {"trace.csv", "vtk/precious.txt", "timings.csv", "../x", "missing"}) {
    EXPECT_FALSE(isRegularFileInside(run.path(), name)) << name;
    EXPECT_THROW(regularFileInside(run.path(), name), FolderInputError) << name;
  }
  try {
    regularFileInside(run.path(), "vtk/precious.txt");
  } catch (const FolderInputError& e) {
    EXPECT_NE(std::string(e.what()).find("vtk: is a link"), std::string::npos) << e.what();
  }
  // Reading: no link followed, no pipe waited on, no device read without end.
  EXPECT_EQ(readRegularFile(run / "summary.json", 100), "{}");
  EXPECT_THROW(readRegularFile(run / "trace.csv", 100), FolderInputError);
  EXPECT_THROW(readRegularFile(run / "timings.csv", 100), FolderInputError);
  EXPECT_THROW(readRegularFile("/dev/zero", 100), FolderInputError);
  try {
    readRegularFile(run / "summary.json", 1);
    FAIL() << "a file larger than asked for was read";
  } catch (const FolderInputError& e) {
    EXPECT_NE(std::string(e.what()).find("holds 2 bytes"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trephine
