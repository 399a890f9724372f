#pragma once
// A run owns its output folder. While it writes there, the folder holds a
// marker (.trephine-run) naming the process and every file and folder the
// run writes; once its outputs are written the run marks it finished, or
// incomplete with the reason (an interrupt, a run-time error, an output that
// could not be written). So a new run into the same folder removes exactly
// what the earlier run wrote (nothing of a user's own, and no frames of two
// runs side by side), and a folder whose run was killed (kill -9, a crash, a
// power cut) says so: its marker still says running, for a process that no
// longer exists.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace trephine {

inline constexpr const char* kRunMarkerName = ".trephine-run";

enum class RunState { kRunning, kFinished, kIncomplete };

struct RunMarker {
  RunState state = RunState::kRunning;
  int64_t pid = 0;
  // When the process started (clock ticks after boot, /proc/PID/stat), so
  // that another process given the same pid is not taken for the run.
  uint64_t processStart = 0;
  std::string reason;                // why incomplete
  std::vector<std::string> outputs;  // names in the folder; a folder's ends in '/'
};

// A marker that cannot be read or says something else than a marker says:
// the message names the file and the line.
class RunFolderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The marker in `folder`, or nothing when there is none. Throws RunFolderError.
std::optional<RunMarker> readRunMarker(const std::filesystem::path& folder);

// Whether the run that wrote `marker` is still running on this machine.
bool runIsAlive(const RunMarker& marker);

// What a folder holds, for the programs that read runs.
enum class RunFolderStatus {
  kNotARun,     // no marker (a folder of files, or written before markers)
  kWriting,     // a live run is writing it
  kKilled,      // the run that wrote it stopped without marking it: partial outputs
  kFinished,    // every output written
  kIncomplete,  // stopped early or an output failed, outputs consistent (marker.reason says why)
};
RunFolderStatus runFolderStatus(const std::optional<RunMarker>& marker);

// Claims `folder` for a run that will write `outputs` (plain names; folders
// end in '/'): creates it, refuses it while another live run writes there,
// removes what the earlier run's marker lists (without a marker: the names
// in `outputs` and the run files of earlier versions), and writes the marker
// saying running. Returns the problem, or nothing when the folder is the
// run's. Files the earlier run did not write are left alone.
std::optional<std::string> claimRunFolder(const std::filesystem::path& folder, const std::vector<std::string>& outputs);

// Rewrites the marker once the outputs are written. Throws FileWriteError.
void markRunFolder(const std::filesystem::path& folder, const std::vector<std::string>& outputs, RunState state,
                   const std::string& reason);

}  // namespace trephine
