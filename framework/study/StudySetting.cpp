#include "framework/study/StudySetting.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "framework/core/AtomicFile.h"
#include "framework/geometry/ExactShape.h"
#include "framework/geometry/ShellTool.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/runtime/Scheduler.h"
#include "framework/study/ExactSphereContact.h"

namespace trephine::study {

namespace {

// A failure of this setting, written to error.txt.
struct SettingError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct StudyPose {
  std::string kind;  // "proxy" or "device"
  Vec3 position;     // mm
  double exactPenetration = std::nan("");
  Vec3 exactNormal = Vec3::Constant(std::nan(""));
};

// `outputDirectory`: where the setting's run writes (empty for the probes).
std::unique_ptr<Simulation> load(const StudyOptions& options, const StudySetting& setting,
                                 const std::filesystem::path& outputDirectory = {}) {
  SimulationOptions simulationOptions = options.simulation;
  simulationOptions.outputDirectory = outputDirectory;
  for (const std::string& o : setting.overrides()) simulationOptions.overrides.push_back(o);
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
        throw SettingError("the scene has several pointshell tools and none touched the target in the reference run");
      tool = t;
    }
  if (!tool) throw SettingError("the scene has no pointshell tool to probe the target with");
  return *tool;
}

// The path of the tool the run's frames in contact with `target` used (the
// first such frame's), or "" when the renderer does not say.
std::string toolTouching(const Simulation& simulation, const ShellContactTarget* target) {
  const HapticFrameLog& log = simulation.hapticLog();
  for (size_t i = 0; i < log.size(); ++i)
    if (log[i].contacts > 0 && log[i].target == target && log[i].tool)
      for (Component* c : simulation.scene().components())
        if (static_cast<const void*>(dynamic_cast<const ShellTool*>(c)) == log[i].tool) return c->path();
  return "";
}

// The rate group that runs the component writing the haptic log: the haptic loop.
const RateGroup* hapticGroup(const Simulation& simulation) {
  for (const RateGroup& group : simulation.scheduler().groups())
    for (const GroupMember& member : group.members)
      if (member.component == simulation.hapticLogOwner()) return &group;
  return nullptr;
}

// Poses from the frames in contact with `target` (after a tool change the
// proxy touches another target: its poses say nothing of this one).
std::vector<StudyPose> posesFromRun(const Simulation& simulation, int perKind, const ShellContactTarget* target) {
  const HapticFrameLog& log = simulation.hapticLog();
  std::vector<size_t> contactFrames;
  for (size_t i = 0; i < log.size(); ++i)
    if (log[i].contacts > 0 && (log[i].target == nullptr || log[i].target == target)) contactFrames.push_back(i);
  std::vector<StudyPose> poses;
  const size_t count = std::min<size_t>(contactFrames.size(), static_cast<size_t>(perKind));
  for (const char* kind : {"proxy", "device"})
    for (size_t j = 0; j < count; ++j) {
      const HapticFrame& frame = log[contactFrames[j * contactFrames.size() / count]];
      poses.push_back({kind, std::string(kind) == "proxy" ? frame.proxy : frame.device});
    }
  return poses;
}

std::string number(double value) {
  std::ostringstream s;
  s.precision(9);
  s << value;
  return s.str();
}

// The exact contact at every pose, or why there is none.
std::string addExactContacts(std::vector<StudyPose>& poses, const Component& targetComponent, const ShellTool& tool) {
  const auto* source = dynamic_cast<const ExactShapeSource*>(&targetComponent);
  if (!source) return targetComponent.path() + " (" + targetComponent.typeName() + ") gives no exact shape";
  const LevelSet shape = source->exactShape();
  if (!shape)
    return targetComponent.path() + " is read from a file (a scan or a mesh), which has no closed form; a phantom "
           "(file=\"phantom:...\") has one";
  // The exact contact is that of a sphere: only for a spherical tool.
  if (tool.boundingRadius() != tool.leadingRadius())
    return "the tool is not a sphere (its bounding radius " + number(tool.boundingRadius()) + " mm, its burr's " +
           number(tool.leadingRadius()) + " mm): the exact contact is a sphere's";
  for (StudyPose& pose : poses) {
    const ExactSphereContact exact = exactSphereContact(shape, pose.position, tool.leadingRadius());
    pose.exactPenetration = std::max(0.0, exact.penetration);
    pose.exactNormal = exact.normal;
  }
  return "";
}


void writePoses(const std::filesystem::path& file, const std::vector<StudyPose>& poses) {
  std::ostringstream s;
  s << "kind,x,y,z,exact_penetration,exact_nx,exact_ny,exact_nz\n";
  for (const StudyPose& p : poses)
    s << p.kind << ',' << number(p.position.x()) << ',' << number(p.position.y()) << ',' << number(p.position.z())
      << ',' << number(p.exactPenetration) << ',' << number(p.exactNormal.x()) << ',' << number(p.exactNormal.y())
      << ',' << number(p.exactNormal.z()) << '\n';
  AtomicFile out(file);  // other processes wait for it: it appears whole or not at all
  out.write(s.str());
  out.commit();
}

std::vector<Vec3> readPositions(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw SettingError("cannot read " + file.string());
  std::string line;
  std::getline(in, line);
  std::vector<Vec3> positions;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string kind, x, y, z;
    if (!std::getline(row, kind, ',') || !std::getline(row, x, ',') || !std::getline(row, y, ',') ||
        !std::getline(row, z, ','))
      throw SettingError(file.string() + ": malformed row '" + line + "'");
    double v[3];
    const std::string* cells[3] = {&x, &y, &z};
    for (int a = 0; a < 3; ++a) {
      const std::string& cell = *cells[a];
      const auto result = std::from_chars(cell.data(), cell.data() + cell.size(), v[a]);
      if (result.ec != std::errc() || result.ptr != cell.data() + cell.size())
        throw SettingError(file.string() + ":" + std::to_string(positions.size() + 2) + ": expected a number, got '" +
                           cell + "'");
    }
    positions.emplace_back(v[0], v[1], v[2]);
  }
  return positions;
}

// Queries the pristine target at every pose, the tool held in the world's
// orientation (the spherical burr does not depend on it): first the broad
// phase alone at every pose (when the target splits its query), then the
// whole query, each timed (two passes, so neither warms the other's caches
// pose by pose).
void probe(Simulation& simulation, const StudyOptions& options, const StudySetting& setting,
           const std::vector<Vec3>& positions, const std::filesystem::path& file) {
  auto [target, component] = findTarget(simulation, options, setting);
  std::string toolPath;
  std::getline(std::ifstream(options.out / kProbeToolFile), toolPath);
  const ShellTool& tool = findTool(simulation, toolPath);
  target->beginFrame(0.0);
  using Clock = std::chrono::steady_clock;
  const auto microseconds = [](Clock::duration d) { return std::chrono::duration<double, std::micro>(d).count(); };
  std::vector<double> broadUs(positions.size(), std::nan(""));
  std::vector<double> candidates(positions.size(), std::nan(""));
  for (size_t i = 0; i < positions.size(); ++i) {
    const auto start = Clock::now();
    const std::optional<size_t> found = target->broadPhase(Pose{positions[i], Quat::Identity()}, tool.shellPoints());
    const double us = microseconds(Clock::now() - start);
    if (!found) break;
    broadUs[i] = us;
    candidates[i] = double(*found);
  }
  std::ostringstream s;
  s << "penetration,nx,ny,nz,query_us,broad_us,candidates\n";
  for (size_t i = 0; i < positions.size(); ++i) {
    const auto start = Clock::now();
    const ShellContact contact = target->collide(Pose{positions[i], Quat::Identity()}, tool.shellPoints(), false);
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

void writeResult(const Simulation& simulation, const std::filesystem::path& file) {
  const HapticStats stats = simulation.hapticLog().stats();
  const RateGroup* group = hapticGroup(simulation);
  const TimingSummary step = group ? group->stepHistogram.summary() : TimingSummary{};
  int64_t removed = 0;
  for (size_t i = 0; i < simulation.hapticLog().size(); ++i) removed += simulation.hapticLog()[i].removed;
  std::ostringstream s;
  s << "complete,frames,contact_frames,step_p50_us,step_p99_us,force_step_p99_N,force_step_max_N,"
       "unexplained_step_p99_N,proxy_inside_frames,nan_frames,force_reversals,removed,wall_s\n";
  s << (simulation.complete() ? 1 : 0) << ',' << stats.frames << ',' << stats.contactFrames << ',' << number(step.p50)
    << ',' << number(step.p99) << ',' << number(stats.forceStepP99) << ',' << number(stats.forceStepMax) << ','
    << (stats.hasUnexplainedSteps ? number(stats.unexplainedStepP99) : "nan") << ',' << stats.proxyInsideFrames << ','
    << stats.nanFrames << ',' << stats.forceReversals << ',' << removed << ',' << number(simulation.wallTime()) << '\n';
  AtomicFile out(file);
  out.write(s.str());
  out.commit();
}

}  // namespace

bool runStudySetting(const StudyOptions& options, const StudySetting& setting) {
  const std::filesystem::path directory = options.out / setting.directoryName();
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  for (const char* stale : {kProbeFile, kResultFile, kErrorFile}) std::filesystem::remove(directory / stale, ec);
  const std::filesystem::path posesFile = options.out / kPosesFile;
  const bool isReference = setting.index == options.referenceIndex;
  try {
    // Every setting's probe runs on an instance of its own, loaded fresh and
    // never run, so that the probe neither changes the run it measures (its
    // counters, caches, warm starts) nor sees a drilled or deformed target.
    auto simulation = load(options, setting, directory);
    std::vector<Vec3> positions;
    if (isReference) {
      // The reference's run gives the poses.
      simulation->run();
      const auto [ranTarget, ranComponent] = findTarget(*simulation, options, setting);
      std::vector<StudyPose> poses = posesFromRun(*simulation, options.posesPerKind, ranTarget);
      if (poses.empty())
        throw SettingError("the reference run has no frame in contact with " + ranComponent->path() +
                           ": there are no poses to compare");
      const std::string toolPath = toolTouching(*simulation, ranTarget);
      std::filesystem::remove(options.out / kProbeToolFile, ec);
      if (!toolPath.empty()) {
        AtomicFile tool(options.out / kProbeToolFile);
        tool.write(toolPath + "\n");
        tool.commit();
      }
      auto probed = load(options, setting);
      auto [target, component] = findTarget(*probed, options, setting);
      const std::string noExactShape = addExactContacts(poses, *component, findTool(*probed, toolPath));
      writePoses(posesFile, poses);
      // Why the reference is a setting, for study.md (none: the exact shape).
      std::filesystem::remove(options.out / kNoExactShapeFile, ec);
      if (!noExactShape.empty()) {
        AtomicFile why(options.out / kNoExactShapeFile);
        why.write(noExactShape + "\n");
        why.commit();
      }
      for (const StudyPose& p : poses) positions.push_back(p.position);
      probe(*probed, options, setting, positions, directory / kProbeFile);
    } else {
      auto probed = load(options, setting);
      probe(*probed, options, setting, readPositions(posesFile), directory / kProbeFile);
      probed.reset();
      simulation->run();
    }
    std::vector<std::string> errors;
    simulation->writeOutputs(directory, &errors);
    if (!simulation->complete()) throw SettingError("run incomplete: " + simulation->incompleteReason());
    if (!errors.empty()) throw SettingError(errors.front());
    writeResult(*simulation, directory / kResultFile);
    return true;
  } catch (const std::exception& e) {
    writeSettingError(directory, setting.label() + ": " + e.what());
    return false;
  }
}

void writeSettingError(const std::filesystem::path& directory, const std::string& message) {
  // Other processes wait for this file: it appears whole or not at all.
  try {
    AtomicFile out(directory / kErrorFile);
    out.write(message + "\n");
    out.commit();
  } catch (const std::exception&) {
    std::ofstream(directory / kErrorFile) << message << "\n";
  }
}

}  // namespace trephine::study
