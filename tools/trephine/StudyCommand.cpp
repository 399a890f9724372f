#include "tools/trephine/StudyCommand.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <thread>

#include "framework/core/OutputFolder.h"
#include "framework/core/Strings.h"
#include "tools/trephine/PlotScript.h"
#include "tools/trephine/RunCommand.h"
#include "tools/trephine/study/ReferenceChoice.h"
#include "tools/trephine/study/StudyReport.h"
#include "tools/trephine/study/StudySetting.h"

extern char** environ;

namespace trephine::cli {

using namespace trephine::study;

namespace {

constexpr const char* kUsageLine =
    "usage: trephine study SCENE --vary path.field=v1,v2[,...] [--vary ...] [--out DIR] [--jobs N] [--duration S]\n"
    "                     [--seed N] [--set path.field=value ...] [--target PATH] [--reference K]\n"
    "                     [--coarse-reference] [--poses N] [--repeat N]\n";

// This process's place among the ranks of an MPI launch (mpirun sets these
// variables; Open MPI, then MPICH and Intel MPI): rank 0 of 1 otherwise.
struct Rank {
  int rank = 0;
  int size = 1;
};

Rank mpiRank() {
  for (const auto& [rankVariable, sizeVariable] :
       {std::pair{"OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE"}, std::pair{"PMI_RANK", "PMI_SIZE"}}) {
    const char* rank = std::getenv(rankVariable);
    const char* size = std::getenv(sizeVariable);
    if (rank && size) {
      const Rank r{std::atoi(rank), std::atoi(size)};
      if (r.size >= 1 && r.rank >= 0 && r.rank < r.size) return r;
    }
  }
  return {};
}

std::optional<int> positiveInteger(const Arguments& a, const std::string& option, std::string& error) {
  const auto text = a.get(option);
  if (!text) return std::nullopt;
  int value = 0;
  const auto result = std::from_chars(text->data(), text->data() + text->size(), value);
  if (text->empty() || result.ec != std::errc() || result.ptr != text->data() + text->size() || value < 1) {
    error = option + " expects a positive integer, got '" + *text + "'";
    return 0;
  }
  return value;
}

// Settings a study runs at most (each is a run of its own and a folder).
constexpr size_t kMostSettings = 10000;
// Most runs of one setting (--repeat).
constexpr int kMostRepeats = 20;

// Which study this process is part of. Under mpirun every rank of one launch
// has the same (Open MPI's job: the launcher's address and its job id, new
// for every mpirun), given to its workers with --study-id; alone, a new
// random one. With another MPI, TREPHINE_STUDY_ID (the same on every rank:
// mpirun -x, or -genv) names it.
std::optional<std::string> launchStudyId(int ranks, std::string& error) {
  std::string launch;
  // Hashed like the launch's names: any text names a study, and the id that
  // goes into the files is hex (no comma or line break to break a table).
  if (const char* given = std::getenv("TREPHINE_STUDY_ID"); given && *given) launch = std::string("given=") + given;
  if (launch.empty())
    for (const char* name : {"OMPI_MCA_orte_hnp_uri", "PMIX_NAMESPACE", "OMPI_MCA_ess_base_jobid"})
      if (const char* value = std::getenv(name)) launch += std::string(name) + "=" + value + ";";
  if (launch.empty() && ranks > 1) {
    error =
        "under this MPI the ranks cannot tell one study from another: give them the same TREPHINE_STUDY_ID "
        "(mpirun -genv TREPHINE_STUDY_ID=$(date +%s%N) ...)";
    return std::nullopt;
  }
  uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a of the launch's names
  if (launch.empty()) {
    std::random_device random;
    launch = std::to_string(random()) + "-" + std::to_string(random()) + "-" + std::to_string(getpid());
  }
  for (const unsigned char c : launch) hash = (hash ^ c) * 0x100000001b3ull;
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return std::string(text);
}

struct StudyRequest {
  StudyOptions options;
  std::vector<StudySetting> settings;
  std::vector<std::string> variationTexts;
  int jobs = 1;
  int repeat = 3;                   // --repeat: runs of each setting, for its timing
  std::optional<int> onlySetting;   // --setting K: run that one here (the study's worker processes)
  std::optional<int> timingRun;     // --timing-run R (with --setting): that setting's R-th run, timed only
  std::optional<int> describeOnly;  // --describe K: load that one and write what it resolves into --describe-to
  std::string describeTo;
  std::optional<int> askedReference;  // --reference K, 0-based
  bool coarseReference = false;       // --coarse-reference: a reference coarser than another setting is meant
};

std::optional<StudyRequest> readRequest(const Arguments& a, std::string& error) {
  StudyRequest request;
  if (a.positional.size() != 1) {
    error = "a study needs one scene";
    return std::nullopt;
  }
  request.options.scene = a.positional[0];
  if (a.variations.empty()) {
    error = "a study needs at least one --vary path.field=v1,v2,...";
    return std::nullopt;
  }
  std::vector<StudyVariation> variations;
  for (const std::string& text : a.variations) {
    auto variation = parseVariation(text, error);
    if (!variation) return std::nullopt;
    for (const StudyVariation& v : variations)
      if (v.field == variation->field) {
        error = "--vary " + v.field + " given twice";
        return std::nullopt;
      }
    variations.push_back(*variation);
  }
  // Bounded before any is made: a product of a billion settings is a usage
  // error, not a study that runs out of memory.
  double product = 1;
  for (const StudyVariation& v : variations) product *= double(v.values.size());
  if (product > double(kMostSettings)) {
    error = "the --vary values make " +
            (product < 1e15 ? std::to_string(static_cast<long long>(product)) : std::string("more than 10^15")) +
            " settings, more than the " + std::to_string(kMostSettings) +
            " a study runs: vary fewer fields or fewer values";
    return std::nullopt;
  }
  request.variationTexts = a.variations;
  request.settings = expandSettings(variations);
  request.options.out = a.get("--out").value_or("runs/study-" + request.options.scene.stem().string());
  request.options.target = a.get("--target").value_or("");
  auto simulation = readSimulationOptions(a, error);
  if (!simulation) return std::nullopt;
  request.options.simulation = *simulation;
  const int count = static_cast<int>(request.settings.size());
  if (auto jobs = positiveInteger(a, "--jobs", error)) request.jobs = *jobs;
  if (auto reference = positiveInteger(a, "--reference", error)) {
    request.options.referenceIndex = *reference - 1;
    request.askedReference = *reference - 1;
  }
  request.coarseReference = a.has("--coarse-reference");
  if (request.coarseReference && !request.askedReference)
    error = "--coarse-reference goes with --reference K (the coarser setting meant as the reference)";
  if (auto poses = positiveInteger(a, "--poses", error)) request.options.posesPerKind = *poses;
  if (auto only = positiveInteger(a, "--setting", error)) request.onlySetting = *only - 1;
  if (auto repeat = positiveInteger(a, "--repeat", error)) request.repeat = *repeat;
  if (auto run = positiveInteger(a, "--timing-run", error)) request.timingRun = *run;
  if (request.repeat > kMostRepeats)
    error =
        "--repeat " + std::to_string(request.repeat) + ": at most " + std::to_string(kMostRepeats) + " runs a setting";
  if (request.timingRun && !request.onlySetting) error = "--timing-run goes with --setting K";
  if (auto describe = positiveInteger(a, "--describe", error)) request.describeOnly = *describe - 1;
  request.describeTo = a.get("--describe-to").value_or("");
  if (auto id = a.get("--study-id")) {
    // A worker: its rank's study, as launchStudyId made it (16 hex digits).
    if (id->size() != 16 || id->find_first_not_of("0123456789abcdef") != std::string::npos) {
      error = "--study-id expects the 16 hex digits a study gives its workers, got '" + *id + "'";
      return std::nullopt;
    }
    request.options.studyId = *id;
  } else if (auto launched = launchStudyId(mpiRank().size, error)) {
    request.options.studyId = *launched;
  }
  if (request.describeOnly && request.describeTo.empty()) error = "--describe needs --describe-to FILE";
  if (!error.empty()) return std::nullopt;
  if (request.options.referenceIndex >= count || (request.onlySetting && *request.onlySetting >= count) ||
      (request.describeOnly && *request.describeOnly >= count)) {
    error = "--reference and --setting take a setting number from 1 to " + std::to_string(count);
    return std::nullopt;
  }
  return request;
}

// The command line of the worker process that runs setting `index` (its
// first run, measured in full; or with `timingRun` >= 2, a run timed only).
std::vector<std::string> workerArguments(const StudyRequest& request, int index, int timingRun = 1) {
  std::vector<std::string> args = {"/proc/self/exe", "study", request.options.scene.string()};
  for (const std::string& v : request.variationTexts) args.insert(args.end(), {"--vary", v});
  for (const std::string& o : request.options.simulation.overrides) args.insert(args.end(), {"--set", o});
  if (request.options.simulation.duration) {
    std::ostringstream d;
    d.precision(17);
    d << *request.options.simulation.duration;
    args.insert(args.end(), {"--duration", d.str()});
  }
  args.insert(args.end(), {"--seed", std::to_string(request.options.simulation.seed)});
  if (!request.options.target.empty()) args.insert(args.end(), {"--target", request.options.target});
  args.insert(args.end(), {"--reference", std::to_string(request.options.referenceIndex + 1), "--poses",
                           std::to_string(request.options.posesPerKind), "--out", request.options.out.string(),
                           "--setting", std::to_string(index + 1), "--study-id", request.options.studyId});
  if (timingRun > 1) args.insert(args.end(), {"--timing-run", std::to_string(timingRun)});
  return args;
}

// The command line of the process that describes setting `index` into `file`.
std::vector<std::string> describerArguments(const StudyRequest& request, int index, const std::filesystem::path& file) {
  std::vector<std::string> args = {"/proc/self/exe", "study", request.options.scene.string()};
  for (const std::string& v : request.variationTexts) args.insert(args.end(), {"--vary", v});
  for (const std::string& o : request.options.simulation.overrides) args.insert(args.end(), {"--set", o});
  if (!request.options.target.empty()) args.insert(args.end(), {"--target", request.options.target});
  args.insert(args.end(), {"--describe", std::to_string(index + 1), "--describe-to", file.string()});
  return args;
}

// What each of `indices` resolves, each setting loaded in a process of its
// own, at most `jobs` at a time (a setting whose load crashes ends only its
// process, and its description says so). The files go to `folder`.
void describeSettings(const StudyRequest& request, const std::vector<int>& indices, int jobs,
                      const std::filesystem::path& folder, std::vector<SettingResolution>& resolutions) {
  // A folder of this process's own, made new: a link planted at its name is
  // removed (the link, not what it points at), never written through.
  std::error_code ec;
  const OutputFolder out = OutputFolder::open(folder.parent_path());
  out.remove(folder.filename().string());
  out.subfolder(folder.filename());
  const auto fileOf = [&](int index) { return folder / (std::to_string(index + 1) + ".txt"); };
  std::map<pid_t, int> running;
  size_t next = 0;
  while (next < indices.size() || !running.empty()) {
    while (next < indices.size() && static_cast<int>(running.size()) < jobs) {
      const int index = indices[next++];
      std::filesystem::remove(fileOf(index), ec);
      const pid_t pid = spawn(describerArguments(request, index, fileOf(index)), false);
      if (pid >= 0) running[pid] = index;
    }
    if (running.empty()) continue;
    int status = 0;
    const pid_t ended = waitpid(-1, &status, 0);
    if (ended < 0 && errno == EINTR) continue;
    if (ended < 0) break;
    running.erase(ended);
  }
  for (const int index : indices) resolutions[size_t(index)] = readSettingResolution(fileOf(index));
  out.remove(folder.filename().string());
}

// A worker that ended without saying why (killed, crashed, not started)
// leaves error.txt, so that nobody waits for its setting.
void recordAbnormalEnd(const StudyRequest& request, int index, const std::string& why) {
  std::filesystem::path directory;
  try {
    directory = settingFolder(request.options.out, request.settings[index]);
  } catch (const FileWriteError& e) {
    std::cerr << "trephine: " << e.what() << "\n";
    return;
  }
  if (studyOfFile(directory / kResultFile) == request.options.studyId ||
      studyOfFile(directory / kErrorFile) == request.options.studyId)
    return;  // the worker's own
  writeSettingError(directory, request.options.studyId, request.settings[index].label() + ": " + why);
}

// A timing run whose worker ended without its file: a file that says so, so
// that the gathering rank does not wait for it.
void recordFailedTimingRun(const StudyRequest& request, int index, int run, const std::string& why) {
  const std::filesystem::path directory = request.options.out / request.settings[index].directoryName();
  if (studyOfFile(timingFile(directory, run)) == request.options.studyId) return;  // the worker's own
  writeTimingFailure(directory, run, request.options.studyId, why);
}

std::string describeStatus(int status) {
  if (WIFSIGNALED(status)) return "the worker process was ended by signal " + std::to_string(WTERMSIG(status));
  return "the worker process exited with status " + std::to_string(WEXITSTATUS(status)) + " and wrote no result";
}

// Removes what an earlier study left for a setting, so that a worker that
// dies before its first step is not mistaken for one that finished.
void clearSetting(const StudyRequest& request, int index) {
  const std::filesystem::path directory = request.options.out / request.settings[index].directoryName();
  std::error_code ec;
  for (const char* stale : {kProbeFile, kResultFile, kErrorFile}) std::filesystem::remove(directory / stale, ec);
  for (int run = 2; run <= kMostRepeats; ++run) std::filesystem::remove(timingFile(directory, run), ec);
}

// This rank's settings done so far, for "setting 3/8 done in 12.4 s; 3 of 8
// done, 37 s so far, about 62 s left", or "setting 3/8 failed after 0.1 s:
// WHY; ...", and its timing runs ("timing run 2 of setting 3/8 done in 9.1
// s; about 40 s left"). The time left is what the runs that succeeded cost
// each, on average, times the settings and timing runs left, shared among
// the workers: a failed setting (which ends at once) says nothing of what the
// others will cost, and none is guessed before a setting has succeeded.
struct StudyProgress {
  size_t all = 0;  // settings this rank runs
  size_t done = 0;
  size_t timingRunsLeft = 0;  // the later rounds' runs still to come (each setting that succeeded, repeat - 1 times)
  int repeat = 1;
  int jobs = 1;
  double succeededSeconds = 0;  // s, the sum of the succeeded runs' own times
  size_t succeeded = 0;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

  // " about 62 s left" for the runs left, or what is unknown.
  std::string timeLeft() const {
    const size_t left = all - done + timingRunsLeft;
    std::ostringstream line;
    if (left > 0 && succeeded > 0) {
      const double workers = double(std::min<size_t>(left, size_t(std::max(jobs, 1))));
      line << ", about " << std::ceil(succeededSeconds / double(succeeded) * double(left) / workers) << " s left";
    } else if (left > 0) {
      line << ", time left unknown until a setting succeeds";
    }
    return line.str();
  }

  std::string timingRunEnded(int index, size_t total, int run, double took, bool ok) {
    if (timingRunsLeft > 0) --timingRunsLeft;
    if (ok) {
      ++succeeded;
      succeededSeconds += took;
    }
    std::ostringstream line;
    line.setf(std::ios::fixed);
    line.precision(1);
    line << "timing run " << run << " of setting " << index + 1 << "/" << total << (ok ? " done in " : " failed after ")
         << took << " s" << (timeLeft().empty() ? "" : ";") << timeLeft();
    return line.str();
  }

  // `error`: the setting's error, empty when it succeeded.
  std::string settingEnded(int index, size_t total, double took, const std::string& error) {
    ++done;
    if (error.empty()) {
      ++succeeded;
      succeededSeconds += took;
      timingRunsLeft += size_t(std::max(repeat - 1, 0));
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::ostringstream line;
    line.setf(std::ios::fixed);
    line.precision(1);
    line << "setting " << index + 1 << "/" << total;
    if (error.empty()) {
      line << " done in " << took << " s";
    } else {
      std::string firstLine = error.substr(0, error.find('\n'));
      line << " failed after " << took << " s: " << firstLine;
    }
    line << "; " << done << " of " << all << " done, " << elapsed << " s so far" << timeLeft();
    return line.str();
  }
};

// The error a setting's worker left (its error.txt, when it is this study's), or "".
std::string settingError(const StudyRequest& request, int index) {
  const std::filesystem::path file = request.options.out / request.settings[index].directoryName() / kErrorFile;
  if (studyOfFile(file) != request.options.studyId) return "";
  return settingErrorMessage(file);
}

// Runs the settings in worker processes, at most `jobs` at a time, saying
// when each starts and ends, and the time the study has left.
void runWorkers(const StudyRequest& request, const std::vector<int>& indices, int jobs, StudyProgress& progress,
                int timingRun = 1) {
  using Steady = std::chrono::steady_clock;
  struct Running {
    int index;
    Steady::time_point started;
  };
  std::map<pid_t, Running> running;
  size_t next = 0;
  while (next < indices.size() || !running.empty()) {
    while (next < indices.size() && static_cast<int>(running.size()) < jobs) {
      const int index = indices[next++];
      if (timingRun == 1) {
        std::cout << "setting " << index + 1 << "/" << request.settings.size() << ": "
                  << request.settings[index].label() << std::endl;
        clearSetting(request, index);
      }
      int spawnError = 0;
      const pid_t pid = spawn(workerArguments(request, index, timingRun), false, &spawnError);
      if (pid < 0 && timingRun > 1) {
        recordFailedTimingRun(request, index, timingRun,
                              std::string("the worker process could not start: ") + std::strerror(spawnError));
        continue;
      }
      if (pid < 0) {
        recordAbnormalEnd(request, index,
                          std::string("the worker process could not start: ") + std::strerror(spawnError));
        std::cout << progress.settingEnded(index, request.settings.size(), 0, settingError(request, index))
                  << std::endl;
        continue;
      }
      running[pid] = {index, Steady::now()};
    }
    if (running.empty()) continue;
    int status = 0;
    const pid_t ended = waitpid(-1, &status, 0);
    if (ended < 0) {
      if (errno == EINTR) continue;
      for (const auto& [pid, worker] : running)
        if (timingRun > 1)
          recordFailedTimingRun(request, worker.index, timingRun, "its worker process was lost");
        else
          recordAbnormalEnd(request, worker.index, "its worker process was lost");
      running.clear();
      continue;
    }
    if (auto it = running.find(ended); it != running.end() && timingRun > 1) {
      const bool ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
      recordFailedTimingRun(request, it->second.index, timingRun, describeStatus(status));
      const double took = std::chrono::duration<double>(Steady::now() - it->second.started).count();
      std::cout << progress.timingRunEnded(it->second.index, request.settings.size(), timingRun, took, ok)
                << std::endl;
      running.erase(it);
      continue;
    }
    if (auto it = running.find(ended); it != running.end()) {
      recordAbnormalEnd(request, it->second.index, describeStatus(status));
      const double took = std::chrono::duration<double>(Steady::now() - it->second.started).count();
      std::cout << progress.settingEnded(it->second.index, request.settings.size(), took,
                                         settingError(request, it->second.index))
                << std::endl;
      running.erase(it);
    }
  }
}

// Under MPI, other ranks write into the shared directory: a file counts only
// when it says it is this study's, so that files an earlier study left in
// the same directory (however recently) are never taken.
bool ofThisStudy(const StudyRequest& request, const std::filesystem::path& file) {
  return studyOfFile(file) == request.options.studyId;
}

bool settingDone(const StudyRequest& request, int index) {
  const std::filesystem::path directory = request.options.out / request.settings[index].directoryName();
  return ofThisStudy(request, directory / kResultFile) || ofThisStudy(request, directory / kErrorFile);
}

// Its first run done and, when that succeeded, every timing run too.
bool settingTimed(const StudyRequest& request, int index) {
  const std::filesystem::path directory = request.options.out / request.settings[index].directoryName();
  if (ofThisStudy(request, directory / kErrorFile)) return true;
  if (!ofThisStudy(request, directory / kResultFile)) return false;
  for (int run = 2; run <= request.repeat; ++run)
    if (!ofThisStudy(request, timingFile(directory, run))) return false;
  return true;
}

void waitFor(const std::function<bool()>& ready) {
  while (!ready()) std::this_thread::sleep_for(std::chrono::milliseconds(200));
}

// pareto.png from study.csv by tools/plot_study.py (matplotlib), and
// pairs.png when several tools or targets touched; a study without them
// still has its csv and tables.
void drawPareto(const std::filesystem::path& out) {
  if (!runPlotScript("plot_study.py", {(out / "study.csv").string()}, "pareto.png")) return;
  std::cout << "pareto    " << (out / "pareto.png").string() << "\n";
  std::error_code ec;
  if (std::filesystem::is_regular_file(out / "pairs.png", ec))
    std::cout << "pairs     " << (out / "pairs.png").string() << "\n";
}

}  // namespace

int studyCommand(const Arguments& a) {
  // A reader of its progress that goes away must not end the study (the
  // settings' files are what counts).
  std::signal(SIGPIPE, SIG_IGN);
  std::string error;
  auto request = readRequest(a, error);
  if (!request) {
    std::cerr << "trephine: " << error << "\n" << kUsageLine;
    return kUsage;
  }
  if (request->onlySetting && request->timingRun && *request->timingRun > 1)
    return runTimingRun(request->options, request->settings[*request->onlySetting], *request->timingRun)
               ? kOk
               : kRuntimeFailure;
  if (request->onlySetting)
    return runStudySetting(request->options, request->settings[*request->onlySetting]) ? kOk : kRuntimeFailure;
  if (request->describeOnly) {
    writeSettingResolution(describeSetting(request->options, request->settings[*request->describeOnly]),
                           request->describeTo);
    return kOk;
  }
  // The first setting is loaded before anything is run (a typo in a field
  // shows here). Unless the reference has an exact shape for every target and
  // tool, every setting is: what each resolves decides the reference. Each
  // is loaded in a process of its own (under MPI, every rank describes them
  // alike, into a folder of its own).
  std::error_code ec;
  std::filesystem::create_directories(request->options.out, ec);
  if (!std::filesystem::is_directory(request->options.out)) {
    std::cerr << "trephine: --out " << request->options.out.string() << ": cannot create a directory there\n";
    return kSceneError;
  }
  // Every setting's folder is the study's own before anything runs: a link
  // planted among them (settings/002 to elsewhere) stops the study here.
  for (const StudySetting& setting : request->settings)
    if (const std::string problem = settingFolderProblem(request->options.out, setting); !problem.empty()) {
      std::cerr << "trephine: --out " << request->options.out.string() << ": " << problem << "\n";
      return kSceneError;
    }
  std::vector<SettingResolution> resolutions(request->settings.size());
  const std::filesystem::path describing = request->options.out / (".describe-" + std::to_string(getpid()));
  const size_t candidate = size_t(request->askedReference.value_or(0));
  std::vector<int> first = {0};
  if (candidate != 0) first.push_back(int(candidate));
  describeSettings(*request, first, request->jobs, describing, resolutions);
  if (!resolutions[0].loaded) {
    std::cerr << resolutions[0].loadError;
    return kSceneError;
  }
  if (!(resolutions[candidate].loaded && resolutions[candidate].exactEverywhere)) {
    std::vector<int> rest;
    for (size_t i = 1; i < resolutions.size(); ++i)
      if (i != candidate) rest.push_back(int(i));
    describeSettings(*request, rest, request->jobs, describing, resolutions);
  }
  const ReferenceChoice reference =
      chooseReference(request->settings, resolutions, request->askedReference, request->coarseReference);
  if (!reference.error.empty()) {
    std::cerr << "trephine: " << reference.error << "\n";
    return kUsage;
  }
  request->options.referenceIndex = reference.index;
  const StudyOptions& options = request->options;
  const Rank rank = mpiRank();
  if (rank.size == 1)
    for (const char* stale : {kPosesFile, kNoExactShapeFile, kReferencesFile, "study.csv", "pairs.csv", "study.md",
                              "pareto.png", "pairs.png"})
      std::filesystem::remove(options.out / stale, ec);

  const int count = static_cast<int>(request->settings.size());
  std::vector<int> mine;
  for (int i = 0; i < count; ++i)
    if (i % rank.size == rank.rank && i != options.referenceIndex) mine.push_back(i);
  // The reference's run gives the poses every other setting is queried at: it
  // runs first, on the rank that owns it; the others wait for its poses.
  const int referenceIndex = options.referenceIndex;
  const bool ownsReference = referenceIndex % rank.size == rank.rank;
  StudyProgress progress;
  progress.all = mine.size() + (ownsReference ? 1 : 0);
  progress.jobs = request->jobs;
  progress.repeat = request->repeat;
  if (ownsReference) runWorkers(*request, {referenceIndex}, 1, progress);
  waitFor([&] { return ofThisStudy(*request, options.out / kPosesFile) || settingDone(*request, referenceIndex); });
  if (!ofThisStudy(*request, options.out / kPosesFile)) {
    std::cerr << "trephine: the reference setting failed, so no setting can be compared: "
              << settingErrorMessage(options.out / request->settings[referenceIndex].directoryName() / kErrorFile)
              << "\n";
    return kRuntimeFailure;
  }
  runWorkers(*request, mine, request->jobs, progress);
  // The timing runs, round by round: each round runs every setting of this
  // rank that ran once more, on the same motion, so that a machine that
  // slows down during the study slows every setting alike.
  std::vector<int> timed;
  if (ownsReference) timed.push_back(referenceIndex);
  timed.insert(timed.end(), mine.begin(), mine.end());
  std::erase_if(timed, [&](int i) {
    return ofThisStudy(*request, options.out / request->settings[i].directoryName() / kErrorFile);
  });
  for (int run = 2; run <= request->repeat && !timed.empty(); ++run) {
    std::cout << "timing round " << run << " of " << request->repeat << ": " << timed.size() << " settings"
              << std::endl;
    runWorkers(*request, timed, request->jobs, progress, run);
  }
  if (rank.rank != 0) return kOk;

  waitFor([&] {
    for (int i = 0; i < count; ++i)
      if (!settingTimed(*request, i)) return false;
    return true;
  });
  std::vector<std::string> written;
  StudyReport report;
  try {
    report = gatherStudy(options.out, request->settings, referenceIndex, reference.reason, request->repeat);
    written = writeStudy(report, options.out, options.scene.string());
  } catch (const std::exception& e) {
    std::cerr << "trephine: " << e.what() << "\n";
    return kRuntimeFailure;
  }
  int failed = 0;
  for (const StudyRow& row : report.rows)
    if (!row.error.empty()) {
      ++failed;
      std::cerr << "trephine: setting " << row.setting.index + 1 << " failed: " << row.error << "\n";
    }
  std::cout << "study     " << count << " settings, " << failed << " failed; reference: " << report.reference << "\n"
            << "outputs   " << options.out.string() << "/ (study.csv, study.md, settings/)\n";
  drawPareto(options.out);
  return failed == 0 ? kOk : kRuntimeFailure;
}

}  // namespace trephine::cli
