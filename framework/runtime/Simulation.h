#pragma once
// A scene loaded, initialised and ready to run: the object behind
// `trephine run`, also used directly by tests and benchmarks.
//
//   Diagnostics d;
//   auto sim = Simulation::fromFile("scenes/examples/plane_touch.xml", options, d);
//   if (!sim) { d.print(std::cerr); return 1; }
//   sim->run();
//   sim->writeOutputs("out");
#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "framework/core/Diagnostics.h"
#include "framework/core/Lifecycle.h"
#include "framework/core/PluginLoader.h"
#include "framework/core/Registry.h"
#include "framework/logs/EventLog.h"
#include "framework/logs/HapticFrameLog.h"
#include "framework/runtime/Scheduler.h"
#include "framework/scene/Scene.h"

namespace trephine {

class SceneLoader;

struct SimulationOptions {
  std::optional<double> duration;  // s; default: the longest a component asks for, else 1 s
  bool realtime = false;
  uint64_t seed = 0;
  std::vector<std::string> overrides;  // "path.field=value"
  bool strict = false;                 // warnings are errors (--strict)
  // The directory writeOutputs() will be given, known before the run
  // (RunPlan::outputDirectory); empty: components write nothing while running.
  std::filesystem::path outputDirectory;
  // The live view's port (RunPlan::liveViewPort); -1: none.
  int liveViewPort = -1;
  // RunPlan::keepDeviceInput.
  bool keepDeviceInput = false;
};

// Registers the components that need no plugin (Recorder).
void registerCoreComponents(Registry& registry);

class Simulation {
 public:
  static std::unique_ptr<Simulation> fromFile(const std::filesystem::path& file, const SimulationOptions& options,
                                              Diagnostics& diagnostics);
  static std::unique_ptr<Simulation> fromString(std::string_view xml, const std::string& fileName,
                                                const SimulationOptions& options, Diagnostics& diagnostics);
  ~Simulation();

  // Runs the whole plan, or until `stop` becomes true.
  void run(const std::atomic<bool>& stop);
  void run();

  // Lets every component write its files, then writes summary.json, trace.csv and timings.csv.
  // Returns the names of the files written (the run's three first); problems are listed in
  // the summary and returned in `errors`.
  std::vector<std::string> writeOutputs(const std::filesystem::path& directory,
                                        std::vector<std::string>* errors = nullptr);

  // Every name the run writes in its output folder: its own three files,
  // each component's (a folder's name ends in '/'), and what the project's
  // tools derive from a run there (plots, the viewer), which a new run makes stale.
  std::vector<std::string> outputNames() const;

  Scene& scene() const { return *m_scene; }
  const RunPlan& plan() const { return m_plan; }
  const Scheduler& scheduler() const { return *m_scheduler; }
  // The log of the tool whose renderer writes trace.csv, and that renderer (null: none).
  const HapticFrameLog& hapticLog() const { return m_hapticLog; }
  const EventLog& events() const { return m_events; }
  const Component* hapticLogOwner() const { return m_hapticLogOwner; }
  // Every tool's log, by its renderer's path (trace.csv's tool among them).
  struct ToolLog {
    const Component* renderer;
    const HapticFrameLog* log;
    bool writesTrace;  // trace.csv's; the others write toolTraceName()
  };
  std::vector<ToolLog> toolLogs() const;

  bool complete() const { return m_complete; }
  const std::string& incompleteReason() const { return m_incompleteReason; }
  // Marks the run as stopped from outside (Ctrl-C) so the summary says why.
  void markInterrupted(std::string reason);
  double wallTime() const { return m_wallTime; }

 private:
  Simulation() = default;
  static std::unique_ptr<Simulation> load(const std::function<std::unique_ptr<Scene>(SceneLoader&)>& read,
                                          const SimulationOptions& options, Diagnostics& diagnostics);
  static std::unique_ptr<Simulation> initialise(std::unique_ptr<Simulation> simulation,
                                                const SimulationOptions& options, Diagnostics& diagnostics);
  class Context;

  std::unique_ptr<PluginLoader> m_plugins;
  std::unique_ptr<Registry> m_registry;
  std::unique_ptr<Scene> m_scene;
  std::unique_ptr<ChannelHub> m_channels;
  EventLog m_events;
  HapticFrameLog m_hapticLog;
  const Component* m_hapticLogOwner = nullptr;
  // The other tools' logs (stable addresses: the renderers keep them).
  std::vector<std::pair<const Component*, std::unique_ptr<HapticFrameLog>>> m_otherToolLogs;
  RunPlan m_plan;
  std::unique_ptr<Scheduler> m_scheduler;
  bool m_folderClaimed = false;  // plan.outputDirectory holds this run's marker
  bool m_ran = false;
  bool m_complete = false;
  std::string m_incompleteReason = "not run";
  double m_wallTime = 0;
};

}  // namespace trephine
