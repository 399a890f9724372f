#pragma once
// Parsing of the trephine command line: a subcommand, one positional
// argument at most, and options. Usage errors exit with code 2.
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

// `valueOptions` take a value ("--out DIR" or "--out=DIR"); `flags` do not.
// Returns the error message on a usage error.
std::optional<std::string> parseArguments(int argc, char** argv, const std::vector<std::string>& valueOptions,
                                          const std::vector<std::string>& flags, Arguments& out);

}  // namespace trephine::cli
