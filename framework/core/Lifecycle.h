#pragma once
// What the framework hands to components during initialisation, preparation
// and after the run. The runtime implements these; components only see them.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/ChannelHub.h"
#include "framework/core/CollisionBackend.h"
#include "framework/logs/EventLog.h"

namespace trephine {

class Component;
class BaseField;
class HapticFrameLog;  // framework/logs/HapticFrameLog.h

class InitContext {
 public:
  virtual ~InitContext() = default;
  // Report a problem at the component's element, or at a field's value.
  virtual void error(const Component& component, std::string message) = 0;
  virtual void error(const BaseField& field, std::string message) = 0;
  // A setting that works but is doubtful (a rendering that may not be
  // passive): reported at the field's value, and the run goes on unless it
  // asked for --strict, which makes warnings errors. Contexts without a
  // warning sink (a benchmark's) drop it.
  virtual void warning(const BaseField& field, std::string message) {
    (void)field;
    (void)message;
  }
  // Something tolerated that the user may want to know of (padding ignored
  // in a file): reported at the field's value; never an error.
  virtual void note(const BaseField& field, std::string message) {
    (void)field;
    (void)message;
  }
  // A new collision back-end registered (by the core or a loaded plugin) for
  // targets of type `kind` under `name`, or null when there is none; and the
  // names registered for `kind`, for the message. Contexts without a registry
  // (a benchmark's) have none.
  virtual std::unique_ptr<CollisionBackend> createBackend(std::string_view kind, std::string_view name) {
    (void)kind;
    (void)name;
    return nullptr;
  }
  virtual std::vector<std::string> backendNames(std::string_view kind) const {
    (void)kind;
    return {};
  }
  // Names of the plugins installed on the search path, loaded or not (for a
  // message's suggestion). Contexts without a loader have none.
  virtual std::vector<std::string> installedPlugins() const { return {}; }
  virtual uint64_t seed() const = 0;  // the run's seed (--seed)
  virtual bool isRealtime() const = 0;
  virtual ChannelHub& channels() = 0;
  virtual EventLog& events() = 0;
  // A force renderer's haptic frame log: every tool's frames are measured
  // (summary.json's `tools`). `writesTrace`: its frames are trace.csv's and
  // the summary's `haptics` (one renderer per scene: a second such claim is
  // reported as an error); the others' go to trace.PATH.csv (toolTraceName).
  virtual HapticFrameLog* claimHapticLog(const Component& component, bool writesTrace = true) = 0;
};

// The trace file of a force renderer that does not write trace.csv: its path
// with the slashes as dots ("/bipolar/force": "trace.bipolar.force.csv").
std::string toolTraceName(const Component& renderer);

// Known once every component is initialised: how long the run is.
struct RunPlan {
  // Longest run (s): every per-frame buffer is preallocated from the duration.
  static constexpr double kMaxDuration = 3600.0;
  // Most component calls in one run (all groups): per-call timings and
  // per-frame records are preallocated, a few hundred bytes per call at most.
  static constexpr uint64_t kMaxCalls = 20'000'000;
  double duration = 1.0;  // s of simulated time
  bool realtime = false;
  uint64_t seed = 0;
  // Where the run's files will go, for components that write as they run
  // (an exporter, in its own group); empty when the run writes no files
  // (tests, validate). FinishContext has the same directory at the end.
  std::filesystem::path outputDirectory;
  // The port of the live view (`trephine run --realtime --view PORT`): the
  // scene's exporter serves the browser viewer there and streams the run to
  // it. -1: no live view; 0: any free port.
  int liveViewPort = -1;
  // Devices keep the raw input they read in memory (HapticDevice::recorded)
  // whatever their `record` field says: a study takes the reference
  // setting's motion from them.
  bool keepDeviceInput = false;
  // Number of calls a component of `rateHz` receives in this run.
  uint64_t callsAt(double rateHz) const;
};

class FinishContext {
 public:
  FinishContext(std::filesystem::path outputDirectory, double simulatedTime)
      : m_outputDirectory(std::move(outputDirectory)), m_simulatedTime(simulatedTime) {}
  // Empty when the run writes no files (tests, validate).
  const std::filesystem::path& outputDirectory() const { return m_outputDirectory; }
  double simulatedTime() const { return m_simulatedTime; }
  // Reserves `fileName` in the output directory for `component` before it is
  // written. False (with an error recorded) when the name is not a plain file
  // name, is one of the run's own files, or another component has it.
  bool claimOutput(const Component& component, const std::string& fileName);
  // "<kind>.<path with '/' as '.'>.csv", unique because names cannot contain '.'.
  static std::string defaultFileName(const std::string& kind, const Component& component);
  // Why `fileName` cannot be a component's output ("it is not a plain file
  // name ...", "it is one of the run's own files"), or nothing.
  static std::optional<std::string> checkFileName(const std::string& fileName);
  void error(const Component& component, std::string message);
  // A file of the run's own (summary.json, trace.csv, timings.csv) that could not be written.
  void runError(std::string message);

  struct Output {
    std::string component;
    std::string file;
  };
  const std::vector<Output>& outputs() const { return m_outputs; }
  const std::vector<std::string>& errors() const { return m_errors; }

 private:
  std::filesystem::path m_outputDirectory;
  double m_simulatedTime;
  std::vector<Output> m_outputs;
  std::vector<std::string> m_errors;
};

}  // namespace trephine
