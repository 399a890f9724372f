#include "tools/trephine/PlotScript.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <iostream>

namespace trephine::cli {

pid_t spawn(const std::vector<std::string>& args, bool searchPath, int* error) {
  std::vector<char*> argv;
  for (const std::string& s : args) argv.push_back(const_cast<char*>(s.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int failed = searchPath ? posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ)
                                : posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ);
  if (failed && error) *error = failed;
  return failed ? -1 : pid;
}

namespace {
std::filesystem::path findScript(const std::string& name) {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  for (const std::filesystem::path& candidate :
       {exe.parent_path().parent_path() / "share/trephine" / name, std::filesystem::path(TREPHINE_SOURCE_DIR) / "tools" / name})
    if (std::filesystem::exists(candidate)) return candidate;
  return {};
}
}  // namespace

bool runPlotScript(const std::string& script, const std::vector<std::string>& args, const std::string& what) {
  const std::filesystem::path path = findScript(script);
  // Debian's interpreter, the one tools/setup gives matplotlib, before
  // whichever python3 comes first in PATH (a virtual environment may lack it).
  std::error_code ec;
  const std::string python = std::filesystem::exists("/usr/bin/python3", ec) ? "/usr/bin/python3" : "python3";
  std::string command = python + " " + (path.empty() ? "tools/" + script : path.string());
  for (const std::string& a : args) command += " " + a;
  int status = -1;
  if (!path.empty()) {
    std::vector<std::string> argv{python, path.string()};
    argv.insert(argv.end(), args.begin(), args.end());
    const pid_t pid = spawn(argv, true);
    if (pid > 0) waitpid(pid, &status, 0);
  }
  if (status == 0) return true;
  // Exit 4: the script found no matplotlib. Anything else (a full disk, a
  // folder it may not write) the script has said above, in its own words.
  const bool noMatplotlib = WIFEXITED(status) && WEXITSTATUS(status) == 4;
  std::cerr << "trephine: " << what << " not drawn ("
            << (path.empty()        ? "the plot script " + script + " is not installed"
                : noMatplotlib      ? std::string("needs python3-matplotlib")
                : WIFEXITED(status) ? "the plot script failed with exit " + std::to_string(WEXITSTATUS(status)) +
                                          ", saying why above"
                                    : std::string("the plot script did not run"))
            << "); draw it with: " << command << "\n";
  return false;
}

}  // namespace trephine::cli
