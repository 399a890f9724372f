#include "tools/trephine/CommandLine.h"

#include <algorithm>

#include "framework/core/Strings.h"

namespace trephine::cli {

std::optional<std::string> parseArguments(int argc, char** argv, const std::vector<std::string>& valueOptions,
                                          const std::vector<std::string>& flags, Arguments& out) {
  std::vector<std::string> known = valueOptions;
  known.insert(known.end(), flags.begin(), flags.end());
  for (int i = 2; i < argc; ++i) {
    std::string arg = argv[i];
    if (!arg.starts_with("--")) {
      out.positional.push_back(arg);
      continue;
    }
    std::string value;
    bool hasInlineValue = false;
    if (const size_t eq = arg.find('='); eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
      hasInlineValue = true;
    }
    const bool takesValue = std::find(valueOptions.begin(), valueOptions.end(), arg) != valueOptions.end();
    const bool isFlag = std::find(flags.begin(), flags.end(), arg) != flags.end();
    if (!takesValue && !isFlag) return "unknown option '" + arg + "'" + didYouMean(arg, known);
    if (takesValue && !hasInlineValue) {
      if (i + 1 >= argc) return "option '" + arg + "' needs a value";
      value = argv[++i];
    }
    if (isFlag && hasInlineValue) return "option '" + arg + "' takes no value";
    if (arg == "--set") {
      out.overrides.push_back(value);
    } else if (arg == "--vary") {
      out.variations.push_back(value);
    } else {
      out.options[arg] = value;
    }
  }
  return std::nullopt;
}

}  // namespace trephine::cli
