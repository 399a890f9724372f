// A run's folder: the marker that says which run wrote what, what a new run
// removes (only that), and how a killed run's folder is told apart.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "framework/runtime/RunFolder.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

namespace fs = std::filesystem;

void touch(const fs::path& file) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << "x";
}

TEST(RunFolderTest, ARunRemovesWhatTheEarlierRunListedAndNothingElse) {
  test::TempDir dir;
  const fs::path run = dir / "run";
  ASSERT_FALSE(claimRunFolder(run, {"summary.json", "vtk.pvd", "vtk/", "skull.mha"}));
  touch(run / "summary.json");
  touch(run / "vtk/tool_00000.vtp");
  touch(run / "skull.mha");
  touch(run / "notes.txt");          // a user's
  touch(run / "mine/summary.json");  // a user's, in a folder the run does not list
  markRunFolder(run, {"summary.json", "vtk.pvd", "vtk/", "skull.mha"}, RunState::kFinished, "");
  ASSERT_EQ(runFolderStatus(readRunMarker(run)), RunFolderStatus::kFinished);

  // The next run writes other files: the earlier run's all go all the same.
  ASSERT_FALSE(claimRunFolder(run, {"summary.json", "trace.csv"}));
  EXPECT_FALSE(fs::exists(run / "summary.json"));
  EXPECT_FALSE(fs::exists(run / "vtk"));
  EXPECT_FALSE(fs::exists(run / "skull.mha"));
  EXPECT_TRUE(fs::exists(run / "notes.txt"));
  EXPECT_TRUE(fs::exists(run / "mine/summary.json"));
  const auto marker = readRunMarker(run);
  ASSERT_TRUE(marker);
  EXPECT_EQ(marker->state, RunState::kRunning);
  EXPECT_EQ(marker->pid, ::getpid());
  EXPECT_EQ(marker->outputs, (std::vector<std::string>{"summary.json", "trace.csv"}));
  // This process is alive: to another run the folder is taken.
  EXPECT_EQ(runFolderStatus(marker), RunFolderStatus::kWriting);
  const auto refused = claimRunFolder(run, {"summary.json"});
  ASSERT_TRUE(refused);
  EXPECT_NE(refused->find("another run (process " + std::to_string(::getpid()) + ") is writing there"),
            std::string::npos);
}

TEST(RunFolderTest, ARunningMarkerOfAProcessThatIsGoneIsAKilledRun) {
  test::TempDir dir;
  // pid 1 exists, but did not start at this time: a pid reused after the run died.
  dir.write(kRunMarkerName, "trephine-run 1\nstate running\npid 1 12345678901\noutput summary.json\n");
  EXPECT_EQ(runFolderStatus(readRunMarker(dir.path())), RunFolderStatus::kKilled);
  touch(dir / "summary.json");
  EXPECT_FALSE(claimRunFolder(dir.path(), {"trace.csv"}));
  EXPECT_FALSE(fs::exists(dir / "summary.json")) << "the killed run's partial outputs go";
}

TEST(RunFolderTest, AMarkerNamingFilesOutsideTheFolderIsRefusedAndRemovesNothing) {
  test::TempDir dir;
  touch(dir / "precious.txt");
  fs::create_directories(dir / "run");
  for (const std::string name : {"../precious.txt", "/etc/passwd", "..", "a/b", ".trephine-run"}) {
    std::ofstream(dir / "run" / kRunMarkerName) << "trephine-run 1\nstate finished\npid 7 7\noutput " << name << "\n";
    try {
      readRunMarker(dir / "run");
      ADD_FAILURE() << name << " was accepted";
    } catch (const RunFolderError& e) {
      EXPECT_NE(std::string(e.what()).find(":4: '" + name + "' is not a name in the run's folder"), std::string::npos)
          << e.what();
    }
    const auto problem = claimRunFolder(dir / "run", {"summary.json"});
    ASSERT_TRUE(problem) << name;
    EXPECT_NE(problem->find("remove it if the folder holds no run"), std::string::npos) << *problem;
  }
  EXPECT_TRUE(fs::exists(dir / "precious.txt"));
}

TEST(RunFolderTest, MalformedMarkersNameTheLine) {
  test::TempDir dir;
  const auto expectError = [&](const std::string& text, const std::string& message) {
    std::ofstream(dir / kRunMarkerName) << text;
    try {
      readRunMarker(dir.path());
      ADD_FAILURE() << "accepted: " << text;
    } catch (const RunFolderError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  expectError("", "empty (expected a run marker)");
  expectError("hello\n", ":1: not a run marker");
  expectError("trephine-run 1\nstate paused\n", ":2: unknown state 'paused'");
  expectError("trephine-run 1\nstate running\npid x\n", ":3: expected 'pid PID START'");
  expectError("trephine-run 1\npid 3 4\n", "no state line");
  EXPECT_FALSE(readRunMarker(dir / "absent"));
}

}  // namespace
}  // namespace trephine
