#pragma once
// Parsing of the trephine command line: a subcommand, one positional
// argument at most, and options. Usage errors exit with code 2.
#include <optional>
#include <string>
#include <vector>

#include "framework/runtime/CommandArguments.h"

namespace trephine::cli {

// `valueOptions` take a value ("--out DIR" or "--out=DIR"); `flags` do not.
// Returns the error message on a usage error.
std::optional<std::string> parseArguments(int argc, char** argv, const std::vector<std::string>& valueOptions,
                                          const std::vector<std::string>& flags, Arguments& out);

}  // namespace trephine::cli
