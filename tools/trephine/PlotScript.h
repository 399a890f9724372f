#pragma once
// Child processes of the trephine program: its workers and the plot scripts
// (tools/plot_*.py, matplotlib) that draw PNGs from the CSV files it writes.
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace trephine::cli {

// Starts `args` (args[0] is the program; searched in PATH when `searchPath`);
// returns its pid, or -1 (and the error in `error`).
pid_t spawn(const std::vector<std::string>& args, bool searchPath, int* error = nullptr);

// Runs `python3 SCRIPT ARGS...` with SCRIPT found next to the installed
// program (share/trephine) or in the source tree's tools/. Returns true when
// it ran and exited 0; else prints to stderr the command that would draw it
// (`what`: the file it draws) and returns false.
bool runPlotScript(const std::string& script, const std::vector<std::string>& args, const std::string& what);

}  // namespace trephine::cli
