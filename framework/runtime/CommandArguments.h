#pragma once
// A subcommand's command line as the trephine program parsed it, and what a
// subcommand returns: what the program hands to the code that runs it, its
// own or a plugin's (PluginCommands.h).
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace trephine::cli {

enum ExitCode { kOk = 0, kSceneError = 1, kUsage = 2, kRuntimeFailure = 3 };

struct Arguments {
  std::string command;
  std::vector<std::string> positional;
  std::map<std::string, std::string> options;  // "--out" -> "dir"; flags map to ""
  std::vector<std::string> overrides;          // every --set value, in order
  std::vector<std::string> variations;         // every --vary value, in order (trephine study)
  bool has(const std::string& option) const { return options.count(option) > 0; }
  std::optional<std::string> get(const std::string& option) const;
};

// The number option `name` (or `fallback` when absent); on a bad value,
// nullopt and `error` names the option and the text.
std::optional<double> numberOption(const Arguments& a, const std::string& name, double fallback, std::string& error);

}  // namespace trephine::cli
