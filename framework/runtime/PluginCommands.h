#pragma once
// Subcommands of the trephine program that a plugin provides, as a registry
// service: the brain plugin's `cellsize` (the grid cell-size experiments of
// the thesis's chapter 5). The program parses the command line, loads the
// plugin and hands the arguments over, so that it links only the framework;
// the plugin runs the command, printing to stdout and stderr and writing its
// outputs, and asks the program to draw its plots (the program knows where
// its plot scripts are installed).
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Interface.h"
#include "framework/runtime/CommandArguments.h"

namespace trephine {

// `python3 SCRIPT ARGUMENTS...`, which draws the PNG `drawn` (for the message
// that says how to draw it by hand when it cannot run).
struct PlotRequest {
  std::string script;  // a file name of the program's plot scripts: "plot_cellsize.py"
  std::vector<std::string> arguments;
  std::string drawn;
};

// Runs a plot script; true when it drew the plot.
using PlotDrawer = std::function<bool(const PlotRequest&)>;

class TREPHINE_INTERFACE PluginCommands {
 public:
  static constexpr std::string_view kTypeName = "PluginCommands";
  virtual ~PluginCommands();
  // Runs the subcommand `arguments.command`; returns its exit code (cli::ExitCode).
  virtual int run(const cli::Arguments& arguments, const PlotDrawer& drawPlot) const = 0;
};

}  // namespace trephine
