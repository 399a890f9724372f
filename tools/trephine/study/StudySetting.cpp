#include "tools/trephine/study/StudySetting.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <span>
#include <sstream>
#include <stdexcept>

#include "framework/core/AtomicFile.h"
#include "framework/core/Lifecycle.h"
#include "framework/devices/DeviceStream.h"
#include "framework/devices/HapticDevice.h"
#include "framework/geometry/DeformableMesh.h"
#include "framework/geometry/ExactShape.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/geometry/ShellTool.h"
#include "framework/runtime/Scheduler.h"
#include "tools/trephine/study/ExactSphereContact.h"
#include "tools/trephine/study/ExactToolContact.h"
#include "tools/trephine/study/MeshSurfaceReference.h"
#include "tools/trephine/study/ScanIsosurface.h"
#include "tools/trephine/study/StudyTable.h"

namespace trephine::study {

namespace {

// A failure of this setting, written to error.txt.
struct SettingError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// mm: the ray step of the search on a scan's isosurface (a twentieth of a
// 1 mm voxel), and how many poses its convergence is checked at.
constexpr double kScanStep = 0.05;
constexpr size_t kConvergencePoses = 20;

struct StudyPose {
  std::string kind;      // "proxy" or "device"
  std::string tool;      // the path of the tool the pose is of
  std::string target;    // and of the target it touched
  std::string renderer;  // the force renderer whose frames these are
  Vec3 position;         // mm
  double exactPenetration = std::nan("");
  Vec3 exactNormal = Vec3::Constant(std::nan(""));
};

// The scene's devices, in the order of the scene.
std::vector<HapticDevice*> devicesOf(const Simulation& simulation) {
  std::vector<HapticDevice*> devices;
  for (Component* c : simulation.scene().components())
    if (auto* device = dynamic_cast<HapticDevice*>(c)) devices.push_back(device);
  return devices;
}

// The reference run's simulated duration (s) and its devices' paths, written
// with its motion: the other settings replay its input and run as long,
// whatever their own devices would plan against their own model. Nothing
// when the file is not this study's (before the reference ran).
struct ReferenceRun {
  double duration = 0;               // s
  std::vector<std::string> devices;  // paths
};
std::optional<ReferenceRun> referenceRun(const StudyOptions& options) {
  const std::filesystem::path file = options.out / kMotionDurationFile;
  std::error_code ec;
  if (!std::filesystem::exists(file, ec) || studyOfFile(file) != options.studyId) return std::nullopt;
  const Table table = readTable(file);
  if (table.size() < 2) return std::nullopt;
  ReferenceRun run;
  run.duration = toNumber(table[1][column(table, "duration_s", file)]);
  if (!(run.duration > 0)) throw SettingError(file.string() + ":2: expected a positive duration_s");
  std::istringstream devices(table[1][column(table, "devices", file)]);
  for (std::string path; std::getline(devices, path, ';');)
    if (!path.empty()) run.devices.push_back(path);
  return run;
}

// Whether the setting varies a field of the device at `path`, which then
// keeps its own input (the motion is what is compared).
bool variesDevice(const std::string& path, const StudySetting& setting) {
  return std::any_of(setting.assignments.begin(), setting.assignments.end(),
                     [&](const auto& a) { return a.first.starts_with(path + "."); });
}

// `outputDirectory`: where the setting's run writes (empty for the probes).
std::unique_ptr<Simulation> load(const StudyOptions& options, const StudySetting& setting,
                                 const std::filesystem::path& outputDirectory = {}) {
  SimulationOptions simulationOptions = options.simulation;
  simulationOptions.outputDirectory = outputDirectory;
  simulationOptions.keepDeviceInput = true;  // the reference's motion, for every other setting
  for (const std::string& o : setting.overrides()) simulationOptions.overrides.push_back(o);
  // The reference's duration, unless --duration says or a device keeps its
  // own motion (it runs as long as that motion, as it would alone).
  if (setting.index != options.referenceIndex && !simulationOptions.duration)
    if (const std::optional<ReferenceRun> reference = referenceRun(options))
      if (std::none_of(reference->devices.begin(), reference->devices.end(),
                       [&](const std::string& d) { return variesDevice(d, setting); }))
        simulationOptions.duration = reference->duration;
  Diagnostics diagnostics;
  auto simulation = Simulation::fromFile(options.scene, simulationOptions, diagnostics);
  if (!simulation) throw SettingError(diagnostics.str());
  return simulation;
}

// The target to probe: --target, else the scene's only one, else the
// component of the first varied field if it is one.
std::pair<ShellContactTarget*, Component*> findTarget(const Simulation& simulation, const StudyOptions& options,
                                                      const StudySetting& setting) {
  if (!options.target.empty()) {
    Component* c = simulation.scene().findComponent(options.target);
    auto* target = dynamic_cast<ShellContactTarget*>(c);
    if (!target) throw SettingError("--target " + options.target + ": no collision target there");
    return {target, c};
  }
  std::vector<Component*> targets;
  for (Component* c : simulation.scene().components())
    if (dynamic_cast<ShellContactTarget*>(c)) targets.push_back(c);
  if (targets.empty()) throw SettingError("the scene has no collision target to study");
  if (targets.size() > 1 && !setting.assignments.empty()) {
    const std::string& field = setting.assignments.front().first;
    const std::string path = field.substr(0, field.rfind('.'));
    for (Component* c : targets)
      if (c->path() == path) return {dynamic_cast<ShellContactTarget*>(c), c};
  }
  if (targets.size() > 1) throw SettingError("the scene has several collision targets: choose one with --target PATH");
  return {dynamic_cast<ShellContactTarget*>(targets.front()), targets.front()};
}

// The tool at `path`, else the scene's only one.
const ShellTool& findTool(const Simulation& simulation, const std::string& path = "") {
  if (!path.empty()) {
    const auto* tool = dynamic_cast<const ShellTool*>(simulation.scene().findComponent(path));
    if (!tool) throw SettingError(path + ": no pointshell tool there");
    return *tool;
  }
  const ShellTool* tool = nullptr;
  for (Component* c : simulation.scene().components())
    if (auto* t = dynamic_cast<const ShellTool*>(c)) {
      if (tool)
        throw SettingError("the scene has several pointshell tools and its renderer does not say which touched");
      tool = t;
    }
  if (!tool) throw SettingError("the scene has no pointshell tool to probe the target with");
  return *tool;
}

// The path of the component whose ShellTool (or ShellContactTarget) is at
// `identity`, as the haptic log names it; "" when none is.
template <typename Role>
std::string pathOf(const Simulation& simulation, const void* identity) {
  for (Component* c : simulation.scene().components())
    if (static_cast<const void*>(dynamic_cast<const Role*>(c)) == identity) return c->path();
  return "";
}

// A tool and a target that touched in a run, with its frames in contact in
// the log of the renderer that rendered them.
struct ContactPair {
  std::string tool, target;  // component paths
  std::string renderer;      // the path of the force renderer whose log holds the frames
  const HapticFrameLog* log = nullptr;
  std::vector<size_t> frames;
};

// Every (tool, target) pair in contact in the run, the studied one first: the
// target of --target (only its pairs), else that of the first varied field
// when it is a target, then by frames in contact. A renderer that does not
// say which tool and target touched stands for the scene's only tool and the
// studied target.
std::vector<ContactPair> pairsFromRun(const Simulation& simulation, const StudyOptions& options,
                                      const StudySetting& setting) {
  std::vector<ContactPair> pairs;
  std::string fallbackTool, fallbackTarget;
  // Every renderer's log, trace.csv's first: each tool's own frames.
  std::vector<Simulation::ToolLog> logs = simulation.toolLogs();
  std::stable_partition(logs.begin(), logs.end(), [](const Simulation::ToolLog& l) { return l.writesTrace; });
  for (const Simulation::ToolLog& toolLog : logs) {
    const HapticFrameLog& log = *toolLog.log;
    for (size_t i = 0; i < log.size(); ++i) {
      if (log[i].contacts <= 0) continue;
      std::string tool = log[i].tool ? pathOf<ShellTool>(simulation, log[i].tool) : "";
      std::string target = log[i].target ? pathOf<ShellContactTarget>(simulation, log[i].target) : "";
      if (tool.empty()) {
        if (fallbackTool.empty()) fallbackTool = dynamic_cast<const Component&>(findTool(simulation)).path();
        tool = fallbackTool;
      }
      if (target.empty()) {
        if (fallbackTarget.empty()) fallbackTarget = findTarget(simulation, options, setting).second->path();
        target = fallbackTarget;
      }
      auto it = std::find_if(pairs.begin(), pairs.end(),
                             [&](const ContactPair& p) { return p.tool == tool && p.target == target; });
      if (it == pairs.end())
        it = pairs.insert(pairs.end(), ContactPair{tool, target, toolLog.renderer->path(), &log, {}});
      if (it->log != &log) continue;  // the same tool rendered by two renderers: the first one's frames
      it->frames.push_back(i);
    }
  }
  for (const ContactPair& p : pairs)
    if (p.renderer.find(',') != std::string::npos)
      throw SettingError("a study names tools and targets in its CSV files; rename the component with a comma in " +
                         p.renderer);
  for (const ContactPair& p : pairs)
    if (p.tool.find(',') != std::string::npos || p.target.find(',') != std::string::npos)
      throw SettingError("a study names tools and targets in its CSV files; rename the component with a comma in " +
                         (p.tool.find(',') != std::string::npos ? p.tool : p.target));
  if (!options.target.empty()) std::erase_if(pairs, [&](const ContactPair& p) { return p.target != options.target; });
  std::string studied;
  if (options.target.empty() && !setting.assignments.empty()) {
    const std::string& field = setting.assignments.front().first;
    studied = field.substr(0, field.rfind('.'));
  }
  std::stable_sort(pairs.begin(), pairs.end(), [&](const ContactPair& a, const ContactPair& b) {
    const bool aStudied = a.target == studied, bStudied = b.target == studied;
    if (aStudied != bStudied) return aStudied;
    return a.frames.size() > b.frames.size();
  });
  return pairs;
}

// The rate group that runs the component writing the haptic log: the haptic loop.
const RateGroup* hapticGroup(const Simulation& simulation) {
  for (const RateGroup& group : simulation.scheduler().groups())
    for (const GroupMember& member : group.members)
      if (member.component == simulation.hapticLogOwner()) return &group;
  return nullptr;
}

// Poses from the frames of one pair (after a tool change the proxy touches
// another target: its poses say nothing of the first).
std::vector<StudyPose> posesOfPair(const ContactPair& pair, int perKind) {
  const HapticFrameLog& log = *pair.log;
  std::vector<StudyPose> poses;
  const size_t count = std::min<size_t>(pair.frames.size(), static_cast<size_t>(perKind));
  for (const char* kind : {"proxy", "device"})
    for (size_t j = 0; j < count; ++j) {
      const HapticFrame& frame = log[pair.frames[j * pair.frames.size() / count]];
      poses.push_back(
          {kind, pair.tool, pair.target, pair.renderer, std::string(kind) == "proxy" ? frame.proxy : frame.device});
    }
  return poses;
}

std::string number(double value) {
  std::ostringstream s;
  s.precision(9);
  s << value;
  return s.str();
}

// The exact contact at every pose of one tool on one target, and what the
// reference is (`description`), or why there is none (returned). The
// reference is independent of every back-end and of the setting: a
// phantom's closed form; a scan's isosurface of its trilinearly interpolated
// density, read again from its file, by root finding (with a convergence
// check); a mesh's boundary triangles at rest, by exact distance.
std::string addExactContacts(std::vector<StudyPose>& poses, const Component& targetComponent, const ShellTool& tool,
                             std::string& description) {
  // A sphere, or a burr on a shaft (ExactToolContact.h); another shape has no
  // reference here. Posed as the probe poses the tool: at each position, in
  // the tool frame's orientation (the identity).
  const ToolSolid solid = tool.solid();
  const bool sphere = tool.boundingRadius() == tool.leadingRadius();
  const bool shaft = solid.shaftLength > 0 && solid.shaftRadius > 0;
  if (!sphere && !shaft)
    return "the tool is neither a sphere nor a burr on a shaft (its bounding radius " +
           number(tool.boundingRadius()) + " mm, its burr's " + number(tool.leadingRadius()) +
           " mm, and it describes no shaft): the exact contact is a sphere's or a burr on a shaft's";
  const double radius = tool.leadingRadius();
  const std::string shape = sphere ? "" : "; the tool a burr on a shaft, the shaft's depth that of its cross-section";
  // The exact contact of the tool at `position` from the exact contact of spheres.
  const auto contactAt = [&](const SphereReference& spheres, const Vec3& position) {
    return sphere ? spheres(position, radius) : exactToolContact(spheres, Pose{position, Quat::Identity()}, solid);
  };
  const auto source = dynamic_cast<const ExactShapeSource*>(&targetComponent);
  if (const LevelSet exact = source ? source->exactShape() : LevelSet{}) {
    const SphereReference spheres = [&](const Vec3& c, double r) { return exactSphereContact(exact, c, r); };
    for (StudyPose& pose : poses) {
      const ExactSphereContact contact = contactAt(spheres, pose.position);
      pose.exactPenetration = std::max(0.0, contact.penetration);
      pose.exactNormal = contact.normal;
    }
    description = "the exact shape of the phantom" + shape;
    return "";
  }
  if (const std::optional<ScanAsRead> scan = source ? source->scanAsRead() : std::nullopt) {
    const LevelSet isosurface = scanIsosurface(*scan);
    const auto withStep = [&](double step) -> SphereReference {
      return [&isosurface, step](const Vec3& c, double r) { return exactSphereContact(isosurface, c, r, step); };
    };
    for (StudyPose& pose : poses) {
      const ExactSphereContact contact = contactAt(withStep(kScanStep), pose.position);
      pose.exactPenetration = std::max(0.0, contact.penetration);
      pose.exactNormal = contact.normal;
    }
    // Convergence: the same search with a step a quarter as long, at up to
    // kConvergencePoses poses spread over the pair's.
    double largest = 0;
    const size_t checked = std::min(poses.size(), kConvergencePoses);
    for (size_t j = 0; j < checked; ++j) {
      const StudyPose& pose = poses[j * poses.size() / checked];
      const double finer = std::max(0.0, contactAt(withStep(kScanStep / 4), pose.position).penetration);
      largest = std::max(largest, std::abs(finer - pose.exactPenetration));
    }
    const Vec3& spacing = scan->volume->spacing();
    description = "the isosurface at " + number(scan->isovalue) + " of the scan's density interpolated trilinearly (" +
                  number(spacing.x()) + " x " + number(spacing.y()) + " x " + number(spacing.z()) +
                  " mm voxels, as its file holds them), found by root finding along rays in double precision" +
                  shape + "; with a step a quarter as long the penetration changed by at most " + number(largest) +
                  " mm at " + std::to_string(checked) + " poses";
    return "";
  }
  if (const auto* deformable = dynamic_cast<const DeformableMesh*>(&targetComponent)) {
    const BoundarySurface surface = boundarySurface(deformable->mesh());
    const SphereReference spheres = [&](const Vec3& c, double r) { return meshSphereContact(surface, c, r); };
    for (StudyPose& pose : poses) {
      const ExactSphereContact contact = contactAt(spheres, pose.position);
      pose.exactPenetration = std::max(0.0, contact.penetration);
      pose.exactNormal = contact.normal;
    }
    description = "the mesh's " + std::to_string(surface.triangles.size()) +
                  " boundary triangles at rest, by exact point-to-triangle distance (inside by the winding number)" +
                  shape;
    return "";
  }
  return targetComponent.path() + " (" + targetComponent.typeName() + ") is neither a phantom, a scan nor a mesh";
}

void writePoses(const std::filesystem::path& file, const std::vector<StudyPose>& poses, const std::string& study) {
  std::ostringstream s;
  s << "kind,tool,target,renderer,x,y,z,exact_penetration,exact_nx,exact_ny,exact_nz,study\n";
  for (const StudyPose& p : poses)
    s << p.kind << ',' << p.tool << ',' << p.target << ',' << p.renderer << ',' << number(p.position.x()) << ','
      << number(p.position.y()) << ',' << number(p.position.z()) << ',' << number(p.exactPenetration) << ','
      << number(p.exactNormal.x()) << ',' << number(p.exactNormal.y()) << ',' << number(p.exactNormal.z()) << ','
      << study << '\n';
  AtomicFile out(file);  // other processes wait for it: it appears whole or not at all
  out.write(s.str());
  out.commit();
}

std::vector<StudyPose> readPoses(const std::filesystem::path& file) {
  Table table;
  try {
    table = readTable(file);
  } catch (const std::exception& e) {
    throw SettingError(e.what());
  }
  const size_t kind = column(table, "kind", file), tool = column(table, "tool", file),
               target = column(table, "target", file), x = column(table, "x", file), y = column(table, "y", file),
               z = column(table, "z", file);
  std::vector<StudyPose> poses;
  for (size_t r = 1; r < table.size(); ++r) {
    const Vec3 position(toNumber(table[r][x]), toNumber(table[r][y]), toNumber(table[r][z]));
    if (!position.allFinite())
      throw SettingError(file.string() + ":" + std::to_string(r + 1) + ": expected a position of three numbers");
    poses.push_back({table[r][kind], table[r][tool], table[r][target], "", position});
  }
  return poses;
}

std::filesystem::path motionFile(const std::filesystem::path& out, const HapticDevice& device) {
  return out / FinishContext::defaultFileName(kMotionFilePrefix, device);
}

// The reference run's device input, each device's in a file of the study's
// folder (a device stream, as a run records it), written before poses.csv,
// for which the other settings wait. An earlier study's are removed first.
void writeMotion(const Simulation& simulation, const StudyOptions& options) {
  const std::filesystem::path& out = options.out;
  {
    std::ostringstream text;
    std::string devices;
    for (const HapticDevice* device : devicesOf(simulation)) devices += (devices.empty() ? "" : ";") + device->path();
    text << "duration_s,devices,study\n"
         << number(simulation.plan().duration) << ',' << devices << ',' << options.studyId << '\n';
    AtomicFile file(out / kMotionDurationFile);
    file.write(text.str());
    file.commit();
  }
  std::error_code ec;
  for (const std::filesystem::directory_entry& entry : std::filesystem::directory_iterator(out, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(std::string(kMotionFilePrefix) + ".") && name.ends_with(".csv") && !entry.is_symlink(ec) &&
        entry.is_regular_file(ec))
      std::filesystem::remove(entry.path(), ec);
  }
  {
    // The times each device took a sample without the jump test (a looping
    // replay starting over), replayed alike.
    std::ostringstream text;
    text << "device,t,study\n";
    for (const HapticDevice* device : devicesOf(simulation))
      for (const double t : device->recordedResets())
        text << device->path() << ',' << number(t) << ',' << options.studyId << '\n';
    AtomicFile file(out / kMotionResetsFile);
    file.write(text.str());
    file.commit();
  }
  for (const HapticDevice* device : devicesOf(simulation)) {
    const std::span<const DeviceSample> input = device->recorded();
    // A device that read nothing (one outside the process that never
    // connected) has no motion to replay: the other settings keep its own.
    if (input.empty()) continue;
    std::ostringstream text;
    writeDeviceStream(text, std::vector<DeviceSample>(input.begin(), input.end()), input.size());
    AtomicFile file(motionFile(out, *device));
    file.write(text.str());
    file.commit();
  }
}

// The times the reference run's `device` took a sample without the jump test.
std::vector<double> referenceResets(const StudyOptions& options, const HapticDevice& device) {
  const std::filesystem::path file = options.out / kMotionResetsFile;
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return {};
  Table table;
  try {
    table = readTable(file);
  } catch (const std::exception& e) {
    throw SettingError(e.what());
  }
  std::vector<double> times;
  const size_t path = column(table, "device", file), t = column(table, "t", file),
               study = column(table, "study", file);
  for (size_t r = 1; r < table.size(); ++r)
    if (table[r][path] == device.path() && table[r][study] == options.studyId) times.push_back(toNumber(table[r][t]));
  return times;
}

// Every device of this setting reads the reference run's input instead of
// its own: one motion for every setting, whatever path a device would plan
// against this setting's model. But for a device whose own field the study
// varies (its path, its speed): there the motion is what is compared, and
// each setting keeps the device's own input.
void replayReferenceMotion(Simulation& simulation, const StudySetting& setting, const StudyOptions& options) {
  const std::filesystem::path& out = options.out;
  for (HapticDevice* device : devicesOf(simulation)) {
    if (variesDevice(device->path(), setting)) continue;
    std::error_code ec;
    if (!std::filesystem::exists(motionFile(out, *device), ec)) continue;  // it read nothing in the reference's run
    DeviceStreamReadResult read = readDeviceStream(motionFile(out, *device));
    if (!read.error.empty()) throw SettingError("the reference run's motion of " + device->path() + ": " + read.error);
    if (read.samples.empty()) throw SettingError("the reference run's motion of " + device->path() + " has no sample");
    device->replaceInput(std::move(read.samples), referenceResets(options, *device));
  }
}

// Queries the pristine targets at every pose with the pose's tool, held in
// the world's orientation (the study's poses are positions): first the broad
// phase alone at every pose (when the target splits its query), then the
// whole query, each timed (two passes, so neither warms the other's caches
// pose by pose).
void probe(Simulation& simulation, const std::vector<StudyPose>& poses, const std::filesystem::path& file) {
  struct Probed {
    ShellContactTarget* target;
    std::span<const ShellPoint> shell;
    size_t memory;  // in `memories`: the probe's own for this tool on this target, as a tool's
  };
  struct ProbeMemory {
    ShellContactTarget* target;
    const ShellPoint* shell;
    ContactMemory memory;
  };
  std::vector<ProbeMemory> memories;
  std::vector<Probed> probed;
  for (const StudyPose& pose : poses) {
    auto* target = dynamic_cast<ShellContactTarget*>(simulation.scene().findComponent(pose.target));
    if (!target) throw SettingError(pose.target + ": no collision target there in this setting");
    const std::span<const ShellPoint> shell = findTool(simulation, pose.tool).shellPoints();
    auto known = std::find_if(memories.begin(), memories.end(),
                              [&](const ProbeMemory& m) { return m.target == target && m.shell == shell.data(); });
    if (known == memories.end()) {
      memories.push_back({target, shell.data(), target->reserveShell(shell)});
      known = memories.end() - 1;
    }
    probed.push_back({target, shell, size_t(known - memories.begin())});
  }
  // One frame of the pristine targets, begun once each (the probe owns it).
  std::vector<ShellContactTarget*> begun;
  for (const Probed& p : probed)
    if (std::find(begun.begin(), begun.end(), p.target) == begun.end()) {
      p.target->beginFrame(0.0);
      begun.push_back(p.target);
    }
  using Clock = std::chrono::steady_clock;
  const auto microseconds = [](Clock::duration d) { return std::chrono::duration<double, std::micro>(d).count(); };
  std::vector<double> broadUs(poses.size(), std::nan(""));
  std::vector<double> candidates(poses.size(), std::nan(""));
  for (size_t i = 0; i < poses.size(); ++i) {
    const auto start = Clock::now();
    const std::optional<size_t> found =
        probed[i].target->broadPhase(Pose{poses[i].position, Quat::Identity()}, probed[i].shell);
    const double us = microseconds(Clock::now() - start);
    if (!found) continue;
    broadUs[i] = us;
    candidates[i] = double(*found);
  }
  std::ostringstream s;
  s << "penetration,nx,ny,nz,query_us,broad_us,candidates\n";
  for (size_t i = 0; i < poses.size(); ++i) {
    const auto start = Clock::now();
    const ShellContact contact = probed[i].target->collide(Pose{poses[i].position, Quat::Identity()}, probed[i].shell,
                                                           false, memories[probed[i].memory].memory);
    const double us = microseconds(Clock::now() - start);
    const bool touching = contact.points > 0;
    const Vec3 n = touching ? contact.normal : Vec3::Zero();
    s << number(touching ? contact.penetration : 0.0) << ',' << number(n.x()) << ',' << number(n.y()) << ','
      << number(n.z()) << ',' << number(us) << ',' << number(broadUs[i]) << ',' << number(candidates[i]) << '\n';
  }
  AtomicFile out(file);
  out.write(s.str());
  out.commit();
}

void writeResult(const Simulation& simulation, const std::filesystem::path& file, const std::string& study) {
  const HapticStats stats = simulation.hapticLog().stats();
  const RateGroup* group = hapticGroup(simulation);
  const TimingSummary step = group ? group->stepHistogram.summary() : TimingSummary{};
  int64_t removed = 0;
  for (size_t i = 0; i < simulation.hapticLog().size(); ++i) removed += simulation.hapticLog()[i].removed;
  std::ostringstream s;
  s << "complete,frames,contact_frames,step_p50_us,step_p99_us,force_step_p99_N,force_step_max_N,"
       "unexplained_step_p99_N,proxy_inside_frames,nan_frames,force_reversals,removed,wall_s,study\n";
  s << (simulation.complete() ? 1 : 0) << ',' << stats.frames << ',' << stats.contactFrames << ',' << number(step.p50)
    << ',' << number(step.p99) << ',' << number(stats.forceStepP99) << ',' << number(stats.forceStepMax) << ','
    << (stats.hasUnexplainedSteps ? number(stats.unexplainedStepP99) : "nan") << ',' << stats.proxyInsideFrames << ','
    << stats.nanFrames << ',' << stats.forceReversals << ',' << removed << ',' << number(simulation.wallTime()) << ','
    << study << '\n';
  // Every tool's closed loop, by its renderer (its whole run: after a tool
  // change, both tools'), for the pairs of pairs.csv; written before result.csv, which the
  // gathering rank waits for.
  std::ostringstream tools;
  tools << "renderer,frames,contact_frames,force_step_p99_N,force_step_max_N,unexplained_step_p99_N,"
           "proxy_inside_frames,nan_frames,study\n";
  for (const Simulation::ToolLog& toolLog : simulation.toolLogs()) {
    const HapticStats t = toolLog.log->stats();
    tools << toolLog.renderer->path() << ',' << t.frames << ',' << t.contactFrames << ',' << number(t.forceStepP99)
          << ',' << number(t.forceStepMax) << ',' << (t.hasUnexplainedSteps ? number(t.unexplainedStepP99) : "nan")
          << ',' << t.proxyInsideFrames << ',' << t.nanFrames << ',' << study << '\n';
  }
  AtomicFile toolsFile(file.parent_path() / kToolsFile);
  toolsFile.write(tools.str());
  toolsFile.commit();
  AtomicFile out(file);
  out.write(s.str());
  out.commit();
}

// A timing file: one row of the run's step times, or why it failed.
void writeTiming(const std::filesystem::path& file, bool complete, const TimingSummary& step, double wall,
                 const std::string& why, const std::string& study) {
  std::string reason = why;
  for (char& c : reason)
    if (c == ',' || c == '\n' || c == '"') c = ' ';
  std::ostringstream s;
  s << "complete,step_p50_us,step_p99_us,wall_s,error,study\n"
    << (complete ? 1 : 0) << ',' << number(complete ? step.p50 : std::nan("")) << ','
    << number(complete ? step.p99 : std::nan("")) << ',' << number(wall) << ',' << reason << ',' << study << '\n';
  AtomicFile out(file);
  out.write(s.str());
  out.commit();
}

}  // namespace

std::filesystem::path timingFile(const std::filesystem::path& settingDirectory, int run) {
  return settingDirectory / ("timing-" + std::to_string(run) + ".csv");
}

void writeTimingFailure(const std::filesystem::path& directory, int run, const std::string& studyId,
                        const std::string& why) {
  try {
    writeTiming(timingFile(directory, run), false, {}, std::nan(""), why, studyId);
  } catch (const std::exception& e) {
    std::cerr << "trephine: " << why << "; and the timing file cannot be written: " << e.what() << "\n";
  }
}

namespace {

// A worker's setting folder, or nothing (said on stderr) when something is in
// its way: nothing is written where a link points; the study's own check
// names it.
std::optional<std::filesystem::path> workerFolder(const StudyOptions& options, const StudySetting& setting) {
  try {
    return settingFolder(options.out, setting);
  } catch (const FileWriteError& e) {
    std::cerr << "trephine: " << setting.label() << ": " << e.what() << "\n";
    return std::nullopt;
  }
}

}  // namespace

bool runTimingRun(const StudyOptions& options, const StudySetting& setting, int run) {
  const std::optional<std::filesystem::path> found = workerFolder(options, setting);
  if (!found) return false;
  const std::filesystem::path& directory = *found;
  try {
    auto simulation = load(options, setting);
    replayReferenceMotion(*simulation, setting, options);
    simulation->run();
    if (!simulation->complete()) throw SettingError("run incomplete: " + simulation->incompleteReason());
    const RateGroup* group = hapticGroup(*simulation);
    writeTiming(timingFile(directory, run), true, group ? group->stepHistogram.summary() : TimingSummary{},
                simulation->wallTime(), "", options.studyId);
    return true;
  } catch (const std::exception& e) {
    writeTimingFailure(directory, run, options.studyId, e.what());
    return false;
  }
}

std::filesystem::path settingFolder(const std::filesystem::path& out, const StudySetting& setting) {
  return OutputFolder::create(out).subfolder(setting.directoryName()).path();
}

std::string settingFolderProblem(const std::filesystem::path& out, const StudySetting& setting) {
  std::filesystem::path path = out;
  for (const std::filesystem::path& part : std::filesystem::path(setting.directoryName())) {
    path /= part;
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::symlink_status(path, ec);
    if (status.type() == std::filesystem::file_type::not_found) return "";
    if (status.type() != std::filesystem::file_type::directory)
      return path.string() + ": is " +
             (status.type() == std::filesystem::file_type::symlink ? std::string("a link") : "not a folder") +
             ", where the study's own folder goes: refusing to write through it";
  }
  return "";
}

bool runStudySetting(const StudyOptions& options, const StudySetting& setting) {
  const std::optional<std::filesystem::path> found = workerFolder(options, setting);
  if (!found) return false;
  const std::filesystem::path& directory = *found;
  std::error_code ec;
  for (const char* stale : {kProbeFile, kResultFile, kErrorFile}) std::filesystem::remove(directory / stale, ec);
  const std::filesystem::path posesFile = options.out / kPosesFile;
  const bool isReference = setting.index == options.referenceIndex;
  try {
    // Every setting's probe runs on an instance of its own, loaded fresh and
    // never run, so that the probe neither changes the run it measures (its
    // counters, caches, warm starts) nor sees a drilled or deformed target.
    auto simulation = load(options, setting, directory);
    if (isReference) {
      // The reference's run gives the poses: of every tool and target that
      // touched, each from its own frames in contact.
      simulation->run();
      const std::vector<ContactPair> pairs = pairsFromRun(*simulation, options, setting);
      if (pairs.empty()) {
        const std::string what = options.target.empty() ? std::string("any collision target") : options.target;
        throw SettingError("the reference run has no frame in contact with " + what +
                           ": there are no poses to compare");
      }
      auto probed = load(options, setting);
      std::vector<StudyPose> poses;
      std::string noExactShape;  // why, per pair, for study.md (none: the exact shape)
      std::string references;    // what the exact reference is, per pair
      for (const ContactPair& pair : pairs) {
        std::vector<StudyPose> ofPair = posesOfPair(pair, options.posesPerKind);
        const Component* target = probed->scene().findComponent(pair.target);
        if (!target) throw SettingError(pair.target + ": no component there in a fresh load of the scene");
        std::string description;
        const std::string why = addExactContacts(ofPair, *target, findTool(*probed, pair.tool), description);
        if (!why.empty()) noExactShape += pair.tool + " on " + pair.target + ": " + why + "\n";
        if (!description.empty()) references += pair.tool + " on " + pair.target + ": " + description + "\n";
        poses.insert(poses.end(), ofPair.begin(), ofPair.end());
      }
      writeMotion(*simulation, options);
      writePoses(posesFile, poses, options.studyId);
      std::filesystem::remove(options.out / kNoExactShapeFile, ec);
      std::filesystem::remove(options.out / kReferencesFile, ec);
      if (!references.empty()) {
        AtomicFile what(options.out / kReferencesFile);
        what.write(references);
        what.commit();
      }
      if (!noExactShape.empty()) {
        AtomicFile why(options.out / kNoExactShapeFile);
        why.write(noExactShape);
        why.commit();
      }
      probe(*probed, poses, directory / kProbeFile);
    } else {
      auto probed = load(options, setting);
      if (studyOfFile(posesFile) != options.studyId)
        throw SettingError(posesFile.string() + " is not this study's (an earlier study's, left in the same folder)");
      probe(*probed, readPoses(posesFile), directory / kProbeFile);
      probed.reset();
      replayReferenceMotion(*simulation, setting, options);
      simulation->run();
    }
    std::vector<std::string> errors;
    simulation->writeOutputs(directory, &errors);
    if (!simulation->complete()) throw SettingError("run incomplete: " + simulation->incompleteReason());
    if (!errors.empty()) throw SettingError(errors.front());
    writeResult(*simulation, directory / kResultFile, options.studyId);
    return true;
  } catch (const std::exception& e) {
    writeSettingError(directory, options.studyId, setting.label() + ": " + e.what());
    return false;
  }
}

std::string studyOfFile(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return "";
  if (file.filename() == kErrorFile) {
    std::ifstream in(file);
    std::string first;
    std::getline(in, first);
    return first.starts_with("study ") ? first.substr(6) : "";
  }
  try {
    const Table table = readTable(file);
    if (table.size() < 2) return "";
    return table[1][column(table, "study", file)];
  } catch (const std::exception&) {
    return "";  // an earlier version's, or cut short: not this study's
  }
}

std::string settingErrorMessage(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::ostringstream text;
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    if (first && line.starts_with("study ")) {
      first = false;
      continue;
    }
    first = false;
    text << line << '\n';
  }
  std::string message = text.str();
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return message;
}

void writeSettingError(const std::filesystem::path& directory, const std::string& studyId, const std::string& message) {
  // Other processes wait for this file: it appears whole or not at all.
  try {
    AtomicFile out(directory / kErrorFile);
    out.write("study " + studyId + "\n" + message + "\n");
    out.commit();
  } catch (const std::exception& e) {
    std::cerr << "trephine: " << message << "; and the error file cannot be written: " << e.what() << "\n";
  }
}

}  // namespace trephine::study
