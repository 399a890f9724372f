#include "framework/runtime/Simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <thread>

#include "framework/core/AtomicFile.h"
#include "framework/core/CollisionBackend.h"
#include "framework/devices/HapticDevice.h"
#include "framework/core/Strings.h"
#include "framework/runtime/Recorder.h"
#include "framework/runtime/RunFolder.h"
#include "framework/runtime/RunOutputs.h"
#include "framework/scene/SceneLoader.h"

namespace trephine {

void registerCoreComponents(Registry& registry) {
  PluginRegistrar registrar(registry, "core");
  registrar.add<Recorder>("Recorder", "Samples another component's published values at its own rate into a CSV file");
}

namespace {

// Depth-first over links: every component comes after the components it links to.
// A link cycle falls back to document order for the components on it.
std::vector<Component*> initialisationOrder(const std::vector<Component*>& components) {
  std::vector<Component*> order;
  std::set<const Component*> done, visiting;
  std::function<void(Component*)> visit = [&](Component* c) {
    if (done.count(c) || visiting.count(c)) return;
    visiting.insert(c);
    for (const BaseField* field : c->fields()) {
      if (const auto* link = dynamic_cast<const BaseLink*>(field); link && link->boundComponent())
        visit(link->boundComponent());
    }
    visiting.erase(c);
    done.insert(c);
    order.push_back(c);
  };
  for (Component* c : components) visit(c);
  return order;
}

// A ticking component reads what it reaches through links (passing through
// passive components). Reaching a ticking component of another rate would read
// another thread's state in real time, so it is refused: such data goes through channels.
std::string groupText(const Component& c) {
  return formatDouble(c.rateHz()) + " Hz" + (c.rateGroup().empty() ? "" : ", group '" + c.rateGroup() + "'");
}

void checkRateGroupLinks(const std::vector<Component*>& components, Diagnostics& diagnostics) {
  for (const Component* reader : components) {
    if (!reader->isTicking()) continue;
    std::set<const Component*> seen{reader};
    std::function<void(const Component*, const BaseLink*)> follow = [&](const Component* c, const BaseLink* first) {
      for (const BaseField* field : c->fields()) {
        const auto* link = dynamic_cast<const BaseLink*>(field);
        if (!link || link->info().initOnly || !link->boundComponent()) continue;
        const Component* target = link->boundComponent();
        if (!seen.insert(target).second) continue;
        const BaseLink* via = first ? first : link;
        if (target->isTicking()) {
          if (target->rateHz() != reader->rateHz() || target->rateGroup() != reader->rateGroup())
            diagnostics.error(via->location(),
                              reader->typeName() + " '" + reader->name() + "' (" + groupText(*reader) + ") reads " +
                                  target->typeName() + " '" + target->path() + "' (" + groupText(*target) +
                                  ") through its links; components of different rate groups exchange data only "
                                  "through channels, so give them the same rate and group");
          continue;  // a ticking target's own links are checked from it
        }
        follow(target, via);
      }
    };
    follow(reader, nullptr);
  }
}

// Every file components will write: a plain name, none of the run's own, no two alike.
void checkDeclaredOutputs(const std::vector<Component*>& components, Diagnostics& diagnostics) {
  std::map<std::string, const Component*> owners;
  for (const Component* c : components) {
    std::vector<OutputFile> outputs;
    c->declareOutputs(outputs);
    for (const OutputFile& output : outputs) {
      const SourceLocation& where = output.field ? output.field->location() : c->location();
      const std::string who = c->typeName() + " '" + c->name() + "'";
      if (auto problem = FinishContext::checkFileName(output.name)) {
        diagnostics.error(where, who + " cannot write '" + output.name + "': " + *problem);
      } else if (const auto [it, added] = owners.emplace(output.name, c); !added) {
        diagnostics.error(where, who + " cannot write '" + output.name + "': " + it->second->path() + " writes it");
      }
    }
  }
}

// In real time every rate group is a thread, and those of periods up to
// 2 ms poll the clock before their deadlines (Scheduler.cpp): more of them
// than cores take the cores from each other, and every group misses.
void warnOfOvercommittedCores(const std::vector<Component*>& components, const RunPlan& plan,
                              Diagnostics& diagnostics, const SourceLocation& where) {
  if (!plan.realtime) return;
  std::set<std::pair<double, std::string>> groups, polling;
  for (const Component* c : components) {
    if (!c->isTicking()) continue;
    groups.emplace(c->rateHz(), c->rateGroup());
    if (c->rateHz() >= 500.0) polling.emplace(c->rateHz(), c->rateGroup());
  }
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  if (polling.size() > cores)
    diagnostics.warning(where, std::to_string(polling.size()) + " rate groups of 500 Hz or more (of " +
                                   std::to_string(groups.size()) + ") poll the clock in threads of their own on " +
                                   std::to_string(cores) +
                                   " cores: in real time they take the cores from each other and miss their "
                                   "deadlines; give such components one rate and group");
}

// A device outside the process moves in wall time: in virtual time the run
// is over before it has moved.
void warnOfOutsideDevicesInVirtualTime(const std::vector<Component*>& components, const RunPlan& plan,
                                       Diagnostics& diagnostics) {
  if (plan.realtime) return;
  for (const Component* c : components)
    if (const auto* device = dynamic_cast<const HapticDevice*>(c); device && device->outsideTheProcess())
      diagnostics.warning(c->location(), c->typeName() + " '" + c->name() +
                                             "' is a device outside the process: run with --realtime (in virtual "
                                             "time the run does not wait for it, and it opens no connection)");
}

}  // namespace

class Simulation::Context final : public InitContext {
 public:
  Context(Simulation& simulation, Diagnostics& diagnostics, const SimulationOptions& options)
      : m_simulation(simulation), m_diagnostics(diagnostics), m_options(options) {}

  void error(const Component& component, std::string message) override {
    m_failed.insert(&component);
    m_diagnostics.error(component.location(), component.typeName() + " '" + component.name() + "': " + message);
  }
  void error(const BaseField& field, std::string message) override {
    const auto* owner = dynamic_cast<const Component*>(&field.owner());
    if (owner) m_failed.insert(owner);
    const std::string of = owner ? " of " + owner->typeName() + " '" + owner->name() + "'" : std::string();
    m_diagnostics.error(field.location(), "invalid " + field.name() + of + ": " + message);
  }
  void warning(const BaseField& field, std::string message) override {
    const auto* owner = dynamic_cast<const Component*>(&field.owner());
    const std::string of = owner ? " of " + owner->typeName() + " '" + owner->name() + "'" : std::string();
    std::string text = field.name() + of + ": " + message;
    if (m_options.strict) {
      m_diagnostics.error(field.location(), std::move(text) + " (an error with --strict)");
    } else {
      m_diagnostics.warning(field.location(), std::move(text));
    }
  }
  void note(const BaseField& field, std::string message) override {
    const auto* owner = dynamic_cast<const Component*>(&field.owner());
    const std::string of = owner ? " of " + owner->typeName() + " '" + owner->name() + "'" : std::string();
    m_diagnostics.note(field.location(), field.name() + of + ": " + message);
  }
  std::unique_ptr<CollisionBackend> createBackend(std::string_view kind, std::string_view name) override {
    return m_simulation.m_registry->createBackend(kind, name);
  }
  std::vector<std::string> backendNames(std::string_view kind) const override {
    return m_simulation.m_registry->backendNames(kind);
  }
  std::vector<std::string> installedPlugins() const override { return m_simulation.m_plugins->available(); }
  uint64_t seed() const override { return m_options.seed; }
  bool isRealtime() const override { return m_options.realtime; }
  ChannelHub& channels() override { return *m_simulation.m_channels; }
  EventLog& events() override { return m_simulation.m_events; }
  HapticFrameLog* claimHapticLog(const Component& component, bool writesTrace) override {
    if (!writesTrace) {
      m_simulation.m_otherToolLogs.emplace_back(&component, std::make_unique<HapticFrameLog>());
      return m_simulation.m_otherToolLogs.back().second.get();
    }
    if (m_simulation.m_hapticLogOwner) {
      error(component, "only one component per scene writes the haptic trace; " +
                           m_simulation.m_hapticLogOwner->path() + " already does (a ForceFeedback's trace=\"false\" leaves it to the other)");
      return nullptr;
    }
    m_simulation.m_hapticLogOwner = &component;
    return &m_simulation.m_hapticLog;
  }

  // Whether a component reported an error during its init, or was not
  // initialised because a component it links to did.
  bool failed(const Component& component) const { return m_failed.count(&component) > 0; }
  void skip(const Component& component) { m_failed.insert(&component); }

 private:
  Simulation& m_simulation;
  Diagnostics& m_diagnostics;
  const SimulationOptions& m_options;
  std::set<const Component*> m_failed;
};

std::unique_ptr<Simulation> Simulation::load(const std::function<std::unique_ptr<Scene>(SceneLoader&)>& read,
                                             const SimulationOptions& options, Diagnostics& diagnostics) {
  std::unique_ptr<Simulation> simulation(new Simulation());
  simulation->m_plugins = std::make_unique<PluginLoader>();
  simulation->m_registry = std::make_unique<Registry>();
  registerCoreComponents(*simulation->m_registry);
  SceneLoader loader(*simulation->m_registry, *simulation->m_plugins);
  simulation->m_scene = read(loader);
  if (!simulation->m_scene) return nullptr;
  return initialise(std::move(simulation), options, diagnostics);
}

std::unique_ptr<Simulation> Simulation::fromFile(const std::filesystem::path& file, const SimulationOptions& options,
                                                 Diagnostics& diagnostics) {
  return load([&](SceneLoader& loader) { return loader.loadFile(file, diagnostics, options.overrides); }, options,
              diagnostics);
}

std::unique_ptr<Simulation> Simulation::fromString(std::string_view xml, const std::string& fileName,
                                                   const SimulationOptions& options, Diagnostics& diagnostics) {
  return load([&](SceneLoader& loader) { return loader.loadString(xml, fileName, diagnostics, options.overrides); },
              options, diagnostics);
}

Simulation::~Simulation() = default;

std::unique_ptr<Simulation> Simulation::initialise(std::unique_ptr<Simulation> simulation,
                                                   const SimulationOptions& options, Diagnostics& diagnostics) {
  Simulation& s = *simulation;
  s.m_channels = std::make_unique<ChannelHub>();
  Context context(s, diagnostics, options);
  const std::vector<Component*> components = s.m_scene->components();

  // Initialise link targets before the components that link to them (document
  // order otherwise); a component that throws is reported at its element. A
  // component that links to one whose init failed is not initialised: its
  // errors would only follow from the first (a device aimed at a brain that
  // has no collision back-end "misses" it), and the first is what to fix.
  for (Component* c : initialisationOrder(components)) {
    bool linksToFailure = false;
    for (const BaseField* field : c->fields())
      if (const auto* link = dynamic_cast<const BaseLink*>(field); link && link->boundComponent())
        linksToFailure = linksToFailure || context.failed(*link->boundComponent());
    if (linksToFailure) {
      context.skip(*c);
      continue;
    }
    try {
      c->init(context);
    } catch (const std::exception& e) {
      context.error(*c, e.what());
    }
  }
  for (const std::string& channel : s.m_channels->unpublished())
    diagnostics.error(s.m_scene->root().location(), "channel " + channel + " is read but nothing publishes it");
  if (diagnostics.hasErrors()) return nullptr;

  // The run's length: as asked, else the longest any component wants, else 1 s.
  double duration = 0;
  const Component* longest = nullptr;
  for (const Component* c : components) {
    const double wanted = c->preferredDuration();
    if (!(wanted <= duration)) {  // also catches NaN
      duration = wanted;
      longest = c;
    }
  }
  const double planned = options.duration.value_or(duration > 0 ? duration : 1.0);
  if (!std::isfinite(planned) || planned > RunPlan::kMaxDuration) {
    const std::string what = "a run of " + formatDouble(planned) + " s is longer than the " +
                             formatDouble(RunPlan::kMaxDuration) + " s that per-frame buffers are sized for";
    if (longest && !options.duration) {
      context.error(*longest, "asks for " + what + "; shorten its motion or pass --duration");
    } else {
      diagnostics.error(s.m_scene->root().location(), what);
    }
    return nullptr;
  }
  // Rounded to whole nanoseconds so that sums of path segments print cleanly (2.3, not 2.3000000000000003).
  s.m_plan.duration = std::round(planned * 1e9) / 1e9;
  uint64_t calls = 0;
  for (const Component* c : components) calls += s.m_plan.callsAt(c->rateHz());
  if (calls > RunPlan::kMaxCalls) {
    diagnostics.error(s.m_scene->root().location(),
                      "a " + formatDouble(s.m_plan.duration) + " s run at these rates makes " + std::to_string(calls) +
                          " component calls, more than the " + std::to_string(RunPlan::kMaxCalls) +
                          " its preallocated buffers are sized for; shorten the run or lower the rates");
    return nullptr;
  }
  s.m_plan.realtime = options.realtime;
  s.m_plan.seed = options.seed;
  s.m_plan.outputDirectory = options.outputDirectory;
  s.m_plan.liveViewPort = options.liveViewPort;
  s.m_plan.keepDeviceInput = options.keepDeviceInput;
  checkRateGroupLinks(components, diagnostics);
  checkDeclaredOutputs(components, diagnostics);
  if (diagnostics.hasErrors()) return nullptr;
  warnOfOvercommittedCores(components, s.m_plan, diagnostics, s.m_scene->root().location());
  warnOfOutsideDevicesInVirtualTime(components, s.m_plan, diagnostics);

  // The output folder becomes the run's before any component writes there
  // (an exporter creates its folder when it prepares): what an earlier run
  // wrote goes, and the marker says a run is writing.
  if (!s.m_plan.outputDirectory.empty()) {
    if (auto problem = claimRunFolder(s.m_plan.outputDirectory, s.outputNames())) {
      diagnostics.error(s.m_scene->root().location(),
                        "output folder " + s.m_plan.outputDirectory.string() + ": " + *problem);
      return nullptr;
    }
    s.m_folderClaimed = true;
  }

  // Every per-frame buffer is allocated here, before the first tick.
  const std::vector<Component*> order = initialisationOrder(components);
  try {
    if (s.m_hapticLogOwner) s.m_hapticLog.reserve(s.m_plan.callsAt(s.m_hapticLogOwner->rateHz()) + 1);
    for (auto& [renderer, log] : s.m_otherToolLogs) log->reserve(s.m_plan.callsAt(renderer->rateHz()) + 1);
    for (Component* c : order) {
      try {
        c->prepare(s.m_plan);
      } catch (const std::bad_alloc&) {
        throw;
      } catch (const std::exception& e) {
        context.error(*c, e.what());
      }
    }
    // Within a rate group, link targets tick before the components that read them.
    s.m_scheduler = std::make_unique<Scheduler>(order, s.m_plan, &s.m_events);
  } catch (const std::bad_alloc&) {
    diagnostics.error(s.m_scene->root().location(), "not enough memory for the buffers of a " +
                                                        formatDouble(s.m_plan.duration) +
                                                        " s run; pass a shorter --duration");
  }
  if (diagnostics.hasErrors()) return nullptr;
  return simulation;
}

void Simulation::run() {
  std::atomic<bool> never{false};
  run(never);
}

void Simulation::run(const std::atomic<bool>& stop) {
  const auto start = std::chrono::steady_clock::now();
  m_scheduler->run(stop);
  m_wallTime = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  m_ran = true;
  m_complete = m_scheduler->completed() && !m_scheduler->failure();
  if (m_scheduler->failure()) {
    m_incompleteReason = "run-time error: " + *m_scheduler->failure();
  } else if (!m_complete) {
    m_incompleteReason = "interrupted";
  } else {
    m_incompleteReason.clear();
  }
}

void Simulation::markInterrupted(std::string reason) {
  m_complete = false;
  m_incompleteReason = std::move(reason);
}

std::vector<std::string> Simulation::writeOutputs(const std::filesystem::path& directory,
                                                  std::vector<std::string>* errors) {
  std::filesystem::create_directories(directory);
  FinishContext finish(directory, m_scheduler->simulatedTime());
  for (Component* c : m_scene->components()) {
    try {
      c->finish(finish);
    } catch (const std::exception& e) {
      finish.error(*c, e.what());
    }
  }
  std::vector<std::string> written = writeRunOutputs(*this, finish, directory);
  for (const FinishContext::Output& o : finish.outputs()) written.push_back(o.file);
  std::vector<std::string> problems = finish.errors();
  // The marker says whether the outputs are whole: finished, or why not.
  if (m_folderClaimed && directory == m_plan.outputDirectory) {
    const bool finished = m_complete && problems.empty();
    const std::string reason = !m_complete        ? m_incompleteReason
                               : problems.empty() ? std::string()
                                                  : "an output could not be written: " + problems.front();
    try {
      markRunFolder(directory, outputNames(), finished ? RunState::kFinished : RunState::kIncomplete, reason);
    } catch (const FileWriteError& e) {
      problems.push_back(e.what());
    }
  }
  if (errors) *errors = std::move(problems);
  return written;
}

std::vector<Simulation::ToolLog> Simulation::toolLogs() const {
  std::vector<ToolLog> logs;
  if (m_hapticLogOwner) logs.push_back({m_hapticLogOwner, &m_hapticLog, true});
  for (const auto& [renderer, log] : m_otherToolLogs) logs.push_back({renderer, log.get(), false});
  std::sort(logs.begin(), logs.end(), [](const ToolLog& a, const ToolLog& b) { return a.renderer->path() < b.renderer->path(); });
  return logs;
}

std::vector<std::string> Simulation::outputNames() const {
  std::vector<std::string> names{"summary.json", "trace.csv", "timings.csv", "force.png", "timings.png", "view/"};
  for (const auto& [renderer, log] : m_otherToolLogs) names.push_back(toolTraceName(*renderer));
  for (const Component* c : m_scene->components()) {
    std::vector<OutputFile> outputs;
    c->declareOutputs(outputs);
    for (const OutputFile& output : outputs) names.push_back(output.name + (output.folder ? "/" : ""));
  }
  return names;
}

}  // namespace trephine
