// What a run leaves when the machine fails it: a full disk, a kill -9, a
// rerun into the same folder. Nothing measured is lost or silently cut
// short, and nothing of an earlier run is taken for this one's.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

namespace fs = std::filesystem;
using test::runProgram;

const std::string kPlaneTouch = (test::sourceDir() / "scenes/examples/plane_touch.xml").string();
const std::string kIntegrated = (test::sourceDir() / "scenes/integrated.xml").string();

// Runs a shell command; returns its exit status and its output (stdout and stderr).
int shell(const std::string& command, std::string& output) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  char buffer[4096];
  size_t n = 0;
  output.clear();
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string quote(const std::string& s) { return "'" + s + "'"; }

// A file the run wrote must be what an ample disk gets, or absent: never cut.
void expectWholeOrAbsent(const fs::path& file, const fs::path& reference) {
  if (!fs::exists(file)) return;
  EXPECT_EQ(test::readFile(file), test::readFile(reference)) << file << " differs from the run on an ample disk";
}

TEST(RunFaultsTest, AFullDiskFailsTheRunLoudlyAndLeavesNoFileCutShort) {
  test::TempDir dir;
  std::string out;
  // The same run on an ample disk: its trace is the reference (virtual time is reproducible).
  ASSERT_EQ(runProgram({"run", kPlaneTouch, "--out", (dir / "ample").string(), "--quiet"}, &out), 0) << out;

  // A 200 KB file system (a tmpfs in a namespace of the test's own), too small
  // for the trace; where namespaces are not allowed (a chroot, many
  // containers), a file size limit of 100 KB (the trace is 177 KB, the
  // summary 3 KB) has writes fail the same way (EFBIG instead of ENOSPC).
  const fs::path copied = dir / "copied";
  const std::string run = quote(test::programPath().string()) + " run " + quote(kPlaneTouch);
  const std::string tmpfs =
      "unshare --user --map-root-user --mount sh -c 'mount -t tmpfs -o size=200k tmpfs \"$0\" && "
      "\"$1\" run \"$2\" --out \"$0/run\"; status=$?; cp -r \"$0/run\" \"$3\"; exit $status' " +
      quote((dir / "mnt").string()) + " " + quote(test::programPath().string()) + " " + quote(kPlaneTouch) + " " +
      quote(copied.string());
  fs::create_directories(dir / "mnt");
  std::string probe;
  const bool namespaces = shell("unshare --user --map-root-user --mount true", probe) == 0;
  int status = 0;
  if (namespaces) {
    status = shell(tmpfs, out);
  } else {
    status = shell("bash -c " + quote("ulimit -f 100; exec " + run + " --out " + copied.string()), out);
  }
  EXPECT_EQ(status, 3) << "a run whose outputs cannot be written has failed: " << out;
  EXPECT_NE(out.find(namespaces ? "No space left on device" : "File too large"), std::string::npos) << out;
  EXPECT_NE(out.find("trace.csv"), std::string::npos) << "the message names the file: " << out;

  expectWholeOrAbsent(copied / "trace.csv", dir / "ample" / "trace.csv");
  expectWholeOrAbsent(copied / "device.tool.device.csv", dir / "ample" / "device.tool.device.csv");
  EXPECT_FALSE(fs::exists(copied / "trace.csv")) << "200 KB cannot hold the 2,300-row trace";
  for (const auto& entry : fs::directory_iterator(copied))
    EXPECT_EQ(entry.path().filename().string().find(".partial-"), std::string::npos) << "a temporary file is left";
  // summary.json fits once the failed trace's space is free again, and says what failed.
  ASSERT_TRUE(fs::exists(copied / "summary.json"));
  const std::string summary = test::readFile(copied / "summary.json");
  EXPECT_TRUE(summary.ends_with("}\n")) << summary.substr(summary.size() > 200 ? summary.size() - 200 : 0);
  EXPECT_NE(summary.find("\"output_errors\""), std::string::npos);
  // The folder's marker says the outputs are not whole.
  EXPECT_NE(test::readFile(copied / ".trephine-run").find("state incomplete"), std::string::npos);
}


// A file-size limit (ulimit -f, as where a container refuses the tmpfs of the
// test above) fails a write as a full disk does: the program ignores
// SIGXFSZ itself, so it is not killed (exit 153) but fails with exit 3 naming
// the file, and leaves no temporary file behind.
TEST(RunFaultsTest, AFileSizeLimitFailsTheRunAsAFullDiskDoesNotBySignal) {
  test::TempDir dir;
  std::string out;
  const fs::path run = dir / "run";
  const int status = shell("bash -c " + quote("ulimit -f 100; exec " + quote(test::programPath().string()) +
                                              " run " + quote(kPlaneTouch) + " --out " + quote(run.string())),
                           out);
  EXPECT_EQ(status, 3) << "killed by SIGXFSZ, or not failed: " << out;
  EXPECT_NE(out.find("File too large"), std::string::npos) << out;
  EXPECT_NE(out.find("trace.csv"), std::string::npos) << "the message names the file: " << out;
  for (const auto& entry : fs::directory_iterator(run))
    EXPECT_EQ(entry.path().filename().string().find(".partial-"), std::string::npos) << "a temporary file is left";
  EXPECT_NE(test::readFile(run / ".trephine-run").find("state incomplete"), std::string::npos);
  // A rerun on an ample disk replaces it whole.
  ASSERT_EQ(runProgram({"run", kPlaneTouch, "--out", run.string(), "--quiet"}, &out), 0) << out;
  EXPECT_NE(test::readFile(run / ".trephine-run").find("state finished"), std::string::npos);
}

// A NIfTI whose data is all there (450^3 int16 voxels: 182 MB, a 180 KB
// gzip of zeros) but more than the memory the process may have: the load
// fails naming the file and why (before, a bare "std::bad_alloc").
TEST(RunFaultsTest, AVolumeLargerThanTheMemoryIsAClearLoadError) {
  if (!test::kTimingChecked) GTEST_SKIP() << "a sanitizer's shadow memory needs more address space than the limit";
  test::TempDir dir;
  // The 352-byte header of a 450 x 450 x 450 int16 volume, then its zeros, through gzip.
  std::string header(352, '\0');
  const auto put = [&](size_t at, const void* value, size_t size) { std::memcpy(header.data() + at, value, size); };
  const int32_t sizeofHdr = 348;
  const int16_t dims[8] = {3, 450, 450, 450, 1, 1, 1, 1}, datatype = 4, bitpix = 16;
  const float pixdim[8] = {1, 1, 1, 1, 1, 1, 1, 1}, offset = 352, slope = 1;
  put(0, &sizeofHdr, 4);
  put(40, dims, sizeof dims);
  put(70, &datatype, 2);
  put(72, &bitpix, 2);
  put(76, pixdim, sizeof pixdim);
  put(108, &offset, 4);
  put(112, &slope, 4);
  put(344, "n+1", 4);
  const fs::path head = dir.write("head.bin", header), volume = dir / "huge.nii.gz";
  std::string out;
  ASSERT_EQ(shell("(cat " + quote(head.string()) + "; head -c 182250000 /dev/zero) | gzip -1 > " + quote(volume.string()),
                  out),
            0)
      << out;
  const fs::path scene = dir.write("huge.xml", "<Node name=\"root\" units=\"mm\"><RequiredPlugin name=\"voxel_skull\"/>"
                                               "<VoxelSkull name=\"skull\" file=\"" + volume.string() +
                                                   "\" isovalue=\"400\"/></Node>");
  const int status = shell("bash -c " + quote("ulimit -v 400000; exec " + quote(test::programPath().string()) +
                                              " validate " + quote(scene.string())),
                           out);
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("huge.nii.gz: the volume it declares does not fit in this machine's memory"), std::string::npos)
      << out;
}

// A reader that goes away: stderr and stdout into a pipe closed at once
// (`| true`). The progress line written after 5 s, and the summary, find no
// reader; the run goes on and its files are whole (before, the first
// progress line ended the process by SIGPIPE, with nothing written).
TEST(RunFaultsTest, AReaderThatGoesAwayDoesNotEndTheRun) {
  test::TempDir dir;
  std::string output;
  const std::string run = quote(test::programPath().string()) + " run " + quote(kPlaneTouch) +
                          " --realtime --duration 5.6 --out " + quote((dir / "run").string());
  // The pipeline's status is `true`'s; what counts is what the run left.
  shell("bash -c " + quote(run + " 2>&1 | true"), output);
  ASSERT_TRUE(fs::exists(dir / "run/summary.json")) << output;
  EXPECT_NE(test::readFile(dir / "run/.trephine-run").find("finished"), std::string::npos)
      << test::readFile(dir / "run/.trephine-run");
  EXPECT_NE(test::readFile(dir / "run/summary.json").find("\"complete\": true"), std::string::npos);
}

TEST(RunFaultsTest, AKilledRunIsRecognisedAndARerunReplacesAllOfIt) {
  test::TempDir dir;
  const fs::path out = dir / "run";
  std::string text;
  // A first run that finishes: 3 s of the default scene, its exporter's frames in vtk/.
  ASSERT_EQ(runProgram({"run", kIntegrated, "--duration", "3", "--out", out.string(), "--quiet"}, &text), 0) << text;
  std::ofstream(out / "notes.txt") << "a user's own file";
  EXPECT_NE(test::readFile(out / ".trephine-run").find("state finished"), std::string::npos);

  // A second, long run into the same folder, killed while it writes frames.
  const pid_t pid = test::startProgram({"run", kIntegrated, "--duration", "60", "--out", out.string(), "--quiet"});
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline &&
         !(fs::exists(out / "vtk" / "tool_00030.vtp") &&
           test::readFile(out / ".trephine-run").find("state running") != std::string::npos))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_NE(test::readFile(out / ".trephine-run").find("state running"), std::string::npos);
  EXPECT_FALSE(fs::exists(out / "summary.json")) << "the first run's summary went when the second began";
  EXPECT_FALSE(fs::exists(out / "vtk.pvd")) << "the first run's index went when the second began";

  // The viewer will not build from the killed run's files unless asked.
  test::FakeViewerAssets assets;
  EXPECT_EQ(runProgram({"view", out.string()}, &text, assets.environment()), 1);
  EXPECT_NE(text.find("stopped without finishing (killed or crashed)"), std::string::npos) << text;
  EXPECT_NE(text.find("--partial"), std::string::npos) << text;

  // A rerun replaces everything the killed run wrote and keeps the user's file.
  const auto rerun = fs::file_time_type::clock::now();
  ASSERT_EQ(runProgram({"run", kIntegrated, "--duration", "1", "--out", out.string(), "--quiet"}, &text), 0) << text;
  EXPECT_NE(test::readFile(out / ".trephine-run").find("state finished"), std::string::npos);
  EXPECT_EQ(test::readFile(out / "notes.txt"), "a user's own file");
  size_t frames = 0;
  for (const auto& entry : fs::recursive_directory_iterator(out / "vtk")) {
    if (!entry.is_regular_file()) continue;
    EXPECT_GE(entry.last_write_time(), rerun) << entry.path() << " is left from an earlier run";
    ++frames;
  }
  EXPECT_GT(frames, 30u) << "1 s at 30 frames a second";
  EXPECT_FALSE(fs::exists(out / "vtk" / "tool_00045.vtp")) << "a frame of the 3 s run is left";
  EXPECT_EQ(runProgram({"view", out.string(), "--triangles", "4000"}, &text, assets.environment()), 0) << text;
}

TEST(RunFaultsTest, AnotherLiveRunsFolderIsRefused) {
  test::TempDir dir;
  const fs::path out = dir / "run";
  const pid_t pid = test::startProgram({"run", kIntegrated, "--duration", "60", "--out", out.string(), "--quiet"});
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline && !fs::exists(out / "vtk" / "tool_00003.vtp"))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::string text;
  EXPECT_EQ(runProgram({"run", kPlaneTouch, "--out", out.string(), "--quiet"}, &text), 1);
  EXPECT_NE(text.find("another run (process " + std::to_string(pid) + ") is writing there"), std::string::npos) << text;
  test::FakeViewerAssets assets;
  EXPECT_EQ(runProgram({"view", out.string()}, &text, assets.environment()), 1);
  EXPECT_NE(text.find("is still writing it"), std::string::npos) << text;
  kill(pid, SIGTERM);  // stops between steps and writes its outputs
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 3) << status;
  EXPECT_NE(test::readFile(out / ".trephine-run").find("state incomplete"), std::string::npos);
  EXPECT_NE(test::readFile(out / ".trephine-run").find("reason interrupted by SIGTERM"), std::string::npos);
}

}  // namespace
}  // namespace trephine
