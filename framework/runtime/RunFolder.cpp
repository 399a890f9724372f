#include "framework/runtime/RunFolder.h"

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <optional>
#include <sstream>

#include "framework/core/AtomicFile.h"
#include "framework/core/FolderInput.h"
#include "framework/core/OutputFolder.h"

namespace trephine {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMagic = "trephine-run 1";

// Files earlier versions wrote into a run folder without a marker.
const char* const kUnmarkedRunFiles[] = {"summary.json", "trace.csv", "timings.csv", "force.png", "timings.png"};

const char* stateName(RunState state) {
  switch (state) {
    case RunState::kRunning:
      return "running";
    case RunState::kFinished:
      return "finished";
    case RunState::kIncomplete:
      return "incomplete";
  }
  return "running";
}

// A name the marker may list: one entry of the folder itself.
bool isOutputName(const std::string& name) {
  const std::string plain = name.ends_with('/') ? name.substr(0, name.size() - 1) : name;
  return !plain.empty() && plain != "." && plain != ".." && plain.find('/') == std::string::npos &&
         plain.find('\\') == std::string::npos && plain != kRunMarkerName;
}

// Field 22 of /proc/PID/stat: the start time in clock ticks after boot; 0 when unknown.
uint64_t processStartTime(int64_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  if (!std::getline(in, stat)) return 0;
  const size_t name = stat.rfind(')');  // the command name may hold spaces and ')'
  if (name == std::string::npos) return 0;
  std::istringstream fields(stat.substr(name + 1));
  std::string field;
  for (int k = 3; k <= 22 && fields >> field; ++k)
    if (k == 22) return std::strtoull(field.c_str(), nullptr, 10);
  return 0;
}

// A marker is a few hundred bytes per output; anything far larger is not one.
constexpr size_t kMaxMarkerBytes = 1 << 20;

void writeMarker(const OutputFolder& folder, const RunMarker& marker) {
  writeFileAtomically(folder, kRunMarkerName, [&](std::ostream& out) {
    out << kMagic << "\n";
    out << "state " << stateName(marker.state) << "\n";
    out << "pid " << marker.pid << " " << marker.processStart << "\n";
    if (!marker.reason.empty()) {
      std::string reason = marker.reason;
      std::replace(reason.begin(), reason.end(), '\n', ' ');
      out << "reason " << reason << "\n";
    }
    for (const std::string& output : marker.outputs) out << "output " << output << "\n";
  });
}

// Removes what an earlier run wrote under `name`, through the folder's
// descriptor: a link there is removed itself, never followed.
void removeOutput(const OutputFolder& folder, const std::string& name, std::vector<std::string>& problems) {
  const bool isFolder = name.ends_with('/');
  const std::string plain = isFolder ? name.substr(0, name.size() - 1) : name;
  const EntryKind kind = folder.kind(plain);
  if (kind == EntryKind::kMissing) return;
  if (isFolder != (kind == EntryKind::kFolder) && kind != EntryKind::kLink)
    return;  // not what the run wrote there: a user's, left alone
  try {
    folder.remove(plain);
  } catch (const FileWriteError& e) {
    problems.push_back(std::string("cannot remove what the earlier run wrote: ") + e.what());
  }
}

// Temporary files of outputs whose writer was killed ("trace.csv.partial-PID-..."):
// no live run writes here (the claim checked), so they are no one's.
void removeTemporaryFiles(const OutputFolder& folder, const std::vector<std::string>& outputs,
                          std::vector<std::string>& problems) {
  std::error_code ec;
  std::vector<std::string> stale;
  for (const auto& entry : fs::directory_iterator(folder.path(), ec)) {
    const std::string name = entry.path().filename().string();
    for (const std::string& output : outputs)
      if (!output.ends_with('/') && name.starts_with(output + ".partial-")) stale.push_back(name);
  }
  for (const std::string& name : stale) {
    if (folder.kind(name) == EntryKind::kFolder) continue;
    try {
      folder.remove(name);
    } catch (const FileWriteError& e) {
      problems.push_back(e.what());
    }
  }
}

}  // namespace

std::optional<RunMarker> readRunMarker(const fs::path& folder) {
  const fs::path file = folder / kRunMarkerName;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(file, ec))) return std::nullopt;
  std::istringstream in;
  try {
    in.str(readRegularFile(file, kMaxMarkerBytes));
  } catch (const FolderInputError& e) {
    throw RunFolderError(std::string(e.what()) + " (a run marker is a small text file)");
  }
  RunMarker marker;
  std::string line;
  int number = 0;
  bool sawState = false;
  const auto fail = [&](const std::string& problem) {
    throw RunFolderError(file.string() + ":" + std::to_string(number) + ": " + problem);
  };
  while (std::getline(in, line)) {
    ++number;
    if (number == 1) {
      if (line != kMagic) fail("not a run marker (expected '" + std::string(kMagic) + "')");
      continue;
    }
    const size_t space = line.find(' ');
    const std::string key = line.substr(0, space), value = space == std::string::npos ? "" : line.substr(space + 1);
    if (key == "state") {
      if (value == "running")
        marker.state = RunState::kRunning;
      else if (value == "finished")
        marker.state = RunState::kFinished;
      else if (value == "incomplete")
        marker.state = RunState::kIncomplete;
      else
        fail("unknown state '" + value + "' (expected running, finished or incomplete)");
      sawState = true;
    } else if (key == "pid") {
      std::istringstream fields(value);
      if (!(fields >> marker.pid >> marker.processStart) || marker.pid <= 0) fail("expected 'pid PID START'");
    } else if (key == "reason") {
      marker.reason = value;
    } else if (key == "output") {
      if (!isOutputName(value)) fail("'" + value + "' is not a name in the run's folder");
      marker.outputs.push_back(value);
    } else {
      fail("unknown line '" + line + "'");
    }
  }
  if (number == 0) throw RunFolderError(file.string() + ": empty (expected a run marker)");
  if (!sawState) throw RunFolderError(file.string() + ": no state line");
  return marker;
}

bool runIsAlive(const RunMarker& marker) {
  if (marker.pid <= 0) return false;
  const uint64_t start = processStartTime(marker.pid);
  return start != 0 && start == marker.processStart;
}

RunFolderStatus runFolderStatus(const std::optional<RunMarker>& marker) {
  if (!marker) return RunFolderStatus::kNotARun;
  switch (marker->state) {
    case RunState::kRunning:
      return runIsAlive(*marker) ? RunFolderStatus::kWriting : RunFolderStatus::kKilled;
    case RunState::kFinished:
      return RunFolderStatus::kFinished;
    case RunState::kIncomplete:
      return RunFolderStatus::kIncomplete;
  }
  return RunFolderStatus::kNotARun;
}

std::optional<std::string> claimRunFolder(const fs::path& folder, const std::vector<std::string>& outputs) {
  for (const std::string& output : outputs)
    if (!isOutputName(output)) return "'" + output + "' is not a name in the run's folder";
  std::optional<OutputFolder> opened;
  try {
    opened = OutputFolder::create(folder);
  } catch (const FileWriteError& e) {
    return std::string("cannot create a directory there (") + e.what() + ")";
  }
  std::error_code ec;

  // What the earlier run wrote goes; what a user put there stays.
  std::optional<RunMarker> earlier;
  try {
    earlier = readRunMarker(folder);
  } catch (const RunFolderError& e) {
    return std::string(e.what()) + "; remove it if the folder holds no run";
  }
  std::vector<std::string> remove;
  if (earlier) {
    if (earlier->state == RunState::kRunning && runIsAlive(*earlier))
      return "another run (process " + std::to_string(earlier->pid) + ") is writing there";
    remove = earlier->outputs;
  } else {
    remove.assign(std::begin(kUnmarkedRunFiles), std::end(kUnmarkedRunFiles));
    for (const auto& entry : fs::directory_iterator(folder, ec)) {
      const std::string name = entry.path().filename().string();
      if ((name.starts_with("device.") || name.starts_with("recording.")) && name.ends_with(".csv"))
        remove.push_back(name);
    }
  }
  remove.insert(remove.end(), outputs.begin(), outputs.end());  // replaced anyway
  std::vector<std::string> problems;
  for (const std::string& name : remove) removeOutput(*opened, name, problems);
  removeTemporaryFiles(*opened, remove, problems);
  if (!problems.empty()) return problems.front();

  RunMarker marker;
  marker.pid = ::getpid();
  marker.processStart = processStartTime(marker.pid);
  marker.outputs = outputs;
  try {
    writeMarker(*opened, marker);
  } catch (const FileWriteError& e) {
    return std::string("cannot write there (") + e.what() + ")";
  }
  return std::nullopt;
}

void markRunFolder(const fs::path& folder, const std::vector<std::string>& outputs, RunState state,
                   const std::string& reason) {
  RunMarker marker;
  marker.state = state;
  marker.pid = ::getpid();
  marker.processStart = processStartTime(marker.pid);
  marker.reason = reason;
  marker.outputs = outputs;
  writeMarker(OutputFolder::open(folder), marker);
}

}  // namespace trephine
