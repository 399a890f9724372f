#pragma once
// Helpers shared by the tests: scenes from inline XML, temporary directories,
// running the trephine program.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "framework/runtime/Simulation.h"

namespace trephine::test {

// Under a sanitizer every thread runs several times slower: a real-time
// test checks what the wall clock decides (a share of frames, a latency, how
// many packets came in the time) only in the plain build.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kTimingChecked = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kTimingChecked = false;
#else
inline constexpr bool kTimingChecked = true;
#endif
#else
inline constexpr bool kTimingChecked = true;
#endif

std::filesystem::path sourceDir();
std::filesystem::path programPath();

// A fresh empty directory under the system temp dir, removed when the object goes away.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "trephine-test");
  ~TempDir();
  const std::filesystem::path& path() const { return m_path; }
  std::filesystem::path operator/(const std::string& name) const { return m_path / name; }
  // Writes `text` to `name` inside the directory and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path m_path;
};

// Loads a scene from an XML string; on failure `diagnostics` holds the errors.
std::unique_ptr<Simulation> loadScene(const std::string& xml, Diagnostics& diagnostics,
                                      const SimulationOptions& options = {},
                                      const std::string& fileName = "inline.xml");

// Loads one of the project's scene files (`relative` to the source tree); a
// scene that fails to load is a test failure (with its errors) and gives null.
std::unique_ptr<Simulation> loadSceneFile(const std::string& relative, const SimulationOptions& options = {});

// Loads a scene from an XML string and runs it to its end; a scene that fails
// to load is a test failure (with its errors) and gives null.
std::unique_ptr<Simulation> runScene(const std::string& xml);

// The scene must fail to load, with `expected` in its errors; `what` names
// the case in a failure (the attribute tried, say).
void expectLoadError(const std::string& xml, const std::string& expected, const std::string& what);

// All diagnostics as one string, one per line.
std::string messages(const Diagnostics& diagnostics);

// Runs `trephine` with arguments; returns the exit code and captures stdout+stderr.
int runProgram(const std::vector<std::string>& arguments, std::string* output = nullptr,
               const std::string& environment = "");

// Starts `trephine` with arguments in the background (its output discarded);
// returns its process id, for kill() and waitForProgram().
int startProgram(const std::vector<std::string>& arguments);
// Waits for a program startProgram started: its exit code, or -1 when a signal ended it.
int waitForProgram(int pid);

std::string readFile(const std::filesystem::path& file);

// A stand-in for the browser viewer's assets, so that tests of `trephine
// view` do not need the bundle built: pass environment() to runProgram.
struct FakeViewerAssets {
  TempDir dir{"trephine-viewer-assets"};
  FakeViewerAssets();
  std::string environment() const { return "TREPHINE_VIEWER_ASSETS=" + dir.path().string(); }
};

// The counter `name` that `component` reports. A counter the component does
// not report is a test failure (and NaN, so that no comparison passes on it).
double counter(const Component& component, const std::string& name);
// The same of the scene's one component of type `type` (the plugins' classes
// stay in their plugins); no such component, or more than one, is a failure too.
double componentCounter(const Simulation& simulation, const std::string& type, const std::string& name);
// The same of the component at `path` (as Scene::findComponent).
double componentCounterAt(const Simulation& simulation, const std::string& path, const std::string& name);

}  // namespace trephine::test
