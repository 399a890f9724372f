#include "tools/trephine/study/ReferenceChoice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "framework/core/AtomicFile.h"
#include "framework/geometry/ExactShape.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/devices/HapticDevice.h"
#include "framework/geometry/ShellTool.h"
#include "framework/runtime/Simulation.h"

namespace trephine::study {

namespace {

// mm, the median distance from a shell point to its nearest neighbour.
double shellSpacing(std::span<const ShellPoint> shell) {
  if (shell.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> nearest;
  nearest.reserve(shell.size());
  for (size_t i = 0; i < shell.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < shell.size(); ++j)
      if (j != i) best = std::min(best, (shell[i].position - shell[j].position).squaredNorm());
    nearest.push_back(std::sqrt(best));
  }
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  return nearest[nearest.size() / 2];
}

std::string millimetres(double value) {
  std::ostringstream s;
  s.precision(3);
  s << value << " mm";
  return s.str();
}

constexpr double kSame = 1e-6;  // relative: sizes this close are one size

// Whether setting `a` resolves everything at least as finely as every other.
bool finest(size_t a, const std::vector<SettingResolution>& resolutions) {
  for (const auto& [name, size] : resolutions[a].sizes)
    for (const SettingResolution& other : resolutions)
      for (const auto& [otherName, otherSize] : other.sizes)
        if (otherName == name && otherSize < size * (1 - kSame)) return false;
  return true;
}

// Where `coarse` resolves something more coarsely than `fine`: "voxels of X 1 mm against 0.5 mm".
std::string coarserIn(const SettingResolution& coarse, const SettingResolution& fine) {
  std::string text;
  for (const auto& [name, size] : coarse.sizes)
    for (const auto& [fineName, fineSize] : fine.sizes)
      if (fineName == name && fineSize < size * (1 - kSame))
        text += (text.empty() ? "" : ", ") + name + " " + millimetres(size) + " against " + millimetres(fineSize);
  return text;
}

std::string sizesOf(const SettingResolution& r) {
  std::string text;
  for (const auto& [name, size] : r.sizes) text += (text.empty() ? "" : ", ") + name + " " + millimetres(size);
  return text;
}

std::string named(const std::vector<StudySetting>& settings, size_t i) {
  return "setting " + std::to_string(i + 1) + " (" + settings[i].label() + ")";
}

}  // namespace

SettingResolution describeSetting(const StudyOptions& options, const StudySetting& setting) {
  SettingResolution r;
  SimulationOptions simulationOptions = options.simulation;
  for (const std::string& o : setting.overrides()) simulationOptions.overrides.push_back(o);
  Diagnostics diagnostics;
  const auto simulation = Simulation::fromFile(options.scene, simulationOptions, diagnostics);
  if (!simulation) {
    r.loadError = diagnostics.str();
    return r;
  }
  r.loaded = true;
  r.exactEverywhere = true;
  for (Component* c : simulation->scene().components()) {
    if (const auto* target = dynamic_cast<const ShellContactTarget*>(c)) {
      if (!options.target.empty() && c->path() != options.target) continue;
      const double size = target->resolution();
      if (std::isfinite(size)) r.sizes.emplace_back("the target " + c->path(), size);
      const auto* source = dynamic_cast<const ExactShapeSource*>(c);
      r.exactEverywhere = r.exactEverywhere && source && source->exactShape();
    }
    if (const auto* tool = dynamic_cast<const ShellTool*>(c)) {
      const double size = shellSpacing(tool->shellPoints());
      if (std::isfinite(size)) r.sizes.emplace_back("the shell of " + c->path(), size);
      r.exactEverywhere = r.exactEverywhere && tool->boundingRadius() == tool->leadingRadius();
    }
  }
  return r;
}

void writeSettingResolution(const SettingResolution& resolution, const std::filesystem::path& file) {
  std::ostringstream text;
  text.precision(17);
  text << "loaded\t" << (resolution.loaded ? 1 : 0) << "\nexact\t" << (resolution.exactEverywhere ? 1 : 0) << "\n";
  for (const auto& [name, size] : resolution.sizes) text << "size\t" << name << "\t" << size << "\n";
  std::string error = resolution.loadError;
  for (char& c : error)
    if (c == '\n') c = '\x1f';  // one line; read back as newlines
  if (!error.empty()) text << "error\t" << error << "\n";
  AtomicFile out(file);
  out.write(text.str());
  out.commit();
}

SettingResolution readSettingResolution(const std::filesystem::path& file) {
  SettingResolution r;
  std::ifstream in(file);
  if (!in) {
    r.loadError = "the setting's description was not written (" + file.string() + "): its process ended first\n";
    return r;
  }
  for (std::string line; std::getline(in, line);) {
    const size_t tab = line.find('\t');
    const std::string key = line.substr(0, tab), rest = tab == std::string::npos ? "" : line.substr(tab + 1);
    if (key == "loaded") r.loaded = rest == "1";
    if (key == "exact") r.exactEverywhere = rest == "1";
    if (key == "error") {
      r.loadError = rest;
      for (char& c : r.loadError)
        if (c == '\x1f') c = '\n';
    }
    if (key == "size") {
      const size_t last = rest.rfind('\t');
      if (last == std::string::npos) continue;
      char* end = nullptr;
      const std::string number = rest.substr(last + 1);
      const double size = std::strtod(number.c_str(), &end);
      if (end != number.c_str() && *end == '\0' && std::isfinite(size)) r.sizes.emplace_back(rest.substr(0, last), size);
    }
  }
  return r;
}

ReferenceChoice chooseReference(const std::vector<StudySetting>& settings,
                                const std::vector<SettingResolution>& resolutions, std::optional<int> asked,
                                bool allowCoarser) {
  ReferenceChoice choice;
  std::vector<size_t> finestSettings;
  bool allAlike = true;
  for (size_t i = 0; i < settings.size(); ++i) {
    if (!resolutions[i].loaded) continue;
    if (finest(i, resolutions)) finestSettings.push_back(i);
    for (size_t j = 0; j < settings.size(); ++j)
      if (resolutions[j].loaded && !coarserIn(resolutions[i], resolutions[j]).empty()) allAlike = false;
  }
  // Against an exact shape the reference's run only gives the poses: setting
  // 1's, unless another is asked for (the others need not be described).
  const bool exact = resolutions.front().loaded && resolutions.front().exactEverywhere;
  const size_t first = asked ? size_t(*asked) : exact || finestSettings.empty() ? 0 : finestSettings.front();
  choice.index = int(first);
  const SettingResolution& chosen = resolutions[first];
  if (chosen.loaded && chosen.exactEverywhere) {
    // Its run gives the poses; the exact shape is what every setting is measured against.
    choice.reason = "";
    return choice;
  }
  if (allAlike) {
    choice.reason = "every setting resolving its targets and tools alike";
    return choice;
  }
  if (std::find(finestSettings.begin(), finestSettings.end(), first) != finestSettings.end()) {
    choice.reason = "the finest (" + sizesOf(chosen) + ")";
    return choice;
  }
  if (finestSettings.empty()) {
    if (asked && allowCoarser) {
      choice.reason = "chosen with --coarse-reference: no setting is the finest in everything";
      return choice;
    }
    choice.error = "no setting resolves every target and tool finest (each is coarser than another somewhere), so "
                   "none is a reference for the others' accuracy; choose one with --reference K and "
                   "--coarse-reference";
    return choice;
  }
  const size_t better = finestSettings.front();
  if (asked && allowCoarser) {
    choice.reason = "coarser than " + named(settings, better) + " (" + coarserIn(chosen, resolutions[better]) +
                    "), chosen with --coarse-reference";
    return choice;
  }
  choice.error = "the reference " + named(settings, first) + " is coarser than " + named(settings, better) + ": " +
                 coarserIn(chosen, resolutions[better]) +
                 "; against it the finer settings would be measured by its own error. Use --reference " +
                 std::to_string(better + 1) + ", or --coarse-reference to compare against setting " +
                 std::to_string(first + 1) + " anyway";
  return choice;
}

}  // namespace trephine::study
